#include "preadaptive_mrac/ros/latency_stats.hpp"

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <numeric>

namespace preadaptive_mrac {
namespace ros1 {
namespace {

double nearestRank(const std::vector<double>& sorted, double p) {
  const auto n = sorted.size();
  auto rank = static_cast<std::size_t>(std::ceil(p * static_cast<double>(n)));
  rank = std::max<std::size_t>(1, std::min(rank, n));
  return sorted[rank - 1];
}

}  // namespace

LatencySummary summarizeLatency(std::vector<double> samples_us) {
  LatencySummary s;
  s.count = samples_us.size();
  if (samples_us.empty()) return s;
  std::sort(samples_us.begin(), samples_us.end());
  s.p50_us = nearestRank(samples_us, 0.50);
  s.p99_us = nearestRank(samples_us, 0.99);
  s.max_us = samples_us.back();
  s.mean_us = std::accumulate(samples_us.begin(), samples_us.end(), 0.0) /
              static_cast<double>(samples_us.size());
  return s;
}

std::string runReportJson(const RunReport& r) {
  nlohmann::ordered_json j;
  j["clock"] = r.clock;
  j["scenario"] = r.scenario;
  j["dt"] = r.dt;
  j["rate_hz"] = r.rate_hz;
  j["steps"] = r.steps;
  j["total_steps"] = r.total_steps;
  j["completed"] = r.completed;
  j["wall_time_s"] = r.wall_time_s;
  j["commands_received"] = r.commands_received;
  j["commands_ignored"] = r.commands_ignored;
  j["stale_steps"] = r.stale_steps;
  j["late_ticks"] = r.late_ticks;
  j["resent_states"] = r.resent_states;
  j["recorder_waits"] = r.recorder_waits;
  j["scheduling"] = r.scheduling;
  j["tick_late_us"] = {
      {"p50", r.tick_late.p50_us}, {"p99", r.tick_late.p99_us}, {"max", r.tick_late.max_us}};
  j["latency_us"] = {{"count", r.latency.count},
                     {"p50", r.latency.p50_us},
                     {"p99", r.latency.p99_us},
                     {"max", r.latency.max_us},
                     {"mean", r.latency.mean_us}};
  return j.dump();
}

}  // namespace ros1
}  // namespace preadaptive_mrac
