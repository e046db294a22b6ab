#include "preadaptive_mrac/ros/inline_queue.hpp"

#include <ros/subscription_queue.h>

#include <boost/make_shared.hpp>

namespace preadaptive_mrac {
namespace ros1 {

/// \brief A callback of the backlog: run under the queue's lock, as an inline one is.
class InlineCallbackQueue::Deferred : public ros::CallbackInterface {
 public:
  Deferred(ros::CallbackInterfacePtr inner, InlineCallbackQueue* queue)
      : inner_(std::move(inner)), queue_(queue) {}
  CallResult call() override {
    std::lock_guard<std::mutex> lock(queue_->run_);
    queue_->runner_.store(std::this_thread::get_id());
    const CallResult r = inner_->call();
    queue_->runner_.store(std::thread::id());
    return r;
  }
  bool ready() override { return inner_->ready(); }

 private:
  ros::CallbackInterfacePtr inner_;
  InlineCallbackQueue* queue_;
};

void InlineCallbackQueue::addCallback(const ros::CallbackInterfacePtr& callback,
                                      uint64_t owner_id) {
  // Only a subscription's message: roscpp adds a timer's callback holding its timer lock,
  // which the callback may need (a timer that stops itself).
  if (!inCallback() && dynamic_cast<ros::SubscriptionQueue*>(callback.get()) != nullptr) {
    std::unique_lock<std::mutex> lock(run_, std::try_to_lock);
    // Not ahead of a waiting callback (a message of another topic may depend on its order).
    if (lock.owns_lock() && backlog_.isEmpty() && callback->ready()) {
      runner_.store(std::this_thread::get_id());
      const ros::CallbackInterface::CallResult r = callback->call();
      runner_.store(std::thread::id());
      // TryAgain: the subscription's callback is running elsewhere (roscpp's own lock).
      if (r != ros::CallbackInterface::TryAgain) return;
    }
  }
  backlog_.addCallback(boost::make_shared<Deferred>(callback, this), owner_id);
}

void InlineCallbackQueue::removeByID(uint64_t owner_id) {
  // The backlog waits for a call of the owner in progress there (which needs run_), then an
  // inline call in progress is waited for by taking run_.
  backlog_.removeByID(owner_id);
  if (!inCallback()) std::lock_guard<std::mutex> wait(run_);
}

void InlineCallbackQueue::callAvailable(ros::WallDuration timeout) {
  backlog_.callAvailable(timeout);
}

}  // namespace ros1
}  // namespace preadaptive_mrac
