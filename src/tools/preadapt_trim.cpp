/// \file preadapt_trim.cpp
/// \brief Trim the JSBSim aircraft at an operating point and linearise it through the
/// package's coupling into x = [e_I, alpha, q]; print the trim and a plant YAML.

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include "cli_common.hpp"
#include "preadaptive_mrac/io/yaml_params.hpp"
#include "preadaptive_mrac/jsbsim/jsbsim_linearise.hpp"
#include "preadaptive_mrac/jsbsim/jsbsim_overlay.hpp"

using namespace preadaptive_mrac;

namespace {

std::string num(double v) {
  char b[40];
  std::snprintf(b, sizeof b, "%.6g", v);
  return b;
}

constexpr double kDeg = 180.0 / M_PI;

/// The plant.jsbsim keys a plant file needs beyond the aircraft and the operating point:
/// those not at their defaults.
std::string jsbsimKeys(const JsbsimParams& p) {
  const JsbsimParams d;
  std::string out;
  if (p.root != d.root)
    out += ", root: \"" + std::filesystem::absolute(p.root).lexically_normal().string() + "\"";
  if (p.initialize != d.initialize) out += ", initialize: " + p.initialize;
  if (p.elevator != d.elevator) out += std::string(", elevator: ") + choiceName(p.elevator);
  if (p.speed_hold != d.speed_hold)
    out += p.speed_hold ? ", speed_hold: true" : ", speed_hold: false";
  if (p.flaps != d.flaps) out += ", flaps: " + formatNumber(p.flaps);
  if (p.gear != d.gear) out += std::string(", gear: ") + choiceName(p.gear);
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  return cli::runTool("preadapt_trim", [&]() -> int {
    CLI::App app{
        "Trim the JSBSim aircraft of plant.jsbsim (default b747_pmrac at Mach 0.8, 40,000 ft) "
        "and linearise it through the package's JSBSim coupling into x = [e_I, alpha, q]. "
        "Prints the trim as comments and a plant YAML on stdout: usable as --plant (with "
        "plant.engine jsbsim) or its A, B, B1r as a controller's design model. Needs JSBSim "
        "(scripts/install_jsbsim). Exit code 2 on bad input, 1 when JSBSim fails.",
        "preadapt_trim"};
    std::string plant_path, mach, alt, dt, duration, amplitude;
    std::vector<std::string> sets;
    cli::addText(app, "--plant", &plant_path, "plant YAML (default config/plant/b747.yaml)");
    cli::addTexts(app, "--set", &sets, "key=value override of the plant's keys (repeatable)");
    cli::addText(app, "--mach", &mach, "Mach number (default plant.jsbsim.mach, 0.8)");
    cli::addText(app, "--altitude-ft", &alt,
                 "altitude [ft] (default plant.jsbsim.altitude_ft, 40000)");
    cli::addText(app, "--dt", &dt, "step of the linearisation runs [s] (default 0.001)");
    cli::addText(app, "--duration", &duration, "length of each run [s] (default 6)");
    cli::addText(app, "--amplitude-deg", &amplitude, "elevator amplitude [deg] (default 0.1)");
    if (!cli::parseCommandLine(app, argc, argv)) return 0;
    ParamValue tree = ParamValue::makeMap();
    try {
      tree.merge(loadYamlFile(plant_path.empty() ? defaultPlantPath() : plant_path));
      for (const auto& s : sets) applyOverride(&tree, s);
    } catch (const FileError& e) {
      throw cli::UsageError(e.what());
    }
    tree.setPath("plant.engine", ParamValue::makeString("jsbsim"));
    if (!mach.empty())
      tree.setPath("plant.jsbsim.mach", ParamValue::makeDouble(cli::parseDouble("--mach", mach)));
    if (!alt.empty())
      tree.setPath("plant.jsbsim.altitude_ft",
                   ParamValue::makeDouble(cli::parseDouble("--altitude-ft", alt)));
    LineariseOptions opt;
    if (!dt.empty()) opt.dt = cli::parseDouble("--dt", dt);
    if (!duration.empty()) opt.duration = cli::parseDouble("--duration", duration);
    if (!amplitude.empty()) opt.amplitude = cli::parseDouble("--amplitude-deg", amplitude) / kDeg;
    if (!(opt.dt > 0.0 && opt.dt <= 0.1)) throw cli::UsageError("--dt: must be in (0, 0.1]");
    if (!(opt.duration >= 2.6)) throw cli::UsageError("--duration: must be >= 2.6 s");
    if (!(opt.amplitude > 0.0 && opt.amplitude < 0.1))
      throw cli::UsageError("--amplitude-deg: must be in (0, 5.7)");
    Sections sections;
    sections.controller = sections.scenario = false;
    sections.strict_top_level = true;
    PlantConfig plant;
    try {
      plant = readRunConfig(tree, KeyStyle{}, sections).plant;
    } catch (const ConfigError& e) {
      std::string line;
      for (const auto& p : e.problems()) line += (line.empty() ? "" : "; ") + p;
      throw cli::UsageError("invalid configuration: " + line);
    }
    const auto t0 = std::chrono::steady_clock::now();
    JsbsimPlant jsb(plant.jsbsim, opt.dt, 0.0);
    jsb.reset();
    const JsbsimTrim tr = jsb.trim();
    const LinearModel lm = lineariseJsbsim(&jsb, opt);
    const double wall =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const auto& A = lm.A;
    const auto& B = lm.B;
    std::printf("# preadapt_trim: JSBSim aircraft %s trimmed at Mach %s, %s ft (level flight)\n",
                plant.jsbsim.aircraft.c_str(), num(plant.jsbsim.mach).c_str(),
                num(plant.jsbsim.altitude_ft).c_str());
    std::printf(
        "# trim: alpha %.4f deg, pitch %.4f deg, elevator %.4f deg (fcs/elevator-pos-rad"
        "), throttle %.6f, thrust %.0f lbf, true airspeed %.3f m/s, Mach %.4f\n",
        tr.alpha * kDeg, tr.pitch * kDeg, tr.elevator * kDeg, tr.throttle, tr.thrust_lbf,
        tr.airspeed, tr.mach);
    std::printf(
        "# linearised through the coupling: +-%.3g deg elevator runs of %g s at dt %g s, "
        "central differences, least squares (fit residual rms: alphadot %.2g of %.2g "
        "rad/s, qdot %.2g of %.2g rad/s^2); %.1f s wall\n",
        opt.amplitude * kDeg, opt.duration, opt.dt, lm.residual_alpha, lm.signal_alpha,
        lm.residual_q, lm.signal_q, wall);
    std::printf(
        "# Z_alpha/mU %.4f, 1 + Z_q/mU %.4f, M_alpha/Iy %.4f, M_q/Iy %.4f, Z_delta/mU "
        "%.5f, M_delta/Iy %.4f (the paper: -0.32, 0.86, -0.93, -0.43, -0.02, -1.16)\n",
        A(1, 1), A(1, 2), A(2, 1), A(2, 2), B[1], B[2]);
    std::printf("plant:\n");
    std::printf(
        "  description: \"%s trimmed at Mach %s, %s ft by preadapt_trim; A, B linearised "
        "through the JSBSim coupling\"\n",
        plant.jsbsim.aircraft.c_str(), num(plant.jsbsim.mach).c_str(),
        num(plant.jsbsim.altitude_ft).c_str());
    std::printf("  engine: jsbsim\n");
    std::printf("  jsbsim: {aircraft: %s, mach: %.17g, altitude_ft: %.17g%s}\n",
                plant.jsbsim.aircraft.c_str(), plant.jsbsim.mach, plant.jsbsim.altitude_ft,
                jsbsimKeys(plant.jsbsim).c_str());
    std::printf("  operating_point: {U: %.17g}\n", tr.airspeed);
    // An ordinary JSBSim aircraft's elevator, from its flight control system.
    const JsbsimElevator& el = jsb.overlay().elevator();
    if (jsb.overlay().generated() && el.limitsKnown())
      std::printf(
          "  actuator: {enabled: true, max_deflection: %.17g, max_rate: %.17g}  # the "
          "aircraft's elevator: travel %.4g to %.4g rad, rate %.4g rad/s (%s)\n",
          el.symmetricTravel(), el.max_rate, el.min_rad, el.max_rad, el.max_rate,
          el.writer.c_str());
    std::printf(
        "  A: [[%.17g, %.17g, %.17g],\n      [%.17g, %.17g, %.17g],\n"
        "      [%.17g, %.17g, %.17g]]\n",
        A(0, 0), A(0, 1), A(0, 2), A(1, 0), A(1, 1), A(1, 2), A(2, 0), A(2, 1), A(2, 2));
    std::printf("  B: [%.17g, %.17g, %.17g]\n", B[0], B[1], B[2]);
    std::printf("  B1r: [%.17g, %.17g, %.17g]\n", lm.B1r[0], lm.B1r[1], lm.B1r[2]);
    std::printf("  x0: [0.0, 0.0, 0.0]\n  output_index: 1\n");
    return 0;
  });
}
