/// \file wakeup_floor.cpp
/// \brief What this machine allows a 1 kHz loop at best, with no ROS and no work at all: the
/// floor under the realtime targets of bench/ros_bench.sh (round trip max <= 1 ms, no stale
/// step). Two measurements on one thread, at the scheduling the realtime runs use:
///
///  1. timer: sleep to absolute 1 ms deadlines (clock_nanosleep TIMER_ABSTIME, as the plant's
///     TickSource) and record how late each wake-up is (as cyclictest does);
///  2. spin: never block, read the clock in a loop and record every gap between two reads, i.e.
///     every time the CPU was taken from a thread that wants it all the time (interrupts, the
///     hypervisor taking the virtual CPU, higher-priority threads). Under SCHED_FIFO the thread
///     spins 0.7 s of each second and sleeps the rest, so that the kernel's realtime
///     throttling (kernel.sched_rt_runtime_us, 0.95 s of each second by default) does not
///     show up as a 50 ms gap.
///
/// A loop whose every step needs two thread wake-ups cannot do better than these numbers: if
/// a thread that does nothing is woken more than 1 ms late here, a plant-controller round trip
/// will be too. Not a test: it passes nothing and fails nothing; it prints what it measured.
///
///   wakeup_floor [--seconds 20] [--priority 0] [--period-us 1000] [--json]

#include <sched.h>
#include <sys/mman.h>
#include <time.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace {

std::int64_t nowNs() {
  timespec t{};
  clock_gettime(CLOCK_MONOTONIC, &t);
  return static_cast<std::int64_t>(t.tv_sec) * 1000000000LL + t.tv_nsec;
}

/// Steal time of all CPUs so far [ms] (/proc/stat, the 8th field of the "cpu" line), -1 if
/// unreadable.
double stealMs() {
  std::ifstream f("/proc/stat");
  std::string line;
  if (!std::getline(f, line) || line.rfind("cpu ", 0) != 0) return -1.0;
  std::istringstream in(line.substr(4));
  long long v[8] = {};
  for (long long& x : v)
    if (!(in >> x)) return -1.0;
  return 1000.0 * static_cast<double>(v[7]) / static_cast<double>(sysconf(_SC_CLK_TCK));
}

struct Stats {
  double p50_us = 0, p99_us = 0, p999_us = 0, max_us = 0;
  long over_200us = 0, over_1ms = 0, count = 0;
};

Stats summarise(std::vector<std::int64_t> ns) {
  Stats s;
  s.count = static_cast<long>(ns.size());
  if (ns.empty()) return s;
  std::sort(ns.begin(), ns.end());
  const auto at = [&](double q) {
    return 1e-3 * static_cast<double>(ns[static_cast<std::size_t>(q * (ns.size() - 1))]);
  };
  s.p50_us = at(0.5);
  s.p99_us = at(0.99);
  s.p999_us = at(0.999);
  s.max_us = 1e-3 * static_cast<double>(ns.back());
  for (const std::int64_t x : ns) {
    if (x > 200000) ++s.over_200us;
    if (x > 1000000) ++s.over_1ms;
  }
  return s;
}

/// Wake-up lateness of `ticks` absolute deadlines `period_ns` apart.
Stats timerFloor(long ticks, std::int64_t period_ns) {
  std::vector<std::int64_t> late(static_cast<std::size_t>(ticks));
  const std::int64_t start = nowNs();
  for (long i = 1; i <= ticks; ++i) {
    const std::int64_t due = start + i * period_ns;
    const timespec ts{static_cast<time_t>(due / 1000000000LL),
                      static_cast<long>(due % 1000000000LL)};
    while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) == EINTR) {
    }
    late[static_cast<std::size_t>(i - 1)] = std::max<std::int64_t>(0, nowNs() - due);
  }
  return summarise(std::move(late));
}

/// Gaps longer than 20 us between consecutive clock reads of a thread that never blocks,
/// over `seconds` of spinning (in windows of `window_s` of each second when `windows`).
struct SpinResult {
  Stats gaps;         ///< the gaps over 20 us only (count = their number)
  double spun_s = 0;  ///< seconds spent spinning
};

SpinResult spinFloor(double seconds, bool windows) {
  constexpr std::int64_t kReport = 20000;  // 20 us: below that, a clock read or a cache miss
  const double window_s = windows ? 0.7 : seconds;
  std::vector<std::int64_t> gaps;
  SpinResult r;
  double left = seconds;
  while (left > 1e-9) {
    const double w = std::min(window_s, left);
    const std::int64_t start = nowNs();
    const std::int64_t end = start + static_cast<std::int64_t>(w * 1e9);
    std::int64_t last = start;
    while (last < end) {
      const std::int64_t t = nowNs();
      if (t - last > kReport) gaps.push_back(t - last);
      last = t;
    }
    r.spun_s += w;
    left -= w;
    if (windows && left > 1e-9) usleep(300000);
  }
  r.gaps = summarise(std::move(gaps));
  return r;
}

std::string statsJson(const Stats& s) {
  char buf[256];
  std::snprintf(buf, sizeof(buf),
                "{\"count\": %ld, \"p50_us\": %.1f, \"p99_us\": %.1f, \"p999_us\": %.1f, "
                "\"max_us\": %.1f, \"over_200us\": %ld, \"over_1ms\": %ld}",
                s.count, s.p50_us, s.p99_us, s.p999_us, s.max_us, s.over_200us, s.over_1ms);
  return buf;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "The machine's floor for a 1 kHz loop: timer wake-up lateness and CPU taken from a "
      "spinning thread, one thread, no ROS (bench/ros_bench.sh prints it beside the realtime "
      "runs)."};
  double seconds = 20.0;
  int priority = 0;
  long period_us = 1000;
  bool json = false;
  app.add_option("--seconds", seconds, "seconds of each measurement (timer, then spin)")
      ->check(CLI::Range(0.1, 3600.0));
  app.add_option("--priority", priority, "SCHED_FIFO priority (0 = normal scheduling)")
      ->check(CLI::Range(0, 99));
  app.add_option("--period-us", period_us, "timer period [us]")->check(CLI::Range(50L, 1000000L));
  app.add_flag("--json", json, "print one JSON line");
  CLI11_PARSE(app, argc, argv);

  std::string sched = "normal";
  if (priority > 0) {
    sched_param sp{};
    sp.sched_priority = priority;
    if (sched_setscheduler(0, SCHED_FIFO, &sp) == 0) {
      sched = "SCHED_FIFO " + std::to_string(priority);
    } else {
      std::fprintf(stderr, "wakeup_floor: cannot use SCHED_FIFO %d (%s); normal scheduling\n",
                   priority, std::strerror(errno));
    }
  }
  // As a realtime process would: no page faults in the loop.
  const bool locked = mlockall(MCL_CURRENT | MCL_FUTURE) == 0;

  const double steal0 = stealMs();
  const long ticks = static_cast<long>(seconds * 1e6 / static_cast<double>(period_us));
  const Stats timer = timerFloor(ticks, period_us * 1000LL);
  const double steal1 = stealMs();
  const SpinResult spin = spinFloor(seconds, priority > 0 && sched != "normal");
  const double steal2 = stealMs();
  const long ncpu = sysconf(_SC_NPROCESSORS_ONLN);

  if (json) {
    std::printf(
        "{\"scheduling\": \"%s\", \"mlockall\": %s, \"cpus\": %ld, \"period_us\": %ld, "
        "\"timer\": %s, \"spin_gaps_over_20us\": %s, \"spin_seconds\": %.2f, "
        "\"steal_ms_timer\": %.0f, \"steal_ms_spin\": %.0f}\n",
        sched.c_str(), locked ? "true" : "false", ncpu, period_us, statsJson(timer).c_str(),
        statsJson(spin.gaps).c_str(), spin.spun_s, steal0 >= 0 ? steal1 - steal0 : -1.0,
        steal0 >= 0 ? steal2 - steal1 : -1.0);
  } else {
    std::printf("scheduling %s, mlockall %s, %ld CPUs\n", sched.c_str(), locked ? "yes" : "no",
                ncpu);
    std::printf(
        "timer, %ld ticks of %ld us: late p50 %.1f us, p99 %.1f us, p99.9 %.1f us, max %.1f us; "
        "%ld later than 200 us, %ld later than 1 ms\n",
        timer.count, period_us, timer.p50_us, timer.p99_us, timer.p999_us, timer.max_us,
        timer.over_200us, timer.over_1ms);
    std::printf("spin, %.1f s: %ld gaps over 20 us, max %.1f us; %ld over 200 us, %ld over 1 ms\n",
                spin.spun_s, spin.gaps.count, spin.gaps.max_us, spin.gaps.over_200us,
                spin.gaps.over_1ms);
    if (steal0 >= 0)
      std::printf("steal time: %.0f ms during the timer run, %.0f ms during the spin run\n",
                  steal1 - steal0, steal2 - steal1);
  }
  return 0;
}
