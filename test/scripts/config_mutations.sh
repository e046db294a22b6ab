#!/usr/bin/env bash
# every key of the shipped YAML files, broken (dropped, wrong type, NaN, wrong size),
# through scenario.launch: a seeded sample of scripts/config_mutation_study (one mutation per
# file and kind, two that must run normally, the rest random; every other one in realtime)
# must end within 30 s with the key named and scripts/lib/launch_checked exiting 2, or run
# normally where the study's EXPECT_RUNS list says so. Then a few through compare.launch, and
# the optional keys dropped: the run goes on and the controller's start-up line "optional keys
# filled with defaults: ..." names the key (no silent default).
# The full set: scripts/config_mutation_study (about 10 minutes).
#   Env: PMRAC_BUILD_DIR (default build), PMRAC_MUTATION_SAMPLE (25), PMRAC_MUTATION_SEED (10).
set -uo pipefail
TEST_NAME=config_mutations
# shellcheck source=test/scripts/lib/ros_build.sh
source "$(dirname "$0")/lib/ros_build.sh"
export ROS_HOSTNAME=localhost
RC=0
/usr/bin/python3 "$ROOT/scripts/config_mutation_study" --check --clock mixed \
  --sample "${PMRAC_MUTATION_SAMPLE:-25}" --seed "${PMRAC_MUTATION_SEED:-10}" || RC=1
/usr/bin/python3 "$ROOT/scripts/config_mutation_study" --check --launch compare \
  --only controller.lqr.R:type --only plant.B:nan --only scenario.theta.1.until:drop \
  --only plant.operating_point.U:drop || RC=1
/usr/bin/python3 "$ROOT/scripts/config_mutation_study" --check \
  --only controller.attention.hysteresis:drop --only controller.attention.confirm_samples:drop \
  --only controller.adaptation.freeze_when_saturated:drop || RC=1
[ "$RC" = 0 ] && echo "config_mutations: PASSED" || echo "config_mutations: FAILED"
exit "$RC"
