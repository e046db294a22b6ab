#pragma once
/// \file node_context.hpp
/// \brief What a node class needs to know about the shape it runs in: its own process
/// (`*_node` executables) or a nodelet in a shared manager (src/ros/nodelets.cpp). The node
/// classes take one of these and never ask ros::this_node or call ros::shutdown themselves,
/// so both shapes share one code path.

#include <ros/ros.h>

#include <atomic>
#include <memory>
#include <string>
#include <vector>

#include "preadaptive_mrac/core/schema/params.hpp"
#include "preadaptive_mrac/ros/inline_queue.hpp"
#include "preadaptive_mrac/ros/node_params.hpp"
#include "preadaptive_mrac/ros/publisher_guard.hpp"
#include "preadaptive_mrac/ros/ros_params.hpp"

namespace preadaptive_mrac {
namespace ros1 {

/// \brief Node handles, name and end-of-run behaviour of one node (process or nodelet).
class NodeContext {
 public:
  /// \brief Process shape, after ros::init(): the global and private node handles of this
  /// process's node; end() records the exit code and shuts the process's node down.
  /// queue: the node's callbacks go there (node handles' queue) instead of the global one.
  static NodeContext forProcess(ros::CallbackQueueInterface* queue = nullptr);
  /// \brief Nodelet shape: the nodelet's node handles (getNodeHandle(), getPrivateNodeHandle())
  /// and name. required: end() ends the manager process with the code (the nodelet stands for
  /// a required node); otherwise the nodelet just stops and stays loaded.
  static NodeContext forNodelet(const ros::NodeHandle& nh, const ros::NodeHandle& pnh,
                                const std::string& name, bool required);

  /// \brief Topics, relative to the node's namespace.
  ros::NodeHandle nh() const { return nh_; }
  /// \brief The private namespace (`~`): parameters, ~progress.
  ros::NodeHandle pnh() const { return pnh_; }
  /// \brief Fully resolved node (or nodelet) name, e.g. "/pa/plant_sim".
  const std::string& name() const { return name_; }
  bool isNodelet() const { return nodelet_; }

  /// \brief The node's run is over with `code` (what its main() would return: 0, or
  /// kExitConfigError, kExitRuntimeError). Process: requestProcessExit(code). Nodelet: the
  /// same when required, else this nodelet alone stops (ok() turns false). Thread-safe.
  void end(int code) const;
  /// \brief The nodelet is being unloaded: ok() turns false (loops and waits return).
  void stop() const { stopped_->store(true); }
  /// \brief Keep running: ros::ok() and neither end() nor stop() was called.
  bool ok() const { return ros::ok() && !stopped_->load(); }

  /// \brief The whole private namespace as a ParamValue map (empty map when there is none).
  ParamValue privateParams() const;
  /// \brief Key style naming fully resolved private parameters: "<name>/controller/lqr/R".
  KeyStyle keyStyle() const;
  /// \brief ROS_FATAL one line per problem, after a summary line naming the node.
  void logConfigProblems(const std::vector<std::string>& problems) const;
  /// \brief One line to stdout (flushed), readable after ros::shutdown() when rosconsole no
  /// longer prints: final summaries (weights saved, bag closed).
  void printFinal(const std::string& line, bool error = false) const;

 private:
  NodeContext() = default;
  ros::NodeHandle nh_, pnh_;
  std::string name_;
  bool nodelet_ = false, required_ = true;
  std::shared_ptr<std::atomic<bool>> stopped_ = std::make_shared<std::atomic<bool>>(false);
};

/// \brief The node's guard for ~accept_from (`names` as read by the parameter reader): each
/// name resolved in the node's namespace (ctx.nh(): a nodelet's own, not its manager's) and
/// through the node's remappings, the warnings logged with ROS_WARN.
PublisherGuard makePublisherGuard(const NodeContext& ctx, const std::vector<std::string>& names);

/// \brief End this process with `code`: the first non-zero code requested wins (a refusal is
/// not overwritten by a clean end of another node), then ros::requestShutdown(). main()
/// (a `*_node` executable or pmrac_manager) returns processExitCode().
/// A normal end (code 0) of a process that roslaunch started (not rostest, not a remote
/// `--child`) ends the launch instead, as Ctrl-C does: SIGINT to roslaunch, which then stops
/// every node in order (the nodelet loaders unload from a manager that is still there) and
/// this process with them. Exiting made roslaunch print a required node's normal end as
/// "REQUIRED process [...] has died!" and the loaders warn that the manager was gone.
void requestProcessExit(int code);
/// \brief The code requested by requestProcessExit (0 when none).
int processExitCode();
/// \brief Whether requestProcessExit has been called.
bool processExitRequested();
/// \brief pmrac_manager: requestProcessExit only records the code, and main() unloads every
/// nodelet while ROS is still up before it shuts ROS down. A nodelet's bond says goodbye on its
/// topic when destroyed; after ros::shutdown() that publisher is invalid and roscpp's assertion
/// stops the manager with SIGTRAP (seen in 6 of 8 refused compare.launch runs, exit code -5).
void deferProcessShutdown();

/// \brief Read and validate a node's parameters with `read(tree, style)` (which throws
/// ConfigError listing every problem). On refusal log each problem (ROS_FATAL, naming its
/// key), end the node with kExitConfigError and return false.
template <class Params, class Reader>
bool readNodeParams(const NodeContext& ctx, Reader read, Params* out) {
  try {
    *out = read(ctx.privateParams(), ctx.keyStyle());
    // One start-up line naming every optional key filled with its default.
    ROS_INFO("%s", defaultsLine(out->defaults_used).c_str());
    return true;
  } catch (const ConfigError& e) {
    ctx.logConfigProblems(e.problems());
  }
  ctx.end(kExitConfigError);
  return false;
}

/// \brief main() (after ros::init()) of a node whose callbacks do all the work: build it with
/// `make` (nullptr when it refused to start), spin until its run ends or shutdown, then
/// finish() it (save, close, report). Returns the process's exit code. With `inline_messages`
/// its callbacks go to an InlineCallbackQueue: a message's callback runs in roscpp's receiving
/// thread, without waking this one (the controller: docs/reference/ros.md, "Threads").
template <class Node>
int spinProcessNode(std::unique_ptr<Node> (*make)(const NodeContext&),
                    bool inline_messages = false) {
  InlineCallbackQueue queue;
  const NodeContext ctx = NodeContext::forProcess(inline_messages ? &queue : nullptr);
  std::unique_ptr<Node> node = make(ctx);
  if (node) {
    if (inline_messages) {
      while (ros::ok()) {
        queue.callAvailable(ros::WallDuration(0.01));
        ros::getGlobalCallbackQueue()->callAvailable();
      }
    } else {
      ros::spin();
    }
    node->finish();
  }
  return processExitCode();
}

}  // namespace ros1
}  // namespace preadaptive_mrac
