// InlineCallbackQueue (src/ros/inline_queue.cpp) without a master: messages queued as roscpp
// queues them (a subscription's queue as the callback), timers as plain callbacks.
#include <gtest/gtest.h>
#include <ros/message_deserializer.h>
#include <ros/subscription_callback_helper.h>
#include <ros/subscription_queue.h>
#include <std_msgs/Int32.h>

#include <atomic>
#include <boost/make_shared.hpp>
#include <future>
#include <thread>
#include <vector>

#include "preadaptive_mrac/ros/inline_queue.hpp"

namespace {

using preadaptive_mrac::ros1::InlineCallbackQueue;

/// A subscription with callback f: deliver() pushes a message the way roscpp does for an
/// intra-process publisher (the message in its subscription queue, that queue added).
class FakeSubscription {
 public:
  explicit FakeSubscription(std::function<void(int)> f)
      : queue_(boost::make_shared<ros::SubscriptionQueue>("/t", 0, false)),
        helper_(
            boost::make_shared<ros::SubscriptionCallbackHelperT<const std_msgs::Int32ConstPtr&>>(
                [f](const std_msgs::Int32ConstPtr& m) { f(m->data); })) {}
  void deliver(InlineCallbackQueue* q, int value) {
    const auto m = boost::make_shared<std_msgs::Int32>();
    m->data = value;
    ros::SerializedMessage s;
    s.message = m;
    s.type_info = &typeid(std_msgs::Int32);
    const auto d = boost::make_shared<ros::MessageDeserializer>(helper_, s,
                                                                boost::shared_ptr<ros::M_string>());
    queue_->push(helper_, d, false, ros::VoidConstWPtr(), true);
    q->addCallback(queue_, reinterpret_cast<uint64_t>(queue_.get()));
  }

 private:
  boost::shared_ptr<ros::SubscriptionQueue> queue_;
  ros::SubscriptionCallbackHelperPtr helper_;
};

/// A callback that is not a message (as a timer's).
class Plain : public ros::CallbackInterface {
 public:
  explicit Plain(std::function<void()> f) : f_(std::move(f)) {}
  CallResult call() override {
    f_();
    return Success;
  }

 private:
  std::function<void()> f_;
};

TEST(InlineCallbackQueue, MessageRunsInTheDeliveringThread) {
  InlineCallbackQueue q;
  std::vector<int> got;
  std::thread::id where;
  FakeSubscription sub([&](int v) {
    got.push_back(v);
    where = std::this_thread::get_id();
  });
  sub.deliver(&q, 7);
  ASSERT_EQ(got, std::vector<int>({7}));  // before addCallback returned
  EXPECT_EQ(where, std::this_thread::get_id());
}

TEST(InlineCallbackQueue, TimerWaitsForTheQueuesThread) {
  InlineCallbackQueue q;
  int calls = 0;
  q.addCallback(boost::make_shared<Plain>([&] { ++calls; }), 1);
  EXPECT_EQ(calls, 0);
  q.callAvailable(ros::WallDuration(0.0));
  EXPECT_EQ(calls, 1);
}

TEST(InlineCallbackQueue, WhileACallbackRunsOthersWaitInOrder) {
  InlineCallbackQueue q;
  std::vector<int> got;
  std::promise<void> entered, release;
  std::shared_future<void> released = release.get_future().share();
  FakeSubscription sub([&](int v) {
    got.push_back(v);
    if (v == 1) {
      entered.set_value();
      released.wait();
    }
  });
  std::thread other([&] { sub.deliver(&q, 1); });  // runs inline there and blocks
  entered.get_future().wait();
  sub.deliver(&q, 2);  // the lock is taken: to the backlog
  int timer = 0;
  q.addCallback(boost::make_shared<Plain>([&] { ++timer; }), 1);
  EXPECT_EQ(got, std::vector<int>({1}));
  release.set_value();
  other.join();
  sub.deliver(&q, 3);  // free now, but behind the backlog: waits too
  EXPECT_EQ(got, std::vector<int>({1}));
  q.callAvailable(ros::WallDuration(0.0));
  EXPECT_EQ(got, std::vector<int>({1, 2, 3}));
  EXPECT_EQ(timer, 1);
}

TEST(InlineCallbackQueue, ACallbackDoesNotRunAnotherInsideItself) {
  InlineCallbackQueue q;
  std::vector<int> got;
  FakeSubscription* self = nullptr;
  FakeSubscription sub([&](int v) {
    got.push_back(v);
    if (v == 1) {
      self->deliver(&q, 2);  // a node publishing to itself
      got.push_back(-1);     // back in the first callback before the second ran
    }
  });
  self = &sub;
  sub.deliver(&q, 1);
  EXPECT_EQ(got, std::vector<int>({1, -1}));
  q.callAvailable(ros::WallDuration(0.0));
  EXPECT_EQ(got, std::vector<int>({1, -1, 2}));
}

TEST(InlineCallbackQueue, RemovedOwnersCallbacksDoNotRun) {
  InlineCallbackQueue q;
  int calls = 0;
  q.addCallback(boost::make_shared<Plain>([&] { ++calls; }), 5);
  q.removeByID(5);
  q.callAvailable(ros::WallDuration(0.0));
  EXPECT_EQ(calls, 0);
}

}  // namespace
