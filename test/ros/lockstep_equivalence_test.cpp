/// \file lockstep_equivalence_test.cpp
/// \brief rostest: plant_sim_node + mrac_controller_node in lockstep reproduce the batch CLI.
///
/// Subscribes every topic of the pair (the launch makes both nodes wait for these
/// subscriptions before step 0, so nothing is missed), waits for the last step's status,
/// runs `preadapt_sim` with the same scenario, mode and seed, and compares:
/// - the run reaches the end: every step 0 .. N-1 exactly once on state, command and status;
/// - alpha (plant/state), theta_hat (controller/status) and u (elevator_cmd) equal the CLI's
///   CSV to 1e-9;
/// - the attention events match the CLI's in count, type and time; pa_robust's verification
///   fields (decision, chosen, candidates, score, score_keep, the estimate set) equal the
///   CLI's, and events without a decision carry the message defaults;
/// - onsets and recoveries appear (oracle: onsets only, it has no phases to recover from;
///   pa_robust: DECISION events too; l1: none, its |e| stays below c_e on scenario 1,
///   docs/research/l1.md), and per-window peaks of |e| equal the CLI's;
/// - in learning modes, ~weights_out holds the episodes of the last event.

#include <gtest/gtest.h>
#include <ros/ros.h>
#include <unistd.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <mutex>
#include <sstream>
#include <string>
#include <vector>

#include "preadaptive_mrac/AdaptationStatus.h"
#include "preadaptive_mrac/AttentionEvent.h"
#include "preadaptive_mrac/ElevatorCommand.h"
#include "preadaptive_mrac/PlantState.h"
#include "preadaptive_mrac/PlantTruth.h"
#include "preadaptive_mrac/core/sim/plant_conditions.hpp"

namespace pm = preadaptive_mrac;

namespace {

struct Recorded {
  std::mutex m;
  std::uint64_t total = 0;
  std::vector<double> alpha, u, t, pitch;
  std::vector<double> elevator, elevator_command, gust, effectiveness;  // the conditions
  std::map<std::string, std::vector<double>> conditions;  // PlantTruth.conditions by name
  std::map<std::uint64_t, std::pair<std::string, double>> envelope;  // step: bound, t
  std::vector<std::vector<double>> theta_hat;
  std::vector<double> e;
  std::vector<int> state_seen, cmd_seen, status_seen;
  std::vector<pm::AttentionEvent> events;
  std::int64_t truth_count = 0;
  bool sized = false;
  // Commands and statuses that arrive before the first state (which gives the size) come over
  // other connections and can overtake it on a loaded machine: kept, replayed by size().
  std::vector<pm::ElevatorCommand> early_cmds;
  std::vector<pm::AdaptationStatus> early_status;
  void size(std::uint64_t n) {
    if (sized) return;
    total = n;
    alpha.assign(n, NAN);
    pitch.assign(n, NAN);
    u.assign(n, NAN);
    t.assign(n, NAN);
    elevator.assign(n, NAN);
    elevator_command.assign(n, NAN);
    gust.assign(n, NAN);
    effectiveness.assign(n, NAN);
    e.assign(n, NAN);
    theta_hat.assign(n, {});
    state_seen.assign(n, 0);
    cmd_seen.assign(n, 0);
    status_seen.assign(n, 0);
    sized = true;
    for (const auto& c : early_cmds) addCmd(c);
    for (const auto& st : early_status) addStatus(st);
    early_cmds.clear();
    early_status.clear();
  }
  void addCmd(const pm::ElevatorCommand& m) {
    if (!sized) {
      early_cmds.push_back(m);
      return;
    }
    if (m.step >= total) return;
    u[m.step] = m.u;
    cmd_seen[m.step]++;
  }
  void addStatus(const pm::AdaptationStatus& m) {
    if (!sized) {
      early_status.push_back(m);
      return;
    }
    if (m.step >= total) return;
    theta_hat[m.step] = m.theta_hat;
    e[m.step] = m.e;
    status_seen[m.step]++;
  }
};

/// The CLI's CSV as columns by name.
std::map<std::string, std::vector<double>> readCsv(const std::string& path) {
  std::ifstream f(path);
  std::map<std::string, std::vector<double>> cols;
  std::string line;
  if (!std::getline(f, line)) return cols;
  std::vector<std::string> names;
  {
    std::stringstream ss(line);
    std::string c;
    while (std::getline(ss, c, ',')) names.push_back(c);
  }
  while (std::getline(f, line)) {
    std::stringstream ss(line);
    std::string c;
    size_t i = 0;
    // strtod, not stod: stod throws on subnormal values (oracle's e decays below 1e-308)
    while (std::getline(ss, c, ',') && i < names.size())
      cols[names[i++]].push_back(std::strtod(c.c_str(), nullptr));
  }
  return cols;
}

/// Run a command; returns its stdout (empty on failure to start) and sets *rc.
std::string runCommand(const std::string& cmd, int* rc) {
  std::string out;
  FILE* p = popen(cmd.c_str(), "r");
  if (p == nullptr) {
    *rc = -1;
    return out;
  }
  char buf[4096];
  size_t n;
  while ((n = fread(buf, 1, sizeof(buf), p)) > 0) out.append(buf, n);
  *rc = pclose(p);
  return out;
}

std::string lastLine(const std::string& s) {
  auto end = s.find_last_not_of('\n');
  if (end == std::string::npos) return "";
  auto start = s.rfind('\n', end);
  return s.substr(start == std::string::npos ? 0 : start + 1,
                  end - (start == std::string::npos ? 0 : start + 1) + 1);
}

}  // namespace

class LockstepTest : public ::testing::Test {
 protected:
  void SetUp() override {
    ros::NodeHandle pnh("~");
    pnh.param<std::string>("mode", mode_, "rac");
    pnh.param<std::string>("scenario", scenario_, "1");
    pnh.param<int>("seed", seed_, 1);
    pnh.param<double>("timeout", timeout_, 400.0);
    pnh.param<std::string>("weights_out", weights_out_, "");
    pnh.param<std::string>("plant_config", plant_config_, "");
  }
  std::string mode_, scenario_, weights_out_, plant_config_;
  int seed_ = 1;
  double timeout_ = 400.0;
};

TEST_F(LockstepTest, ReproducesBatchCli) {
  ros::NodeHandle nh;
  Recorded rec;
  auto hints = ros::TransportHints().tcpNoDelay();
  // Queue size 0 = unbounded: a test must not lose samples to a full queue.
  ros::Subscriber s1 = nh.subscribe<pm::PlantState>(
      "plant/state", 0,
      [&rec](const pm::PlantState::ConstPtr& m) {
        std::lock_guard<std::mutex> l(rec.m);
        rec.size(m->total_steps);
        if (m->step >= rec.total) return;
        rec.alpha[m->step] = m->alpha;
        rec.pitch[m->step] = m->theta_pitch;
        rec.t[m->step] = m->t;
        rec.elevator[m->step] = m->elevator;
        rec.elevator_command[m->step] = m->elevator_command;
        rec.state_seen[m->step]++;
      },
      ros::VoidConstPtr(), hints);
  ros::Subscriber s2 = nh.subscribe<pm::ElevatorCommand>(
      "controller/elevator_cmd", 0,
      [&rec](const pm::ElevatorCommand::ConstPtr& m) {
        std::lock_guard<std::mutex> l(rec.m);
        rec.addCmd(*m);
      },
      ros::VoidConstPtr(), hints);
  ros::Subscriber s3 = nh.subscribe<pm::AdaptationStatus>(
      "controller/status", 0,
      [&rec](const pm::AdaptationStatus::ConstPtr& m) {
        std::lock_guard<std::mutex> l(rec.m);
        rec.addStatus(*m);
      },
      ros::VoidConstPtr(), hints);
  ros::Subscriber s4 = nh.subscribe<pm::AttentionEvent>(
      "controller/attention", 0,
      [&rec](const pm::AttentionEvent::ConstPtr& m) {
        std::lock_guard<std::mutex> l(rec.m);
        rec.events.push_back(*m);
      },
      ros::VoidConstPtr(), hints);
  ros::Subscriber s5 = nh.subscribe<pm::PlantTruth>(
      "plant/truth", 0,
      [&rec](const pm::PlantTruth::ConstPtr& m) {
        std::lock_guard<std::mutex> l(rec.m);
        rec.truth_count++;
        // Truth can overtake the first state (which sizes the record): only sized steps.
        if (rec.sized && m->step < rec.total) {
          rec.gust[m->step] = m->gust_w;
          rec.effectiveness[m->step] = m->effectiveness;
          rec.envelope[m->step] = {m->envelope_bound, m->envelope_exit_t};
          for (size_t i = 0; i < m->condition_names.size() && i < m->conditions.size(); ++i) {
            auto& v = rec.conditions[m->condition_names[i]];
            if (v.empty()) v.assign(rec.total, NAN);
            v[m->step] = m->conditions[i];
          }
        }
      },
      ros::VoidConstPtr(), hints);
  ros::AsyncSpinner spinner(1);
  spinner.start();

  // Wait (bounded) for the last step's state, command and status. The controller publishes
  // the status last, but each topic has a connection of its own and the publisher's outgoing
  // queues are served independently: with a fast (nodelet) pair, the last status can arrive
  // while earlier commands are still in the command connection's queue.
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(timeout_);
  bool done = false;
  while (ros::ok() && ros::WallTime::now() < deadline) {
    {
      std::lock_guard<std::mutex> l(rec.m);
      done = rec.sized && rec.total > 0 && rec.status_seen[rec.total - 1] > 0 &&
             rec.cmd_seen[rec.total - 1] > 0 && rec.state_seen[rec.total - 1] > 0 &&
             rec.truth_count >= static_cast<std::int64_t>(rec.total);
    }
    if (done) break;
    ros::WallDuration(0.05).sleep();
  }
  ASSERT_TRUE(done) << "no state, command, status and truth for the last step within " << timeout_
                    << " s";
  // Attention events have a connection of their own too and their number is not known here:
  // take them until none has arrived for 0.5 s (bounded by the same deadline).
  std::size_t events_seen = 0;
  ros::WallTime quiet_since = ros::WallTime::now();
  while (ros::ok() && ros::WallTime::now() < deadline &&
         (ros::WallTime::now() - quiet_since).toSec() < 0.5) {
    {
      std::lock_guard<std::mutex> l(rec.m);
      if (rec.events.size() != events_seen) {
        events_seen = rec.events.size();
        quiet_since = ros::WallTime::now();
      }
    }
    ros::WallDuration(0.05).sleep();
  }
  spinner.stop();

  // --- the batch CLI, same scenario, mode, seed and dt
  const std::string csv = std::string(std::getenv("TMPDIR") ? std::getenv("TMPDIR") : "/tmp") +
                          "/pmrac_lockstep_cli_" + mode_ + "_" + std::to_string(::getpid()) +
                          ".csv";
  int rc = 0;
  const std::string cmd = std::string(PMRAC_SIM_BIN) + " --scenario " + scenario_ + " --mode " +
                          mode_ + " --seed " + std::to_string(seed_) + " --dt 0.001 --json --csv " +
                          csv + (plant_config_.empty() ? "" : " --plant " + plant_config_);
  const std::string out = runCommand(cmd, &rc);
  ASSERT_EQ(rc, 0) << cmd;
  const YAML::Node json = YAML::Load(lastLine(out));
  const auto cols = readCsv(csv);
  std::remove(csv.c_str());
  ASSERT_TRUE(cols.count("x1") && cols.count("theta_hat0") && cols.count("u"));
  const size_t n = cols.at("x1").size();
  ASSERT_EQ(n, rec.total) << "steps: CLI " << n << ", ROS " << rec.total;
  ASSERT_EQ(json["steps"].as<std::uint64_t>(), rec.total);

  // --- every step exactly once
  for (size_t k = 0; k < n; ++k) {
    ASSERT_EQ(rec.state_seen[k], 1) << "state of step " << k;
    ASSERT_EQ(rec.cmd_seen[k], 1) << "command of step " << k;
    ASSERT_EQ(rec.status_seen[k], 1) << "status of step " << k;
  }
  EXPECT_EQ(rec.truth_count, static_cast<std::int64_t>(n));

  // --- series equal to 1e-9
  double max_alpha = 0.0, max_th = 0.0, max_u = 0.0, max_t = 0.0;
  for (size_t k = 0; k < n; ++k) {
    max_alpha = std::max(max_alpha, std::abs(rec.alpha[k] - cols.at("x1")[k]));
    max_u = std::max(max_u, std::abs(rec.u[k] - cols.at("u")[k]));
    max_t = std::max(max_t, std::abs(rec.t[k] - cols.at("t")[k]));
    ASSERT_EQ(rec.theta_hat[k].size(), 3u);
    for (int i = 0; i < 3; ++i)
      max_th = std::max(max_th, std::abs(rec.theta_hat[k][static_cast<size_t>(i)] -
                                         cols.at("theta_hat" + std::to_string(i))[k]));
  }
  EXPECT_LE(max_alpha, 1e-9) << "alpha";
  // The linear model has no flight path: rviz's pitch is drawn on a level one, the nose at
  // alpha (the integral of q looped the aircraft). An engine's pitch is its own.
  if (cols.count("pitch") == 0) {
    double max_pitch = 0.0;
    for (size_t k = 0; k < n; ++k)
      max_pitch = std::max(max_pitch, std::abs(rec.pitch[k] - rec.alpha[k]));
    EXPECT_EQ(max_pitch, 0.0) << "theta_pitch against alpha on the linear plant";
  }
  EXPECT_LE(max_th, 1e-9) << "theta_hat";
  EXPECT_LE(max_u, 1e-9) << "u";
  EXPECT_LE(max_t, 1e-12) << "t";
  std::printf("[lockstep %s] %zu steps; max |diff| alpha %.3g, theta_hat %.3g, u %.3g\n",
              mode_.c_str(), n, max_alpha, max_th, max_u);

  // --- a plant with conditions writes their columns; the published elevator
  // (applied over the previous step), the command it was given and the gust equal them.
  if (cols.count("u_applied")) {
    double max_el = 0.0, max_cmd = 0.0, max_gust = 0.0, max_lambda = 0.0, gust_rms = 0.0;
    int moved = 0;
    for (size_t k = 0; k < n; ++k) {
      const double applied = k == 0 ? 0.0 : cols.at("u_applied")[k - 1];
      const double cmd = k == 0 ? 0.0 : cols.at("u")[k - 1];
      max_el = std::max(max_el, std::abs(rec.elevator[k] - applied));
      max_cmd = std::max(max_cmd, std::abs(rec.elevator_command[k] - cmd));
      if (!std::isnan(rec.gust[k])) {
        max_gust = std::max(max_gust, std::abs(rec.gust[k] - cols.at("w_gust")[k]));
        max_lambda =
            std::max(max_lambda, std::abs(rec.effectiveness[k] - cols.at("effectiveness")[k]));
      }
      gust_rms += cols.at("w_gust")[k] * cols.at("w_gust")[k];
      moved += applied != cmd ? 1 : 0;
    }
    EXPECT_LE(max_el, 1e-12) << "elevator (applied)";
    EXPECT_LE(max_cmd, 1e-12) << "elevator_command";
    EXPECT_LE(max_gust, 1e-12) << "gust_w";
    EXPECT_LE(max_lambda, 0.0) << "effectiveness";
    // The conditions are on: the servo moves behind the command, and there is a gust.
    EXPECT_GT(moved, static_cast<int>(n / 2));
    EXPECT_GT(std::sqrt(gust_rms / static_cast<double>(n)), 0.1);
    std::printf("[lockstep %s] conditions: max |diff| elevator %.3g, command %.3g, gust %.3g\n",
                mode_.c_str(), max_el, max_cmd, max_gust);
  }
  // The truth's record: every row of the table the CSV has, by name, equals its
  // CSV column: held over [t, t + dt] at step k (an engine's flight outputs: at t_k), or of the
  // step before for the after-step rows. The engine's rows are in the truth exactly
  // when the CSV has them (a JSBSim run), the plant's always.
  int rows_compared = 0;
  for (const pm::PlantConditionColumn& c : pm::kPlantConditionTable) {
    const bool in_truth = rec.conditions.count(c.name) > 0;
    if (c.engine) {
      EXPECT_EQ(in_truth, cols.count(c.name) > 0) << "engine row " << c.name;
    } else {
      EXPECT_TRUE(in_truth) << "PlantTruth has no condition " << c.name;
    }
    if (!cols.count(c.name) || !in_truth) continue;
    const bool after = c.known == pm::ConditionKnown::kAfterStep;
    double max_diff = 0.0;
    size_t seen = 0;
    for (size_t k = 0; k < n; ++k) {
      const double got = rec.conditions.at(c.name)[k];
      if (std::isnan(got)) continue;
      const double want = after ? (k == 0 ? 0.0 : cols.at(c.name)[k - 1]) : cols.at(c.name)[k];
      max_diff = std::max(max_diff, std::abs(got - want));
      ++seen;
    }
    EXPECT_GT(seen, n / 2) << c.name;
    EXPECT_LE(max_diff, 0.0) << "PlantTruth condition " << c.name;
    ++rows_compared;
  }
  std::printf("[lockstep %s] %d rows of the conditions record equal the CSV's\n", mode_.c_str(),
              rows_compared);

  // --- the truth says the CLI's first exit from the flight envelope (its bound and
  // time) from the sample after it on, and nothing before it.
  {
    const YAML::Node ex = json["envelope_exit"];
    std::uint64_t from = rec.total, seen = 0;
    if (ex && !ex.IsNull()) from = ex["step"].as<std::uint64_t>() + 1;
    for (const auto& kv : rec.envelope) {
      if (kv.first + 1 < from) {
        EXPECT_EQ(kv.second.first, "") << "step " << kv.first;
        EXPECT_EQ(kv.second.second, -1.0) << "step " << kv.first;
      } else if (kv.first >= from) {
        EXPECT_EQ(kv.second.first, ex["bound"].as<std::string>()) << "step " << kv.first;
        EXPECT_EQ(kv.second.second, ex["t"].as<double>()) << "step " << kv.first;
        ++seen;
      }
    }
    if (from < rec.total) {
      EXPECT_GT(seen, 0u) << "no truth after the envelope exit";
    }
    std::printf("[lockstep %s] envelope exit: %s\n", mode_.c_str(),
                from < rec.total ? ex["text"].as<std::string>().c_str() : "none");
  }

  // --- events: count, type and time; pa_robust's decisions
  const YAML::Node ev = json["events"];
  ASSERT_EQ(ev.size(), rec.events.size()) << "event count";
  const std::map<std::string, std::uint8_t> codes = {
      {"keep", pm::AttentionEvent::DECISION_KEEP},
      {"fit", pm::AttentionEvent::DECISION_FIT},
      {"memory", pm::AttentionEvent::DECISION_MEMORY},
      {"network", pm::AttentionEvent::DECISION_NETWORK}};
  int onsets = 0, recoveries = 0, decision_events = 0, decisions = 0;
  for (size_t i = 0; i < rec.events.size(); ++i) {
    const pm::AttentionEvent& m = rec.events[i];
    EXPECT_EQ(ev[i]["type"].as<std::string>(), m.type_name) << "event " << i;
    EXPECT_NEAR(ev[i]["t"].as<double>(), m.t, 1e-9) << "event " << i;
    EXPECT_NEAR(ev[i]["e"].as<double>(), m.e, 1e-9) << "event " << i;
    if (m.type == pm::AttentionEvent::ONSET) ++onsets;
    if (m.type == pm::AttentionEvent::RECOVERED) ++recoveries;
    if (m.type == pm::AttentionEvent::DECISION) {
      ++decision_events;
      EXPECT_EQ(m.type_name, "decision") << "event " << i;
    }
    if (ev[i]["decision"]) {
      ++decisions;
      const std::string d = ev[i]["decision"].as<std::string>();
      EXPECT_EQ(m.decision, d) << "event " << i;
      ASSERT_TRUE(codes.count(d)) << "event " << i << ": decision '" << d << "'";
      EXPECT_EQ(m.decision_code, codes.at(d)) << "event " << i;
      EXPECT_EQ(m.chosen, ev[i]["chosen"].as<int>()) << "event " << i;
      EXPECT_EQ(m.candidates, ev[i]["candidates"].as<int>()) << "event " << i;
      const double score = ev[i]["score"].as<double>();
      const double score_keep = ev[i]["score_keep"].as<double>();
      EXPECT_NEAR(m.score, score, 1e-12 * std::max(1.0, std::abs(score))) << "event " << i;
      EXPECT_NEAR(m.score_keep, score_keep, 1e-12 * std::max(1.0, std::abs(score_keep)))
          << "event " << i;
      const YAML::Node after = ev[i]["theta_hat_after"];
      ASSERT_EQ(after.size(), m.theta_hat_after.size()) << "event " << i;
      for (size_t j = 0; j < after.size(); ++j)
        EXPECT_NEAR(m.theta_hat_after[j], after[j].as<double>(), 1e-9) << "event " << i;
    } else {
      // the defaults of an event without a verification
      EXPECT_EQ(m.decision, "") << "event " << i;
      EXPECT_EQ(m.decision_code, pm::AttentionEvent::DECISION_NONE) << "event " << i;
      EXPECT_EQ(m.chosen, -1) << "event " << i;
      EXPECT_EQ(m.candidates, 0) << "event " << i;
      EXPECT_EQ(m.score, 0.0) << "event " << i;
      EXPECT_EQ(m.score_keep, 0.0) << "event " << i;
    }
  }
  if (mode_ ==
      "l1") {  // |e| stays below c_e on scenario 1 (docs/research/l1.md): no crossing at all
    EXPECT_EQ(onsets, 0);
  } else {
    EXPECT_GE(onsets, 1);
  }
  // oracle resets theta_hat at each switch and has no phases, so nothing recovers
  if (mode_ != "oracle" && mode_ != "l1") {
    EXPECT_GE(recoveries, 1);
  }
  if (mode_ == "pa_robust") {
    EXPECT_GE(decision_events, 1);
    EXPECT_GE(decisions, onsets) << "every pa_robust onset is verified";
  } else {
    EXPECT_EQ(decisions, 0) << "only pa_robust verifies";
    EXPECT_EQ(decision_events, 0) << "only pa_robust verifies";
  }
  std::printf(
      "[lockstep %s] %zu events: %d onsets, %d recoveries, %d decision events, %d "
      "decisions\n",
      mode_.c_str(), rec.events.size(), onsets, recoveries, decision_events, decisions);

  // --- per-window peaks of |e| (windows hold (t_start, t_end]; sample 0 in the first)
  const YAML::Node win = json["windows"];
  ASSERT_GE(win.size(), 1u);
  std::vector<double> t_end, peak(win.size(), 0.0);
  for (size_t w = 0; w < win.size(); ++w) t_end.push_back(win[w]["t_end"].as<double>());
  for (size_t k = 0; k < n; ++k) {
    size_t w = 0;
    while (w + 1 < t_end.size() && rec.t[k] > t_end[w]) ++w;
    peak[w] = std::max(peak[w], std::abs(rec.e[k]));
  }
  for (size_t w = 0; w < win.size(); ++w) {
    const double cli = win[w]["peak_abs_e"].as<double>();
    EXPECT_NEAR(peak[w], cli, 1e-12 * std::max(1.0, cli)) << "window " << w;
    std::printf("[lockstep %s] window %zu (%g, %g]: peak |e| ROS %.17g CLI %.17g\n", mode_.c_str(),
                w, win[w]["t_start"].as<double>(), t_end[w], peak[w], cli);
  }

  // --- weights saved after each learning episode
  if (!weights_out_.empty() &&
      (mode_ == "pa_learn" || mode_ == "pa_learn_exact" || mode_ == "pa_robust")) {
    std::int64_t last_episodes = 0;
    for (const auto& e : rec.events)
      last_episodes = std::max<std::int64_t>(last_episodes, e.episodes);
    ASSERT_GE(last_episodes, 1) << "no learning episode in a learning mode";
    const YAML::Node w = YAML::LoadFile(weights_out_);
    EXPECT_EQ(w["episodes"].as<std::int64_t>(), last_episodes) << weights_out_;
    std::remove(weights_out_.c_str());
  }
}

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "lockstep_equivalence_test");
  return RUN_ALL_TESTS();
}
