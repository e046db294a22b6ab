#include "preadaptive_mrac/io/setup.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <sstream>

#include "preadaptive_mrac/io/yaml_params.hpp"

namespace preadaptive_mrac {

std::string configDir() {
  if (const char* env = std::getenv("PREADAPTIVE_MRAC_CONFIG_DIR")) return env;
#ifdef PREADAPTIVE_MRAC_CONFIG_DIR
  return PREADAPTIVE_MRAC_CONFIG_DIR;
#else
  return "config";
#endif
}

std::string scenarioPath(const std::string& arg) {
  if (arg == "1" || arg == "2" || arg == "3")
    return configDir() + "/scenarios/scenario" + arg + ".yaml";
  return arg;
}

std::string defaultPlantPath() { return configDir() + "/plant/b747.yaml"; }
std::string defaultControllerPath() { return configDir() + "/controller/default.yaml"; }

namespace {
// Which keys a design failure is about, so the message names what to fix.
std::string keysForCause(const std::string& cause) {
  if (cause == "not_stabilizable") return "plant.A";
  if (cause == "q_not_psd" || cause == "q_not_symmetric" || cause == "hamiltonian_imaginary_axis")
    return "controller.lqr.Q";
  if (cause == "r_not_positive") return "controller.lqr.R";
  return "plant.A";
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
    r.rejectUnusedUnder("controller");
  }
  if (sections.scenario) {
    rc.scenario = Scenario::read(r, n > 0 ? n : 1, "scenario");
    r.rejectUnusedUnder("scenario");
  }
  if (sections.strict_top_level && tree.type() == ParamValue::Type::kMap) {
    for (const auto& kv : tree.map()) {
      const bool known = (kv.first == "plant" && sections.plant) ||
                         (kv.first == "controller" && sections.controller) ||
                         (kv.first == "scenario" && sections.scenario);
      if (!known) r.fail(kv.first, "unknown key (expected plant, controller or scenario)");
    }
  }
  if (sections.plant && sections.controller && r.ok()) {
    try {
      (void)designController(rc.plant.A, rc.plant.B, rc.controller.Q, rc.controller.R);
    } catch (const SolverError& e) {
      r.fail(keysForCause(e.cause()), std::string(e.what()) + " [" + e.cause() + "]");
    }
  }
  r.throwIfProblems();
  return rc;
}

namespace {

class Json {
 public:
  std::string str() const { return os_.str(); }
  Json& raw(const std::string& s) {
    os_ << s;
    return *this;
  }
  Json& num(double v) {
    if (!std::isfinite(v)) {
      os_ << "null";
    } else {
      char buf[40];
      std::snprintf(buf, sizeof(buf), "%.17g", v);
      os_ << buf;
    }
    return *this;
  }
  Json& str(const std::string& s) {
    os_ << '"';
    for (char c : s) {
      switch (c) {
        case '"':
          os_ << "\\\"";
          break;
        case '\\':
          os_ << "\\\\";
          break;
        case '\n':
          os_ << "\\n";
          break;
        case '\t':
          os_ << "\\t";
          break;
        default:
          if (static_cast<unsigned char>(c) < 0x20) {
            char buf[8];
            std::snprintf(buf, sizeof(buf), "\\u%04x", c);
            os_ << buf;
          } else {
            os_ << c;
          }
      }
    }
    os_ << '"';
    return *this;
  }
  template <typename V>
  Json& vec(const V& v) {
    os_ << '[';
    for (Eigen::Index i = 0; i < v.size(); ++i) {
      if (i) os_ << ',';
      num(v[i]);
    }
    os_ << ']';
    return *this;
  }
  Json& key(const std::string& k) {
    str(k);
    os_ << ':';
    return *this;
  }

 private:
  std::ostringstream os_;
};

}  // namespace

std::string runSummaryJson(const RunInfo& info, const Controller& ctl, const SimResult& res) {
  Json j;
  const auto& d = ctl.design();
  j.raw("{").key("scenario").str(info.scenario);
  j.raw(",").key("mode").str(info.mode);
  j.raw(",").key("seed").num(static_cast<double>(info.seed));
  j.raw(",").key("dt").num(info.dt);
  j.raw(",").key("overrides").raw("[");
  for (size_t i = 0; i < info.overrides.size(); ++i) {
    if (i) j.raw(",");
    j.str(info.overrides[i]);
  }
  j.raw("]");
  j.raw(",").key("K").vec(d.K);
  j.raw(",").key("P").raw("[");
  for (int i = 0; i < d.P.rows(); ++i) {
    if (i) j.raw(",");
    j.vec(d.P.row(i));
  }
  j.raw("]");
  j.raw(",").key("care_residual").num(d.care_residual);
  j.raw(",").key("lyapunov_residual").num(d.lyapunov_residual);
  j.raw(",").key("steps").num(static_cast<double>(res.steps));
  j.raw(",").key("events").raw("[");
  for (size_t i = 0; i < res.events.size(); ++i) {
    const Event& e = res.events[i];
    if (i) j.raw(",");
    j.raw("{").key("type").str(eventTypeName(e.type));
    j.raw(",").key("t").num(e.t);
    j.raw(",").key("e").num(e.e);
    j.raw(",").key("e_dot").num(e.e_dot);
    j.raw(",").key("theta_hat_before").vec(e.theta_hat_before);
    if (e.type == Event::Type::kOnset) {
      j.raw(",").key("reset").raw(e.reset ? "true" : "false");
      if (e.reset) j.raw(",").key("theta_hat_reset").vec(e.theta_hat_after);
    }
    if (e.decision != Event::Decision::kNone) {  // pa_robust: what verification chose
      j.raw(",").key("decision").str(decisionName(e.decision));
      j.raw(",").key("chosen").num(e.chosen);
      j.raw(",").key("candidates").num(e.candidates);
      j.raw(",").key("score").num(e.score);
      j.raw(",").key("score_keep").num(e.score_keep);
      j.raw(",").key("theta_hat_after").vec(e.theta_hat_after);
    }
    if (e.type == Event::Type::kRecovered) {
      j.raw(",").key("cost").num(e.cost);
      j.raw(",").key("learned").raw(e.learned ? "true" : "false");
      if (e.learned) j.raw(",").key("grad").vec(e.grad);
    }
    j.raw(",").key("episodes").num(static_cast<double>(e.episodes));
    j.raw("}");
  }
  j.raw("]");
  j.raw(",").key("windows").raw("[");
  for (size_t i = 0; i < res.metrics.windows.size(); ++i) {
    const WindowMetrics& w = res.metrics.windows[i];
    if (i) j.raw(",");
    j.raw("{").key("t_start").num(w.t_start);
    j.raw(",").key("t_end").num(w.t_end);
    j.raw(",").key("theta").vec(w.theta);
    j.raw(",").key("peak_abs_e").num(w.peak_abs_e);
    j.raw(",").key("iae").num(w.iae);
    j.raw(",").key("recovery_time");
    if (w.recovery_time >= 0.0)
      j.num(w.recovery_time);
    else
      j.raw("null");
    j.raw(",").key("onsets").num(w.onsets);
    j.raw(",").key("recoveries").num(w.recoveries);
    j.raw("}");
  }
  j.raw("]");
  j.raw(",").key("iae").num(res.metrics.iae);
  j.raw(",").key("peak_abs_e").num(res.metrics.peak_abs_e);
  j.raw(",").key("max_abs_u").num(res.metrics.max_abs_u);
  j.raw(",").key("episodes").num(static_cast<double>(ctl.network().state().episodes));
  j.raw(",").key("theta_hat_final").vec(ctl.thetaHat());
  j.raw(",").key("wall_time_s").num(info.wall_time_s);
  j.raw("}");
  return j.str();
}

std::string scenarioToYaml(const Scenario& sc) {
  auto num = [](double v) {
    char buf[40];
    std::snprintf(buf, sizeof(buf), "%.17g", v);
    return std::string(buf);
  };
  std::ostringstream os;
  os << "scenario:\n";
  os << "  name: " << Json().str(sc.name).str() << "\n";
  os << "  description: " << Json().str(sc.description).str() << "\n";
  os << "  theta:\n";
  for (const auto& seg : sc.theta) {
    os << "    - {until: " << num(seg.until) << ", theta: [";
    for (Eigen::Index i = 0; i < seg.theta.size(); ++i) os << (i ? ", " : "") << num(seg.theta[i]);
    os << "]}\n";
  }
  os << "  reference:\n";
  for (const auto& seg : sc.reference)
    os << "    - {until: " << num(seg.until) << ", r: " << num(seg.r) << "}\n";
  return os.str();
}

void writeSeriesCsv(const std::string& path, const Series& s) {
  std::unique_ptr<FILE, int (*)(FILE*)> f(std::fopen(path.c_str(), "w"), &std::fclose);
  if (!f) throw FileError(path + ": cannot write CSV");
  const int n = s.x.empty() ? 0 : static_cast<int>(s.x.front().size());
  std::string header = "t";
  for (int i = 0; i < n; ++i) header += ",x" + std::to_string(i);
  for (int i = 0; i < n; ++i) header += ",xr" + std::to_string(i);
  header += ",e,e_dot_est,u";
  for (int i = 0; i < n; ++i) header += ",theta_hat" + std::to_string(i);
  for (int i = 0; i < n; ++i) header += ",theta_true" + std::to_string(i);
  header += ",phase,u_baseline,u_adaptive,r,saturated\n";
  std::fputs(header.c_str(), f.get());
  for (size_t k = 0; k < s.t.size(); ++k) {
    std::fprintf(f.get(), "%.17g", s.t[k]);
    for (int i = 0; i < n; ++i) std::fprintf(f.get(), ",%.17g", s.x[k][i]);
    for (int i = 0; i < n; ++i) std::fprintf(f.get(), ",%.17g", s.x_r[k][i]);
    std::fprintf(f.get(), ",%.17g,%.17g,%.17g", s.e[k], s.e_dot[k], s.u[k]);
    for (int i = 0; i < n; ++i) std::fprintf(f.get(), ",%.17g", s.theta_hat[k][i]);
    for (int i = 0; i < n; ++i) std::fprintf(f.get(), ",%.17g", s.theta_true[k][i]);
    std::fprintf(f.get(), ",%d,%.17g,%.17g,%.17g,%d\n", s.phase[k], s.u_bl[k], s.u_ad[k], s.r[k],
                 s.saturated[k]);
  }
  if (std::ferror(f.get())) throw FileError(path + ": write error");
}

}  // namespace preadaptive_mrac
