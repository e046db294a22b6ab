#include "preadaptive_mrac/ros/bag_recorder.hpp"

#include <cstring>
#include <ctime>
#include <filesystem>
#include <sstream>

#include "preadaptive_mrac/PlantState.h"
#include "preadaptive_mrac/RecorderProgress.h"
#include "preadaptive_mrac/ros/ros_params.hpp"

namespace preadaptive_mrac {
namespace ros1 {
namespace {

std::string dateSuffix() {
  const std::time_t now = std::time(nullptr);
  std::tm tm{};
  localtime_r(&now, &tm);
  char buf[32];
  std::strftime(buf, sizeof(buf), "%Y-%m-%d-%H-%M-%S", &tm);
  return buf;
}

}  // namespace

BagRecorder::BagRecorder(const ros::NodeHandle& nh, const BagRecorderParams& params)
    : nh_(nh), progress_every_(params.progress_every) {
  progress_pub_ = ros::NodeHandle("~").advertise<RecorderProgress>("progress", 100);
  path_ =
      params.output.empty() ? params.output_prefix + "_" + dateSuffix() + ".bag" : params.output;
  const std::filesystem::path dir = std::filesystem::path(path_).parent_path();
  if (!dir.empty()) std::filesystem::create_directories(dir);
  bag_.open(path_, rosbag::bagmode::Write);
  for (const auto& t : params.topics) {
    const std::string resolved = nh_.resolveName(t);
    counts_[resolved] = 0;
    // Queue size 0: unbounded, so nothing is dropped however far behind this node falls.
    subs_.push_back(nh_.subscribe<topic_tools::ShapeShifter>(
        resolved, 0,
        boost::function<void(const ros::MessageEvent<topic_tools::ShapeShifter const>&)>(
            [this, resolved](const ros::MessageEvent<topic_tools::ShapeShifter const>& ev) {
              callback(resolved, ev);
            }),
        ros::VoidConstPtr(), ros::TransportHints().tcpNoDelay()));
  }
  ROS_INFO("recording %zu topic(s) to %s", params.topics.size(), path_.c_str());
}

bool BagRecorder::hasHeader(const topic_tools::ShapeShifter& msg) {
  auto it = has_header_.find(msg.getDataType());
  if (it != has_header_.end()) return it->second;
  // The first field line of the definition (comments and constants aside).
  bool header = false;
  std::istringstream def(msg.getMessageDefinition());
  std::string line;
  while (std::getline(def, line)) {
    const auto b = line.find_first_not_of(" \t");
    if (b == std::string::npos || line[b] == '#') continue;
    std::istringstream fields(line.substr(b));
    std::string type, name;
    fields >> type >> name;
    if (name.find('=') != std::string::npos || type.find('=') != std::string::npos) continue;
    header = (type == "Header" || type == "std_msgs/Header") && name == "header";
    break;
  }
  has_header_[msg.getDataType()] = header;
  return header;
}

void BagRecorder::callback(const std::string& topic,
                           const ros::MessageEvent<topic_tools::ShapeShifter const>& ev) {
  const topic_tools::ShapeShifter& msg = *ev.getConstMessage();
  ros::Time t = ros::Time::now();
  if (hasHeader(msg) && msg.size() >= 12) {
    // std_msgs/Header: uint32 seq, then the stamp as uint32 sec, uint32 nsec (little endian).
    buf_.resize(msg.size());
    ros::serialization::OStream os(buf_.data(), static_cast<uint32_t>(buf_.size()));
    msg.write(os);
    std::uint32_t sec = 0, nsec = 0;
    std::memcpy(&sec, buf_.data() + 4, 4);
    std::memcpy(&nsec, buf_.data() + 8, 4);
    t = ros::Time(sec, nsec);
  }
  // A bag cannot hold time 0 (simulation time before the first /clock).
  if (t < ros::TIME_MIN) t = ros::TIME_MIN;
  try {
    bag_.write(topic, t, ev.getConstMessage(), ev.getConnectionHeaderPtr());
    ++counts_[topic];
    reportProgress(topic, msg);
  } catch (const std::exception& e) {
    ROS_ERROR_THROTTLE(1.0, "bag write failed on %s: %s", topic.c_str(), e.what());
  }
}

void BagRecorder::reportProgress(const std::string& topic, const topic_tools::ShapeShifter& msg) {
  if (msg.getDataType() != ros::message_traits::datatype<PlantState>()) return;
  const PlantState::ConstPtr st = msg.instantiate<PlantState>();
  if (!st) return;
  const bool last = st->total_steps > 0 && st->step + 1 >= st->total_steps;
  if (!last && st->step % static_cast<std::uint64_t>(progress_every_) != 0) return;
  RecorderProgress p;
  p.header.stamp = st->header.stamp;
  p.topic = topic;
  p.step = st->step;
  p.total_steps = st->total_steps;
  progress_pub_.publish(p);
}

int BagRecorder::run() {
  // One thread: each callback writes its message (the bag buffers chunks in memory).
  ros::spin();
  subs_.clear();
  bag_.close();
  std::string summary;
  for (const auto& kv : counts_) summary += " " + kv.first + "=" + std::to_string(kv.second);
  printAfterShutdown("closed " + path_ + "; messages:" + summary);
  return 0;
}

int runBagRecorderNode() {
  ros::NodeHandle pnh("~");
  BagRecorderParams p;
  std::vector<std::string> problems;
  XmlRpc::XmlRpcValue v;
  if (!pnh.getParam("topics", v) || v.getType() != XmlRpc::XmlRpcValue::TypeArray ||
      v.size() == 0) {
    problems.push_back(pnh.resolveName("topics") + ": expected a non-empty list of topic names");
  } else {
    for (int i = 0; i < v.size(); ++i) {
      if (v[i].getType() != XmlRpc::XmlRpcValue::TypeString) {
        problems.push_back(pnh.resolveName("topics") + "[" + std::to_string(i) +
                           "]: expected a topic name");
      } else {
        p.topics.push_back(static_cast<std::string>(v[i]));
      }
    }
  }
  pnh.param<std::string>("output", p.output, "");
  pnh.param<std::string>("output_prefix", p.output_prefix, "");
  pnh.param<int>("progress_every", p.progress_every, 100);
  if (p.progress_every < 1)
    problems.push_back(pnh.resolveName("progress_every") + ": must be >= 1, got " +
                       std::to_string(p.progress_every));
  if (p.output.empty() && p.output_prefix.empty())
    problems.push_back(pnh.resolveName("output") + ": set ~output or ~output_prefix");
  if (!problems.empty()) {
    logConfigProblems(problems);
    return kExitConfigError;
  }
  try {
    BagRecorder r(ros::NodeHandle(), p);
    return r.run();
  } catch (const std::exception& e) {
    ROS_FATAL("cannot record: %s", e.what());
    return kExitRuntimeError;
  }
}

}  // namespace ros1
}  // namespace preadaptive_mrac
