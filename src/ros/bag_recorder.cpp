#include "preadaptive_mrac/ros/bag_recorder.hpp"

#include <tf2_msgs/TFMessage.h>

#include <algorithm>
#include <boost/make_shared.hpp>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <sstream>
#include <type_traits>

#include "preadaptive_mrac/AdaptationStatus.h"
#include "preadaptive_mrac/AttentionEvent.h"
#include "preadaptive_mrac/ElevatorCommand.h"
#include "preadaptive_mrac/PlantState.h"
#include "preadaptive_mrac/PlantTruth.h"
#include "preadaptive_mrac/RecorderConnections.h"
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

/// The message deserialized as M, or null when it is of another type.
template <class M>
boost::shared_ptr<M const> instantiateAs(const topic_tools::ShapeShifter& msg) {
  if (msg.getDataType() != ros::message_traits::datatype<M>()) return {};
  return msg.instantiate<M>();
}

}  // namespace

BagRecorder::BagRecorder(const NodeContext& ctx, const BagRecorderParams& params)
    : ctx_(ctx),
      nh_(ctx.nh()),
      params_(params),
      guard_(makePublisherGuard(ctx, params.accept_from)),
      progress_every_(params.progress_every) {
  base_ =
      params.output.empty() ? params.output_prefix + "_" + dateSuffix() + ".bag" : params.output;
  // Under the user's home (the default bag_dir, ~/.ros/bags, on a fresh account) the missing
  // folders are made; elsewhere only one missing folder is, so a mistyped path does not grow a
  // tree of folders anywhere the node may write.
  const std::filesystem::path dir = std::filesystem::path(base_).parent_path();
  const char* home = std::getenv("HOME");
  const bool under_home =
      home != nullptr && home[0] == '/' && base_.rfind(std::string(home) + "/", 0) == 0;
  if (!dir.empty() && !std::filesystem::is_directory(dir)) {
    if (under_home)
      std::filesystem::create_directories(dir);
    else if (!dir.parent_path().empty() && !std::filesystem::is_directory(dir.parent_path()))
      throw std::runtime_error("the folder of " + base_ + " does not exist, nor does " +
                               dir.parent_path().string() + " (only one missing folder is made)");
    else
      std::filesystem::create_directory(dir);
  }
  single_ = base_;
  // Split series are named like rosbag record --split: <base>_0.bag, <base>_1.bag, ...
  if (base_.size() > 4 && base_.compare(base_.size() - 4, 4, ".bag") == 0)
    base_.resize(base_.size() - 4);
  openBag();
  for (std::size_t i = 0; i < params.topics.size(); ++i) {
    const std::string resolved = nh_.resolveName(params.topics[i]);
    const std::string type = i < params.types.size() ? params.types[i] : std::string();
    counts_[resolved] = 0;
    sub_topics_.push_back(resolved);
    // Queue size 0: unbounded, so nothing is dropped however far behind this node falls.
    if (type == ros::message_traits::datatype<PlantState>()) {
      subs_.push_back(subscribeTyped<PlantState>(resolved));
    } else if (type == ros::message_traits::datatype<PlantTruth>()) {
      subs_.push_back(subscribeTyped<PlantTruth>(resolved));
    } else if (type == ros::message_traits::datatype<ElevatorCommand>()) {
      subs_.push_back(subscribeTyped<ElevatorCommand>(resolved));
    } else if (type == ros::message_traits::datatype<AttentionEvent>()) {
      subs_.push_back(subscribeTyped<AttentionEvent>(resolved));
    } else if (type == ros::message_traits::datatype<AdaptationStatus>()) {
      subs_.push_back(subscribeTyped<AdaptationStatus>(resolved));
    } else if (type == ros::message_traits::datatype<tf2_msgs::TFMessage>()) {
      subs_.push_back(subscribeTyped<tf2_msgs::TFMessage>(resolved));
    } else {
      subs_.push_back(nh_.subscribe<topic_tools::ShapeShifter>(
          resolved, 0,
          boost::function<void(const ros::MessageEvent<topic_tools::ShapeShifter const>&)>(
              [this, resolved](const ros::MessageEvent<topic_tools::ShapeShifter const>& ev) {
                callback(resolved, ev);
              }),
          ros::VoidConstPtr(), ros::TransportHints().tcpNoDelay()));
    }
  }
  // Advertised last: a plant that sees this publisher knows every subscription above exists
  // (in a nodelet manager, where subscribers in one process share one connection and cannot be
  // counted, that is how the plant knows the recorder is ready before step 0).
  // Unbounded (0): one topic's progress must not push another's last step out of the queue.
  // With a bounded queue a fast recorder's burst of status progress dropped the states' and
  // commands' last ones on their way to a slow subscriber (reconfigure.test, 1 run in 3).
  progress_pub_ = ctx.pnh().advertise<RecorderProgress>("progress", 0);
  // A publisher that appears after this node subscribed (a controller of the user's started
  // later) is connected to by roscpp's threads some milliseconds after the master says so; a
  // plant waits for this message before step 0, so the first commands are not missed.
  connections_pub_ = ctx.pnh().advertise<RecorderConnections>("connections", 1, true);
  publishConnections();
  connections_timer_ = nh_.createWallTimer(
      ros::WallDuration(0.005), [this](const ros::WallTimerEvent&) { publishConnections(); });
  ROS_INFO("recording %zu topic(s) to %s", params.topics.size(), path_.c_str());
  if (guard_.enabled())
    ROS_INFO("writing messages only from %s (~accept_from)", guard_.acceptedText().c_str());
}

void BagRecorder::openBag() {
  const bool split = params_.split_size_mb > 0.0 || params_.split_duration > 0.0;
  path_ = split ? base_ + "_" + std::to_string(index_) + ".bag" : single_;
  // Nothing recorded before is replaced: an existing bag (or one being written) of this name.
  for (const std::string& p : {path_, path_ + ".active"})
    if (std::filesystem::exists(p))
      throw std::runtime_error(p + " exists: not replaced (choose another ~output)");
  bag_.open(path_ + ".active", static_cast<std::uint32_t>(params_.chunk_size_kb) * 1024u);
  opened_wall_ = ros::WallTime::now().toSec();
}

bool BagRecorder::closeBag() {
  // The file open is <name>.active; path_ may have been renamed since (finish: incomplete).
  const std::string active = bag_.fileName();
  try {
    bag_.close();
  } catch (const std::exception& e) {
    // Not thrown on: finish() runs in the destructor. The file keeps its `.active` name, and
    // path_ says so: the name reported is the file that exists.
    ROS_ERROR("could not close %s: %s", active.c_str(), e.what());
    if (write_failures_++ == 0) write_error_ = e.what();
    path_ = active;
    return false;
  }
  std::error_code ec;
  std::filesystem::rename(active, path_, ec);
  if (ec) {
    ROS_ERROR("could not rename %s to %s: %s", active.c_str(), path_.c_str(), ec.message().c_str());
    path_ = active;
    return false;
  }
  return true;
}

bool BagRecorder::splitDue() const {
  if (params_.split_size_mb > 0.0 &&
      static_cast<double>(bag_.size()) >= params_.split_size_mb * 1024.0 * 1024.0)
    return true;
  return params_.split_duration > 0.0 &&
         ros::WallTime::now().toSec() - opened_wall_ >= params_.split_duration;
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
  if (!guard_.admitEvent(ev, topic)) return;
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
  const auto st = instantiateAs<PlantState>(msg);
  if (st && isRepeat(topic, ev.getPublisherName(), st->step, st->header.stamp)) return;
  const auto cmd = instantiateAs<ElevatorCommand>(msg);
  if (cmd && isRepeat(topic, ev.getPublisherName(), cmd->step, cmd->header.stamp)) return;
  record(topic, t, *ev.getConstMessage(), ev.getConnectionHeaderPtr(), st.get());
  // The stepped topics of typedCallback (their step is only known deserialized).
  if (cmd) {
    reportStepProgress(topic, cmd->header.stamp, cmd->step);
  } else if (const auto m = instantiateAs<AdaptationStatus>(msg)) {
    reportStepProgress(topic, m->header.stamp, m->step);
  } else if (const auto m = instantiateAs<PlantTruth>(msg)) {
    reportStepProgress(topic, m->header.stamp, m->step);
  }
}

template <class M>
ros::Subscriber BagRecorder::subscribeTyped(const std::string& resolved) {
  return nh_.subscribe<M>(
      resolved, 0,
      boost::function<void(const ros::MessageEvent<M const>&)>(
          [this, resolved](const ros::MessageEvent<M const>& ev) { typedCallback(resolved, ev); }),
      ros::VoidConstPtr(), ros::TransportHints().tcpNoDelay());
}

template <class M>
void BagRecorder::typedCallback(const std::string& topic, const ros::MessageEvent<M const>& ev) {
  if (!guard_.admitEvent(ev, topic)) return;
  const M& msg = *ev.getConstMessage();
  ros::Time t = ros::Time::now();
  const PlantState* state = nullptr;
  if constexpr (ros::message_traits::HasHeader<M>::value) t = msg.header.stamp;
  // tf has no header of its own: its transforms' stamp (simulation time in lockstep, where
  // ROS time is the wall clock and not the run's time).
  if constexpr (std::is_same<M, tf2_msgs::TFMessage>::value)
    if (!msg.transforms.empty()) t = msg.transforms.front().header.stamp;
  if constexpr (std::is_same<M, PlantState>::value) state = &msg;
  // A run that left the flight envelope: the bag's name will say so.
  if constexpr (std::is_same<M, PlantTruth>::value)
    if (envelope_exit_.empty() && !msg.envelope_exit.empty()) envelope_exit_ = msg.envelope_exit;
  if constexpr (std::is_same<M, PlantState>::value || std::is_same<M, ElevatorCommand>::value)
    if (isRepeat(topic, ev.getPublisherName(), msg.step, msg.header.stamp)) return;
  record(topic, t, msg, ev.getConnectionHeaderPtr(), state);
  // The controller's and the truth's messages come on connections of their own and can be
  // far behind the states (measured under load: every state written, 25481 of 60000
  // statuses): their progress too, so a reader can tell when every step of them is in.
  if constexpr (std::is_same<M, PlantTruth>::value || std::is_same<M, ElevatorCommand>::value ||
                std::is_same<M, AdaptationStatus>::value)
    reportStepProgress(topic, msg.header.stamp, msg.step);
}

bool BagRecorder::isRepeat(const std::string& topic, const std::string& publisher,
                           std::uint64_t step, const ros::Time& stamp) {
  // Per publisher: another node's message of the same step (a stray publisher) is not a
  // repeat, and is recorded.
  const std::pair<std::uint64_t, ros::Time> key(step, stamp);
  auto& last = last_written_[topic][publisher];  // no copy of either name once both are known
  if (last && *last == key) {
    ++repeats_[topic];
    return true;
  }
  last = key;
  return false;
}

template <class M>
void BagRecorder::record(const std::string& topic, ros::Time t, const M& msg,
                         const boost::shared_ptr<ros::M_string>& connection_header,
                         const PlantState* state) {
  // A bag cannot hold time 0 (simulation time before the first /clock).
  if (t < ros::TIME_MIN) t = ros::TIME_MIN;
  try {
    bag_.write(topic, t, msg, connection_header);
    ++counts_[topic];
    if (state != nullptr) {
      bool& done = state_done_[topic];
      done = done || (state->total_steps > 0 && state->step + 1 >= state->total_steps);
      reportProgress(topic, *state);
    }
    if (splitDue()) {
      closeBag();
      ROS_INFO("closed %s (split)", path_.c_str());
      ++index_;
      openBag();
    }
  } catch (const std::exception& e) {
    if (write_failures_++ == 0) write_error_ = e.what();
    ROS_ERROR_THROTTLE(1.0, "bag write failed on %s: %s", topic.c_str(), e.what());
  }
}

void BagRecorder::publishConnections() {
  std::vector<std::uint32_t> now;
  now.reserve(subs_.size());
  for (const ros::Subscriber& sub : subs_) now.push_back(sub.getNumPublishers());
  if (connections_pub_ && now != connected_) {
    connected_ = now;
    const auto m = boost::make_shared<RecorderConnections>();
    m->topics = sub_topics_;
    m->publishers = now;
    connections_pub_.publish(RecorderConnections::ConstPtr(m));
  }
}

void BagRecorder::reportProgress(const std::string& topic, const PlantState& st) {
  total_steps_ = std::max(total_steps_, st.total_steps);
  const bool last = st.total_steps > 0 && st.step + 1 >= st.total_steps;
  if (!last && st.step % static_cast<std::uint64_t>(progress_every_) != 0) return;
  const auto p = boost::make_shared<RecorderProgress>();
  p->header.stamp = st.header.stamp;
  p->topic = topic;
  p->step = st.step;
  p->total_steps = st.total_steps;
  progress_pub_.publish(RecorderProgress::ConstPtr(p));
}

void BagRecorder::reportStepProgress(const std::string& topic, const ros::Time& stamp,
                                     std::uint64_t step) {
  // The scenario's length from the states (one plant's run; 0 before the first state).
  const bool last = total_steps_ > 0 && step + 1 >= total_steps_;
  if (!last && step % static_cast<std::uint64_t>(progress_every_) != 0) return;
  const auto p = boost::make_shared<RecorderProgress>();
  p->header.stamp = stamp;
  p->topic = topic;
  p->step = step;
  p->total_steps = total_steps_;
  progress_pub_.publish(RecorderProgress::ConstPtr(p));
}

BagRecorder::~BagRecorder() { finish(); }

void BagRecorder::finish() {
  if (closed_) return;
  closed_ = true;
  connections_timer_.stop();
  subs_.clear();
  std::uint64_t total = 0;
  for (const auto& kv : counts_) total += kv.second;
  bool complete = true;
  for (const auto& kv : state_done_) complete = complete && kv.second;
  if (total == 0) {
    // Nothing came (a launch refused at start-up): a bag named like a run would look like data.
    try {
      bag_.close();
    } catch (const std::exception&) {
      // Removed below either way.
    }
    std::error_code ec;
    std::filesystem::remove(path_ + ".active", ec);
    ctx_.printFinal("no message came: removed the empty " + path_ + ".active (no bag written)");
    return;
  }
  // A plant's states stopped before its last step (another node refused or died, or the run
  // was interrupted), or messages could not be written (a full disk): kept, under a name that
  // says so.
  const bool lost = write_failures_ > 0;
  if (!complete || lost) path_ = path_.substr(0, path_.size() - 4) + ".incomplete.bag";
  // A run that left the flight envelope: <name>.envelope_exit.bag (and the line below says it).
  if (!envelope_exit_.empty()) path_ = path_.substr(0, path_.size() - 4) + ".envelope_exit.bag";
  const bool closed = closeBag();
  std::string summary;
  for (const auto& kv : counts_) summary += " " + kv.first + "=" + std::to_string(kv.second);
  std::string repeats;
  for (const auto& kv : repeats_) repeats += " " + kv.first + "=" + std::to_string(kv.second);
  if (!repeats.empty()) summary += "; repeats not written again:" + repeats;
  if (guard_.dropped() > 0)
    summary += "; not written, from publishers not in ~accept_from: " + guard_.droppedText();
  // The reason given is the real one: lost writes (and an unclosed file) before a short run.
  std::string why;
  if (lost)
    why = " (incomplete: " + std::to_string(write_failures_) +
          " message(s) or the index could not be written: " + write_error_ + ")";
  else if (!complete)
    why = " (incomplete: a plant stopped before its last step)";
  ctx_.printFinal(
      (closed ? "closed " : "could not close the bag; what was written is in ") + path_ +
      (closed ? std::string() : " (unindexed: scripts/reindex_bags recovers it)") +
      (index_ > 0 ? " (" + std::to_string(index_ + 1) + " split bags)" : std::string()) + why +
      (envelope_exit_.empty() ? "" : " (left the flight envelope at " + envelope_exit_ + ")") +
      "; messages:" + summary);
}

std::unique_ptr<BagRecorder> makeBagRecorder(const NodeContext& ctx) {
  // The types ~types may name: those subscribeTyped is instantiated for, and "" (any type).
  const std::vector<std::string> types = {"",
                                          ros::message_traits::datatype<PlantState>(),
                                          ros::message_traits::datatype<PlantTruth>(),
                                          ros::message_traits::datatype<ElevatorCommand>(),
                                          ros::message_traits::datatype<AttentionEvent>(),
                                          ros::message_traits::datatype<AdaptationStatus>(),
                                          ros::message_traits::datatype<tf2_msgs::TFMessage>()};
  const auto read = [&types](const ParamValue& tree, const KeyStyle& style) {
    return readBagRecorderParams(tree, style, types);
  };
  BagRecorderParams p;
  if (!readNodeParams(ctx, read, &p)) return nullptr;
  try {
    return std::make_unique<BagRecorder>(ctx, p);
  } catch (const std::exception& e) {
    ROS_FATAL("%s: cannot record: %s", ctx.name().c_str(), e.what());
    ctx.end(kExitRuntimeError);
    return nullptr;
  }
}

int runBagRecorderNode() {
  // One thread: each callback appends its message to the chunk in memory (BagWriter). Not
  // inline in roscpp's receiving thread, as the nodelet is in the publisher's: tried, and
  // reconfigure.test then missed the recorder's last ~progress (1 run of 1; passes without).
  return spinProcessNode(makeBagRecorder);
}

}  // namespace ros1
}  // namespace preadaptive_mrac
