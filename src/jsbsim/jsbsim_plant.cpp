#include "preadaptive_mrac/jsbsim/jsbsim_plant.hpp"

#include <cmath>
#include <cstdio>
#include <cstring>
#include <iterator>
#include <vector>

#include "preadaptive_mrac/core/sim/plant.hpp"

namespace preadaptive_mrac {

namespace {

constexpr double kFt = 0.3048;  // [m/ft]
// What JSBSim's output socket sends after every model pass: the aerodynamics' copy of the
// frame (the step's completion marker), the elevator command, then the deviations from the
// references (jsbsim/README.md "precision" and "lockstep"). `iterate 1` gives two lines: one
// from the pass that takes the command in (the models but the integrator, on the state before
// the step: the marker still at the frame before) and one from the step itself (marker + 1).
const char* const kOutputs[] = {"pmrac/sync/frame",    "fcs/pmrac-elevator-cmd-rad",
                                "pmrac/dev/theta-rad", "pmrac/dev/gamma-rad",
                                "pmrac/dev/q-rad_sec", "pmrac/dev/vt-fps",
                                "pmrac/dev/h-sl-ft"};
// The output prints 7 significant digits: the marker is exact below this frame.
constexpr std::int64_t kMaxFrame = 9999999;
// An elevator command no step sends (7 digits, exact), held while reset() has the trimmed state
// printed: it tells that line from any left over from JSBSim's start.
constexpr double kMarkCommand = 1234567.0;

/// The root the aircraft is under (JSBSim's binary looked for first, so a missing binary is
/// the first thing said).
std::string aircraftRoot(const JsbsimParams& p) {
  findJsbsimExecutable(p.executable);
  return findJsbsimRoot(p.root, p.aircraft);
}

JsbsimLaunch launchOf(const JsbsimParams& p, double dt, const JsbsimOverlay& overlay) {
  JsbsimLaunch l;
  l.executable = p.executable;
  l.root = overlay.root();
  l.aircraft = p.aircraft;
  l.initialize = overlay.initialize();
  l.dt = dt;
  l.timeout = p.timeout;
  l.shared_memory = p.shared_memory;
  l.outputs.assign(std::begin(kOutputs), std::end(kOutputs));
  return l;
}

void appendSet(std::string* packet, const char* property, double value) {
  char line[160];
  const int n = std::snprintf(line, sizeof line, "set %s %.17g\n", property, value);
  packet->append(line, static_cast<size_t>(n));
}

}  // namespace

JsbsimPlant::JsbsimPlant(const JsbsimParams& params, double dt, double e_i0)
    : params_(params),
      dt_(dt),
      e_i0_(e_i0),
      overlay_(aircraftRoot(params), params),
      proc_(launchOf(params, dt, overlay_)),
      refs_{{{"pmrac/ref/theta-rad", &theta_, 1e-4},
             {"pmrac/ref/gamma-rad", &gamma_, 1e-4},
             {"pmrac/ref/q-rad_sec", &q_, 1e-4},
             {"pmrac/ref/vt-fps", &vt_, 0.1},
             {"pmrac/ref/h-sl-ft", &h_, 1.0}}} {
  x_.setZero(3);
  packet_.reserve(1024);
  // JSBSim's trim starts from the initial condition and leaves it changed: the attitude and
  // position the initialize file gave are read once (6 digits) and written back before every
  // trim, so that every reset() trims from the same point to the same bits.
  static const char* const kIc[] = {"ic/lat-gc-rad", "ic/long-gc-rad", "ic/psi-true-rad",
                                    "ic/phi-rad",    "ic/beta-rad",    "ic/alpha-rad"};
  const std::vector<double> v = proc_.get(std::vector<std::string>(std::begin(kIc), std::end(kIc)));
  for (size_t i = 0; i < v.size(); ++i) appendSet(&ic_packet_, kIc[i], v[i]);
  ic_lines_ = v.size();
  reset();
}

void JsbsimPlant::reset() {
  char where[160];
  std::snprintf(where, sizeof where, "Mach %g, %g ft", params_.mach, params_.altitude_ft);
  // Nominal inputs, no wind, the operating point; then JSBSim's trim from it.
  std::string p = ic_packet_;
  std::size_t sets = 8 + ic_lines_;
  if (overlay_.generated()) {
    // An ordinary aircraft's configuration: JSBSim's trim moves its kinematics (flaps, gear)
    // to their commands at once, so the run starts with them there.
    const bool down = params_.gear == JsbsimGear::kDown;
    std::snprintf(where + std::strlen(where), sizeof where - std::strlen(where),
                  ", flaps %g, gear %s", params_.flaps, down ? "down" : "up");
    appendSet(&p, "fcs/flap-cmd-norm", params_.flaps);
    appendSet(&p, "gear/gear-cmd-norm", down ? 1.0 : 0.0);
    sets += 2;
  }
  appendSet(&p, "fcs/pmrac-elevator-cmd-rad", 0.0);
  appendSet(&p, "pmrac/fault/elevator-effectiveness", 1.0);
  appendSet(&p, "pmrac/fault/pitch-damping", 1.0);
  appendSet(&p, "pmrac/fault/cg-shift-mac", 0.0);
  appendSet(&p, "atmosphere/wind-down-fps", 0.0);
  appendSet(&p, "ic/h-sl-ft", params_.altitude_ft);
  appendSet(&p, "ic/mach", params_.mach);
  appendSet(&p, "ic/gamma-rad", 0.0);
  for (const auto& line : proc_.transact(p, sets))
    if (line.find("set successful") == std::string::npos)
      throw JsbsimError(
          "JSBSim refused an input of the aircraft '" + params_.aircraft +
          "' (is it the package's, with the fcs/pmrac-* and pmrac/* properties?): " + line);
  proc_.trim(where);
  // 6 significant digits first; they become the references of the full-precision reads.
  const std::vector<std::string> names = {"attitude/theta-rad",    "flight-path/gamma-rad",
                                          "velocities/q-rad_sec",  "velocities/vt-fps",
                                          "position/h-sl-ft",      "fcs/elevator-pos-rad",
                                          "fcs/throttle-cmd-norm", "propulsion/engine/thrust-lbs",
                                          "velocities/mach"};
  const std::vector<double> v = proc_.get(names);
  theta_ = v[0];
  gamma_ = v[1];
  q_ = v[2];
  vt_ = v[3];
  h_ = v[4];
  trim_.elevator = v[5];
  trim_.throttle = v[6];
  trim_.thrust_lbf = v[7];
  trim_.mach = v[8];
  // The deviations are computed when the aerodynamics runs: trim again (from the same
  // operating point, so to the same state) with the references set, then read them.
  p = ic_packet_;
  appendSet(&p, "ic/h-sl-ft", params_.altitude_ft);
  appendSet(&p, "ic/mach", params_.mach);
  appendSet(&p, "ic/gamma-rad", 0.0);
  appendSet(&p, "pmrac/ref/theta-rad", theta_);
  appendSet(&p, "pmrac/ref/gamma-rad", gamma_);
  appendSet(&p, "pmrac/ref/q-rad_sec", q_);
  appendSet(&p, "pmrac/ref/vt-fps", vt_);
  appendSet(&p, "pmrac/ref/h-sl-ft", h_);
  proc_.transact(p, 8 + ic_lines_);
  refs_[0].at = theta_;
  refs_[1].at = gamma_;
  refs_[2].at = q_;
  refs_[3].at = vt_;
  refs_[4].at = h_;
  proc_.trim(where);
  // JSBSim prints the trimmed state on demand (the elevator command marking the line), and
  // its frame is the one the steps count from (the trim does not advance it).
  p.clear();
  appendSet(&p, "fcs/pmrac-elevator-cmd-rad", kMarkCommand);
  p += "set simulation/force-output 0\n";
  appendSet(&p, "fcs/pmrac-elevator-cmd-rad", 0.0);
  for (const auto& line : proc_.transact(p, 3))
    if (line.compare(0, 14, "set successful") != 0)
      throw JsbsimError("JSBSim refused printing the trimmed state: '" + line + "'");
  for (;;) {
    const std::vector<double>& out = proc_.readOutput();
    if (out[1] != kMarkCommand) continue;  // a line of JSBSim's start
    frame_ = static_cast<std::int64_t>(out[0]);
    takeOutput(out);
    break;
  }
  trim_.pitch = theta_;
  trim_.flight_path = gamma_;
  trim_.alpha = theta_ - gamma_;
  trim_.q = q_;
  trim_.airspeed = vt_ * kFt;
  trim_.altitude = h_ * kFt;
  x_.setZero(3);
  x_[0] = e_i0_;
  faults_ = sent_faults_ = PhysicalFaults{};
  wind_sent_ = false;
  de_ = 0.0;
  flight_ = {theta_, vt_ * kFt, h_ * kFt, gamma_};
}

void JsbsimPlant::setFaults(const PhysicalFaults& faults) {
  if (overlay_.generated() && faults != PhysicalFaults{})
    throw JsbsimError("scenario.faults: the aircraft '" + params_.aircraft +
                      "' has no fault model (the pmrac/fault/* properties act only in an aircraft "
                      "written for the package, such as b747_pmrac): leave scenario.faults out");
  faults_ = faults;
}

void JsbsimPlant::readFrame(std::int64_t frame) {
  if (frame > kMaxFrame)
    throw JsbsimError("JSBSim's output socket prints 7 significant digits: a run is limited to " +
                      std::to_string(kMaxFrame) + " frames of one JSBSim process");
  for (;;) {
    const std::vector<double>& v = proc_.readOutput();
    const auto marker = static_cast<std::int64_t>(v[0]);
    if (marker > frame)
      throw JsbsimError("JSBSim lost the lockstep: its aerodynamics ran frame " +
                        std::to_string(marker) + " where frame " + std::to_string(frame) +
                        " was expected");
    if (marker < frame) continue;  // the pass before the step
    takeOutput(v);
    return;
  }
}

void JsbsimPlant::takeOutput(const std::vector<double>& v) {
  theta_ = refs_[0].at + v[2];
  gamma_ = refs_[1].at + v[3];
  q_ = refs_[2].at + v[4];
  vt_ = refs_[3].at + v[5];
  h_ = refs_[4].at + v[6];
}

void JsbsimPlant::step(double dt, const Vec& theta, double effect, double r, double gust) {
  // The paper's matched uncertainty in the elevator path: deflection = Lambda u + theta^T x.
  de_ = effect + theta.dot(x_);
  packet_.clear();
  appendSet(&packet_, "fcs/pmrac-elevator-cmd-rad", de_);
  size_t lines = 1;
  if (gust != 0.0 || wind_sent_) {
    // An updraft w_g raises alpha: the air moves up, the wind's down component is -w_g.
    appendSet(&packet_, "atmosphere/wind-down-fps", -gust / kFt);
    wind_sent_ = true;
    ++lines;
  }
  if (faults_ != sent_faults_) {
    appendSet(&packet_, "pmrac/fault/cg-shift-mac", faults_.cg_shift);
    appendSet(&packet_, "pmrac/fault/elevator-effectiveness", faults_.elevator_effectiveness);
    appendSet(&packet_, "pmrac/fault/pitch-damping", faults_.pitch_damping);
    sent_faults_ = faults_;
    lines += 3;
  }
  // A reference moves to its variable's value once the deviation has grown past its bound:
  // the output's 7 significant digits of a deviation of at most about the bound then resolve
  // the variable to 5e-11 rad (theta, gamma), 5e-11 rad/s (q), 5e-8 ft/s (airspeed), 5e-7 ft
  // (altitude), at the cost of a `set` only every so many steps.
  for (Ref& ref : refs_) {
    if (std::abs(*ref.value - ref.at) > ref.bound) {
      appendSet(&packet_, ref.property, *ref.value);
      ref.at = *ref.value;
      ++lines;
    }
  }
  packet_ += "iterate 1\n";
  ++lines;
  // The step's line comes on the output socket; the replies, sent before it, are read after
  // it (a refused command, which would keep the step from coming, is seen while waiting).
  proc_.send(packet_);
  const double alpha_before = x_[1];
  ++frame_;
  readFrame(frame_);
  const auto& rep = proc_.replies(lines);
  for (size_t i = 0; i + 1 < lines; ++i)
    if (rep[i].compare(0, 14, "set successful") != 0)
      throw JsbsimError("JSBSim refused a step input: '" + rep[i] + "'");
  x_[1] = (theta_ - gamma_) - trim_.alpha;
  x_[2] = q_ - trim_.q;
  x_[0] += dt * (0.5 * (alpha_before + x_[1]) - r);
  flight_ = {theta_, vt_ * kFt, h_ * kFt, gamma_};
}

namespace {

// plant.engine jsbsim: this library's one registration line.
[[maybe_unused]] const bool kRegistered =
    registerPlantEngine(PlantEngineKind::kJsbsim, [](const PlantConfig& cfg, double dt) {
      return std::make_unique<JsbsimPlant>(cfg.jsbsim, dt, cfg.x0.size() > 0 ? cfg.x0[0] : 0.0);
    });

}  // namespace

}  // namespace preadaptive_mrac
