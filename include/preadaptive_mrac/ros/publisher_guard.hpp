#pragma once
/// \file publisher_guard.hpp
/// \brief Take a topic's messages only from the publishers a node expects (~accept_from):
/// the caller id of each message's connection header against a list of node names.
/// Others are dropped, counted, and warned about once per publisher and topic.
///
/// A guard against a stray or misconfigured node (a second plant or a test publisher left
/// running, a remapping gone wrong), NOT a defence against an attacker: a ROS 1 caller id is
/// whatever the publishing node says it is, so anyone who reaches the master can claim the
/// expected name (docs/reference/ros.md, "Network exposure").
///
/// ROS-free (no ROS headers), so the matching is tested without a master; the nodes pass each
/// ros::MessageEvent to admit().

#include <atomic>
#include <cstdint>
#include <functional>
#include <map>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

namespace preadaptive_mrac {
namespace ros1 {

/// \brief Whether `name` is a node name ~accept_from can hold: ROS graph-name characters
/// (letters, digits, '_', '/'), starting with a letter or '/', no empty component ("//", a
/// trailing '/'), not private ('~'). On false `why` says what is wrong.
bool validCallerName(const std::string& name, std::string* why);

/// \brief A name of ~accept_from resolved in the node's namespace `ns` ("/", "/rac"), as ROS
/// resolves a relative topic: "/mrac_controller" stays, "mrac_controller" in "/rac" becomes
/// "/rac/mrac_controller". (A nodelet's namespace is its own, not its manager's.)
std::string resolveCallerName(const std::string& ns, const std::string& name);
/// \brief resolveCallerName of each name.
std::vector<std::string> resolveCallerNames(const std::string& ns,
                                            const std::vector<std::string>& names);

/// \brief The accept-list of one node (shared by its guarded subscriptions).
///
/// Thread-safe: admit() may run on several callback threads at once. Accepting costs a
/// comparison of the caller id with each listed name and takes no lock; only a drop locks.
class PublisherGuard {
 public:
  /// \brief Called with the text of each warning (the node logs it: ROS_WARN).
  using Warn = std::function<void(const std::string&)>;
  /// \brief At most this many (publisher, topic) pairs are named in warnings and diagnostics;
  /// drops from further ones are still counted.
  static constexpr std::size_t kMaxNamed = 16;

  /// \brief accepted: fully resolved caller ids (resolveCallerNames); empty = accept every
  /// publisher (the guard is off). key: the parameter's resolved name, for the warnings
  /// ("/plant_sim/accept_from").
  explicit PublisherGuard(std::vector<std::string> accepted = {}, std::string key = "~accept_from",
                          Warn warn = {});

  /// \brief True when a list was given (else every publisher is accepted).
  bool enabled() const { return !accepted_.empty(); }
  /// \brief True when `caller_id` is in the list (or the guard is off).
  bool accepts(const std::string& caller_id) const;

  /// \brief Whether to take a message of `topic` from `caller_id`. On false the message is
  /// counted as dropped and, the first time for this caller id and topic, warned about.
  bool admit(const std::string& caller_id, const std::string& topic);
  /// \brief The same for a ros::MessageEvent (its connection header's caller id); with the
  /// guard off the header is not even looked at.
  template <class Event>
  bool admitEvent(const Event& event, const std::string& topic) {
    return !enabled() || admit(event.getPublisherName(), topic);
  }

  /// \brief Messages dropped so far (every topic).
  std::int64_t dropped() const { return dropped_.load(std::memory_order_relaxed); }
  /// \brief "any publisher" or the accepted names, comma-separated.
  std::string acceptedText() const;
  /// \brief The dropped publishers: "/stray on /controller/elevator_cmd: 12, ..." ("none");
  /// beyond kMaxNamed pairs, "and N more message(s) from other publishers".
  std::string droppedText() const;

 private:
  std::vector<std::string> accepted_;
  std::string key_;
  Warn warn_;
  std::atomic<std::int64_t> dropped_{0};
  mutable std::mutex mutex_;                                           ///< guards the fields below
  std::map<std::pair<std::string, std::string>, std::int64_t> named_;  ///< (caller, topic)
  std::int64_t unnamed_ = 0;  ///< drops from pairs beyond kMaxNamed
};

}  // namespace ros1
}  // namespace preadaptive_mrac
