#pragma once
/// \file bag_recorder.hpp
/// \brief A bag recorder that never drops a message: unbounded subscriber queues, and
/// back-pressure on a lockstep plant. `rosbag record` subscribes with a fixed queue of 100
/// messages per topic and drops the oldest when it falls behind, which it does under a
/// lockstep run (thousands of samples per second) on a loaded machine; a lockstep bag must
/// hold every step.

#include <ros/ros.h>
#include <topic_tools/shape_shifter.h>

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "preadaptive_mrac/PlantState.h"
#include "preadaptive_mrac/ros/bag_writer.hpp"
#include "preadaptive_mrac/ros/node_context.hpp"
#include "preadaptive_mrac/ros/node_params.hpp"

namespace preadaptive_mrac {
namespace ros1 {

/// \brief Subscribes to every topic of any type and writes each message into one bag, at the
/// time of its header stamp when its type starts with a std_msgs/Header (every message of
/// this package: the sample's simulation time in lockstep), else at the receipt time (ROS
/// time). So bag times are exact sample times however /clock is published.
///
/// For each PlantState topic it publishes ~progress (RecorderProgress) every
/// ~progress_every steps and at the last step, once the state is in the bag: a lockstep plant
/// waits on it instead of outrunning the recorder. Likewise for each PlantTruth,
/// ElevatorCommand and AdaptationStatus topic (their step; last: the states' total_steps), so
/// a reader knows when those, which arrive on connections of their own, are in the bag too.
///
/// A PlantState or ElevatorCommand that repeats the last one written on its topic (same
/// step, same stamp: a lockstep plant re-sends its state when the controller has not answered
/// within ~resend_interval, and the controller answers the repeat with its command again) is
/// not written again: the bag holds each step once. Such repeats are counted and named in the
/// closing line.
class BagRecorder {
 public:
  /// \brief Opens the bag (creating its directory) and subscribes; throws on failure.
  /// Callbacks run wherever ctx.nh()'s queue is served, one at a time (a single-threaded
  /// spinner, or the nodelet's thread polling its queue every millisecond); each is short (the
  /// message appended to the chunk in memory, a chunk's write once it is full).
  BagRecorder(const NodeContext& ctx, const BagRecorderParams& params);
  /// \brief finish().
  ~BagRecorder();
  /// \brief Unsubscribe, close the bag (renaming `.active` away) and print what it holds.
  /// Idempotent.
  void finish();
  /// \brief The bag being written (without the `.active` suffix it carries while open).
  const std::string& path() const { return path_; }

 private:
  void callback(const std::string& topic,
                const ros::MessageEvent<topic_tools::ShapeShifter const>& ev);
  /// \brief A typed topic: written at its header stamp (or receipt time without a header).
  template <class M>
  void typedCallback(const std::string& topic, const ros::MessageEvent<M const>& ev);
  /// \brief Subscribe `resolved` with type M (typedCallback).
  template <class M>
  ros::Subscriber subscribeTyped(const std::string& resolved);
  /// \brief Write one message (any type rosbag can write), count it, report progress for a
  /// PlantState (step, total), split when due.
  template <class M>
  void record(const std::string& topic, ros::Time t, const M& msg,
              const boost::shared_ptr<ros::M_string>& connection_header, const PlantState* state);
  /// \brief Whether (step, stamp) is the last one `publisher` had written on `topic` (then
  /// counted in repeats_, and the message is not to be written); else remembered as the last.
  bool isRepeat(const std::string& topic, const std::string& publisher, std::uint64_t step,
                const ros::Time& stamp);
  void reportProgress(const std::string& topic, const PlantState& st);
  /// \brief Progress of a stepped topic that is not a PlantState (every ~progress_every steps
  /// and at the states' last step).
  void reportStepProgress(const std::string& topic, const ros::Time& stamp, std::uint64_t step);
  /// \brief Whether a message type's definition starts with `Header header` (cached).
  bool hasHeader(const topic_tools::ShapeShifter& msg);
  /// \brief Open bag number `index_` as `<path>.active` (like rosbag record), so a crash
  /// leaves a file that `rosbag reindex` (scripts/reindex_bags) can recover.
  void openBag();
  /// \brief Close the bag and rename `<path>.active` to `<path>`. False when it could not
  /// (logged; path_ then names the `.active` file that is left).
  bool closeBag();
  /// \brief Whether the split size or duration is reached (then the next bag is opened).
  bool splitDue() const;
  /// \brief Publish ~connections when a subscription's number of publishers has changed.
  void publishConnections();

  NodeContext ctx_;
  ros::NodeHandle nh_;
  BagRecorderParams params_;
  bool closed_ = false;
  std::string envelope_exit_;  ///< the first PlantTruth.envelope_exit recorded ("" = none)
  std::string single_;         ///< the bag's path when not splitting (~output as given)
  std::string base_;           ///< path of the split series, without `.bag`
  std::string path_;           ///< the bag being written (final name, without `.active`)
  int index_ = 0;              ///< split number
  double opened_wall_ = 0.0;
  BagWriter bag_;         ///< rosbag's file format, each chunk written in one go
  PublisherGuard guard_;  ///< ~accept_from: messages of other publishers are never written
  std::uint64_t write_failures_ = 0;  ///< messages that could not be written
  std::string write_error_;           ///< the first write failure's reason
  std::vector<ros::Subscriber> subs_;
  std::vector<std::string> sub_topics_;  ///< resolved topic of each of subs_
  ros::Publisher progress_pub_;
  /// ~connections (RecorderConnections, latched): the publishers of each subscription, sent
  /// again by connections_timer_ when a number changes.
  ros::Publisher connections_pub_;
  ros::WallTimer connections_timer_;
  std::vector<std::uint32_t> connected_;  ///< the numbers last sent
  int progress_every_ = 100;
  std::uint64_t total_steps_ = 0;  ///< the largest total_steps of the states recorded
  std::map<std::string, std::uint64_t> counts_;
  /// PlantState topics recorded, and whether each reached its plant's last step: a bag
  /// closed before that (a launch ended by another node's refusal, an interrupted run) is
  /// renamed <name>.incomplete.bag, so it does not pass for a run (a bag of no message at all
  /// is removed).
  std::map<std::string, bool> state_done_;
  /// The step and stamp of the last PlantState or ElevatorCommand written, per topic and
  /// publisher.
  std::map<std::string, std::map<std::string, std::optional<std::pair<std::uint64_t, ros::Time>>>>
      last_written_;
  std::map<std::string, std::uint64_t> repeats_;  ///< repeats not written, per topic
  std::map<std::string, bool> has_header_;        ///< by datatype
  std::vector<std::uint8_t> buf_;
};

/// \brief Read ~ (readBagRecorderParams: every problem at once, ROS_FATAL each,
/// ctx.end(kExitConfigError), nullptr; else the start-up line of defaults) and open the bag
/// (failure: ctx.end(kExitRuntimeError), nullptr). Node and nodelet.
std::unique_ptr<BagRecorder> makeBagRecorder(const NodeContext& ctx);

/// \brief main() after ros::init(): makeBagRecorder, spin until shutdown, close the bag.
int runBagRecorderNode();

}  // namespace ros1
}  // namespace preadaptive_mrac
