#include "preadaptive_mrac/io/setup.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>

#include "preadaptive_mrac/core/control/attention_thresholds.hpp"
#include "preadaptive_mrac/core/controller/mode_registry.hpp"
#include "preadaptive_mrac/core/sim/plant_engine.hpp"
#include "preadaptive_mrac/io/yaml_params.hpp"

namespace preadaptive_mrac {

std::string configDir() {
  if (const char* env = std::getenv("PREADAPTIVE_MRAC_CONFIG_DIR")) return env;
  // Found from where the executable is, never from a path compiled in: the package may be used
  // from its devel space, an install space or a Debian package, with the source gone. A tool
  // sits in <prefix>/bin (the batch tools) or <prefix>/lib/preadaptive_mrac (nodes, tests;
  // rosrun's links resolve to bin), and the package's files in <prefix>/share/preadaptive_mrac
  // (in a devel space config/ there is a link to the source's, made by CMake).
  std::error_code ec;
  const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    for (const char* up : {"..", "../.."}) {
      const std::filesystem::path dir = exe.parent_path() / up / "share/preadaptive_mrac/config";
      if (std::filesystem::is_directory(dir, ec)) return dir.lexically_normal().string();
    }
  }
  return "config";  // neither: relative to the working directory (a source checkout)
}

std::string scenarioPath(const std::string& arg) {
  if (arg == "1" || arg == "2" || arg == "3")
    return configDir() + "/scenarios/scenario" + arg + ".yaml";
  return arg;
}

std::string defaultPlantPath() { return configDir() + "/plant/b747.yaml"; }
std::string defaultControllerPath() { return configDir() + "/controller/default.yaml"; }

namespace {
// Which keys a design failure is about, so the message names what to fix: the model the
// controller designs on is controller.model.A (and .B) when that is given, else the plant's.
std::string keysForCause(const std::string& cause, const DesignModelSection& model) {
  const std::string a = model.A.size() > 0   ? "controller.model.A"
                        : model.B.size() > 0 ? "controller.model.B"
                                             : "plant.A";
  if (cause == "not_stabilizable") return a;
  if (cause == "q_not_psd" || cause == "q_not_symmetric" || cause == "hamiltonian_imaginary_axis")
    return "controller.lqr.Q";
  if (cause == "r_not_positive") return "controller.lqr.R";
  return a;
}
}  // namespace

std::string runLengthProblem(double end_s, double dt) {
  if (!(dt > 0.0) || !(end_s > 0.0)) return {};  // refused elsewhere, by their own keys
  const double steps = std::ceil(end_s / dt);
  if (steps <= static_cast<double>(kMaxRunSteps)) return {};
  return "the scenario's " + formatNumber(end_s) + " s at " + formatNumber(dt) + " s a step is " +
         formatNumber(steps) + " steps, more than the " + std::to_string(kMaxRunSteps) +
         " a run may have (a larger step, or a shorter scenario)";
}

namespace {
// Every end of a segment of the scenario's schedules within kMaxRunSeconds, each named.
void checkDurations(ParamReader& r, const ParamValue& tree) {
  for (const char* schedule : {"theta", "reference", "effectiveness", "faults"}) {
    const std::string key = std::string("scenario.") + schedule;
    const ParamValue* list = tree.findPath(key);
    if (list == nullptr || list->type() != ParamValue::Type::kList) continue;
    for (size_t i = 0; i < list->list().size(); ++i) {
      const std::string until = key + "." + std::to_string(i) + ".until";
      const ParamValue* v = tree.findPath(until);
      if (v == nullptr || !v->isNumber() || !r.usable(until)) continue;
      if (v->asDouble() > kMaxRunSeconds)
        r.fail(until, "must be <= " + formatNumber(kMaxRunSeconds) + " s (the longest run), got " +
                          formatNumber(v->asDouble()));
    }
  }
}
}  // namespace

RunConfig readRunConfig(const ParamValue& tree, const KeyStyle& style, Sections sections) {
  ParamReader r(tree, style);
  RunConfig rc;
  int n = -1;
  if (sections.plant) {
    rc.plant = PlantConfig::read(r, "plant");
    if (rc.plant.A.rows() == rc.plant.A.cols() && rc.plant.A.rows() > 0) n = rc.plant.n();
    r.rejectUnusedUnder("plant");
  }
  if (sections.controller) {
    rc.controller = ControllerConfig::read(r, n, "controller");
    checkModeName(r, "controller.mode", rc.controller.mode);
    r.rejectUnusedUnder("controller");
  }
  if (sections.scenario) {
    rc.scenario = Scenario::read(r, std::max(n, 0), "scenario");
    r.rejectUnusedUnder("scenario");
    checkDurations(r, tree);
    if (sections.plant && !rc.scenario.faults.empty() &&
        !plantEngineRules(rc.plant.engine).physical_faults)
      r.fail("scenario.faults", std::string(kFaultsNeedAerodynamics) +
                                    ": the linear model has no CG or aerodynamics (use theta or "
                                    "scenario.effectiveness on it)");
  }
  if (sections.strict_top_level && tree.type() == ParamValue::Type::kMap) {
    for (const auto& kv : tree.map()) {
      const bool known = (kv.first == "plant" && sections.plant) ||
                         (kv.first == "controller" && sections.controller) ||
                         (kv.first == "scenario" && sections.scenario);
      if (!known) r.fail(kv.first, "unknown key (expected plant, controller or scenario)");
    }
  }
  if (sections.controller && sections.scenario && r.usable("controller.sample_time") && r.ok()) {
    const std::string why = runLengthProblem(rc.scenario.endTime(), rc.controller.sample_time);
    if (!why.empty()) r.fail("controller.sample_time", why);
  }
  if (sections.plant && sections.controller && r.ok()) {
    try {
      rc.design = Controller::designOf(designModelOf(rc.plant, rc.controller), rc.controller);
    } catch (const SolverError& e) {
      r.fail(keysForCause(e.cause(), rc.controller.model),
             std::string(e.what()) + " [" + e.cause() + "]");
    }
  }
  if (sections.controller && r.ok()) {
    const std::string why = deriveAttention(&rc);
    if (!why.empty()) r.fail("controller.attention.hysteresis", why);
  }
  r.throwIfProblems();
  rc.defaults_used = r.defaultsUsed();
  return rc;
}

std::string deriveAttention(RunConfig* rc) {
  ControllerConfig& c = rc->controller;
  rc->derived.clear();
  if (c.thresholds != AttentionThresholds::kDerived || !rc->design) return "";
  const DesignModel model = designModelOf(rc->plant, c);
  const int out = model.output_index;
  const double noise = rc->plant.noise.std.size() > out ? rc->plant.noise.std[out] : 0.0;
  const DerivedAttention d =
      deriveAttentionThresholds(rc->design->Ar, model.B, model.B1r + c.k0 * model.B, out, c.command,
                                std::abs(noise), c.sample_time);
  c.c_e = d.c_e;
  c.c_ed = d.c_ed;
  const auto num = [](double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.4g", v);
    return std::string(buf);
  };
  rc->derived.push_back("controller.attention.c_e = " + num(d.c_e) +
                        " rad (unit regime d = " + num(d.disturbance) + " rad, loop error peak " +
                        num(d.error_peak) + " rad, noise floor " + num(d.noise_floor) + " rad)");
  rc->derived.push_back("controller.attention.c_ed = " + num(d.c_ed) + " rad/s");
  if (!(c.hysteresis < c.c_e))
    return "must be below the derived c_e = " + num(c.c_e) + ", got " + formatNumber(c.hysteresis);
  return "";
}

namespace {
template <typename V>
nlohmann::ordered_json vec(const V& v) {
  auto a = nlohmann::ordered_json::array();
  for (Eigen::Index i = 0; i < v.size(); ++i) a.push_back(v[i]);
  return a;
}
}  // namespace

nlohmann::ordered_json envelopeExitJson(const EnvelopeExit& x) {
  using J = nlohmann::ordered_json;
  if (!x.exited) return J(nullptr);
  J j;
  j["t"] = x.t;
  j["step"] = x.step;
  j["bound"] = x.bound;
  j["key"] = x.key.empty() ? J(nullptr) : J("plant.envelope." + x.key);
  // JSON has no NaN or infinity: a number that is not finite is written as its text
  auto num = [](double v) { return std::isfinite(v) ? J(v) : J(formatNumber(v)); };
  j["value"] = num(x.value);
  j["limit"] = x.limit;
  J xs = J::array();
  for (Eigen::Index i = 0; i < x.x.size(); ++i) xs.push_back(num(x.x[i]));
  j["x"] = xs;
  j["u_command"] = num(x.u_command);
  J c;
  for (const PlantConditionColumn& col : kPlantConditionTable)
    if (x.rows.has(col)) c[col.name] = num(x.conditions.*col.field);
  j["conditions"] = c;
  j["non_finite"] = x.non_finite;
  j["non_finite_t"] = x.non_finite ? J(x.non_finite_t) : J(nullptr);
  j["text"] = x.describe();
  return j;
}

nlohmann::ordered_json runSummary(const RunInfo& info, const Controller& ctl,
                                  const SimResult& res) {
  using J = nlohmann::ordered_json;
  const auto& d = ctl.design();
  J j;
  j["scenario"] = info.scenario;
  j["mode"] = info.mode;
  j["seed"] = info.seed;
  j["dt"] = info.dt;
  j["overrides"] = info.overrides;
  j["K"] = vec(d.K);
  j["P"] = J::array();
  for (int i = 0; i < d.P.rows(); ++i) j["P"].push_back(vec(d.P.row(i)));
  j["care_residual"] = d.care_residual;
  j["lyapunov_residual"] = d.lyapunov_residual;
  j["steps"] = res.steps;
  j["events"] = J::array();
  for (const Event& e : res.events) {
    J o;
    o["type"] = eventTypeName(e.type);
    o["t"] = e.t;
    o["e"] = e.e;
    o["e_dot"] = e.e_dot;
    o["theta_hat_before"] = vec(e.theta_hat_before);
    if (e.type == Event::Type::kOnset) {
      o["reset"] = e.reset;
      if (e.reset) o["theta_hat_reset"] = vec(e.theta_hat_after);
    }
    if (e.decision != Event::Decision::kNone) {  // pa_robust: what verification chose
      o["decision"] = decisionName(e.decision);
      o["chosen"] = e.chosen;
      o["candidates"] = e.candidates;
      o["score"] = e.score;
      o["score_keep"] = e.score_keep;
      o["theta_hat_after"] = vec(e.theta_hat_after);
    }
    if (e.type == Event::Type::kRecovered) {
      o["cost"] = e.cost;
      o["learned"] = e.learned;
      if (e.learned) o["grad"] = vec(e.grad);
    }
    o["episodes"] = e.episodes;
    j["events"].push_back(std::move(o));
  }
  j["windows"] = J::array();
  for (const WindowMetrics& w : res.metrics.windows) {
    J o;
    o["t_start"] = w.t_start;
    o["t_end"] = w.t_end;
    o["theta"] = vec(w.theta);
    o["peak_abs_e"] = w.peak_abs_e;
    o["iae"] = w.iae;
    o["recovery_time"] = w.recovery_time >= 0.0 ? J(w.recovery_time) : J(nullptr);
    o["onsets"] = w.onsets;
    o["recoveries"] = w.recoveries;
    j["windows"].push_back(std::move(o));
  }
  j["iae"] = res.metrics.iae;
  j["peak_abs_e"] = res.metrics.peak_abs_e;
  j["max_abs_u"] = res.metrics.max_abs_u;
  j["envelope_exit"] = envelopeExitJson(res.envelope_exit);  // null: the run stayed inside
  j["episodes"] = ctl.network().state().episodes;
  j["theta_hat_final"] = vec(ctl.thetaHat());
  j["regimes"] = ctl.network().state().regimes.size();
  j["defaults"] = info.defaults_used;
  j["wall_time_s"] = info.wall_time_s;
  return j;
}

std::string runSummaryJson(const RunInfo& info, const Controller& ctl, const SimResult& res) {
  return runSummary(info, ctl, res).dump();
}

std::string scenarioToYaml(const Scenario& sc) {
  auto num = [](double v) {
    char buf[40];
    std::snprintf(buf, sizeof(buf), "%.17g", v);
    return std::string(buf);
  };
  std::ostringstream os;
  os << "scenario:\n";
  os << "  name: " << nlohmann::json(sc.name).dump() << "\n";
  os << "  description: " << nlohmann::json(sc.description).dump() << "\n";
  os << "  theta:\n";
  for (const auto& seg : sc.theta) {
    os << "    - {until: " << num(seg.until) << ", theta: [";
    for (Eigen::Index i = 0; i < seg.theta.size(); ++i) os << (i ? ", " : "") << num(seg.theta[i]);
    os << "]}\n";
  }
  os << "  reference:\n";
  for (const auto& seg : sc.reference)
    os << "    - {until: " << num(seg.until) << ", r: " << num(seg.r) << "}\n";
  if (!sc.effectiveness.empty()) {
    os << "  effectiveness:\n";
    for (const auto& seg : sc.effectiveness)
      os << "    - {until: " << num(seg.until) << ", value: " << num(seg.value) << "}\n";
  }
  if (!sc.faults.empty()) {
    os << "  faults:\n";
    for (const auto& seg : sc.faults) {
      os << "    - {until: " << num(seg.until);
      for (const auto& key : Scenario::kFaultKeys)
        os << ", " << key.name << ": " << num(seg.*key.field);
      os << "}\n";
    }
  }
  return os.str();
}

void writeSeriesCsv(const std::string& path, const Series& s) {
  std::unique_ptr<FILE, int (*)(FILE*)> f(std::fopen(path.c_str(), "w"), &std::fclose);
  if (!f) throw FileError(path + ": cannot write CSV");
  // Rows are formatted into one line buffer and written through a large stdio buffer: a run
  // of scenario 3 is 140 000 rows of 20 numbers. std::to_chars with a precision is specified
  // as printf's %.17g (and %d for the integers), so the bytes are the same.
  std::setvbuf(f.get(), nullptr, _IOFBF, 1 << 20);
  const int n = s.x.empty() ? 0 : static_cast<int>(s.x.front().size());
  std::string header = "t";
  for (int i = 0; i < n; ++i) header += ",x" + std::to_string(i);
  for (int i = 0; i < n; ++i) header += ",xr" + std::to_string(i);
  header += ",e,e_dot_est,u";
  for (int i = 0; i < n; ++i) header += ",theta_hat" + std::to_string(i);
  for (int i = 0; i < n; ++i) header += ",theta_true" + std::to_string(i);
  header += ",phase,u_baseline,u_adaptive,r,saturated";
  // Columns of the plant's conditions only when a run has them (Series::conditions, the rows
  // of Series::condition_rows): a run of the ideal plant writes the paper's columns alone, a
  // run of the linear plant never has the engine's rows.
  std::vector<const PlantConditionColumn*> cols;
  if (!s.conditions.empty())
    for (const PlantConditionColumn& c : kPlantConditionTable)
      if (s.condition_rows.has(c)) cols.push_back(&c);
  for (const PlantConditionColumn* c : cols) header += std::string(",") + c->name;
  header += '\n';
  std::fputs(header.c_str(), f.get());
  std::string line;
  char buf[64];
  auto num = [&](double v) {
    const auto r = std::to_chars(buf, buf + sizeof(buf), v, std::chars_format::general, 17);
    line.append(buf, r.ptr);
  };
  auto integer = [&](int v) {
    const auto r = std::to_chars(buf, buf + sizeof(buf), v);
    line.append(buf, r.ptr);
  };
  auto vec = [&](const Vec& v) {
    for (int i = 0; i < n; ++i) {
      line += ',';
      num(v[i]);
    }
  };
  for (size_t k = 0; k < s.t.size(); ++k) {
    line.clear();
    num(s.t[k]);
    vec(s.x[k]);
    vec(s.x_r[k]);
    for (double v : {s.e[k], s.e_dot[k], s.u[k]}) {
      line += ',';
      num(v);
    }
    vec(s.theta_hat[k]);
    vec(s.theta_true[k]);
    line += ',';
    integer(s.phase[k]);
    for (double v : {s.u_bl[k], s.u_ad[k], s.r[k]}) {
      line += ',';
      num(v);
    }
    line += ',';
    integer(s.saturated[k]);
    for (const PlantConditionColumn* c : cols) {
      const double v = s.conditions[k].*c->field;
      line += ',';
      if (c->isFlag())
        integer(v != 0.0 ? 1 : 0);
      else
        num(v);
    }
    line += '\n';
    std::fwrite(line.data(), 1, line.size(), f.get());
  }
  if (std::ferror(f.get())) throw FileError(path + ": write error");
}

}  // namespace preadaptive_mrac
