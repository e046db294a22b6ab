#pragma once
/// \file controller_reconfigure.hpp
/// \brief dynamic_reconfigure of the controller's tunables (cfg/ControllerTuning.cfg) and the
/// controller/param_change record of every change applied.

#include <dynamic_reconfigure/server.h>
#include <ros/ros.h>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "preadaptive_mrac/ControllerTuningConfig.h"
#include "preadaptive_mrac/ParamChange.h"
#include "preadaptive_mrac/core/controller/controller.hpp"
#include "preadaptive_mrac/core/schema/params.hpp"

namespace preadaptive_mrac {
namespace ros1 {

/// \brief The tunables a reconfigure request asks for.
ControllerTunables fromReconfigure(const ControllerTuningConfig& c);
/// \brief The reconfigure values showing `t`.
void toReconfigure(const ControllerTunables& t, ControllerTuningConfig* c);

/// \brief When a step's command or estimate is not finite (an adaptation that diverged: theta_hat
/// overflowed), reset the controller to its start (theta_hat0, the attention idle, the reference
/// model at x0) and answer the step with the baseline -K x within the elevator's limits, so no NaN
/// is ever commanded. Returns true when it did; `out` is then the baseline's step.
bool recoverNonFinite(Controller* ctl, const Vec& x, StepOutput* out);

/// \brief Serves dynamic_reconfigure for a Controller and records the changes it applies.
///
/// A request is checked with the core's validation (validateTunables: the YAML's rules, keys
/// named in `style`); a refused request is logged (ERROR, one line per problem) and answered
/// with the values in force and `refusal` naming each problem, so the client sees the old
/// values kept and why (the .cfg has no min/max: the server would clamp what was asked). An
/// accepted one is queued in the Controller (Controller::setTunables), which applies it at the
/// start of its next step; afterStep() then publishes one ParamChange per changed key on
/// `controller/param_change`, stamped with that step. Callbacks must be serialised with the
/// controller's steps (one callback queue, one spinner thread), as in mrac_controller_node.
class ControllerReconfigure {
 public:
  /// \param nh namespace of controller/param_change (the node's)
  /// \param server_nh namespace of the server (`~reconfigure`)
  ControllerReconfigure(const ros::NodeHandle& nh, const ros::NodeHandle& server_nh,
                        Controller* controller, const KeyStyle& style);

  /// \brief After each controller step: when `out` says queued tunables took effect, publish
  /// each changed key stamped with the state's step, t and stamp.
  void afterStep(const StepOutput& out, std::uint64_t step, double t, const ros::Time& stamp);

  /// \brief recoverNonFinite() on the node's controller, said once (an ERROR naming the step),
  /// then counted: nonFiniteResets(), in the diagnostics.
  bool recover(StepOutput* out, const Vec& x, std::uint64_t step, double t);
  std::int64_t nonFiniteResets() const { return non_finite_resets_; }

  /// \brief Requests refused so far.
  std::int64_t refused() const { return refused_; }
  /// \brief The problems of the last request when it was refused, '' after an accepted one.
  const std::string& lastRefusal() const { return last_refusal_; }
  /// \brief Changes applied so far (keys).
  std::int64_t applied() const { return applied_; }

 private:
  void callback(ControllerTuningConfig& config, uint32_t level);
  /// \brief Count, log and answer a refused request with the values in force and `refusal`.
  void refuse(const std::vector<std::string>& problems, ControllerTuningConfig* config);

  Controller* ctl_;
  KeyStyle style_;
  ros::Publisher change_pub_;
  ControllerTunables in_effect_;  ///< what the controller runs with
  ControllerTunables accepted_;   ///< the last accepted request (queued or in effect)
  std::int64_t refused_ = 0, applied_ = 0, non_finite_resets_ = 0;
  std::string last_refusal_;
  boost::recursive_mutex server_mutex_;
  std::unique_ptr<dynamic_reconfigure::Server<ControllerTuningConfig>> server_;
};

}  // namespace ros1
}  // namespace preadaptive_mrac
