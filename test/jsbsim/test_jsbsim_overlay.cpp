// Any JSBSim aircraft as the plant: the package's interface added by a generated overlay to an
// aircraft in ordinary JSBSim form (jsbsim/aircraft/navion, and small flight control systems
// written here), its elevator found in the aircraft's own flight control system, the user's
// files left as they were, and the aircraft that has no elevator the package can find refused
// naming the cause. The plant tests need the JSBSim binary (scripts/install_jsbsim).

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "preadaptive_mrac/jsbsim/jsbsim_overlay.hpp"
#include "preadaptive_mrac/jsbsim/jsbsim_plant.hpp"
#include "preadaptive_mrac/jsbsim/jsbsim_xml.hpp"

namespace preadaptive_mrac {
namespace {

namespace fs = std::filesystem;

bool noChildLeft() { return ::waitpid(-1, nullptr, WNOHANG) == -1 && errno == ECHILD; }

std::string readText(const fs::path& p) {
  std::ifstream f(p);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

/// The Navion at its reference condition (Nelson: sea level, 176 ft/s), from the package's
/// root, with nothing but the aircraft and the operating point given.
JsbsimParams navion() {
  JsbsimParams p;
  p.aircraft = "navion";
  p.mach = 0.1576;
  p.altitude_ft = 0.0;
  return p;
}

/// A root holding one aircraft `name` whose flight control system is `fcs` (XML of a
/// <flight_control>), with no engine: enough for the package to look for its elevator.
std::string rootWith(const std::string& name, const std::string& fcs) {
  const fs::path root = fs::path(::testing::TempDir()) / ("pmrac_test_root_" + name);
  fs::remove_all(root);
  fs::create_directories(root / "aircraft" / name);
  std::ofstream(root / "aircraft" / name / (name + ".xml"))
      << "<?xml version=\"1.0\"?>\n<fdm_config name=\"" << name << "\" version=\"2.0\">\n"
      << "  <metrics> <wingarea unit=\"FT2\"> 100 </wingarea> </metrics>\n"
      << fcs << "\n  <aerodynamics>\n  </aerodynamics>\n</fdm_config>\n";
  return root.string();
}

TEST(JsbsimXml, EditsLeaveEveryOtherByte) {
  const std::string text =
      "<?xml version=\"1.0\"?>\n<!-- <not> an element -->\n<a x='1'>\n  <b>text</b>\n"
      "  <c/>\n</a>\n";
  const auto root = parseXml(text);
  ASSERT_EQ(root->name, "a");
  EXPECT_EQ(root->attribute("x"), "1");
  ASSERT_EQ(root->children.size(), 2u);
  const XmlElement& b = *root->children[0];
  EXPECT_EQ(b.text, "text");
  EXPECT_EQ(text.substr(b.open_begin, b.close_end - b.open_begin), "<b>text</b>");
  TextEdits edits;
  edits.replace(b.open_end, b.close_begin - b.open_end, "new");
  edits.insert(root->close_begin, "<d/>\n");
  edits.insert(root->close_begin, "<e/>\n");
  EXPECT_EQ(edits.apply(text),
            "<?xml version=\"1.0\"?>\n<!-- <not> an element -->\n<a x='1'>\n  <b>new</b>\n"
            "  <c/>\n<d/>\n<e/>\n</a>\n");
  EXPECT_THROW(parseXml("<a><b></a>"), XmlError);
}

TEST(JsbsimOverlay, FindsTheNavionsElevatorInItsFlightControlSystem) {
  const std::optional<JsbsimElevator> el = jsbsimOrdinaryElevator(navion());
  ASSERT_TRUE(el.has_value());
  EXPECT_EQ(el->writer, "<actuator> 'Elevator Actuator'");
  EXPECT_DOUBLE_EQ(el->rad_per_command, 0.4363);  // the aerosurface_scale's 25 deg
  EXPECT_DOUBLE_EQ(el->min_rad, -0.4363);
  EXPECT_DOUBLE_EQ(el->max_rad, 0.4363);
  EXPECT_DOUBLE_EQ(el->max_rate, 1.0472);
  // b747_pmrac carries the interface: flown as it is.
  EXPECT_FALSE(jsbsimOrdinaryElevator(JsbsimParams{}).has_value());
}

TEST(JsbsimOverlay, AsymmetricTravelAndNegatedInputs) {
  // A command negated twice, a gain, and a zero-centred scale of 20 deg up, 17 deg down
  // without an actuator: the command's gain is the mean of the two halves' slopes.
  const std::string root = rootWith("asym", R"(
  <flight_control name="asym">
    <channel name="Pitch">
      <pure_gain name="Elevator Inverted">
        <input>-fcs/elevator-cmd-norm</input>
        <gain> -2.0 </gain>
      </pure_gain>
      <summer name="Pitch Trim Sum">
        <input>fcs/elevator-inverted</input>
        <input>fcs/pitch-trim-cmd-norm</input>
        <clipto> <min> -1 </min> <max> 1 </max> </clipto>
      </summer>
      <aerosurface_scale name="Elevator Control">
        <input>fcs/pitch-trim-sum</input>
        <range> <min> -0.35 </min> <max> 0.30 </max> </range>
        <output>fcs/elevator-pos-rad</output>
      </aerosurface_scale>
    </channel>
  </flight_control>)");
  const JsbsimElevator el = findJsbsimElevator(root, "asym", JsbsimElevatorDrive::kCommand);
  EXPECT_DOUBLE_EQ(el.rad_per_command, 2.0 * 0.5 * (0.30 + 0.35));
  EXPECT_DOUBLE_EQ(el.min_rad, -0.35);
  EXPECT_DOUBLE_EQ(el.max_rad, 0.30);
  EXPECT_DOUBLE_EQ(el.symmetricTravel(), 0.30);
  EXPECT_EQ(el.max_rate, 0.0);  // no actuator: no rate
}

TEST(JsbsimOverlay, AnAircraftWithoutAnElevatorIsRefusedNamingTheCause) {
  const std::string root = rootWith("noelevator", R"(
  <flight_control name="none">
    <channel name="Roll">
      <aerosurface_scale name="Aileron Control">
        <input>fcs/aileron-cmd-norm</input>
        <range> <min> -0.3 </min> <max> 0.3 </max> </range>
        <output>fcs/aileron-pos-rad</output>
      </aerosurface_scale>
    </channel>
  </flight_control>)");
  JsbsimParams p;
  p.root = root;
  p.aircraft = "noelevator";
  // A temporary folder of its own: nothing may be left in it.
  const fs::path tmp = fs::path(::testing::TempDir()) / "pmrac_test_tmp_noelevator";
  fs::remove_all(tmp);
  fs::create_directories(tmp);
  const char* old_tmp = std::getenv("TMPDIR");
  const std::string saved = old_tmp ? old_tmp : "";
  ::setenv("TMPDIR", tmp.c_str(), 1);
  try {
    JsbsimOverlay overlay(root, p);
    FAIL() << "an aircraft without an elevator was accepted";
  } catch (const JsbsimError& e) {
    const std::string m = e.what();
    EXPECT_EQ(m.rfind("plant.jsbsim.aircraft: the aircraft 'noelevator' has no elevator", 0), 0u)
        << m;
    EXPECT_NE(m.find("writes fcs/elevator-pos-rad"), std::string::npos) << m;
  }
  if (old_tmp)
    ::setenv("TMPDIR", saved.c_str(), 1);
  else
    ::unsetenv("TMPDIR");
  EXPECT_TRUE(fs::is_empty(tmp));  // refused before any overlay was made
}

TEST(JsbsimOverlay, AChainThePackageCannotFollowNeedsTheSurfaceDrive) {
  const std::string root = rootWith("func", R"(
  <flight_control name="func">
    <channel name="Pitch">
      <fcs_function name="Elevator Schedule">
        <function> <product> <property>fcs/elevator-cmd-norm</property> <value>0.3</value> </product> </function>
      </fcs_function>
      <actuator name="Elevator Actuator">
        <input>fcs/elevator-schedule</input>
        <rate_limit> 0.9 </rate_limit>
        <clipto> <min> -0.3 </min> <max> 0.3 </max> </clipto>
        <output>fcs/elevator-pos-rad</output>
      </actuator>
    </channel>
  </flight_control>)");
  try {
    findJsbsimElevator(root, "func", JsbsimElevatorDrive::kCommand);
    FAIL() << "a command the package cannot scale was accepted";
  } catch (const JsbsimError& e) {
    const std::string m = e.what();
    EXPECT_EQ(m.rfind("plant.jsbsim.elevator:", 0), 0u) << m;
    EXPECT_NE(m.find("set plant.jsbsim.elevator to surface"), std::string::npos) << m;
  }
  const JsbsimElevator el = findJsbsimElevator(root, "func", JsbsimElevatorDrive::kSurface);
  EXPECT_DOUBLE_EQ(el.max_rate, 0.9);
  EXPECT_DOUBLE_EQ(el.symmetricTravel(), 0.3);
}

TEST(JsbsimOverlay, TheUsersFolderIsLinkedNotWrittenAndTheOverlayGoes) {
  const std::string root = findJsbsimRoot("", "navion");
  const fs::path file = fs::path(root) / "aircraft/navion/navion.xml";
  const std::string before = readText(file);
  std::string overlay_root;
  {
    const JsbsimParams p = navion();
    JsbsimOverlay overlay(root, p);
    ASSERT_TRUE(overlay.generated());
    overlay_root = overlay.root();
    EXPECT_NE(overlay_root, root);
    const fs::path dst = fs::path(overlay_root) / "aircraft/navion";
    EXPECT_TRUE(fs::is_symlink(dst / "Engines/navion_thrust.xml"));
    EXPECT_TRUE(fs::is_symlink(dst / "cruise_sl_176fps.xml"));
    EXPECT_FALSE(fs::is_symlink(dst / "navion.xml"));
    const std::string rewritten = readText(dst / "navion.xml");
    EXPECT_TRUE(jsbsimHasInterface(rewritten));
    EXPECT_NE(rewritten.find("pmrac/sync/frame"), std::string::npos);
    // The default initial condition is b747_pmrac's, not in the Navion's folder: a level
    // start at the operating point is generated.
    EXPECT_EQ(overlay.initialize(), "pmrac_operating_point");
    EXPECT_TRUE(fs::is_regular_file(dst / "pmrac_operating_point.xml"));
  }
  EXPECT_FALSE(fs::exists(overlay_root));
  EXPECT_EQ(readText(file), before);
  // b747_pmrac: nothing generated.
  const JsbsimOverlay own(findJsbsimRoot("", "b747_pmrac"), JsbsimParams{});
  EXPECT_FALSE(own.generated());
  EXPECT_EQ(own.initialize(), "cruise_m080_h40k");
}

// The speed hold: the Navion's own Throttle channel reads the held throttle instead of the
// trim's command; off, the aircraft's throttle chain is as written. An aircraft with a throttle
// chain but no engine is refused naming the key.
TEST(JsbsimOverlay, TheSpeedHoldGoesThroughTheAircraftsOwnThrottleChannel) {
  const std::string root = findJsbsimRoot("", "navion");
  JsbsimParams p = navion();
  {
    JsbsimOverlay on(root, p);
    const std::string text = readText(fs::path(on.root()) / "aircraft/navion/navion.xml");
    EXPECT_NE(text.find("<system name=\"pmrac-speed-hold\">"), std::string::npos);
    EXPECT_NE(text.find("<input>pmrac/speed-hold/throttle-0</input>"), std::string::npos);
    EXPECT_EQ(text.find("<input>fcs/throttle-cmd-norm[0]</input>"), std::string::npos);
    // The aircraft's Throttle channel reads the command: the hold does not write the position.
    EXPECT_EQ(text.find("<output>fcs/throttle-pos-norm[0]</output>\n      </fcs_function>"),
              std::string::npos);
  }
  p.speed_hold = false;
  {
    JsbsimOverlay off(root, p);
    const std::string text = readText(fs::path(off.root()) / "aircraft/navion/navion.xml");
    EXPECT_EQ(text.find("pmrac-speed-hold"), std::string::npos);
    EXPECT_NE(text.find("<input>fcs/throttle-cmd-norm[0]</input>"), std::string::npos);
  }
  const std::string glider = rootWith(
      "glider",
      "  <flight_control name=\"FCS\"> <channel name=\"Pitch\">\n"
      "    <pure_gain name=\"Elevator\"> <input>fcs/elevator-cmd-norm</input> <gain>0.4</gain>\n"
      "      <output>fcs/elevator-pos-rad</output> </pure_gain>\n"
      "  </channel> </flight_control>");
  JsbsimParams g;
  g.aircraft = "glider";
  try {
    JsbsimOverlay o(glider, g);
    ADD_FAILURE() << "an aircraft without an engine was given a speed hold";
  } catch (const JsbsimError& e) {
    EXPECT_NE(std::string(e.what()).find("plant.jsbsim.speed_hold: the aircraft 'glider' has no "
                                         "<engine>"),
              std::string::npos)
        << e.what();
  }
  g.speed_hold = false;
  EXPECT_NO_THROW(JsbsimOverlay o(glider, g));
}

/// The pitch rate 0.1 s after a 0.01 rad trailing-edge-down step, from the trim.
double pitchAfterStep(JsbsimPlant* p) {
  const Vec theta = Vec::Zero(3);
  for (int k = 0; k < 100; ++k) p->step(0.001, theta, 0.01, 0.0, 0.0);
  return p->state()[2];
}

TEST(JsbsimOverlay, TheNavionFliesThroughItsOwnFlightControlSystemOrAtTheSurface) {
  std::string dir;
  {
    JsbsimPlant cmd(navion(), 0.001, 0.0);
    dir = cmd.overlay().root();
    // JSBSim's trim at Nelson's condition: level, 176 ft/s, alpha and elevator near 0 (the
    // datum is the reference condition's trim), half throttle.
    EXPECT_NEAR(cmd.trim().airspeed / 0.3048, 176.0, 0.1);
    EXPECT_NEAR(cmd.trim().alpha, 0.0, 0.5 * M_PI / 180.0);
    EXPECT_NEAR(cmd.trim().elevator, 0.0, 0.5 * M_PI / 180.0);
    EXPECT_NEAR(cmd.trim().throttle, 0.48, 0.02);
    // Trailing edge down pitches the nose down, through the FCS's actuator as at the surface
    // (the actuator's rate limit lets the FCS's path reach the 0.01 rad step a few ms after
    // the surface's, so the two differ a little).
    const double q_cmd = pitchAfterStep(&cmd);
    JsbsimParams s = navion();
    s.elevator = JsbsimElevatorDrive::kSurface;
    JsbsimPlant surf(s, 0.001, 0.0);
    const double q_surf = pitchAfterStep(&surf);
    EXPECT_LT(q_cmd, -0.005);
    EXPECT_LT(q_surf, -0.005);
    EXPECT_NEAR(q_cmd, q_surf, 0.1 * std::abs(q_surf));
    // No fault model in an ordinary aircraft.
    PhysicalFaults f;
    f.pitch_damping = 0.5;
    EXPECT_THROW(cmd.setFaults(f), JsbsimError);
    cmd.setFaults(PhysicalFaults{});
  }
  EXPECT_FALSE(fs::exists(dir));
  EXPECT_TRUE(noChildLeft());
}

/// A copy of the Navion under a root of its own, given flaps and a retractable gear as JSBSim
/// aircraft usually have them: kinematics from fcs/flap-cmd-norm and gear/gear-cmd-norm (5 s
/// each way), a lift increment of the flaps and a drag increment of the gear.
std::string navionWithFlapsAndGear() {
  const fs::path root = fs::path(::testing::TempDir()) / "pmrac_test_root_navion_flaps";
  fs::remove_all(root);
  fs::create_directories(root / "aircraft");
  fs::copy(fs::path(findJsbsimRoot("", "navion")) / "aircraft/navion", root / "aircraft/navion",
           fs::copy_options::recursive);
  const fs::path file = root / "aircraft/navion/navion.xml";
  std::string text = readText(file);
  const auto insert = [&](const std::string& at_text, const std::string& what, bool after) {
    const std::size_t at = text.find(at_text);
    ASSERT_NE(at, std::string::npos) << at_text;
    text.insert(after ? at + at_text.size() : at, what);
  };
  const std::string kinematic =
      "    <kinematic name=\"%s\"> <input>%s</input>\n"
      "      <traverse> <setting> <position>0</position> <time>0</time> </setting>\n"
      "                 <setting> <position>1</position> <time>5</time> </setting> </traverse>\n"
      "      <output>%s</output> </kinematic>\n";
  char flaps[512], gear[512];
  std::snprintf(flaps, sizeof flaps, kinematic.c_str(), "flaps", "fcs/flap-cmd-norm",
                "fcs/flap-pos-norm");
  std::snprintf(gear, sizeof gear, kinematic.c_str(), "gear", "gear/gear-cmd-norm",
                "gear/gear-pos-norm");
  insert("  </flight_control>",
         std::string("   <channel name=\"configuration\">\n") + flaps + gear + "   </channel>\n",
         false);
  const auto increment = [](const char* name, const char* prop, double c) {
    return std::string("      <function name=\"aero/force/") + name +
           "\"> <product> <property>aero/qbar-psf</property>"
           " <property>metrics/Sw-sqft</property> <property>" +
           prop + "</property> <value>" + std::to_string(c) + "</value> </product> </function>\n";
  };
  insert("<axis name=\"LIFT\">\n", increment("flap_lift", "fcs/flap-pos-norm", 0.3), true);
  insert("<axis name=\"DRAG\">\n", increment("gear_drag", "gear/gear-pos-norm", 0.02), true);
  std::ofstream(file) << text;
  return root.string();
}

TEST(JsbsimOverlay, FlapsAndGearAreSetBeforeTheTrimAndStayThere) {
  JsbsimParams clean = navion();
  clean.root = navionWithFlapsAndGear();
  JsbsimParams landing = clean;
  landing.flaps = 1.0;
  landing.gear = JsbsimGear::kDown;
  JsbsimPlant a(clean, 0.001, 0.0), b(landing, 0.001, 0.0);
  // The flaps' lift lowers the trimmed alpha, the gear's drag raises the throttle.
  EXPECT_LT(b.trim().alpha, a.trim().alpha - 0.5 * M_PI / 180.0);
  EXPECT_GT(b.trim().throttle, a.trim().throttle + 0.02);
  // Trimmed with flaps and gear where they stay: level flight goes on with nothing moving.
  const Vec theta = Vec::Zero(3);
  for (JsbsimPlant* p : {&a, &b}) {
    for (int k = 0; k < 2000; ++k) p->step(0.001, theta, 0.0, 0.0, 0.0);
    EXPECT_LT(std::abs(p->state()[1]), 2e-4);  // alpha's deviation after 2 s [rad]
  }
}

}  // namespace
}  // namespace preadaptive_mrac
