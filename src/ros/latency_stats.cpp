#include "preadaptive_mrac/ros/latency_stats.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <sstream>

namespace preadaptive_mrac {
namespace ros1 {
namespace {

double nearestRank(const std::vector<double>& sorted, double p) {
  const auto n = sorted.size();
  auto rank = static_cast<std::size_t>(std::ceil(p * static_cast<double>(n)));
  rank = std::max<std::size_t>(1, std::min(rank, n));
  return sorted[rank - 1];
}

std::string jsonString(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    switch (c) {
      case '"':
        out += "\\\"";
        break;
      case '\\':
        out += "\\\\";
        break;
      case '\n':
        out += "\\n";
        break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) {
          char buf[8];
          std::snprintf(buf, sizeof(buf), "\\u%04x", static_cast<unsigned>(c));
          out += buf;
        } else {
          out += c;
        }
    }
  }
  return out + "\"";
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
  std::ostringstream os;
  os.precision(10);
  os << "{\"clock\": " << jsonString(r.clock) << ", \"scenario\": " << jsonString(r.scenario)
     << ", \"dt\": " << r.dt << ", \"rate_hz\": " << r.rate_hz << ", \"steps\": " << r.steps
     << ", \"total_steps\": " << r.total_steps
     << ", \"completed\": " << (r.completed ? "true" : "false")
     << ", \"wall_time_s\": " << r.wall_time_s << ", \"commands_received\": " << r.commands_received
     << ", \"commands_ignored\": " << r.commands_ignored << ", \"stale_steps\": " << r.stale_steps
     << ", \"late_ticks\": " << r.late_ticks << ", \"resent_states\": " << r.resent_states
     << ", \"recorder_waits\": " << r.recorder_waits
     << ", \"latency_us\": {\"count\": " << r.latency.count << ", \"p50\": " << r.latency.p50_us
     << ", \"p99\": " << r.latency.p99_us << ", \"max\": " << r.latency.max_us
     << ", \"mean\": " << r.latency.mean_us << "}}";
  return os.str();
}

}  // namespace ros1
}  // namespace preadaptive_mrac
