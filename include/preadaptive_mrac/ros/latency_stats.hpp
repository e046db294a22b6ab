#pragma once
/// \file latency_stats.hpp
/// \brief Round-trip statistics of the plant node (state published -> command received) and
/// its JSON report. ROS-free.

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace preadaptive_mrac {
namespace ros1 {

/// \brief Summary of a set of latency samples [us].
struct LatencySummary {
  std::size_t count = 0;
  double p50_us = 0.0, p99_us = 0.0, max_us = 0.0, mean_us = 0.0;
};

/// \brief Nearest-rank percentiles (p50 = the ceil(0.5 n)-th smallest sample) of `samples_us`;
/// all zero for no samples. Sorts a copy.
LatencySummary summarizeLatency(std::vector<double> samples_us);

/// \brief Latency samples [us] kept in a fixed histogram: its memory does not grow with the
/// number of samples, so a run of any length costs the same. Bins are log-spaced by a factor
/// kRatio from 1 us to kTopUs; a percentile is the geometric middle of the nearest-rank sample's
/// bin (relative error <= (kRatio - 1) / 2, 0.25 %), clamped to the smallest and largest sample;
/// count, mean and max are exact. Samples below 1 us (and negative ones: clocks of two hosts)
/// fall into the first bin, whose percentile is 0, clamped; above kTopUs into the last.
class LatencyStats {
 public:
  static constexpr double kRatio = 1.005;
  static constexpr double kTopUs = 1e10;      ///< 10^4 s
  static constexpr std::size_t kBins = 4619;  ///< ceil(ln(kTopUs) / ln(kRatio)) + 2

  /// \brief Add one sample; non-finite samples are counted apart and never binned.
  void add(double us);
  /// \brief Nearest-rank p50 and p99, exact max and mean of the finite samples.
  LatencySummary summary() const;
  /// \brief Samples that were NaN or infinite (not in the summary).
  std::uint64_t nonFinite() const { return non_finite_; }

 private:
  static std::size_t binOf(double us);
  double percentile(double p) const;

  std::array<std::uint64_t, kBins> bins_{};
  std::uint64_t count_ = 0, non_finite_ = 0;
  double sum_ = 0.0, min_ = 0.0, max_ = 0.0;
};

/// \brief What the plant node reports at the end of a run.
struct RunReport {
  std::string clock;                   ///< lockstep | realtime
  std::string scenario;                ///< scenario name
  double dt = 0.0;                     ///< step [s]
  double rate_hz = 0.0;                ///< realtime tick rate [Hz] (0 in lockstep)
  std::int64_t steps = 0;              ///< steps integrated
  std::int64_t total_steps = 0;        ///< steps of the scenario
  bool completed = false;              ///< reached the scenario's end
  double wall_time_s = 0.0;            ///< from step 0 to the last step [s]
  std::int64_t commands_received = 0;  ///< commands that answered a published state
  std::int64_t commands_ignored = 0;   ///< commands for a step other than the one expected
  std::int64_t stale_steps =
      0;  ///< realtime: steps integrated without their own answer (ZOH on an older command)
  std::int64_t late_ticks = 0;      ///< realtime: ticks that started more than one period late
  std::int64_t resent_states = 0;   ///< lockstep: states published again for want of an answer
  std::int64_t recorder_waits = 0;  ///< lockstep: waits (<= 0.1 s each) for a lagging recorder
  LatencySummary latency;           ///< state publication -> command arrival [us], wall clock
  std::string scheduling;           ///< realtime: the tick thread's ("normal", "SCHED_FIFO 80")
  LatencySummary tick_late;         ///< realtime: wake-up after each tick's deadline [us]
};

/// \brief One JSON object (single line, keys in this order) for a report.
std::string runReportJson(const RunReport& r);

}  // namespace ros1
}  // namespace preadaptive_mrac
