#pragma once
/// \file inline_queue.hpp
/// \brief A callback queue whose callbacks run in the thread that queues them, when they can:
/// a node on it answers a message without a thread wake-up (docs/reference/ros.md, "Threads").

#include <ros/callback_queue.h>
#include <ros/callback_queue_interface.h>

#include <atomic>
#include <cstdint>
#include <mutex>
#include <thread>

namespace preadaptive_mrac {
namespace ros1 {

/// \brief Runs each message's callback at once in the thread that adds it (roscpp's: a
/// publisher's in the same process, the receiving thread for a message from another process),
/// unless another callback of this queue is running or waiting: then it waits in a backlog
/// that callAvailable() serves, as do timers and services always. Callbacks run one at a time in
/// any case, as on a single-threaded queue, so a node needs no locks of its own; a callback that
/// queues another (a node publishing to itself) does not run it inside itself.
///
/// Messages of one subscription stay in order whatever runs where (roscpp's subscription queue
/// hands out the oldest message to whichever call comes first). Meant for a node whose
/// callbacks are short and never block (the controller): a long one holds up the thread that
/// published the message, which in a lockstep run is the plant's loop waiting for the answer
/// anyway.
class InlineCallbackQueue : public ros::CallbackQueueInterface {
 public:
  void addCallback(const ros::CallbackInterfacePtr& callback, uint64_t owner_id = 0) override;
  /// \brief Waits for a callback of owner_id running in another thread, then drops the
  /// owner's waiting ones.
  void removeByID(uint64_t owner_id) override;
  /// \brief Run the backlog; waits up to `timeout` for one when it is empty.
  void callAvailable(ros::WallDuration timeout);

 private:
  class Deferred;
  /// \brief Whether the calling thread is running a callback of this queue now.
  bool inCallback() const { return runner_.load() == std::this_thread::get_id(); }

  ros::CallbackQueue backlog_;
  std::mutex run_;                                          ///< held while a callback runs
  std::atomic<std::thread::id> runner_{std::thread::id()};  ///< the thread holding run_
};

}  // namespace ros1
}  // namespace preadaptive_mrac
