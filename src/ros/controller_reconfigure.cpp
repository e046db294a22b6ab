#include "preadaptive_mrac/ros/controller_reconfigure.hpp"

#include <cmath>

#include "preadaptive_mrac/core/controller/tunables.hpp"

namespace preadaptive_mrac {
namespace ros1 {

// The copies are generated from the tables' tunable rows (params/*.yaml, forEachTunable's
// neighbours in preadaptive_mrac/params/controller_params.hpp): the reconfigure names are theirs.
ControllerTunables fromReconfigure(const ControllerTuningConfig& c) {
  ControllerTunables t;
  tunablesFromReconfigure(c, &t);
  return t;
}

void toReconfigure(const ControllerTunables& t, ControllerTuningConfig* c) {
  tunablesToReconfigure(t, c);
}

bool recoverNonFinite(Controller* ctl, const Vec& x, StepOutput* out) {
  const bool finite = std::isfinite(out->u) && std::isfinite(out->u_unsaturated) &&
                      (out->theta_hat.size() == 0 || out->theta_hat.allFinite());
  if (finite) return false;
  ctl->reset();
  StepOutput base;
  base.e = std::isfinite(out->e) ? out->e : 0.0;
  base.e_dot = std::isfinite(out->e_dot) ? out->e_dot : 0.0;
  base.u = ctl->safeCommand(x, StalePolicy::kBaselineHold);
  base.u_baseline = base.u_unsaturated = base.u;
  base.x_ref = Vec::Zero(x.size());  // the reference model restarts at the plant's trim
  base.theta_hat = ctl->thetaHat();
  base.tunables_applied = out->tunables_applied;
  *out = base;
  return true;
}

bool ControllerReconfigure::recover(StepOutput* out, const Vec& x, std::uint64_t step, double t) {
  if (!recoverNonFinite(ctl_, x, out)) return false;
  if (non_finite_resets_++ == 0)
    ROS_ERROR(
        "step %llu (t = %.3f s): the controller's command or estimate is not finite (an "
        "adaptation that diverged); reset to its start and answered with the baseline -K x "
        "(said once; the diagnostics count every such reset)",
        static_cast<unsigned long long>(step), t);
  return true;
}

ControllerReconfigure::ControllerReconfigure(const ros::NodeHandle& nh,
                                             const ros::NodeHandle& server_nh,
                                             Controller* controller, const KeyStyle& style)
    : ctl_(controller), style_(style) {
  in_effect_ = accepted_ = ctl_->tunables();
  ros::NodeHandle pub_nh(nh);
  change_pub_ = pub_nh.advertise<ParamChange>("controller/param_change", 100);
  server_ = std::make_unique<dynamic_reconfigure::Server<ControllerTuningConfig>>(server_mutex_,
                                                                                  server_nh);
  // The server starts from the cfg's defaults (or values left on the parameter server by an
  // earlier run); show the YAML's values instead, before the first callback.
  ControllerTuningConfig initial;
  toReconfigure(in_effect_, &initial);
  server_->updateConfig(initial);
  server_->setCallback([this](ControllerTuningConfig& c, uint32_t level) { callback(c, level); });
}

void ControllerReconfigure::callback(ControllerTuningConfig& config, uint32_t level) {
  (void)level;
  const ControllerTunables requested = fromReconfigure(config);
  const auto changes = diffTunables(accepted_, requested);
  config.refusal = "";  // only a refusal of this request is shown
  if (changes.empty()) return;
  std::vector<std::string> problems = validateTunables(ctl_->config(), requested, style_);
  if (problems.empty()) {
    try {
      ctl_->setTunables(requested);
    } catch (const std::exception& e) {  // the same validation: not expected
      problems.push_back(e.what());
    }
  }
  if (!problems.empty()) {
    refuse(problems, &config);
    return;
  }
  accepted_ = requested;
  last_refusal_.clear();
  for (const auto& c : changes)
    ROS_INFO("reconfigure: %s %s -> %s (from the next step)",
             (style_.root + "controller" + style_.separator + c.key).c_str(),
             formatNumber(c.old_value).c_str(), formatNumber(c.new_value).c_str());
}

void ControllerReconfigure::refuse(const std::vector<std::string>& problems,
                                   ControllerTuningConfig* config) {
  ++refused_;
  // Where the user asked: the answer (dynparam get, rqt_reconfigure, the client's return
  // value) carries the old values and the problems; the console and the diagnostics too.
  last_refusal_.clear();
  for (const auto& p : problems) last_refusal_ += (last_refusal_.empty() ? "" : "; ") + p;
  ROS_ERROR("reconfigure refused, %zu problem(s); keeping the values in force:", problems.size());
  for (const auto& p : problems) ROS_ERROR("  %s", p.c_str());
  toReconfigure(accepted_, config);
  config->refusal = "refused, values kept: " + last_refusal_;
}

void ControllerReconfigure::afterStep(const StepOutput& out, std::uint64_t step, double t,
                                      const ros::Time& stamp) {
  if (!out.tunables_applied) return;
  const ControllerTunables now = ctl_->tunables();
  for (const auto& c : diffTunables(in_effect_, now)) {
    ParamChange m;
    m.header.stamp = stamp;
    m.step = step;
    m.t = t;
    m.name = "controller." + c.key;
    m.old_value = c.old_value;
    m.new_value = c.new_value;
    change_pub_.publish(m);
    ++applied_;
    ROS_INFO("step %llu (t = %.3f s): %s = %s (was %s)", static_cast<unsigned long long>(step), t,
             m.name.c_str(), formatNumber(c.new_value).c_str(), formatNumber(c.old_value).c_str());
  }
  in_effect_ = now;
}

}  // namespace ros1
}  // namespace preadaptive_mrac
