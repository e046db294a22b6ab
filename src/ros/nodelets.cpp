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

#include <algorithm>
#include <atomic>
#include <memory>
#include <optional>
#include <pluginlib/class_list_macros.hpp>
#include <string>
#include <thread>
#include <vector>

#include "preadaptive_mrac/ros/bag_recorder.hpp"
#include "preadaptive_mrac/ros/mrac_controller_node.hpp"
#include "preadaptive_mrac/ros/node_context.hpp"
#include "preadaptive_mrac/ros/plant_sim_node.hpp"
#include "preadaptive_mrac/ros/run_monitor.hpp"

namespace preadaptive_mrac {
namespace ros1 {
/// \brief Base of the package's nodelets: the context of the node class it wraps.
class ContextNodelet : public nodelet::Nodelet {
 protected:
  /// \brief The nodelet's node handles and name; required when the loader's arguments hold
  /// `--required`.
  NodeContext makeContext() {
    const std::vector<std::string>& argv = getMyArgv();
    const bool required = std::find(argv.begin(), argv.end(), "--required") != argv.end();
    return NodeContext::forNodelet(getNodeHandle(), getPrivateNodeHandle(), getName(), required);
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
  }

 private:
  void onInit() override {
    ctx_ = makeContext();
    PlantNodeParams params;
    if (!readNodeParams(*ctx_, readPlantNodeParams, &params)) return;
    node_ = std::make_unique<PlantSimNode>(*ctx_, params);
    thread_ = std::thread([this] {
      const int code = node_->run();
      if (!unloading_) ctx_->end(code);
    });
  }

  std::optional<NodeContext> ctx_;
  std::unique_ptr<PlantSimNode> node_;
  std::thread thread_;
  std::atomic<bool> unloading_{false};
};

/// \brief A node class whose callbacks do all the work (controller, recorder, run monitor):
/// built by `kMake` in onInit() from the nodelet's context, finish()ed on unload (the
/// controller saves its weights, the recorder closes its bag). Its callbacks run on the
/// nodelet's single-threaded queue, one at a time, as in a single-threaded process.
template <class Node, std::unique_ptr<Node> (*kMake)(const NodeContext&)>
class CallbackNodelet : public ContextNodelet {
 public:
  ~CallbackNodelet() override {
    if (ctx_) ctx_->stop();
    if (node_) node_->finish();
  }

 private:
  void onInit() override {
    ctx_ = makeContext();
    node_ = kMake(*ctx_);
  }

  std::optional<NodeContext> ctx_;
  std::unique_ptr<Node> node_;
};

using MracControllerNodelet = CallbackNodelet<MracControllerNode, makeMracControllerNode>;
using BagRecorderNodelet = CallbackNodelet<BagRecorder, makeBagRecorder>;
/// With the required flag it ends the manager when every plant has finished.
using RunMonitorNodelet = CallbackNodelet<RunMonitor, makeRunMonitor>;

}  // namespace ros1
}  // namespace preadaptive_mrac

PLUGINLIB_EXPORT_CLASS(preadaptive_mrac::ros1::PlantSimNodelet, nodelet::Nodelet)
PLUGINLIB_EXPORT_CLASS(preadaptive_mrac::ros1::MracControllerNodelet, nodelet::Nodelet)
PLUGINLIB_EXPORT_CLASS(preadaptive_mrac::ros1::BagRecorderNodelet, nodelet::Nodelet)
PLUGINLIB_EXPORT_CLASS(preadaptive_mrac::ros1::RunMonitorNodelet, nodelet::Nodelet)
