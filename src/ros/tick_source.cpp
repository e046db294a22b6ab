#include "preadaptive_mrac/ros/tick_source.hpp"

#include <dirent.h>
#include <pthread.h>
#include <sched.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>

namespace preadaptive_mrac {
namespace ros1 {
namespace {

constexpr std::int64_t kNsPerS = 1000000000;

timespec toTimespec(std::int64_t ns) {
  timespec ts{};
  ts.tv_sec = static_cast<time_t>(ns / kNsPerS);
  ts.tv_nsec = static_cast<long>(ns % kNsPerS);
  return ts;
}

}  // namespace

std::int64_t monotonicNs() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<std::int64_t>(ts.tv_sec) * kNsPerS + ts.tv_nsec;
}

TickSource::TickSource(double period_s)
    : period_s_(period_s), period_ns_(static_cast<std::int64_t>(std::llround(period_s * 1e9))) {
  if (period_ns_ < 1) period_ns_ = 1;
}

void TickSource::start() {
  start_ns_ = monotonicNs();
  ticks_ = 0;
  last_late_s_ = 0.0;
}

double TickSource::waitNext() {
  ++ticks_;
  const std::int64_t due = start_ns_ + ticks_ * period_ns_;
  const timespec ts = toTimespec(due);
  // EINTR (a signal) only interrupts the sleep: sleep again towards the same deadline.
  while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) == EINTR) {
  }
  last_late_s_ = static_cast<double>(monotonicNs() - due) * 1e-9;
  if (last_late_s_ < 0.0) last_late_s_ = 0.0;
  return last_late_s_;
}

double TickSource::deadline() const {
  return static_cast<double>(start_ns_ + ticks_ * period_ns_) * 1e-9;
}

std::string SchedulingResult::describe() const {
  std::string s = fifo ? "SCHED_FIFO " + std::to_string(priority) : std::string("normal");
  if (pinned) s += ", CPU " + std::to_string(cpu);
  if (others_raised >= 0) s += ", " + std::to_string(others_raised) + " other thread(s) raised";
  return s;
}

SchedulingResult applyRealtimeScheduling(int priority, int cpu, bool whole_process) {
  SchedulingResult r;
  if (priority > 0) {
    sched_param sp{};
    sp.sched_priority = priority;
    const int err = pthread_setschedparam(pthread_self(), SCHED_FIFO, &sp);
    if (err == 0) {
      r.fifo = true;
      r.priority = priority;
    } else {
      r.warnings += "~rt_priority " + std::to_string(priority) + ": cannot use SCHED_FIFO (" +
                    std::strerror(err) +
                    "; needs CAP_SYS_NICE or an rtprio limit >= " + std::to_string(priority) +
                    " in /etc/security/limits.conf), keeping normal scheduling. ";
    }
  }
  if (cpu >= 0) {
    if (cpu >= CPU_SETSIZE) {
      r.warnings += "~cpu_affinity " + std::to_string(cpu) + ": beyond CPU_SETSIZE. ";
    } else {
      cpu_set_t set;
      CPU_ZERO(&set);
      CPU_SET(cpu, &set);
      const int err = pthread_setaffinity_np(pthread_self(), sizeof(set), &set);
      if (err == 0) {
        r.pinned = true;
        r.cpu = cpu;
      } else {
        r.warnings += "~cpu_affinity " + std::to_string(cpu) + ": cannot pin to this CPU (" +
                      std::strerror(err) + "), running on any CPU. ";
      }
    }
  }
  if (whole_process && r.fifo) {
    const int raised = raiseOtherThreads(r.priority);
    if (raised >= 0)
      r.others_raised = raised;
    else
      r.warnings += "~rt_priority " + std::to_string(priority) +
                    ": cannot read /proc/self/task, the process's other threads keep normal "
                    "scheduling. ";
  }
  if (!r.warnings.empty()) r.warnings.pop_back();
  return r;
}

int raiseOtherThreads(int priority) {
  if (priority <= 0) return 0;
  DIR* dir = opendir("/proc/self/task");
  if (dir == nullptr) return -1;
  const pid_t self = static_cast<pid_t>(syscall(SYS_gettid));
  int raised = 0;
  while (const dirent* e = readdir(dir)) {
    char* end = nullptr;
    const long tid = std::strtol(e->d_name, &end, 10);
    if (end == e->d_name || *end != '\0' || tid <= 0 || static_cast<pid_t>(tid) == self) continue;
    if (sched_getscheduler(static_cast<pid_t>(tid)) != SCHED_OTHER) continue;
    sched_param sp{};
    sp.sched_priority = priority;
    if (sched_setscheduler(static_cast<pid_t>(tid), SCHED_FIFO, &sp) == 0) ++raised;
  }
  closedir(dir);
  return raised;
}

}  // namespace ros1
}  // namespace preadaptive_mrac
