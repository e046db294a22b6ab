/// \file nodelets.cpp
/// \brief The four node classes as nodelets (nodelet_plugins.xml), for one manager process:
/// messages between them pass as pointers, without serialisation, copy or socket. Each
/// nodelet only builds the same class its `*_node` executable builds, from the nodelet's node
/// handles (NodeContext::forNodelet); nothing else knows which shape it runs in.
///
/// Loader arguments (`nodelet load preadaptive_mrac/PlantSim MANAGER [--required]`):
/// `--required` makes the nodelet stand for a required node: when its run ends (a refused
/// parameter, a timeout, the plant's last step) the manager process ends with the node's exit
/// code (pmrac_manager returns it), which ends a launch that requires the manager.

#include <nodelet/nodelet.h>
#include <pthread.h>
#include <ros/callback_queue.h>
#include <ros/master.h>
#include <ros/network.h>
#include <xmlrpcpp/XmlRpcClient.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <memory>
#include <optional>
#include <pluginlib/class_list_macros.hpp>
#include <string>
#include <thread>
#include <vector>

#include "preadaptive_mrac/ros/bag_recorder.hpp"
#include "preadaptive_mrac/ros/inline_queue.hpp"
#include "preadaptive_mrac/ros/mrac_controller_node.hpp"
#include "preadaptive_mrac/ros/node_context.hpp"
#include "preadaptive_mrac/ros/plant_sim_node.hpp"
#include "preadaptive_mrac/ros/run_monitor.hpp"

namespace preadaptive_mrac {
namespace ros1 {
namespace {

/// \brief The XML-RPC URI of node `name` from the master ("" when it is not registered).
std::string lookupNode(const std::string& name) {
  XmlRpc::XmlRpcValue args, result, payload;
  args[0] = ros::this_node::getName();
  args[1] = name;
  if (!ros::master::execute("lookupNode", args, result, payload, false)) return "";
  return payload.getType() == XmlRpc::XmlRpcValue::TypeString ? static_cast<std::string>(payload)
                                                              : std::string();
}

/// \brief Whether the node at `uri` answers getPid (what `rosnode ping` asks). A killed node's
/// port refuses the connection at once.
bool nodeAnswers(const std::string& uri) {
  std::string host;
  uint32_t port = 0;
  if (!ros::network::splitURI(uri, host, port)) return true;  // cannot ask: take it as alive
  XmlRpc::XmlRpcClient client(host.c_str(), static_cast<int>(port), "/");
  XmlRpc::XmlRpcValue args, result;
  args[0] = ros::this_node::getName();
  const bool ok = client.execute("getPid", args, result) && !client.isFault();
  client.close();
  return ok;
}

/// \brief Watch the loader of a required nodelet (`nodelet load TYPE MANAGER --required`, a
/// process of its own with the nodelet's name) from a detached thread, twice a second: when it
/// stops answering three times in a row, end the run (kExitRuntimeError), as its unload would.
/// The manager's bond does not always do it: a loader SIGKILLed in the first seconds of a run left
/// the plant flying to its end. The thread holds copies only, so it may outlive the nodelet.
void watchLoader(NodeContext ctx) {
  std::thread([ctx] {
    std::string uri;
    int failures = 0;
    while (ctx.ok()) {
      std::this_thread::sleep_for(std::chrono::milliseconds(500));
      if (!ctx.ok()) break;
      if (uri.empty()) {
        uri = lookupNode(ctx.name());
        continue;
      }
      failures = nodeAnswers(uri) ? 0 : failures + 1;
      if (failures >= 3 && ctx.ok()) {
        ROS_ERROR(
            "%s: its loader has gone (node %s no longer answers at %s) before the run ended: "
            "the run ends here (exit code %d)",
            ctx.name().c_str(), ctx.name().c_str(), uri.c_str(), kExitRuntimeError);
        ctx.end(kExitRuntimeError);
        break;
      }
    }
  }).detach();
}

}  // namespace

/// \brief Base of the package's nodelets: the context of the node class it wraps.
class ContextNodelet : public nodelet::Nodelet {
 protected:
  /// \brief The loader's arguments hold `--required`.
  bool isRequired() const {
    const std::vector<std::string>& argv = getMyArgv();
    return std::find(argv.begin(), argv.end(), "--required") != argv.end();
  }

  /// \brief The nodelet's node handles and name; required when the loader's arguments hold
  /// `--required`.
  /// queue: serve the node's callbacks from this queue (a thread of the nodelet's own) instead
  /// of the nodelet's single-threaded queue (the manager's worker threads).
  NodeContext makeContext(ros::CallbackQueueInterface* queue = nullptr) {
    const bool required = isRequired();
    ros::NodeHandle nh = getNodeHandle(), pnh = getPrivateNodeHandle();
    if (queue) {
      nh.setCallbackQueue(queue);
      pnh.setCallbackQueue(queue);
    }
    return NodeContext::forNodelet(nh, pnh, getName(), required);
  }

  /// \brief Name the calling thread after the nodelet (the last 15 characters of its name:
  /// what top -H, perf and gdb show).
  void nameThisThread() const {
    const std::string& n = getName();
    pthread_setname_np(pthread_self(), n.substr(n.size() > 15 ? n.size() - 15 : 0).c_str());
  }
};

/// \brief PlantSimNode: its loop (lockstep or realtime) runs in a thread of its own and serves
/// the plant's own callback queue; onInit() returns at once.
class PlantSimNodelet : public ContextNodelet {
 public:
  ~PlantSimNodelet() override {
    unloading_ = true;
    if (ctx_) ctx_->stop();
    if (thread_.joinable()) thread_.join();
    // Unloaded mid-run while the manager goes on: its loader was killed (the bond broke) or
    // unloaded it. The run is over, so a required plant ends the manager as its own end does:
    // the launch ends and the recorder closes its bag as incomplete (else the controller would
    // go on sending stale commands to no plant, and the recorder writing them, without end).
    if (node_ && !run_over_ && !node_->report().completed && ros::ok() && !ros::isShuttingDown()) {
      ROS_ERROR(
          "%s: unloaded before its run ended (its loader has gone): the run ends here "
          "(exit code %d)",
          ctx_->name().c_str(), kExitRuntimeError);
      ctx_->end(kExitRuntimeError);
    }
  }

 private:
  void onInit() override {
    ctx_ = makeContext();
    PlantNodeParams params;
    if (!readNodeParams(*ctx_, readPlantNodeParams, &params)) return;
    node_ = makePlantSimNode(*ctx_, params);
    if (!node_) return;
    if (isRequired()) watchLoader(*ctx_);
    thread_ = std::thread([this] {
      nameThisThread();
      const int code = node_->run();
      if (!unloading_) {
        run_over_ = true;
        ctx_->end(code);
      }
    });
  }

  std::optional<NodeContext> ctx_;
  std::unique_ptr<PlantSimNode> node_;
  std::thread thread_;
  std::atomic<bool> unloading_{false};
  std::atomic<bool> run_over_{false};  ///< run() returned by itself (not for an unload)
};

/// \brief A node class whose callbacks do all the work (controller, recorder, run monitor):
/// built by `kMake` in onInit() from the nodelet's context, finish()ed on unload (the
/// controller saves its weights, the recorder closes its bag). Every callback of it (messages,
/// timers, reconfigure) goes to a queue of its own, served by a thread of its own, one at a time
/// as in a single-threaded process. Not the nodelet's single-threaded queue: the manager hands
/// each callback of that to a worker through its own manager thread, two thread wake-ups per
/// message, and the recorder takes four to five messages per lockstep step (docs/reference/ros.md).
/// Here a message is one push onto the queue, and a thread that is behind takes its backlog in one
/// go. The controller's queue (Queue = InlineCallbackQueue) runs a message's callback in the
/// publisher's thread when it is free: the lockstep round trip is the plant's loop alone, with
/// no thread wake-up; its thread serves only timers, services and a backlog.
/// kPollUs > 0: the thread does not wait on its queue (woken by every message pushed) but takes
/// what has come every kPollUs microseconds (the recorder: a message costs it 0.5 us to write,
/// far less than its wake-up, and nothing needs its answer within a millisecond).
template <class Node, std::unique_ptr<Node> (*kMake)(const NodeContext&),
          class Queue = ros::CallbackQueue, int kPollUs = 0>
class CallbackNodelet : public ContextNodelet {
 public:
  ~CallbackNodelet() override {
    if (ctx_) ctx_->stop();
    if (thread_.joinable()) thread_.join();
    // A polling thread leaves what came since its last poll: taken now, so that the recorder
    // closes its bag with every message it received (Ctrl-C, a plant that ended early).
    if (kPollUs > 0 && node_) queue_.callAvailable(ros::WallDuration());
    if (node_) node_->finish();
  }

 private:
  void onInit() override {
    ctx_ = makeContext(&queue_);
    node_ = kMake(*ctx_);
    if (!node_) return;
    thread_ = std::thread([this] {
      nameThisThread();
      if (kPollUs > 0) {
        while (ctx_->ok()) {
          queue_.callAvailable(ros::WallDuration());
          std::this_thread::sleep_for(std::chrono::microseconds(kPollUs));
        }
      } else {
        while (ctx_->ok()) queue_.callAvailable(ros::WallDuration(0.01));
      }
    });
  }

  Queue queue_;
  std::optional<NodeContext> ctx_;
  std::unique_ptr<Node> node_;
  std::thread thread_;
};

using MracControllerNodelet =
    CallbackNodelet<MracControllerNode, makeMracControllerNode, InlineCallbackQueue>;
/// The recorder's thread takes its messages every millisecond: waiting on its queue, it was asleep
/// and woken for nearly every message (perf: 12.6 % of the plant's thread in futex wakes, 23 % of
/// the recorder's in thread switches; docs/performance.md). Not inline in the publisher's thread
/// as the controller: tried, and in 1 of 3 compare.launch runs neither plant ever received the
/// recorder's ~progress (cause not found).
using BagRecorderNodelet = CallbackNodelet<BagRecorder, makeBagRecorder, ros::CallbackQueue, 1000>;
/// With the required flag it ends the manager when every plant has finished.
using RunMonitorNodelet = CallbackNodelet<RunMonitor, makeRunMonitor>;

}  // namespace ros1
}  // namespace preadaptive_mrac

PLUGINLIB_EXPORT_CLASS(preadaptive_mrac::ros1::PlantSimNodelet, nodelet::Nodelet)
PLUGINLIB_EXPORT_CLASS(preadaptive_mrac::ros1::MracControllerNodelet, nodelet::Nodelet)
PLUGINLIB_EXPORT_CLASS(preadaptive_mrac::ros1::BagRecorderNodelet, nodelet::Nodelet)
PLUGINLIB_EXPORT_CLASS(preadaptive_mrac::ros1::RunMonitorNodelet, nodelet::Nodelet)
