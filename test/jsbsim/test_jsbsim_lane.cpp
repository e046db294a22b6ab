/// \file test_jsbsim_lane.cpp
/// \brief The shared-memory lane on its own (no JSBSim): the rings keep bytes in order across
/// their end and when full, a reader waits as long as asked and wakes for a writer, and the
/// environment JSBSim is started with names the lane. The lane carrying JSBSim's own bytes is
/// test_jsbsim's Jsbsim.SharedMemoryCarriesTheSocketsBytes.

#include <fcntl.h>
#include <gtest/gtest.h>
#include <stdlib.h>
#include <sys/mman.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "preadaptive_mrac/jsbsim/jsbsim_lane.hpp"
#include "preadaptive_mrac/jsbsim/jsbsim_lane_ring.hpp"

namespace preadaptive_mrac {
namespace {

std::string pattern(size_t n, size_t from) {
  std::string s(n, '\0');
  for (size_t i = 0; i < n; ++i) s[i] = static_cast<char>('a' + (from + i) % 26);
  return s;
}

TEST(JsbsimLaneRing, KeepsTheBytesInOrderAcrossItsEnd) {
  auto r = std::make_unique<lane::Ring>();
  // Chunks of a size that does not divide the ring: writes and reads cross its end.
  const size_t chunk = 100003;
  std::string got;
  for (size_t k = 0, sent = 0; k < 12; ++k, sent += chunk) {
    const std::string out = pattern(chunk, sent);
    ASSERT_EQ(lane::write(r.get(), out.data(), out.size()), chunk);
    std::string in(chunk, '\0');
    ASSERT_EQ(lane::read(r.get(), &in[0], 70001), 70001u);
    ASSERT_EQ(lane::read(r.get(), &in[70001], chunk), chunk - 70001);
    ASSERT_EQ(in, out) << "chunk " << k;
  }
  EXPECT_EQ(lane::available(*r), 0u);
}

TEST(JsbsimLaneRing, AFullRingTakesWhatFitsAndTheWriterWaitsForRoom) {
  auto r = std::make_unique<lane::Ring>();
  const std::string big = pattern(lane::kRingBytes + 5000, 0);
  EXPECT_EQ(lane::write(r.get(), big.data(), big.size()), lane::kRingBytes);
  EXPECT_EQ(lane::write(r.get(), "x", 1), 0u);
  std::string in(lane::kRingBytes, '\0');
  ASSERT_EQ(lane::read(r.get(), &in[0], in.size()), lane::kRingBytes);
  EXPECT_EQ(in, big.substr(0, lane::kRingBytes));
  // Three ring-fulls through a reader on another thread: nothing lost, nothing reordered.
  const std::string many = pattern(3 * lane::kRingBytes + 777, 11);
  std::string seen;
  std::thread reader([&] {
    std::vector<char> buf(4096);
    while (seen.size() < many.size()) {
      const size_t n = lane::read(r.get(), buf.data(), buf.size());
      seen.append(buf.data(), n);
      if (n == 0) std::this_thread::yield();
    }
  });
  EXPECT_TRUE(lane::writeAll(r.get(), many.data(), many.size(), 1000000L, [] { return true; }));
  reader.join();
  EXPECT_EQ(seen, many);
  // A writer whose reader is gone stops instead of waiting for ever.
  ASSERT_EQ(lane::write(r.get(), big.data(), lane::kRingBytes), lane::kRingBytes);
  EXPECT_FALSE(lane::writeAll(r.get(), "y", 1, 1000000L, [] { return false; }));
}

class JsbsimLaneFile : public ::testing::Test {
 protected:
  void SetUp() override {
    char t[] = "/tmp/pmrac_lane_test_XXXXXX";
    ASSERT_NE(::mkdtemp(t), nullptr);
    dir_ = t;
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::string dir_;
};

TEST_F(JsbsimLaneFile, AReaderWaitsAsLongAsAskedAndWakesForAWriter) {
  JsbsimLane l(dir_ + "/lane");
  EXPECT_FALSE(l.attached());
  std::string into;
  const auto t0 = std::chrono::steady_clock::now();
  EXPECT_FALSE(l.receive(true, &into, 50));
  const double waited =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_GE(waited, 0.045);
  EXPECT_LT(waited, 1.0);
  EXPECT_EQ(JsbsimLane::tryMake(dir_ + "/lane"), nullptr);  // one lane per file
  // The writer's side is JSBSim's preload library in a run: here the file mapped again, as it
  // maps it, written 100 ms after the reader began to wait.
  const int fd = ::open((dir_ + "/lane").c_str(), O_RDWR);
  ASSERT_GE(fd, 0);
  void* m = ::mmap(nullptr, sizeof(lane::Shared), PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0);
  ::close(fd);
  ASSERT_NE(m, MAP_FAILED);
  auto* shared = static_cast<lane::Shared*>(m);
  EXPECT_EQ(shared->magic, lane::kMagic);
  shared->attached.store(1);
  EXPECT_TRUE(l.attached());
  std::thread writer([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    lane::write(&shared->outputs, "line\n", 5);
  });
  const auto t1 = std::chrono::steady_clock::now();
  EXPECT_TRUE(l.receive(true, &into, 5000));
  const double woke = std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
  writer.join();
  EXPECT_EQ(into, "line\n");
  EXPECT_GE(woke, 0.09);
  EXPECT_LT(woke, 2.0);
  EXPECT_FALSE(l.receive(false, &into, 0));  // the other ring is empty
  ::munmap(m, sizeof(lane::Shared));
}

TEST_F(JsbsimLaneFile, JsbsimsEnvironmentNamesTheLaneAndKeepsTheRest) {
  ::setenv("LD_PRELOAD", "/x/libother.so", 1);
  ::setenv("PMRAC_JSBSIM_LANE", "/stale/lane", 1);
  ::setenv("PMRAC_LANE_TEST_KEEP", "kept", 1);
  JsbsimLane l(dir_ + "/lane");
  const auto env = JsbsimLane::childEnvironment(&l, "/lib/libpmrac_jsbsim_lane.so", 4100, 4200);
  const auto none = JsbsimLane::childEnvironment(nullptr, "", 0, 0);
  ::unsetenv("LD_PRELOAD");
  ::unsetenv("PMRAC_JSBSIM_LANE");
  ::unsetenv("PMRAC_LANE_TEST_KEEP");
  auto count = [](const std::vector<std::string>& e, const std::string& prefix) {
    size_t n = 0;
    for (const auto& s : e) n += s.compare(0, prefix.size(), prefix) == 0;
    return n;
  };
  auto has = [](const std::vector<std::string>& e, const std::string& s) {
    for (const auto& x : e)
      if (x == s) return true;
    return false;
  };
  EXPECT_TRUE(has(env, "LD_PRELOAD=/lib/libpmrac_jsbsim_lane.so:/x/libother.so"));
  EXPECT_TRUE(has(env, "PMRAC_JSBSIM_LANE=" + dir_ + "/lane"));
  EXPECT_TRUE(has(env, "PMRAC_JSBSIM_LANE_IN=4100"));
  EXPECT_TRUE(has(env, "PMRAC_JSBSIM_LANE_OUT=4200"));
  EXPECT_TRUE(has(env, "PMRAC_LANE_TEST_KEEP=kept"));
  EXPECT_EQ(count(env, "LD_PRELOAD="), 1u);
  EXPECT_EQ(count(env, "PMRAC_JSBSIM_LANE="), 1u);
  // Without a lane: the user's preload as it was, no stale lane for JSBSim to attach to.
  EXPECT_TRUE(has(none, "LD_PRELOAD=/x/libother.so"));
  EXPECT_EQ(count(none, "PMRAC_JSBSIM_LANE"), 0u);
}

}  // namespace
}  // namespace preadaptive_mrac
