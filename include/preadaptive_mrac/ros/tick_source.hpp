#pragma once
/// \file tick_source.hpp
/// \brief The realtime plant's tick: absolute deadlines on CLOCK_MONOTONIC, and optional
/// SCHED_FIFO priority and CPU affinity for the ticking thread. ROS-free (POSIX).

#include <time.h>

#include <cstdint>
#include <string>

namespace preadaptive_mrac {
namespace ros1 {

/// \brief Periodic ticks that do not drift: tick k is due at start + k period exactly, and
/// waitNext() sleeps with clock_nanosleep(TIMER_ABSTIME) until that deadline, so a late wake-up
/// or a slow step never shifts the later deadlines (a relative sleep would add each delay).
/// Behind schedule, waitNext() returns at once until the ticks have caught up.
class TickSource {
 public:
  /// \brief period_s: tick period [s], > 0.
  explicit TickSource(double period_s);
  /// \brief Tick 0 is now; the next waitNext() waits for tick 1.
  void start();
  /// \brief Sleep until the next tick's deadline. Returns how late [s] after it the thread
  /// runs (>= 0): the wake-up delay, or, behind schedule, how far behind it is.
  double waitNext();
  /// \brief Whether the last waitNext() returned more than one period after its deadline.
  bool late() const { return last_late_s_ > period_s_; }
  /// \brief Ticks waited for since start().
  std::int64_t ticks() const { return ticks_; }
  /// \brief Deadline of the last tick waited for [s, CLOCK_MONOTONIC].
  double deadline() const;
  /// \brief Deadline of the next tick [ns, CLOCK_MONOTONIC].
  std::int64_t nextDeadlineNs() const { return start_ns_ + (ticks_ + 1) * period_ns_; }
  double period() const { return period_s_; }

 private:
  double period_s_;
  std::int64_t period_ns_;
  std::int64_t start_ns_ = 0;
  std::int64_t ticks_ = 0;
  double last_late_s_ = 0.0;
};

/// \brief Now [ns] on CLOCK_MONOTONIC.
std::int64_t monotonicNs();

/// \brief What applyRealtimeScheduling could do.
struct SchedulingResult {
  bool fifo = false;             ///< SCHED_FIFO is in effect
  bool pinned = false;           ///< the thread is pinned to the CPU asked for
  int priority = 0;              ///< the SCHED_FIFO priority in effect (0: normal scheduling)
  int cpu = -1;                  ///< the CPU the thread is pinned to (-1: any)
  int others_raised = -1;        ///< other threads of the process raised too (-1: not asked)
  std::string warnings;          ///< "" or what failed and why (names ~rt_priority, ~cpu_affinity)
  std::string describe() const;  ///< e.g. "SCHED_FIFO 80, CPU 1, 4 other thread(s) raised"
};

/// \brief For the calling thread: SCHED_FIFO at `priority` (1..99; 0 = leave the policy) and
/// affinity to CPU `cpu` (-1 = leave). Never throws; a refusal (no CAP_SYS_NICE, rtprio limit
/// 0, no such CPU) leaves normal scheduling and is described in `warnings`. With
/// `whole_process` and SCHED_FIFO granted, every other thread of the process too
/// (raiseOtherThreads): for a node in a process of its own, whose messages roscpp's receiving
/// thread reads first; not in a nodelet manager, whose other threads are the other nodelets'.
SchedulingResult applyRealtimeScheduling(int priority, int cpu, bool whole_process = false);

/// \brief SCHED_FIFO at `priority` for every other thread of this process that runs under
/// normal scheduling (/proc/self/task): in a node of its own, roscpp's receiving thread reads
/// every message from another process before a callback sees it, and at normal priority it
/// waits behind any busy process. Returns how many threads were raised; -1 when
/// /proc/self/task could not be read. Never throws.
int raiseOtherThreads(int priority);

}  // namespace ros1
}  // namespace preadaptive_mrac
