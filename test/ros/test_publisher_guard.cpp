/// \file test_publisher_guard.cpp
/// \brief PublisherGuard (~accept_from) without a master: which caller ids pass,
/// what a drop counts and warns, how names are checked and resolved.

#include <gtest/gtest.h>

#include <string>
#include <thread>
#include <vector>

#include "preadaptive_mrac/ros/publisher_guard.hpp"

namespace pm = preadaptive_mrac;
using pm::ros1::PublisherGuard;

namespace {

struct Warnings {
  std::vector<std::string> lines;
  PublisherGuard::Warn sink() {
    return [this](const std::string& w) { lines.push_back(w); };
  }
};

/// What a ros::MessageEvent offers the guard.
struct FakeEvent {
  std::string caller;
  mutable int asked = 0;
  const std::string& getPublisherName() const {
    ++asked;
    return caller;
  }
};

}  // namespace

TEST(PublisherGuard, EmptyListAcceptsEveryPublisher) {
  PublisherGuard g;
  EXPECT_FALSE(g.enabled());
  EXPECT_TRUE(g.admit("/anyone", "/plant/state"));
  EXPECT_TRUE(g.admit("", "/plant/state"));
  EXPECT_EQ(g.dropped(), 0);
  EXPECT_EQ(g.acceptedText(), "any publisher");
  EXPECT_EQ(g.droppedText(), "none");
  // Off: the connection header is not even looked at.
  FakeEvent e{"/stray"};
  EXPECT_TRUE(g.admitEvent(e, "/plant/state"));
  EXPECT_EQ(e.asked, 0);
}

TEST(PublisherGuard, OnlyTheListedCallerIdsPassExactly) {
  Warnings w;
  PublisherGuard g({"/mrac_controller", "/pmrac_manager"}, "/plant_sim/accept_from", w.sink());
  EXPECT_TRUE(g.enabled());
  EXPECT_TRUE(g.admit("/mrac_controller", "/controller/elevator_cmd"));
  EXPECT_TRUE(g.admit("/pmrac_manager", "/controller/elevator_cmd"));
  // No prefix, suffix, namespace or case matching: a caller id is one exact name.
  for (const char* other : {"/mrac_controller2", "/mrac", "mrac_controller", "/rac/mrac_controller",
                            "/MRAC_CONTROLLER", "", "unknown_publisher"}) {
    EXPECT_FALSE(g.admit(other, "/controller/elevator_cmd")) << other;
  }
  EXPECT_EQ(g.dropped(), 7);
  EXPECT_EQ(w.lines.size(), 7u);
  EXPECT_EQ(g.acceptedText(), "/mrac_controller, /pmrac_manager");
}

TEST(PublisherGuard, DropsAreCountedAndWarnedOncePerPublisherAndTopic) {
  Warnings w;
  PublisherGuard g({"/plant_sim"}, "/mrac_controller/accept_from", w.sink());
  for (int i = 0; i < 5; ++i) EXPECT_FALSE(g.admit("/stray_plant", "/plant/state"));
  ASSERT_EQ(w.lines.size(), 1u);
  const std::string& line = w.lines[0];
  EXPECT_NE(line.find("/stray_plant"), std::string::npos) << line;
  EXPECT_NE(line.find("/plant/state"), std::string::npos) << line;
  EXPECT_NE(line.find("/mrac_controller/accept_from: /plant_sim"), std::string::npos) << line;
  // The same publisher on another topic, and another publisher: one warning each.
  EXPECT_FALSE(g.admit("/stray_plant", "/plant/truth"));
  EXPECT_FALSE(g.admit("/other", "/plant/state"));
  EXPECT_FALSE(g.admit("/other", "/plant/state"));
  EXPECT_EQ(w.lines.size(), 3u);
  EXPECT_TRUE(g.admit("/plant_sim", "/plant/state"));
  EXPECT_EQ(g.dropped(), 8);
  EXPECT_EQ(g.droppedText(),
            "/other on /plant/state: 2, /stray_plant on /plant/state: 5, "
            "/stray_plant on /plant/truth: 1");
}

TEST(PublisherGuard, AdmitEventReadsTheCallerId) {
  PublisherGuard g({"/plant_sim"});
  FakeEvent good{"/plant_sim"}, bad{"/stray"};
  EXPECT_TRUE(g.admitEvent(good, "/plant/state"));
  EXPECT_FALSE(g.admitEvent(bad, "/plant/state"));
  EXPECT_EQ(good.asked, 1);
  EXPECT_EQ(g.dropped(), 1);
}

TEST(PublisherGuard, NamesAreBoundedButEveryDropCounted) {
  Warnings w;
  PublisherGuard g({"/plant_sim"}, "~accept_from", w.sink());
  const int n = static_cast<int>(PublisherGuard::kMaxNamed) + 10;
  for (int i = 0; i < n; ++i) EXPECT_FALSE(g.admit("/stray_" + std::to_string(i), "/t"));
  for (int i = 0; i < n; ++i) EXPECT_FALSE(g.admit("/stray_" + std::to_string(i), "/t"));
  EXPECT_EQ(g.dropped(), 2 * n);
  EXPECT_EQ(w.lines.size(), PublisherGuard::kMaxNamed);
  EXPECT_NE(w.lines.back().find("counted without a name"), std::string::npos) << w.lines.back();
  EXPECT_NE(g.droppedText().find("and 20 more message(s) from other publishers"), std::string::npos)
      << g.droppedText();
}

TEST(PublisherGuard, ConcurrentDropsAreAllCounted) {
  PublisherGuard g({"/plant_sim"});
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t) {
    threads.emplace_back([&g, t] {
      for (int i = 0; i < 10000; ++i) {
        g.admit("/stray_" + std::to_string(t), "/plant/state");
        g.admit("/plant_sim", "/plant/state");
      }
    });
  }
  for (auto& th : threads) th.join();
  EXPECT_EQ(g.dropped(), 40000);
}

TEST(CallerNames, ValidNames) {
  std::string why;
  for (const char* ok : {"/mrac_controller", "mrac_controller", "/rac/plant_sim", "pa/plant_sim",
                         "/pmrac_manager", "/rostopic_4321_1700000000000", "/a_1/b_2"}) {
    EXPECT_TRUE(pm::ros1::validCallerName(ok, &why)) << ok << ": " << why;
  }
}

TEST(CallerNames, InvalidNamesSayWhy) {
  const std::vector<std::pair<std::string, std::string>> bad = {
      {"", "empty"},
      {"~plant", "private"},
      {"1node", "start with a letter"},
      {"/plant sim", "character ' '"},
      {"/plant-sim", "character '-'"},
      {"/", "empty name component"},
      {"/rac/", "empty name component"},
      {"/rac//plant", "empty name component"},
  };
  for (const auto& b : bad) {
    std::string why;
    EXPECT_FALSE(pm::ros1::validCallerName(b.first, &why)) << b.first;
    EXPECT_NE(why.find(b.second), std::string::npos) << b.first << ": " << why;
  }
}

TEST(CallerNames, RelativeNamesResolveInTheNodesNamespace) {
  using pm::ros1::resolveCallerName;
  EXPECT_EQ(resolveCallerName("/", "mrac_controller"), "/mrac_controller");
  EXPECT_EQ(resolveCallerName("", "mrac_controller"), "/mrac_controller");
  EXPECT_EQ(resolveCallerName("/rac", "mrac_controller"), "/rac/mrac_controller");
  EXPECT_EQ(resolveCallerName("/rac/", "pmrac_manager"), "/rac/pmrac_manager");
  EXPECT_EQ(resolveCallerName("/rac", "/pmrac_manager"), "/pmrac_manager");
  EXPECT_EQ(pm::ros1::resolveCallerNames("/pa", {"plant_sim", "/x"}),
            (std::vector<std::string>{"/pa/plant_sim", "/x"}));
}
