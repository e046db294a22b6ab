// JSBSim as the plant engine: the coupling (trim, lockstep, determinism,
// signs), the linearisation against Heffley and Jewell's condition 9, the configuration's
// rules, and the failures: JSBSim not found, an aircraft that does not load, a trim that
// fails, a JSBSim killed mid-run. Each must end with an error saying what is wrong, and leave
// no JSBSim process behind. These tests need the JSBSim binary (scripts/install_jsbsim; CI's
// scripts/test installs it): without it they FAIL with the install hint, they do not skip.

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "preadaptive_mrac/core/closed_loop.hpp"
#include "preadaptive_mrac/core/sim/scenario_plant.hpp"
#include "preadaptive_mrac/jsbsim/jsbsim_linearise.hpp"
#include "preadaptive_mrac/jsbsim/jsbsim_plant.hpp"
#include "preadaptive_mrac/jsbsim/jsbsim_process.hpp"
#include "test_helpers.hpp"

namespace preadaptive_mrac {
namespace {

constexpr double kDeg = M_PI / 180.0;

/// No child process of this test is left, running or unreaped.
bool noChildLeft() { return ::waitpid(-1, nullptr, WNOHANG) == -1 && errno == ECHILD; }

bool alive(pid_t pid) {
  struct stat st;
  return pid > 0 && ::stat(("/proc/" + std::to_string(pid)).c_str(), &st) == 0;
}

RunConfig jsbsimConfig(const std::string& scenario = "1") {
  ParamValue tree = test::packageTree(scenario);
  tree.setPath("plant.engine", ParamValue::makeString("jsbsim"));
  return readRunConfig(tree);
}

TEST(Jsbsim, TrimsAtTheDefaultOperatingPoint) {
  const RunConfig cfg = jsbsimConfig();
  JsbsimPlant p(cfg.plant.jsbsim, 0.001, 0.0);
  p.reset();
  const JsbsimTrim& t = p.trim();
  // jsbsim/README.md: alpha 4.4525 deg (= theta, level), elevator 0.105 deg, throttle 0.197,
  // 774.46 ft/s.
  EXPECT_NEAR(t.alpha / kDeg, 4.4525, 0.01);
  EXPECT_NEAR(t.pitch, t.alpha, 1e-6);
  EXPECT_NEAR(t.elevator / kDeg, 0.105, 0.01);
  EXPECT_NEAR(t.throttle, 0.1972, 0.001);
  EXPECT_NEAR(t.airspeed, 774.46 * 0.3048, 0.1);
  EXPECT_NEAR(t.altitude, 40000 * 0.3048, 1.0);
  EXPECT_NEAR(t.mach, 0.8, 1e-4);
}

TEST(Jsbsim, LockstepIsDeterministicAndHasThePapersSigns) {
  const RunConfig cfg = jsbsimConfig();
  JsbsimPlant a(cfg.plant.jsbsim, 0.001, 0.0);
  const Vec theta = Vec::Zero(3);
  // Left alone at the trim: it stays there (the trim's residual acceleration only).
  for (int k = 0; k < 200; ++k) a.step(0.001, theta, 0.0, 0.0, 0.0);
  EXPECT_LT(std::abs(a.state()[1]), 1e-6);
  EXPECT_LT(std::abs(a.state()[2]), 1e-6);
  // reset() trims again: back at the trim (to ~1e-9: not to the bit, JSBSim's trim depends
  // on more than its initial condition; every run is a fresh process, which is).
  a.reset();
  EXPECT_LT(std::abs(a.state()[1]), 1e-8);
  JsbsimPlant fresh(cfg.plant.jsbsim, 0.001, 0.0), b(cfg.plant.jsbsim, 0.001, 0.0);
  // Trailing edge down (+) pitches the nose down: q < 0, as B's M_delta/Iy < 0; and two
  // processes given the same inputs give the same bits.
  for (int k = 0; k < 500; ++k) {
    const double de = k < 250 ? 0.01 : -0.01;
    fresh.step(0.001, theta, de, 0.0, 0.0);
    b.step(0.001, theta, de, 0.0, 0.0);
    ASSERT_EQ(fresh.state()[1], b.state()[1]) << "step " << k;
    ASSERT_EQ(fresh.state()[2], b.state()[2]) << "step " << k;
    ASSERT_EQ(fresh.flight().altitude, b.flight().altitude) << "step " << k;
    if (k == 100) {
      EXPECT_LT(fresh.state()[2], -1e-3);
    }
  }
  // e_I integrates alpha - r.
  JsbsimPlant c(cfg.plant.jsbsim, 0.001, 0.5);
  c.reset();
  for (int k = 0; k < 100; ++k) c.step(0.001, theta, 0.0, 0.1, 0.0);
  EXPECT_NEAR(c.state()[0], 0.5 - 0.1 * 0.1, 1e-8);
}

TEST(Jsbsim, SharedMemoryCarriesTheSocketsBytes) {
  // The lane (plant.jsbsim.shared_memory, the default) and loopback TCP carry the same bytes:
  // the same inputs give the same bits, through either.
  RunConfig cfg = jsbsimConfig();
  JsbsimPlant lane(cfg.plant.jsbsim, 0.001, 0.0);
  cfg.plant.jsbsim.shared_memory = false;
  JsbsimPlant tcp(cfg.plant.jsbsim, 0.001, 0.0);
  EXPECT_TRUE(lane.process().sharedMemory());
  EXPECT_FALSE(tcp.process().sharedMemory());
  const Vec theta = Vec::Constant(3, 0.1);
  for (int k = 0; k < 1500; ++k) {
    const double de = 0.01 * std::sin(0.01 * k);
    lane.step(0.001, theta, de, 0.05, k >= 700 ? 0.3 : 0.0);
    tcp.step(0.001, theta, de, 0.05, k >= 700 ? 0.3 : 0.0);
    ASSERT_EQ(lane.state(), tcp.state()) << "step " << k;
    ASSERT_EQ(lane.flight().altitude, tcp.flight().altitude) << "step " << k;
  }
  // Without the preload library the sockets carry them, as with shared_memory false.
  ::setenv("PMRAC_JSBSIM_LANE_PRELOAD", "/nonexistent/libpmrac_jsbsim_lane.so", 1);
  cfg.plant.jsbsim.shared_memory = true;
  JsbsimPlant fallback(cfg.plant.jsbsim, 0.001, 0.0);
  ::unsetenv("PMRAC_JSBSIM_LANE_PRELOAD");
  EXPECT_FALSE(fallback.process().sharedMemory());
  fallback.step(0.001, theta, 0.01, 0.05, 0.0);
}

TEST(Jsbsim, ScenarioPlantRunsTheClosedLoopOnJsbsim) {
  RunConfig cfg = jsbsimConfig();
  cfg.plant.turbulence.enabled = true;
  cfg.plant.turbulence.sigma_w = 1.5;
  cfg.plant.turbulence.length_scale = 533.4;
  // Two seconds of scenario 1 (theta 0.1 from the start), the paper's controller on it.
  cfg.scenario.theta.resize(1);
  cfg.scenario.theta[0].until = 2.0;
  cfg.scenario.reference.resize(1);
  cfg.scenario.reference[0].until = 2.0;
  const SimResult r = test::simulate(cfg);
  ASSERT_EQ(r.steps, 2000);
  // The flight outputs are rows of the conditions record (the plant's rows too: gusts).
  ASSERT_EQ(r.series.conditions.size(), 2000u);
  EXPECT_TRUE(r.series.condition_rows.engine);
  EXPECT_TRUE(r.series.condition_rows.plant);
  const auto& c = r.series.conditions;
  // The loop tracks r = 0.1 rad from the trim: alpha rises towards it, no blow-up.
  EXPECT_GT(r.series.x.back()[1], 0.03);
  EXPECT_LT(r.metrics.peak_abs_e, 0.2);
  EXPECT_NEAR(c.front().airspeed, 236.055, 0.01);
  EXPECT_NEAR(c.front().altitude, 12192.0, 0.5);
  EXPECT_NE(c.back().altitude, c.front().altitude);  // read every step
  // The pitch attitude carries alpha: theta - gamma - alpha_trim = x_alpha.
  const size_t k = 1500;
  EXPECT_NEAR(c[k].pitch - c[k].flight_path - c.front().pitch + c.front().flight_path,
              r.series.x[k][1], 1e-9);
}

TEST(Jsbsim, FlightRowsOnlyOnTheEngine) {
  // Without plant conditions the record of a JSBSim run has the engine's rows alone; the
  // linear plant's has none (its CSV and truth never gain them).
  RunConfig cfg = jsbsimConfig();
  cfg.scenario.theta.resize(1);
  cfg.scenario.theta[0].until = 0.05;
  cfg.scenario.reference.resize(1);
  cfg.scenario.reference[0].until = 0.05;
  ScenarioPlant jsb(cfg.plant, cfg.scenario, 0.001);
  EXPECT_FALSE(jsb.conditionRows().plant);
  EXPECT_TRUE(jsb.conditionRows().engine);
  EXPECT_NEAR(jsb.conditions().airspeed, 236.055, 0.01);
  const SimResult r = test::simulate(cfg);
  ASSERT_EQ(r.series.conditions.size(), 50u);
  EXPECT_FALSE(r.series.condition_rows.plant);
  cfg.plant.engine = PlantEngineKind::kLinear;
  ScenarioPlant lin(cfg.plant, cfg.scenario, 0.001);
  EXPECT_FALSE(lin.conditionRows().any());
  EXPECT_TRUE(test::simulate(cfg).series.conditions.empty());
}

TEST(Jsbsim, PhysicalFaultsActFromTheirSegment) {
  RunConfig cfg = jsbsimConfig();
  cfg.scenario.theta.resize(1);
  cfg.scenario.theta[0].until = 1.0;
  cfg.scenario.theta[0].theta.setZero(3);
  cfg.scenario.reference.resize(1);
  cfg.scenario.reference[0].until = 1.0;
  Scenario lossy = cfg.scenario;
  Scenario::FaultSegment nominal{0.5}, half{1.0};
  half.elevator_effectiveness = 0.5;
  lossy.faults = {nominal, half};
  ScenarioPlant a(cfg.plant, cfg.scenario, 0.001), b(cfg.plant, lossy, 0.001);
  // The same elevator step from 0.5 s: half the elevator's effect on the pitch rate at first
  // (the first 20 ms, before alpha moves much); identical before the fault.
  for (int k = 0; k < 520; ++k) {
    const double u = k < 500 ? 0.0 : 0.01;
    a.advance(u);
    b.advance(u);
    if (k == 499) {
      ASSERT_EQ(a.state()[2], b.state()[2]);
    }
  }
  // The fault halves the whole deflection, the trim's included: the moment changes by
  // 0.5 (u + de_trim) - de_trim against u.
  const double de_trim = dynamic_cast<JsbsimPlant*>(b.engine())->trim().elevator;
  EXPECT_NEAR(b.state()[2] / a.state()[2], (0.5 * (0.01 + de_trim) - de_trim) / 0.01, 0.02);
  // A CG shift aft from the start: statically less stable, the trimmed aircraft pitches up.
  Scenario aft = cfg.scenario;
  Scenario::FaultSegment shifted{1.0};
  shifted.cg_shift = 0.05;
  aft.faults = {shifted};
  ScenarioPlant c(cfg.plant, aft, 0.001);
  for (int k = 0; k < 500; ++k) c.advance(0.0);
  EXPECT_GT(c.state()[2], 1e-3);
}

TEST(Jsbsim, PaRobustJudgesARecalledRegimeByItsLoss) {
  // Regime B (half the elevator's effectiveness, CG aft) for 15 s, C, then B again on the
  // aircraft's elevator. Back in B, pa_robust recalls B with the loss it identified there. The
  // detection must judge the data by that model: the plant applies half of every command, the
  // error feedback's included, and that half missing is what the recalled loss says, not a new
  // switch. 10 onsets in B's return; judged by theta alone, 40 (and the probe runs on).
  // The regimes and faults are those of scenario 7 of `preadapt_family --seed 13579 --faults
  // cg_shift=0:0.1,elevator_effectiveness=0.5:1,pitch_damping=0.3:1 --set plant.engine=jsbsim`.
  RunConfig cfg = jsbsimConfig();
  cfg.controller.mode = "pa_robust";
  cfg.plant.actuator.enabled = true;
  cfg.plant.actuator.max_deflection = 0.35;
  cfg.plant.actuator.max_rate = 0.65;
  Eigen::VectorXd b(3), c(3);
  b << 0.98086587659952151, 1.4393776866732906, 0.67271468589764405;
  c << 0.50822849063636055, 0.64599093547125552, 0.88061203539145916;
  Scenario& s = cfg.scenario;
  s.theta = {{5.0, Eigen::VectorXd::Constant(3, 0.1)}, {20.0, b}, {35.0, c}, {50.0, b}};
  s.reference = {{50.0, 0.1}};
  Scenario::FaultSegment nominal{5.0}, fb{20.0}, fc{35.0}, fb2{50.0};
  fb.cg_shift = fb2.cg_shift = 0.049084513441438542;
  fb.elevator_effectiveness = fb2.elevator_effectiveness = 0.52956489156405684;
  fb.pitch_damping = fb2.pitch_damping = 0.72822428590515498;
  fc.cg_shift = 0.012012070296213729;
  fc.elevator_effectiveness = 0.92298403380733318;
  fc.pitch_damping = 0.51678641327315744;
  s.faults = {nominal, fb, fc, fb2};
  const SimResult r = test::simulate(cfg);
  ASSERT_EQ(r.metrics.windows.size(), 4u);
  EXPECT_LT(r.metrics.windows[3].onsets, 20);
  EXPECT_FALSE(r.envelope_exit.exited);
}

TEST(Jsbsim, LinearisationMatchesConditionNine) {
  const RunConfig cfg = jsbsimConfig();
  JsbsimPlant p(cfg.plant.jsbsim, 0.001, 0.0);
  LineariseOptions opt;
  opt.duration = 3.0;
  const LinearModel lm = lineariseJsbsim(&p, opt);
  // Condition 9 of R. K. Heffley and W. F. Jewell, "Aircraft Handling Qualities Data", NASA
  // CR-2144 (1972) (jsbsim/README.md [HJ]): Z_alpha/mU -0.310, 1 + Z_q/mU 0.987, M_alpha/Iy
  // -0.794, M_q/Iy -0.425, Z_delta/mU -0.023, M_delta/Iy -1.152.
  // Z_alpha is the least well determined (the slow speed mode leaks into alphadot).
  EXPECT_NEAR(lm.A(1, 1), -0.310, 0.03);
  EXPECT_NEAR(lm.A(1, 2), 0.987, 0.01);
  EXPECT_NEAR(lm.A(2, 1), -0.794, 0.03);
  EXPECT_NEAR(lm.A(2, 2), -0.425, 0.01);
  EXPECT_NEAR(lm.B[1], -0.023, 0.002);
  EXPECT_NEAR(lm.B[2], -1.152, 0.02);
  EXPECT_EQ(lm.A.row(0), (Eigen::RowVector3d() << 0.0, 1.0, 0.0).finished());
  EXPECT_LT(lm.residual_q, 0.01 * lm.signal_q);
}

TEST(Jsbsim, ConfigurationRulesNameTheKey) {
  ParamValue tree = test::packageTree("1");
  tree.setPath("plant.engine", ParamValue::makeString("fsim"));
  try {
    readRunConfig(tree);
    FAIL() << "plant.engine fsim accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("plant.engine"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("linear, jsbsim"), std::string::npos) << e.what();
  }
  tree = test::packageTree("1");
  tree.setPath("plant.engine", ParamValue::makeString("jsbsim"));
  applyOverride(&tree, "plant.x0=[0,0.1,0]");
  applyOverride(&tree, "plant.jsbsim.mach=-1");
  try {
    readRunConfig(tree);
    FAIL() << "x0 alpha 0.1 and Mach -1 accepted on jsbsim";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("plant.x0"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("plant.jsbsim.mach"), std::string::npos) << e.what();
  }
}

TEST(JsbsimFailure, MissingBinarySaysHowToInstall) {
  JsbsimParams p;
  p.executable = "/nonexistent/JSBSim";
  try {
    JsbsimPlant plant(p, 0.001, 0.0);
    FAIL() << "started without a binary";
  } catch (const JsbsimError& e) {
    EXPECT_NE(std::string(e.what()).find("scripts/install_jsbsim"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("plant.jsbsim.executable"), std::string::npos) << e.what();
  }
}

TEST(JsbsimFailure, BadAircraftNameIsAnErrorAndNoProcess) {
  JsbsimParams p;
  p.aircraft = "b747_nonexistent";
  try {
    JsbsimPlant plant(p, 0.001, 0.0);
    FAIL() << "started with an aircraft that does not exist";
  } catch (const JsbsimError& e) {
    EXPECT_NE(std::string(e.what()).find("plant.jsbsim.aircraft"), std::string::npos) << e.what();
  }
  // An aircraft folder whose file does not load: JSBSim itself ends, the error says why.
  const std::string root = ::testing::TempDir() + "pmrac_bad_root";
  ASSERT_EQ(std::system(("rm -rf " + root + " && mkdir -p " + root + "/aircraft/broken && " +
                         "echo '<fdm_config name=\"broken\"><metrics>' > " + root +
                         "/aircraft/broken/broken.xml")
                            .c_str()),
            0);
  p.aircraft = "broken";
  p.root = root;
  p.timeout = 5.0;
  try {
    JsbsimPlant plant(p, 0.001, 0.0);
    FAIL() << "started with a broken aircraft file";
  } catch (const JsbsimError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("plant.jsbsim.aircraft", 0), 0u) << e.what();
    EXPECT_NE(std::string(e.what()).find("not well-formed XML"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(noChildLeft());
}

/// A copy of the package's aircraft root in a fresh temporary folder, to break.
std::filesystem::path copyOfTheRoot(const std::string& name) {
  const std::filesystem::path to = ::testing::TempDir() + "pmrac_" + name;
  std::filesystem::remove_all(to);
  std::filesystem::copy(findJsbsimRoot("", "b747_pmrac"), to,
                        std::filesystem::copy_options::recursive);
  return to;
}

void writeFile(const std::filesystem::path& path, const std::string& text) {
  std::ofstream(path) << text;
}

/// The package's aircraft renamed `name`, its fcs/pmrac-* and pmrac/* properties renamed so
/// that it loads and flies but lacks the package's interface (as JSBSim's own aircraft do;
/// `keep_command`: all but fcs/pmrac-elevator-cmd-rad).
void addAircraftWithoutInterface(const std::filesystem::path& root, const std::string& name,
                                 bool keep_command = false) {
  const std::filesystem::path from = root / "aircraft/b747_pmrac";
  std::ifstream in(from / "b747_pmrac.xml");
  std::stringstream ss;
  ss << in.rdbuf();
  std::string xml = ss.str();
  std::vector<std::pair<std::string, std::string>> renames = {
      {"pmrac/", "other/"}, {"name=\"b747_pmrac\"", "name=\"" + name + "\""}};
  if (!keep_command)
    renames.insert(renames.begin(), {"fcs/pmrac-elevator-cmd-rad", "fcs/other-elevator-cmd-rad"});
  for (const auto& [a, b] : renames)
    for (size_t at = xml.find(a); at != std::string::npos; at = xml.find(a, at + b.size()))
      xml.replace(at, a.size(), b);
  std::filesystem::create_directories(root / "aircraft" / name);
  writeFile(root / "aircraft" / name / (name + ".xml"), xml);
  std::filesystem::copy(from / "cruise_m080_h40k.xml", root / "aircraft" / name);
}

struct LoadFailure {
  std::string message;
  double seconds = 0.0;  ///< wall time to the error
};

/// Start the plant on `p` (which must fail) and time it.
LoadFailure failToLoad(const JsbsimParams& p) {
  const auto t0 = std::chrono::steady_clock::now();
  LoadFailure f;
  try {
    JsbsimPlant plant(p, 0.001, 0.0);
    ADD_FAILURE() << "started with the aircraft '" << p.aircraft << "' under " << p.root;
  } catch (const JsbsimError& e) {
    f.message = e.what();
  }
  f.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return f;
}

/// The error comes within ~2 s of the start (not at plant.jsbsim.timeout), its headline names
/// `key` and it holds `cause`; no JSBSim is left.
void expectNamedFast(const LoadFailure& f, const std::string& key, const std::string& cause) {
  EXPECT_LT(f.seconds, 3.0) << f.message;
  EXPECT_EQ(f.message.compare(0, key.size() + 1, key + ":"), 0) << f.message;
  EXPECT_NE(f.message.find(cause), std::string::npos) << f.message;
  EXPECT_EQ(f.message.find("plant.jsbsim.timeout"), std::string::npos) << f.message;
  EXPECT_TRUE(noChildLeft());
}

TEST(JsbsimFailure, AnAircraftThatDoesNotLoadFailsFastNamingTheCause) {
  const RunConfig cfg = jsbsimConfig();
  JsbsimParams p = cfg.plant.jsbsim;
  const std::filesystem::path root = copyOfTheRoot("load_failures");
  p.root = root.string();
  p.timeout = 10.0;  // the default: each failure must come long before it

  // No such aircraft folder: refused before JSBSim starts.
  p.aircraft = "737";
  expectNamedFast(failToLoad(p), "plant.jsbsim.aircraft", "no aircraft '737'");

  // An ordinary aircraft (none of the package's properties) gets the interface from a
  // generated overlay, but this one's elevator comes from an <fcs_function> the package cannot
  // follow back to fcs/elevator-cmd-norm: refused before JSBSim starts, naming the fix.
  addAircraftWithoutInterface(root, "737");
  expectNamedFast(failToLoad(p), "plant.jsbsim.elevator",
                  "cannot follow it back to fcs/elevator-cmd-norm");
  // An aircraft that names the package's command (so is taken as written for the package) but
  // lacks the rest of the interface: JSBSim, loading the output socket's properties, says
  // which it does not have (and leaves them out of the lines).
  p.aircraft = "767";
  addAircraftWithoutInterface(root, "767", true);
  expectNamedFast(failToLoad(p), "plant.jsbsim.aircraft", "has no property pmrac/dev/");

  // No such initial condition.
  p.aircraft = "b747_pmrac";
  p.initialize = "cruise_m090_h99k";
  expectNamedFast(failToLoad(p), "plant.jsbsim.initialize",
                  "no initial condition 'cruise_m090_h99k'");

  // An initial-condition file that is not one.
  writeFile(root / "aircraft/b747_pmrac/not_an_ic.xml", "<?xml version=\"1.0\"?>\n<foo/>\n");
  p.initialize = "not_an_ic";
  expectNamedFast(failToLoad(p), "plant.jsbsim.initialize", "is not an <initialize> file");

  // The engine file the aircraft names is missing (fatal to JSBSim; so is the thruster's).
  p.initialize = "cruise_m080_h40k";
  std::filesystem::remove(root / "engine/pmrac_thrust.xml");
  expectNamedFast(failToLoad(p), "plant.jsbsim.aircraft, plant.jsbsim.root",
                  "Could not open file: pmrac_thrust");
  std::filesystem::remove_all(root);
}

TEST(Jsbsim, AnAircraftWithoutTheInterfaceFliesAtTheSurface) {
  // b747_pmrac without its interface, flown through a generated overlay with the package's
  // deflection added at the surface (its elevator is an <fcs_function> the command drive cannot
  // scale): the same aircraft, so the same trim and the same sign.
  const RunConfig cfg = jsbsimConfig();
  JsbsimParams p = cfg.plant.jsbsim;
  const std::filesystem::path root = copyOfTheRoot("surface_drive");
  addAircraftWithoutInterface(root, "737");
  p.root = root.string();
  p.aircraft = "737";
  p.elevator = JsbsimElevatorDrive::kSurface;
  {
    JsbsimPlant plant(p, 0.001, 0.0);
    EXPECT_TRUE(plant.overlay().generated());
    EXPECT_NEAR(plant.trim().alpha / kDeg, 4.4525, 0.01);  // b747_pmrac's (jsbsim/README.md)
    const Vec theta = Vec::Zero(3);
    for (int k = 0; k < 100; ++k) plant.step(0.001, theta, 0.01, 0.0, 0.0);
    EXPECT_LT(plant.state()[2], -1e-3);
  }
  EXPECT_TRUE(noChildLeft());
  std::filesystem::remove_all(root);
}

TEST(JsbsimFailure, ARefusedPropertyEndsItsPacketOnly) {
  // A refused property that ends its packet is an answer (the caller's error); one with more
  // commands behind it is fatal at once (JSBSim answers none of them).
  JsbsimLaunch l;
  JsbsimProcess proc(l);
  EXPECT_THROW(proc.get({"pmrac/no-such-property"}), JsbsimError);
  EXPECT_GT(proc.pid(), 0);
  EXPECT_NEAR(proc.get({"ic/mach"})[0], 0.8, 1e-6);
  const auto t0 = std::chrono::steady_clock::now();
  try {
    proc.get({"pmrac/no-such-property", "ic/mach"});
    FAIL() << "read on after a refused property";
  } catch (const JsbsimError& e) {
    EXPECT_NE(std::string(e.what()).find("no property pmrac/no-such-property"), std::string::npos)
        << e.what();
  }
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 3.0);
  EXPECT_LT(proc.pid(), 0);
}

TEST(JsbsimFailure, ARefusedStepInputEndsTheWaitForItsFrame) {
  // A refused `set` drops the `iterate` behind it, so the output line waited for never comes:
  // the refusal is seen while waiting, long before the timeout.
  JsbsimLaunch l;
  l.outputs = {"simulation/frame"};
  JsbsimProcess proc(l);
  const auto t0 = std::chrono::steady_clock::now();
  proc.send("set pmrac/no-such-property 1\niterate 1\n");
  try {
    for (double frame = 0.0; frame < 2.0;) frame = proc.readOutput()[0];  // JSBSim's start: 0, 1
    FAIL() << "a frame came after a refused step input";
  } catch (const JsbsimError& e) {
    EXPECT_NE(std::string(e.what()).find("no property pmrac/no-such-property"), std::string::npos)
        << e.what();
  }
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 3.0);
  EXPECT_LT(proc.pid(), 0);
  EXPECT_TRUE(noChildLeft());
}

TEST(JsbsimFailure, ASilentJsbsimStillEndsAtTheTimeout) {
  // Alive, nothing fatal in its output, no reply coming: plant.jsbsim.timeout is the last resort.
  JsbsimLaunch l;
  l.timeout = 0.5;
  JsbsimProcess proc(l);
  const auto t0 = std::chrono::steady_clock::now();
  try {
    proc.transact("get ic/mach\n", 2);
    FAIL() << "two replies to one command";
  } catch (const JsbsimError& e) {
    EXPECT_NE(std::string(e.what()).find("did not answer within 500 ms (plant.jsbsim.timeout)"),
              std::string::npos)
        << e.what();
    // What /proc said of it: running, waiting or stopped, and its CPU time.
    EXPECT_NE(std::string(e.what()).find("(it was still running (state "), std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find(" s of CPU), killed now)"), std::string::npos) << e.what();
  }
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_GT(s, 0.45);
  EXPECT_LT(s, 3.0);
  EXPECT_LT(proc.pid(), 0);
}

TEST(JsbsimLog, FindsTheFatalLinesOnly) {
  const JsbsimNames n{"737", "cruise", "/r"};
  EXPECT_FALSE(diagnoseJsbsimLog("JSBSim startup beginning ...\n\nScript: \"x\"\n", n).found());
  EXPECT_FALSE(diagnoseJsbsimLog("Could not bind to TCP input socket, error = 98\n", n).found());
  // A failed lookup alone: the cause, but not certain (a refused `get` leaves the same line).
  JsbsimFault f = diagnoseJsbsimLog(
      "Start: x\nFGPropertyManager::GetNode() No node found for fcs/pmrac-elevator-cmd-rad\n", n);
  EXPECT_TRUE(f.found());
  EXPECT_FALSE(f.certain);
  EXPECT_EQ(f.key, "plant.jsbsim.aircraft");
  f = diagnoseJsbsimLog(
      "Could not open file: Path \"/r/aircraft/737/cruise.xml\"\n"
      "File: Path \"/r/aircraft/737/cruise\" could not be read.\n",
      n);
  EXPECT_TRUE(f.certain);
  EXPECT_EQ(f.message(),
            "plant.jsbsim.initialize: no initial condition 'cruise': JSBSim looks for "
            "/r/aircraft/737/cruise.xml; JSBSim said: \"Could not open file: Path "
            "\"/r/aircraft/737/cruise.xml\"\"");
}

TEST(JsbsimFailure, FailedTrimEndsWithAnErrorAndNoProcess) {
  const RunConfig cfg = jsbsimConfig();
  JsbsimParams p = cfg.plant.jsbsim;
  p.mach = 0.3;  // beyond the lift at 40,000 ft: JSBSim's trim fails and the process ends
  try {
    JsbsimPlant plant(p, 0.001, 0.0);
    FAIL() << "trim at Mach 0.3, 40,000 ft succeeded";
  } catch (const JsbsimError& e) {
    EXPECT_NE(std::string(e.what()).find("trim failed"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("plant.jsbsim.mach"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(noChildLeft());
}

TEST(JsbsimFailure, KilledMidRunEndsWithAnErrorAndNoProcess) {
  // Through the shared-memory lane and through the sockets.
  for (const bool shared_memory : {true, false}) {
    RunConfig cfg = jsbsimConfig();
    cfg.plant.jsbsim.shared_memory = shared_memory;
    pid_t pid = -1;
    const auto t0 = std::chrono::steady_clock::now();
    try {
      ScenarioPlant sim(cfg.plant, cfg.scenario, 0.001);
      auto* engine = dynamic_cast<JsbsimPlant*>(sim.engine());
      ASSERT_NE(engine, nullptr);
      EXPECT_EQ(engine->process().sharedMemory(), shared_memory);
      pid = engine->process().pid();
      for (int k = 0; k < 100; ++k) sim.advance(0.0);
      ::kill(pid, SIGKILL);
      for (int k = 0; k < 100; ++k) sim.advance(0.0);
      FAIL() << "ran on after JSBSim was killed";
    } catch (const JsbsimError& e) {
      EXPECT_NE(std::string(e.what()).find("killed by signal 9"), std::string::npos) << e.what();
    }
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 2.0);
    EXPECT_FALSE(alive(pid));
    EXPECT_TRUE(noChildLeft());
  }
}

TEST(JsbsimFailure, DestructorEndsTheProcess) {
  const RunConfig cfg = jsbsimConfig();
  pid_t pid = -1;
  {
    JsbsimPlant p(cfg.plant.jsbsim, 0.001, 0.0);
    pid = p.process().pid();
    EXPECT_TRUE(alive(pid));
  }
  EXPECT_FALSE(alive(pid));
}

}  // namespace
}  // namespace preadaptive_mrac
