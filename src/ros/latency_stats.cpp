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

std::size_t LatencyStats::binOf(double us) {
  if (!(us >= 1.0)) return 0;
  const double b = 1.0 + std::floor(std::log(us) / std::log(kRatio));
  return b >= static_cast<double>(kBins - 1) ? kBins - 1 : static_cast<std::size_t>(b);
}

void LatencyStats::add(double us) {
  if (!std::isfinite(us)) {
    ++non_finite_;
    return;
  }
  if (count_ == 0 || us < min_) min_ = us;
  if (count_ == 0 || us > max_) max_ = us;
  ++count_;
  sum_ += us;
  ++bins_[binOf(us)];
}

double LatencyStats::percentile(double p) const {
  auto rank = static_cast<std::uint64_t>(std::ceil(p * static_cast<double>(count_)));
  rank = std::max<std::uint64_t>(1, std::min(rank, count_));
  std::uint64_t seen = 0;
  std::size_t b = 0;
  for (; b < kBins; ++b) {
    seen += bins_[b];
    if (seen >= rank) break;
  }
  // Bin b >= 1 holds [kRatio^(b-1), kRatio^b); bin 0 everything below 1 us (said as 0), the
  // last everything above kTopUs (said as the largest sample).
  const double mid = b == 0           ? 0.0
                     : b >= kBins - 1 ? max_
                                      : std::pow(kRatio, static_cast<double>(b) - 0.5);
  return std::max(min_, std::min(max_, mid));
}

LatencySummary LatencyStats::summary() const {
  LatencySummary s;
  s.count = static_cast<std::size_t>(count_);
  if (count_ == 0) return s;
  s.p50_us = percentile(0.50);
  s.p99_us = percentile(0.99);
  s.max_us = max_;
  s.mean_us = sum_ / static_cast<double>(count_);
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
