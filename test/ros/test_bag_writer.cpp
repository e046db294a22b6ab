// BagWriter (src/ros/bag_writer.cpp) without a master: the same calls written with rosbag::Bag
// (uncompressed, the same chunk threshold) give the same file, byte for byte, and rosbag
// reads it back.
#include <gtest/gtest.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <std_msgs/Float64.h>
#include <tf2_msgs/TFMessage.h>
#include <topic_tools/shape_shifter.h>

#include <boost/make_shared.hpp>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "preadaptive_mrac/ElevatorCommand.h"
#include "preadaptive_mrac/PlantState.h"
#include "preadaptive_mrac/ros/bag_writer.hpp"

namespace {

using preadaptive_mrac::ElevatorCommand;
using preadaptive_mrac::PlantState;
using preadaptive_mrac::ros1::BagWriter;
using preadaptive_mrac::ros1::publisherConnectionHeader;

std::vector<char> contents(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  return std::vector<char>(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>());
}

std::string tmpPath(const std::string& name) {
  return ::testing::TempDir() + "pmrac_test_bag_writer_" + name + ".bag";
}

/// Writes the same messages into a rosbag::Bag and a BagWriter.
struct BothBags {
  BothBags(const std::string& name, std::uint32_t threshold)
      : ref_path(tmpPath(name + "_rosbag")), path(tmpPath(name)) {
    ref.setChunkThreshold(threshold);
    ref.open(ref_path, rosbag::bagmode::Write);
    ours.open(path, threshold);
  }
  ~BothBags() {
    std::remove(ref_path.c_str());
    std::remove(path.c_str());
  }
  template <class M>
  void write(const std::string& topic, const ros::Time& t, const M& m,
             const boost::shared_ptr<ros::M_string>& header) {
    ref.write(topic, t, m, header);
    ours.write(topic, t, m, header);
    // rosbag's size is as of the end of the file before this message's record.
    EXPECT_GT(ours.size(), ref.getSize()) << topic << " at " << t;
  }
  void close() {
    ref.close();
    ours.close();
    EXPECT_EQ(ours.size(), contents(path).size());
  }
  std::string ref_path, path;
  rosbag::Bag ref;
  BagWriter ours;
};

PlantState state(std::uint64_t k) {
  PlantState m;
  m.header.stamp = ros::Time(1.0 + 1e-3 * static_cast<double>(k));
  m.step = k;
  m.total_steps = 100000;
  m.x = {1e-3 * static_cast<double>(k), -2.0, 0.5};
  return m;
}

TEST(BagWriter, SameBytesAsRosbagOverManyChunks) {
  BothBags b("chunks", 4096);  // about 25 messages a chunk: many chunks and their indexes
  const auto st_hdr = publisherConnectionHeader<PlantState>("/plant/state", "/plant");
  const auto cmd_hdr =
      publisherConnectionHeader<ElevatorCommand>("/controller/elevator_cmd", "/ctl");
  const auto tf_hdr = publisherConnectionHeader<tf2_msgs::TFMessage>("/tf", "/plant");
  for (std::uint64_t k = 0; k < 3000; ++k) {
    const PlantState st = state(k);
    b.write("/plant/state", st.header.stamp, st, st_hdr);
    ElevatorCommand cmd;
    cmd.header.stamp = st.header.stamp;
    cmd.step = k;
    cmd.u = -0.01 * static_cast<double>(k % 7);
    b.write("/controller/elevator_cmd", cmd.header.stamp, cmd, cmd_hdr);
    if (k % 10 == 0) {
      tf2_msgs::TFMessage tf;
      tf.transforms.resize(1);
      tf.transforms[0].header.stamp = st.header.stamp;
      tf.transforms[0].child_frame_id = "aircraft";
      // Out of time order now and then (earlier than the chunk's start), and equal times:
      // the index sorts by time, ties in the order written, as rosbag's.
      const ros::Time t =
          k % 40 == 0 ? ros::Time(0.5 + 1e-3 * static_cast<double>(k)) : st.header.stamp;
      b.write("/tf", t, tf, tf_hdr);
    }
  }
  b.close();
  const std::vector<char> ref = contents(b.ref_path), ours = contents(b.path);
  ASSERT_GT(ref.size(), 100000u);
  ASSERT_EQ(ours.size(), ref.size());
  EXPECT_TRUE(ours == ref) << "first difference at byte "
                           << (std::mismatch(ours.begin(), ours.end(), ref.begin()).first -
                               ours.begin());

  rosbag::Bag in(b.path, rosbag::bagmode::Read);
  rosbag::View states(in, rosbag::TopicQuery("/plant/state"));
  ASSERT_EQ(states.size(), 3000u);
  std::uint64_t k = 0;
  for (const rosbag::MessageInstance& m : states) {
    const auto s = m.instantiate<PlantState>();
    ASSERT_TRUE(s);
    EXPECT_EQ(s->step, k);
    EXPECT_EQ(s->x[0], 1e-3 * static_cast<double>(k));
    ++k;
  }
}

TEST(BagWriter, ConnectionsAsRosbagCountsThem) {
  BothBags b("connections", 768 * 1024);
  // No connection header (one connection per topic); two publishers on one topic; the same
  // header's contents at another address (the same connection); a ShapeShifter.
  std_msgs::Float64 f;
  f.data = 2.5;
  const auto a = publisherConnectionHeader<std_msgs::Float64>("/x", "/a");
  const auto a_copy = boost::make_shared<ros::M_string>(*a);
  const auto c = publisherConnectionHeader<std_msgs::Float64>("/x", "/c");
  topic_tools::ShapeShifter shifter;
  {
    std::vector<std::uint8_t> buf(ros::serialization::serializationLength(f));
    ros::serialization::OStream os(buf.data(), static_cast<std::uint32_t>(buf.size()));
    ros::serialization::serialize(os, f);
    shifter.morph(ros::message_traits::md5sum(f), ros::message_traits::datatype(f),
                  ros::message_traits::definition(f), "0");
    ros::serialization::IStream is(buf.data(), static_cast<std::uint32_t>(buf.size()));
    ros::serialization::deserialize(is, shifter);
  }
  for (int i = 0; i < 3; ++i) {
    const ros::Time t(10 + i, 0);
    b.write("/x", t, f, a);
    b.write("/x", t, f, c);
    b.write("/x", t, f, a_copy);
    b.write("/y", t, f, boost::shared_ptr<ros::M_string>());
    b.write("/z", t, shifter, a);  // the same header on another topic: another connection
  }
  b.close();
  EXPECT_TRUE(contents(b.path) == contents(b.ref_path));
  rosbag::Bag in(b.path, rosbag::bagmode::Read);
  rosbag::View all(in);
  EXPECT_EQ(all.size(), 15u);
  EXPECT_EQ(all.getConnections().size(), 4u);
}

TEST(BagWriter, AnEmptyBagAndAReopenedWriter) {
  const std::string ref_path = tmpPath("empty_rosbag"), path = tmpPath("empty");
  { rosbag::Bag ref(ref_path, rosbag::bagmode::Write); }
  BagWriter w;
  w.open(path, 1024);
  w.write("/old", ros::Time(1, 0), state(1));
  w.close();
  w.close();  // idempotent
  // Nothing of the first file carries over into the next.
  w.open(path, 1024);
  w.close();
  EXPECT_TRUE(contents(path) == contents(ref_path));
  EXPECT_EQ(contents(path).size(), 13u + 4104u);
  std::remove(ref_path.c_str());
  std::remove(path.c_str());
}

TEST(BagWriter, RefusesAFileItCannotCreate) {
  BagWriter w;
  try {
    w.open("/nonexistent_dir_pmrac/x.bag", 1024);
    FAIL() << "opened a file in a directory that does not exist";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent_dir_pmrac/x.bag"), std::string::npos)
        << e.what();
  }
  EXPECT_FALSE(w.isOpen());
}

}  // namespace
