/// \file bench_bag_writer.cpp
/// \brief The recorder's writing alone, no ROS communication: a lockstep run's messages (per
/// step a PlantState, a PlantTruth, a tf, an ElevatorCommand and an AdaptationStatus, each
/// with a subscriber's connection header) written into a bag by rosbag::Bag (the recorder
/// before) and by BagWriter (after), alternately, wall time of each. Not a test: it prints
/// what it measured (medians), and the system calls of either can be counted with
/// `strace -c -f`.
///
///   bench_bag_writer [--steps 140000] [--reps 3] [--dir /tmp] [--only rosbag|writer]

#include <rosbag/bag.h>
#include <tf2_msgs/TFMessage.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

#include "preadaptive_mrac/AdaptationStatus.h"
#include "preadaptive_mrac/ElevatorCommand.h"
#include "preadaptive_mrac/PlantState.h"
#include "preadaptive_mrac/PlantTruth.h"
#include "preadaptive_mrac/ros/bag_writer.hpp"

namespace {

namespace pm = preadaptive_mrac;
using pm::ros1::publisherConnectionHeader;

/// Write `steps` lockstep steps into `bag` (rosbag::Bag or BagWriter: the same write call).
template <class Bag>
void writeRun(Bag& bag, std::uint64_t steps) {
  const auto st_h = publisherConnectionHeader<pm::PlantState>("/plant/state", "/plant_sim");
  const auto tr_h = publisherConnectionHeader<pm::PlantTruth>("/plant/truth", "/plant_sim");
  const auto tf_h = publisherConnectionHeader<tf2_msgs::TFMessage>("/tf", "/plant_sim");
  const auto cmd_h =
      publisherConnectionHeader<pm::ElevatorCommand>("/controller/elevator_cmd", "/ctl");
  const auto ad_h =
      publisherConnectionHeader<pm::AdaptationStatus>("/controller/adaptation", "/ctl");
  pm::PlantState st;
  st.x = {0.0, 0.0, 0.0};
  st.total_steps = steps;
  pm::PlantTruth tr;
  tf2_msgs::TFMessage tf;
  tf.transforms.resize(1);
  tf.transforms[0].header.frame_id = "world";
  tf.transforms[0].child_frame_id = "aircraft";
  pm::ElevatorCommand cmd;
  pm::AdaptationStatus ad;
  for (std::uint64_t k = 0; k < steps; ++k) {
    const ros::Time t(1.0 + 1e-3 * static_cast<double>(k));
    st.header.stamp = tr.header.stamp = cmd.header.stamp = ad.header.stamp = t;
    tf.transforms[0].header.stamp = t;
    st.step = cmd.step = ad.step = tr.step = k;
    st.x[1] = 1e-3 * static_cast<double>(k);
    bag.write("/plant/truth", t, tr, tr_h);
    bag.write("/tf", t, tf, tf_h);
    bag.write("/plant/state", t, st, st_h);
    bag.write("/controller/elevator_cmd", t, cmd, cmd_h);
    bag.write("/controller/adaptation", t, ad, ad_h);
  }
}

double seconds(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"bag writing cost: rosbag::Bag against BagWriter"};
  std::uint64_t steps = 140000;
  int reps = 3;
  std::string dir = "/tmp", only;
  app.add_option("--steps", steps, "lockstep steps (5 messages each)");
  app.add_option("--reps", reps, "runs of each, alternated");
  app.add_option("--dir", dir, "where the bags go (removed after each run)");
  app.add_option("--only", only, "rosbag or writer: run one of them (for strace -c)")
      ->check(CLI::IsMember({"rosbag", "writer"}));
  CLI11_PARSE(app, argc, argv);
  const std::string path = dir + "/pmrac_bench_bag_writer.bag";
  std::vector<double> t_rosbag, t_writer;
  for (int r = 0; r < reps; ++r) {
    if (only != "writer") {
      const auto t0 = std::chrono::steady_clock::now();
      rosbag::Bag bag(path, rosbag::bagmode::Write);
      writeRun(bag, steps);
      bag.close();
      t_rosbag.push_back(seconds(t0));
    }
    if (only != "rosbag") {
      const auto t0 = std::chrono::steady_clock::now();
      pm::ros1::BagWriter bag;
      bag.open(path, 768 * 1024);
      writeRun(bag, steps);
      bag.close();
      t_writer.push_back(seconds(t0));
    }
    std::remove(path.c_str());
  }
  const double n = 5.0 * static_cast<double>(steps);
  if (!t_rosbag.empty())
    std::printf("rosbag::Bag: %.3f s (median of %d), %.2f us a message\n", median(t_rosbag), reps,
                1e6 * median(t_rosbag) / n);
  if (!t_writer.empty())
    std::printf("BagWriter:   %.3f s (median of %d), %.2f us a message\n", median(t_writer), reps,
                1e6 * median(t_writer) / n);
  return 0;
}
