// Configuration: every problem at once, named by key; the CLI's exit codes and JSON.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <iterator>
#include <sstream>
#include <stdexcept>

#include "preadaptive_mrac/core/controller/controller.hpp"
#include "preadaptive_mrac/core/controller/mode_registry.hpp"
#include "preadaptive_mrac/core/controller/tunables.hpp"
#include "preadaptive_mrac/core/solvers.hpp"
#include "preadaptive_mrac/io/yaml_params.hpp"
#include "preadaptive_mrac/params/modes_params.hpp"
#include "test_helpers.hpp"

using namespace preadaptive_mrac;

namespace {
std::vector<std::string> problemsOf(const ParamValue& tree, const KeyStyle& style = {}) {
  try {
    readRunConfig(tree, style);
  } catch (const ConfigError& e) {
    return e.problems();
  }
  return {};
}
bool mentions(const std::vector<std::string>& ps, const std::string& s) {
  for (const auto& p : ps)
    if (p.find(s) != std::string::npos) return true;
  return false;
}
std::string joined(const std::vector<std::string>& ps) {
  std::string o;
  for (const auto& p : ps) o += p + "\n";
  return o;
}

struct CmdResult {
  int code;
  std::string out;
};
CmdResult runBin(const std::string& bin, const std::string& args) {
  const std::string cmd = bin + " " + args + " 2>&1";
  FILE* p = popen(cmd.c_str(), "r");
  std::string out;
  char buf[4096];
  while (fgets(buf, sizeof(buf), p)) out += buf;
  const int status = pclose(p);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, out};
}
CmdResult runCli(const std::string& args) { return runBin(PMRAC_SIM_BIN, args); }
std::string tmpFile(const std::string& name, const std::string& text) {
  const std::string p = "/tmp/pmrac_test_" + std::to_string(getpid()) + "_" + name;
  std::ofstream(p) << text;
  return p;
}
}  // namespace

TEST(Config, PackageFilesAreValid) {
  const RunConfig c = test::packageConfig("3");
  EXPECT_EQ(c.plant.n(), 3);
  EXPECT_EQ(c.scenario.theta.size(), 10u);
  EXPECT_DOUBLE_EQ(c.scenario.endTime(), 140.0);
  EXPECT_EQ(c.controller.mode, "pa_learn");
  EXPECT_DOUBLE_EQ(c.controller.c_e, 0.005);
}

TEST(Config, EveryProblemAtOnceNamedByKey) {
  ParamValue t = test::packageTree();
  t.map()["controller"].map()["attention"].map().erase("c_e");                // missing
  t.setPath("controller.adaptation.gamma", ParamValue::makeString("ten"));    // wrong type
  t.setPath("controller.attention.c_ed", ParamValue::makeDouble(-1));         // sign
  t.setPath("controller.sample_time", ParamValue::makeDouble(std::nan("")));  // non-finite
  t.setPath("plant.B", ParamValue::makeList({ParamValue::makeInt(1), ParamValue::makeInt(2)}));
  t.setPath("controller.attention.ce", ParamValue::makeDouble(0.1));  // typo
  t.setPath("scenario.theta.2.until", ParamValue::makeDouble(3.0));   // not increasing
  const auto ps = problemsOf(t);
  EXPECT_TRUE(mentions(ps, "controller.attention.c_e: missing")) << joined(ps);
  EXPECT_TRUE(mentions(ps, "controller.adaptation.gamma: expected a number, got string"))
      << joined(ps);
  EXPECT_TRUE(mentions(ps, "controller.attention.c_ed: must be in [1e-06, 10], got -1"))
      << joined(ps);
  EXPECT_TRUE(mentions(ps, "controller.sample_time: expected a finite number")) << joined(ps);
  EXPECT_TRUE(mentions(ps, "plant.B: expected 3 numbers")) << joined(ps);
  EXPECT_TRUE(mentions(ps, "controller.attention.ce: unknown key")) << joined(ps);
  EXPECT_TRUE(mentions(ps, "scenario.theta.2.until: segments must end at increasing times"))
      << joined(ps);
  EXPECT_GE(ps.size(), 7u);
}

// a typo inside a scenario segment was reported only as the key it replaced.
TEST(Config, TypoInAScenarioSegmentIsNamed) {
  ParamValue t = test::packageTree();
  t.map()["scenario"].map()["theta"].list()[1].map().erase("until");
  t.setPath("scenario.theta.1.untill", ParamValue::makeDouble(20.0));
  const auto ps = problemsOf(t);
  EXPECT_TRUE(mentions(ps, "scenario.theta.1.until: missing")) << joined(ps);
  EXPECT_TRUE(mentions(ps, "scenario.theta.1.untill: unknown key")) << joined(ps);
}

// with the plant section misspelt, the state size is unknown; a theta vector was
// then checked against a guessed size of 1 (a spurious scenario problem).
TEST(Config, MisspeltPlantSectionIsNotEchoedAsAScenarioProblem) {
  ParamValue t = test::packageTree();
  t.map()["plnat"] = t.map()["plant"];
  t.map().erase("plant");
  t.setPath("scenario.theta.1.theta",
            ParamValue::makeList(
                {ParamValue::makeDouble(1), ParamValue::makeDouble(2), ParamValue::makeDouble(3)}));
  t.map()["scenario"].map()["theta"].list()[1].map().erase("scale");
  Sections sections;
  sections.strict_top_level = true;
  std::vector<std::string> ps;
  try {
    readRunConfig(t, KeyStyle{}, sections);
  } catch (const ConfigError& e) {
    ps = e.problems();
  }
  EXPECT_TRUE(mentions(ps, "plnat: unknown key")) << joined(ps);
  EXPECT_TRUE(mentions(ps, "plant.A: missing")) << joined(ps);
  EXPECT_FALSE(mentions(ps, "scenario.")) << joined(ps);
}

TEST(Config, RosStyleNamesAreFullyResolved) {
  ParamValue t = test::packageTree();
  t.map()["controller"].map()["attention"].map().erase("c_e");
  const auto ps = problemsOf(t, KeyStyle{"/mrac_controller/", '/'});
  EXPECT_TRUE(mentions(ps, "/mrac_controller/controller/attention/c_e: missing")) << joined(ps);
}

TEST(Config, NonStabilisablePlantIsRefusedNamingTheKey) {
  ParamValue t = test::packageTree();
  // Make the integrator unreachable and unstable: A(0,0) = 1 with B(0) = 0 and no coupling.
  t.setPath("plant.A",
            ParamValue::makeList(
                {ParamValue::makeList({ParamValue::makeDouble(1), ParamValue::makeDouble(0),
                                       ParamValue::makeDouble(0)}),
                 ParamValue::makeList({ParamValue::makeDouble(0), ParamValue::makeDouble(-0.32),
                                       ParamValue::makeDouble(0.86)}),
                 ParamValue::makeList({ParamValue::makeDouble(0), ParamValue::makeDouble(-0.93),
                                       ParamValue::makeDouble(-0.43)})}));
  const auto ps = problemsOf(t);
  EXPECT_TRUE(mentions(ps, "plant.A: (A, B) is not stabilisable")) << joined(ps);
  EXPECT_TRUE(mentions(ps, "[not_stabilizable]")) << joined(ps);
}

TEST(Config, ScenarioSegments) {
  ParamValue t = test::packageTree();
  t.setPath("scenario.theta.1.theta",
            ParamValue::makeList(
                {ParamValue::makeDouble(1), ParamValue::makeDouble(2), ParamValue::makeDouble(3)}));
  auto ps = problemsOf(t);
  EXPECT_TRUE(mentions(ps, "scenario.theta.1: give exactly one of 'scale'")) << joined(ps);
  t.map()["scenario"].map()["theta"].list()[1].map().erase("scale");
  const RunConfig c = readRunConfig(t);
  EXPECT_DOUBLE_EQ(c.scenario.thetaAt(10.0)[2], 3.0);
}

TEST(Cli, JsonHasTheDocumentedFields) {
  const CmdResult r = runCli("--scenario 1 --mode rac --json");
  ASSERT_EQ(r.code, 0) << r.out;
  const std::string last = r.out.substr(r.out.rfind('{', r.out.find("\"scenario\"")));
  for (const char* key :
       {"\"scenario\":\"1\"", "\"mode\":\"rac\"", "\"seed\":", "\"dt\":0.001", "\"K\":[",
        "\"P\":[[", "\"events\":[", "\"windows\":[", "\"iae\":", "\"peak_abs_e\":",
        "\"max_abs_u\":", "\"wall_time_s\":", "\"recovery_time\":", "\"type\":\"onset\""})
    EXPECT_NE(last.find(key), std::string::npos) << key;
}

// a run that loses the aircraft says so: one stderr line with the time and the
// bound, and the JSON's envelope_exit (null for a run that stayed inside, with nothing on
// stderr). The reproducer; the sweep names the run in its summary.
TEST(Cli, LeavingTheEnvelopeIsSaidOnceWithTheTime) {
  const std::string lost = tmpFile("lost.yaml",
                                   "scenario:\n  name: lost\n  theta:\n"
                                   "    - {until: 5.0, scale: 0.1}\n"
                                   "    - {until: 60.0, scale: -5.0}\n"
                                   "  reference:\n    - {until: 60.0, r: 0.1}\n");
  const CmdResult r =
      runCli("--scenario " + lost + " --mode rac --set plant.actuator.enabled=true --json");
  ASSERT_EQ(r.code, 0) << r.out;
  const auto first = r.out.find("left the flight envelope");
  ASSERT_NE(first, std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("left the flight envelope", first + 1), std::string::npos) << "once";
  EXPECT_EQ(r.out.rfind("preadapt_sim: left the flight envelope at t = 5.", first),
            first - std::string("preadapt_sim: ").size());
  EXPECT_NE(r.out.find("(plant.envelope.max_pitch_rate); the run went on"), std::string::npos);
  EXPECT_NE(r.out.find("\"envelope_exit\":{\"t\":5."), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\"bound\":\"pitch_rate\""), std::string::npos);
  EXPECT_NE(r.out.find("\"conditions\":{\"u_applied\":"), std::string::npos);
  const CmdResult ok = runCli("--scenario 1 --mode rac --json");
  ASSERT_EQ(ok.code, 0);
  EXPECT_NE(ok.out.find("\"envelope_exit\":null"), std::string::npos);
  EXPECT_EQ(ok.out.find("envelope_exit\":{"), std::string::npos);
  EXPECT_EQ(ok.out.find("left the flight envelope"), std::string::npos);
  EXPECT_EQ(std::count(ok.out.begin(), ok.out.end(), '\n'), 1) << "only the JSON line";
  const CmdResult sw =
      runBin(PMRAC_SWEEP_BIN,
             "--scenario " + lost + " --modes rac --seeds 1 --set plant.actuator.enabled=true");
  ASSERT_EQ(sw.code, 0) << sw.out;
  EXPECT_NE(sw.out.find("preadapt_sweep: 1 of 1 run(s) left the flight envelope:\n  run 0 "
                        "(mode rac, seed 1): left the flight envelope at t = 5."),
            std::string::npos)
      << sw.out;
  const CmdResult bad = runCli("--scenario 1 --set plant.envelope.max_alpha=-1");
  EXPECT_EQ(bad.code, 2);
  EXPECT_NE(bad.out.find("plant.envelope.max_alpha"), std::string::npos) << bad.out;
}

// preadapt_sweep once crashed (SIGSEGV) on every run: it iterated over items() of a temporary.
TEST(Cli, SweepPrintsOneJsonLinePerRunInIndexOrder) {
  const CmdResult r = runBin(PMRAC_SWEEP_BIN, "--scenario 1 --modes rac,pa --seeds 1-2 --jobs 2");
  ASSERT_EQ(r.code, 0) << r.out;
  std::istringstream lines(r.out);
  std::string line;
  int n = 0;
  while (std::getline(lines, line)) {
    if (line.empty() || line[0] != '{') continue;
    EXPECT_EQ(line.rfind("{\"index\":" + std::to_string(n) + ",", 0), 0u) << line.substr(0, 80);
    EXPECT_NE(line.find("\"peak_abs_e\":"), std::string::npos);
    ++n;
  }
  EXPECT_EQ(n, 4) << r.out;
}

TEST(Cli, BadInputIsExitCodeTwoWithOneLine) {
  const std::string bad_yaml = tmpFile("bad.yaml", "scenario: {name: x, theta: [ {until: 1\n");
  const std::string nan_yaml =
      tmpFile("nan.yaml", "scenario:\n  name: x\n  theta:\n    - {until: 10, scale: .nan}\n");
  struct Case {
    std::string args, expect;
  } cases[] = {
      {"--scenario 1 --mode foo", "--mode: unknown mode 'foo'"},
      {"--scenario 1 --mode rac --set controller.attention.cee=1",
       "controller.attention.cee: unknown key"},
      {"--scenario 1 --mode rac --set nosuch.key=1", "nosuch: unknown key"},
      {"--scenario /nonexistent/s.yaml --mode rac", "/nonexistent/s.yaml: cannot open file"},
      {"--scenario 4 --mode rac", "--scenario: expected 1, 2, 3 or the path of a scenario YAML"},
      {"--scenario " + bad_yaml + " --mode rac", "malformed YAML"},
      {"--scenario " + nan_yaml + " --mode rac",
       "scenario.theta.0.scale: expected a finite number"},
      {"--scenario 1 --mode rac --dt 0", "--dt: must be > 0"},
      {"--scenario 1 --mode rac --dt -0.1", "--dt: must be > 0"},
      {"--scenario 1 --mode rac --dt nan", "--dt: expected a finite number"},
      {"--scenario 1 --mode rac --set controller.lqr.R=0", "controller.lqr.R: must be > 0"},
      {"--scenario 1 --mode rac --seed -3", "--seed: expected a non-negative integer"},
      {"--mode rac", "--scenario is required"},
      {"--scenario 1 --bogus", "unknown argument '--bogus'"},
      {"--scenario 1 --weights-in /nonexistent/w.yaml", "--weights-in: /nonexistent/w.yaml"},
  };
  for (const auto& c : cases) {
    const CmdResult r = runCli(c.args);
    EXPECT_EQ(r.code, 2) << c.args << "\n" << r.out;
    EXPECT_NE(r.out.find(c.expect), std::string::npos) << c.args << "\n" << r.out;
    EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << c.args << "\n" << r.out;
  }
}

TEST(Cli, WeightsCarryOverBetweenRuns) {
  const std::string w = "/tmp/pmrac_test_" + std::to_string(getpid()) + "_w.yaml";
  const std::string common = "--scenario 1 --mode pa_learn --set controller.attention.c_ed=0.015";
  ASSERT_EQ(runCli(common + " --weights-out " + w).code, 0);
  const CmdResult second = runCli(common + " --weights-in " + w + " --json");
  ASSERT_EQ(second.code, 0) << second.out;
  // Episodes continue from the first run's count (4 phases in scenario 1 with c_ed = 0.015).
  EXPECT_NE(second.out.find("\"episodes\":8,\"theta_hat_final\""), std::string::npos) << second.out;
}

TEST(Cli, WeightsOutNeverReplacesAFileWithoutForce) {
  const std::string w = "/tmp/pmrac_test_" + std::to_string(getpid()) + "_keep.yaml";
  std::remove(w.c_str());
  const std::string common = "--scenario 1 --mode pa_learn --dt 0.01";
  ASSERT_EQ(runCli(common + " --weights-out " + w).code, 0);
  const CmdResult again = runCli(common + " --weights-out " + w);
  EXPECT_EQ(again.code, 2) << again.out;
  EXPECT_NE(again.out.find("--weights-out: '" + w + "' exists: not replaced"), std::string::npos)
      << again.out;
  EXPECT_EQ(std::count(again.out.begin(), again.out.end(), '\n'), 1) << again.out;
  // Continuing the network read from it, or asked to: replaced.
  EXPECT_EQ(runCli(common + " --weights-in " + w + " --weights-out " + w).code, 0);
  EXPECT_EQ(runCli(common + " --weights-out " + w + " --force").code, 0);
  std::remove(w.c_str());
}

TEST(Config, NonScalarMapKeysAreAFileErrorNotACrash) {
  // Found by fuzz/fuzz_yaml_config: a list as a map key threw an uncaught yaml-cpp exception.
  for (const char* text : {"? [a, b]\n: 1\n", "plant: {[1]: 2}\n", "{? {a: 1} : x}\n"}) {
    try {
      parseYaml(text, "keys.yaml");
      FAIL() << "accepted: " << text;
    } catch (const FileError& e) {
      EXPECT_NE(std::string(e.what()).find("keys.yaml: line"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("plain name"), std::string::npos) << e.what();
    }
  }
  ParamValue t = ParamValue::makeMap();
  EXPECT_THROW(applyOverride(&t, "controller.mode={[1]: 2}"), FileError);
}

// params/modes.yaml is the one list of modes: every row's law and strategy are registered, the
// registry keeps the table's order, and a row's `truth` says what its strategy does (the launch
// files count plant/truth's subscribers from it: a wrong flag would stall a lockstep run).
TEST(ModeRegistry, EveryTableRowIsARegisteredLawAndStrategy) {
  const std::deque<ModeEntry>& modes = modeRegistry();
  ASSERT_EQ(modes.size(), std::size(params::kModeRows));
  for (std::size_t i = 0; i < modes.size(); ++i) {
    const ModeEntry& m = modes[i];
    EXPECT_STREQ(m.name, params::kModeRows[i].name);
    RunConfig cfg = test::packageConfig("1");
    cfg.controller.mode = m.name;
    Controller ctl(designModelOf(cfg.plant, cfg.controller), cfg.controller);
    EXPECT_EQ(ctl.mode(), m.name);
    EXPECT_EQ(m.truth, ctl.needsTruth()) << m.name << ": " << ctl.truthUse();
  }
  EXPECT_EQ(std::string(modes[0].name), "rac");  // the reproduction's baseline leads
}

// controller.model, the controller's own design model.
namespace {
ParamValue matrixValue(const Eigen::MatrixXd& m) {
  std::vector<ParamValue> rows;
  for (Eigen::Index i = 0; i < m.rows(); ++i) {
    std::vector<ParamValue> row;
    for (Eigen::Index j = 0; j < m.cols(); ++j) row.push_back(ParamValue::makeDouble(m(i, j)));
    rows.push_back(ParamValue::makeList(row));
  }
  return ParamValue::makeList(rows);
}
ParamValue vectorValue(const Eigen::VectorXd& v) {
  std::vector<ParamValue> l;
  for (Eigen::Index i = 0; i < v.size(); ++i) l.push_back(ParamValue::makeDouble(v[i]));
  return ParamValue::makeList(l);
}
// A plant that differs from the package's B-747 in every aerodynamic entry.
void otherPlant(Eigen::MatrixXd* A, Eigen::VectorXd* B, Eigen::VectorXd* B1r) {
  *A = test::packageConfig("1").plant.A;
  *B = test::packageConfig("1").plant.B;
  *B1r = test::packageConfig("1").plant.B1r;
  A->row(1) *= 1.3;
  A->row(2) *= 0.75;
  (*B)[1] *= 0.6;
  (*B)[2] *= 1.4;
  (*B1r)[0] = -2.0;
}
}  // namespace

TEST(DesignModel, AbsentIsThePlantsAndGivenIsDesignedOn) {
  const RunConfig plain = test::packageConfig("1");
  EXPECT_TRUE(plain.controller.model.empty());
  ASSERT_TRUE(plain.design.has_value());
  const ControllerDesign own =
      designController(plain.plant.A, plain.plant.B, plain.controller.Q, plain.controller.R);
  EXPECT_EQ(plain.design->K, own.K);  // bit for bit: the plant's own design
  EXPECT_EQ(plain.design->P, own.P);
  Eigen::MatrixXd A;
  Eigen::VectorXd B, B1r;
  otherPlant(&A, &B, &B1r);
  ParamValue t = test::packageTree();
  t.setPath("controller.model.A", matrixValue(A));
  t.setPath("controller.model.B", vectorValue(B));
  const RunConfig c = readRunConfig(t);
  EXPECT_EQ(c.controller.model.A, A);
  EXPECT_EQ(c.controller.model.B1r.size(), 0);  // left out: the plant's
  const DesignModel m = designModelOf(c.plant, c.controller);
  EXPECT_EQ(m.A, A);
  EXPECT_EQ(m.B, B);
  EXPECT_EQ(m.B1r, c.plant.B1r);
  EXPECT_EQ(c.plant.A, plain.plant.A);  // the plant itself is untouched
  const ControllerDesign d = designController(A, B, c.controller.Q, c.controller.R);
  EXPECT_EQ(c.design->K, d.K);
  EXPECT_EQ(Controller(designModelOf(c.plant, c.controller), c.controller).design().K, d.K);
  EXPECT_NE(d.K, own.K);
}

// Every law and strategy sees the plant only through the model: a controller on plant P with
// controller.model = Q answers every sample exactly as one built on plant Q without a model.
TEST(DesignModel, EveryModeUsesTheModelNotThePlant) {
  Eigen::MatrixXd A;
  Eigen::VectorXd B, B1r;
  otherPlant(&A, &B, &B1r);
  for (const ModeEntry& mode : modeRegistry()) {
    RunConfig cfg = test::packageConfig("1");
    cfg.controller.mode = mode.name;
    PlantConfig q = cfg.plant;
    q.A = A;
    q.B = B;
    q.B1r = B1r;
    ControllerConfig with_model = cfg.controller;
    with_model.model.A = A;
    with_model.model.B = B;
    with_model.model.B1r = B1r;
    Controller on_model(designModelOf(cfg.plant, with_model), with_model);
    Controller on_q(designModelOf(q, cfg.controller), cfg.controller);
    Controller on_p(designModelOf(cfg.plant, cfg.controller), cfg.controller);
    Vec x(3), theta(3);
    theta << 2.0, -1.0, 0.5;
    bool differs_from_p = false;
    for (int k = 0; k < 3000; ++k) {
      const double t = k * cfg.controller.sample_time;
      x << 0.01 * std::sin(t), 0.05 * std::sin(3.0 * t) + 0.02, 0.1 * std::cos(2.0 * t);
      StepInput in;
      in.t = t;
      in.x = &x;
      in.r = 0.1;
      in.theta_true = &theta;
      const StepOutput a = on_model.step(in), b = on_q.step(in), c = on_p.step(in);
      ASSERT_EQ(a.u, b.u) << mode.name << " at sample " << k;
      ASSERT_EQ(a.theta_hat, b.theta_hat) << mode.name << " at sample " << k;
      ASSERT_EQ(a.x_ref, b.x_ref) << mode.name << " at sample " << k;
      differs_from_p = differs_from_p || a.u != c.u;
    }
    EXPECT_TRUE(differs_from_p) << mode.name << ": the model changed nothing";
  }
}

TEST(DesignModel, BadModelsAreRefusedNamingTheKey) {
  const auto problems = [](const std::string& key, const ParamValue& v,
                           const std::string& key2 = "", const ParamValue* v2 = nullptr) {
    ParamValue t = test::packageTree();
    t.setPath(key, v);
    if (v2) t.setPath(key2, *v2);
    return problemsOf(t);
  };
  auto ps = problems("controller.model.A", matrixValue(Eigen::MatrixXd::Identity(2, 2)));
  EXPECT_TRUE(mentions(ps, "controller.model.A: expected 3 rows, got 2")) << joined(ps);
  ps = problems("controller.model.B", vectorValue(Eigen::VectorXd::Ones(4)));
  EXPECT_TRUE(mentions(ps, "controller.model.B: expected 3 numbers")) << joined(ps);
  ps = problems("controller.model.B1r", vectorValue(Eigen::VectorXd::Ones(2)));
  EXPECT_TRUE(mentions(ps, "controller.model.B1r: expected 3 numbers")) << joined(ps);
  Eigen::MatrixXd A = test::packageConfig("1").plant.A;
  A(2, 1) = std::nan("");
  ps = problems("controller.model.A", matrixValue(A));
  EXPECT_TRUE(mentions(ps, "controller.model.A[2][1]: expected a finite number")) << joined(ps);
  Eigen::VectorXd B = Eigen::VectorXd::Zero(3);
  B[2] = INFINITY;
  ps = problems("controller.model.B", vectorValue(B));
  EXPECT_TRUE(mentions(ps, "controller.model.B")) << joined(ps);
  ps = problems("controller.model.B", vectorValue(Eigen::VectorXd::Zero(3)));
  EXPECT_TRUE(mentions(ps, "controller.model.B: must not be all zero")) << joined(ps);
  // alpha unstable and out of B's reach: (A, B) not stabilisable, the CARE has no solution.
  Eigen::MatrixXd U(3, 3);
  U << 0, 1, 0, 0, 1, 0, 0, 0, -1;
  const ParamValue b_q = vectorValue(Eigen::Vector3d(0, 0, 1));
  ps = problems("controller.model.A", matrixValue(U), "controller.model.B", &b_q);
  EXPECT_TRUE(mentions(ps, "controller.model.A: (A, B) is not stabilisable")) << joined(ps);
  // The same B alone against the plant's A is stabilisable (q drives alpha): accepted.
  EXPECT_TRUE(problems("controller.model.B", b_q).empty());
  // A mode on the imaginary axis out of B's reach: no stabilising solution, A_r not Hurwitz.
  Eigen::MatrixXd Z(3, 3);
  Z << 0, 1, 0, 0, 0, 0, 0, 0, -1;
  ps = problems("controller.model.A", matrixValue(Z), "controller.model.B", &b_q);
  EXPECT_TRUE(mentions(ps, "controller.model.A: ")) << joined(ps);
  EXPECT_EQ(ps.size(), 1u) << joined(ps);
  ps = problems("controller.model.C", ParamValue::makeDouble(1));
  EXPECT_TRUE(mentions(ps, "controller.model.C: unknown key")) << joined(ps);
}

TEST(Cli, DesignModelBySet) {
  CmdResult r = runCli(
      "--scenario 1 --mode rac --json --set "
      "'controller.model.A=[[0,1,0],[0,-0.4,0.9],[0,-1.1,-0.5]]'");
  ASSERT_EQ(r.code, 0) << r.out;
  const CmdResult plain = runCli("--scenario 1 --mode rac --json");
  ASSERT_EQ(plain.code, 0) << plain.out;
  const auto K = [](const std::string& out) { return out.substr(out.find("\"K\""), 80); };
  EXPECT_NE(K(r.out), K(plain.out));  // designed on the model
  r = runCli("--scenario 1 --mode rac --set 'controller.model.A=[[0,1],[0,-0.4]]'");
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("controller.model.A: expected 3 rows, got 2"), std::string::npos) << r.out;
}

// ---- Bounds of what a configuration may ask, checked before anything is built.

namespace {
// 9 levels of 9 aliases each: 404 bytes that expand to 9^9 (387 million) values.
std::string aliasBomb() {
  std::string y = "a0: &a0 [x, x, x, x, x, x, x, x, x]\n";
  for (int l = 1; l < 9; ++l) {
    const std::string prev = "*a" + std::to_string(l - 1);
    y += "a" + std::to_string(l) + ": &a" + std::to_string(l) + " [";
    for (int i = 0; i < 9; ++i) y += (i ? "," : "") + prev;
    y += "]\n";
  }
  return y;
}
std::string fileErrorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const FileError& e) {
    return e.what();
  }
  return "(accepted)";
}
double secondsOf(const std::function<void()>& f) {
  const auto t0 = std::chrono::steady_clock::now();
  f();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}
}  // namespace

TEST(ConfigLimits, AliasBombRefusedQuicklyNamingTheCause) {
  const std::string bomb = aliasBomb();
  EXPECT_LT(bomb.size(), 500u);
  std::string what;
  const double s = secondsOf([&] { what = fileErrorOf([&] { parseYaml(bomb, "bomb.yaml"); }); });
  EXPECT_LT(s, 1.0);
  EXPECT_NE(what.find("bomb.yaml: a"), std::string::npos) << what;
  EXPECT_NE(what.find("aliases"), std::string::npos) << what;
  // Through the CLI: exit 2 and one line, within seconds.
  const CmdResult r = runCli("--scenario " + tmpFile("bomb.yaml", bomb) + " --mode rac");
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("aliases"), std::string::npos) << r.out;
}

TEST(ConfigLimits, DepthAndSizeRefused) {
  const std::string deep = "scenario: " + std::string(100, '[') + std::string(100, ']') + "\n";
  const std::string what = fileErrorOf([&] { parseYaml(deep, "deep.yaml"); });
  EXPECT_NE(what.find("nested deeper than 64 levels"), std::string::npos) << what;
  // A file of 1.75 million segments (50 MB): refused by its size, unread.
  const std::string big = "/tmp/pmrac_test_" + std::to_string(getpid()) + "_big.yaml";
  {
    std::ofstream f(big);
    f << "scenario:\n  name: big\n  theta:\n";
    char line[64];
    for (int i = 1; i <= 1750000; ++i) {
      std::snprintf(line, sizeof(line), "    - {until: %d.0, scale: 0.5}\n", i);
      f << line;
    }
  }
  std::string big_what;
  const double s = secondsOf([&] { big_what = fileErrorOf([&] { loadYamlFile(big); }); });
  EXPECT_LT(s, 1.0);
  EXPECT_NE(big_what.find("more than 1048576 bytes"), std::string::npos) << big_what;
  const CmdResult r = runCli("--scenario " + big + " --mode rac");
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("bytes"), std::string::npos) << r.out;
  std::remove(big.c_str());
}

TEST(ConfigLimits, DurationStepsAndSampleTimeNamed) {
  const std::string until9 = tmpFile("until9.yaml",
                                     "scenario:\n  name: long\n  theta:\n"
                                     "    - {until: 10.0, scale: 0.5}\n"
                                     "    - {until: 1.0e+9, scale: 1.0}\n");
  const std::string until300 = tmpFile("until300.yaml",
                                       "scenario:\n  name: long\n  theta:\n"
                                       "    - {until: 1.0e+300, scale: 1.0}\n");
  const struct {
    std::string args, expect;
  } cases[] = {
      {"--scenario " + until9 + " --mode rac", "scenario.theta.1.until: must be <= 86400"},
      {"--scenario " + until300 + " --mode rac", "scenario.theta.0.until: must be <= 86400"},
      {"--scenario 1 --mode rac --set controller.sample_time=1e-9",
       "controller.sample_time: the scenario's"},
      {"--scenario 1 --mode rac --set controller.sample_time=2", "controller.sample_time: must be"},
  };
  for (const auto& c : cases) {
    CmdResult r;
    const double s = secondsOf([&] { r = runCli(c.args); });
    EXPECT_LT(s, 5.0) << c.args;
    EXPECT_EQ(r.code, 2) << c.args << "\n" << r.out;
    EXPECT_NE(r.out.find(c.expect), std::string::npos) << c.args << "\n" << r.out;
  }
  EXPECT_EQ(runLengthProblem(20.0, 1e-3), "");
  EXPECT_NE(runLengthProblem(1e4 + 1.0, 1e-3), "");
}

TEST(ConfigParsing, DuplicateKeyNamesBothLines) {
  const std::string y =
      "controller:\n"
      "  attention:\n"
      "    c_e: 0.005\n"
      "    c_ed: 0.02\n"
      "    c_e: 0.5\n";
  const std::string what = fileErrorOf([&] { parseYaml(y, "dup.yaml"); });
  EXPECT_NE(what.find("dup.yaml: controller.attention.c_e: duplicate key (lines 3 and 5)"),
            std::string::npos)
      << what;
  const CmdResult r = runCli("--scenario 1 --mode rac --controller " + tmpFile("dup.yaml", y));
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("lines 3 and 5"), std::string::npos) << r.out;
}

TEST(ConfigParsing, HugeListIndexNamesTheKey) {
  const CmdResult r =
      runCli("--scenario 1 --mode rac --set scenario.theta.12345678901234567890.until=3");
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_EQ(r.out.find("stoul"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("scenario.theta.12345678901234567890.until"), std::string::npos) << r.out;
  ParamValue t = test::packageTree();
  EXPECT_EQ(t.findPath("scenario.theta.12345678901234567890.until"), nullptr);
  EXPECT_THROW(t.setPath("scenario.theta.99.until", ParamValue::makeDouble(1.0)),
               std::out_of_range);
}

TEST(ConfigParsing, BadCeReportsOnlyCe) {
  ParamValue t = test::packageTree();
  t.setPath("controller.attention.c_e", ParamValue::makeDouble(0.0));
  t.setPath("controller.attention.hysteresis", ParamValue::makeDouble(0.001));
  const auto ps = problemsOf(t);
  EXPECT_TRUE(mentions(ps, "controller.attention.c_e: must be in [1e-06, 1], got 0")) << joined(ps);
  EXPECT_FALSE(mentions(ps, "hysteresis")) << joined(ps);
  EXPECT_EQ(ps.size(), 1u) << joined(ps);
}

TEST(ConfigTuning, RuntimeTuningWithinTheYamlsRanges) {
  const RunConfig rc = test::packageConfig("1");
  const ControllerTunables base = ControllerTunables::of(rc.controller);
  const struct {
    std::function<void(ControllerTunables*)> set;
    std::string key;
  } cases[] = {
      {[](ControllerTunables* t) { t->gamma = 1e308; }, "controller.adaptation.gamma"},
      {[](ControllerTunables* t) { t->c_e = 1e300; }, "controller.attention.c_e"},
      {[](ControllerTunables* t) { t->c_ed = 1e-300; }, "controller.attention.c_ed"},
      {[](ControllerTunables* t) { t->confirm_samples = 2147483647; },
       "controller.attention.confirm_samples"},
      {[](ControllerTunables* t) { t->gamma_pa = 1e300; }, "controller.preadaptation.gamma_pa"},
  };
  for (const auto& c : cases) {
    ControllerTunables t = base;
    c.set(&t);
    const auto ps = validateTunables(rc.controller, t);
    EXPECT_EQ(ps.size(), 1u) << c.key << "\n" << joined(ps);
    EXPECT_TRUE(mentions(ps, c.key + ": must be in")) << joined(ps);
  }
  EXPECT_TRUE(validateTunables(rc.controller, base).empty());
}
