#include "preadaptive_mrac/ros/node_context.hpp"

#include <signal.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <iterator>
#include <mutex>
#include <utility>

namespace preadaptive_mrac {
namespace ros1 {
namespace {

std::mutex g_exit_mutex;
int g_exit_code = 0;
bool g_exit_requested = false;
bool g_defer_shutdown = false;

}  // namespace

NodeContext NodeContext::forProcess(ros::CallbackQueueInterface* queue) {
  NodeContext c;
  c.nh_ = ros::NodeHandle();
  c.pnh_ = ros::NodeHandle("~");
  if (queue) {
    c.nh_.setCallbackQueue(queue);
    c.pnh_.setCallbackQueue(queue);
  }
  c.name_ = ros::this_node::getName();
  return c;
}

NodeContext NodeContext::forNodelet(const ros::NodeHandle& nh, const ros::NodeHandle& pnh,
                                    const std::string& name, bool required) {
  NodeContext c;
  c.nh_ = nh;
  c.pnh_ = pnh;
  c.name_ = name;
  c.nodelet_ = true;
  c.required_ = required;
  return c;
}

void NodeContext::end(int code) const {
  stopped_->store(true);
  if (nodelet_ && !required_) {
    ROS_INFO("%s: finished (code %d); not required, so the manager keeps running", name_.c_str(),
             code);
    return;
  }
  requestProcessExit(code);
}

ParamValue NodeContext::privateParams() const {
  XmlRpc::XmlRpcValue v;
  // getParam on the private namespace itself returns the whole subtree.
  if (!ros::param::get(pnh_.getNamespace(), v)) return ParamValue::makeMap();
  if (v.getType() != XmlRpc::XmlRpcValue::TypeStruct) return ParamValue::makeMap();
  return fromXmlRpc(v);
}

KeyStyle NodeContext::keyStyle() const {
  KeyStyle s;
  s.root = pnh_.getNamespace() + "/";
  s.separator = '/';
  return s;
}

void NodeContext::logConfigProblems(const std::vector<std::string>& problems) const {
  ROS_FATAL("%s: refusing to start, %zu parameter problem(s):", name_.c_str(), problems.size());
  for (const auto& p : problems) ROS_FATAL("  %s", p.c_str());
}

void NodeContext::printFinal(const std::string& line, bool error) const {
  std::FILE* f = error ? stderr : stdout;
  std::fprintf(f, "[%s] %s: %s\n", error ? "ERROR" : " INFO", name_.c_str(), line.c_str());
  std::fflush(f);
}

PublisherGuard makePublisherGuard(const NodeContext& ctx, const std::vector<std::string>& names) {
  // Resolved as the node resolves any name, remappings included: a pair of compare.launch in a
  // user's namespace names its manager one level up by a remapping (scripts/lib/parent_names).
  std::vector<std::string> accepted;
  accepted.reserve(names.size());
  for (const auto& n : resolveCallerNames(ctx.nh().getNamespace(), names))
    accepted.push_back(ctx.nh().resolveName(n));
  return PublisherGuard(std::move(accepted), ctx.keyStyle().root + "accept_from",
                        [](const std::string& warning) { ROS_WARN("%s", warning.c_str()); });
}

namespace {
// SIGINT to the parent process when it is a local roslaunch; false when it is not (or the
// signal failed), and the caller then exits on its own.
bool endLaunchQuietly() {
  const pid_t parent = getppid();
  std::ifstream f("/proc/" + std::to_string(parent) + "/cmdline");
  const std::string cmdline((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  bool roslaunch = false;
  for (std::size_t b = 0; b < cmdline.size();) {
    std::size_t e = cmdline.find('\0', b);
    if (e == std::string::npos) e = cmdline.size();
    const std::string arg = cmdline.substr(b, e - b);
    // A remote child (`roslaunch -c NAME -u URI`): its parent launch owns the run.
    if (arg == "-c" || arg == "-u" || arg.rfind("--child", 0) == 0 ||
        arg.rfind("--server_uri", 0) == 0 || arg == "--core")
      return false;
    const std::size_t slash = arg.rfind('/');
    if (arg.substr(slash == std::string::npos ? 0 : slash + 1) == "roslaunch") roslaunch = true;
    b = e + 1;
  }
  if (!roslaunch || kill(parent, SIGINT) != 0) return false;
  ROS_INFO("the run has finished: ending the launch (SIGINT to roslaunch, pid %d)",
           static_cast<int>(parent));
  return true;
}
}  // namespace

void requestProcessExit(int code) {
  if (code == 0 && endLaunchQuietly()) return;
  {
    std::lock_guard<std::mutex> lock(g_exit_mutex);
    if (!g_exit_requested || (g_exit_code == 0 && code != 0)) g_exit_code = code;
    g_exit_requested = true;
    if (g_defer_shutdown) return;
  }
  // Deferred to roscpp's own thread (within 0.1 s): ros::shutdown() here could run inside a
  // nodelet manager's load service callback (a nodelet refusing its parameters in onInit()),
  // while the manager is still setting the nodelet up.
  ros::requestShutdown();
}

bool processExitRequested() {
  std::lock_guard<std::mutex> lock(g_exit_mutex);
  return g_exit_requested;
}

void deferProcessShutdown() {
  std::lock_guard<std::mutex> lock(g_exit_mutex);
  g_defer_shutdown = true;
}

int processExitCode() {
  std::lock_guard<std::mutex> lock(g_exit_mutex);
  return g_exit_code;
}

}  // namespace ros1
}  // namespace preadaptive_mrac
