#include "preadaptive_mrac/jsbsim/jsbsim_fork.hpp"

#include <unistd.h>

#include <cerrno>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <mutex>
#include <sstream>
#include <thread>

namespace preadaptive_mrac {

namespace {

/// \brief The thread every JSBSim is forked from. PR_SET_PDEATHSIG fires when the *thread*
/// that forked the child ends, not its process: a JSBSim forked by a thread that ends before
/// the run (a nodelet's onInit served by a thread that goes, a pool's worker) would be killed
/// mid-run. This thread lives until the process ends (detached, never joined; the object is
/// never destroyed), so the child dies exactly with the process, whatever ends it.
class ForkThread {
 public:
  static ForkThread& instance() {
    static ForkThread* const t = new ForkThread();  // never destroyed: the thread outlives main
    return *t;
  }
  /// \brief fork() on this thread; the child runs `child` (async-signal-safe calls only, then
  /// exec or _exit). The child's pid, or -1 with errno set.
  pid_t fork(const std::function<void()>& child) {
    std::lock_guard<std::mutex> one(call_);  // one fork at a time
    std::unique_lock<std::mutex> l(m_);
    job_ = &child;
    done_ = false;
    cv_.notify_all();
    cv_.wait(l, [this] { return done_; });
    errno = err_;
    return pid_;
  }

 private:
  ForkThread() {
    std::thread([this] { loop(); }).detach();
  }
  void loop() {
    std::unique_lock<std::mutex> l(m_);
    for (;;) {
      cv_.wait(l, [this] { return job_ != nullptr; });
      const pid_t p = ::fork();
      if (p == 0) {
        (*job_)();
        ::_exit(127);
      }
      err_ = errno;
      pid_ = p;
      job_ = nullptr;
      done_ = true;
      cv_.notify_all();
    }
  }
  std::mutex call_, m_;
  std::condition_variable cv_;
  const std::function<void()>* job_ = nullptr;
  bool done_ = false;
  pid_t pid_ = -1;
  int err_ = 0;
};

}  // namespace

pid_t forkFromLastingThread(const std::function<void()>& child) {
  return ForkThread::instance().fork(child);
}

std::string processState(pid_t pid) {
  if (pid <= 0) return {};
  std::ifstream in("/proc/" + std::to_string(pid) + "/stat");
  std::string line;
  if (!std::getline(in, line)) return {};
  // pid (comm) state ppid ...: the name may hold spaces, so read after its last ')'.
  const size_t close = line.rfind(')');
  if (close == std::string::npos) return {};
  std::istringstream rest(line.substr(close + 1));
  std::string state, field;
  rest >> state;
  unsigned long long utime = 0, stime = 0;
  for (int i = 4; i <= 15 && rest >> field; ++i) {  // utime and stime are fields 14 and 15
    // (strtoull, not stoull: this serves an error message and must not throw itself)
    if (i == 14) utime = std::strtoull(field.c_str(), nullptr, 10);
    if (i == 15) stime = std::strtoull(field.c_str(), nullptr, 10);
  }
  if (state.empty()) return {};
  const long hz = ::sysconf(_SC_CLK_TCK);
  char cpu[64];
  std::snprintf(cpu, sizeof cpu, "%.2f", static_cast<double>(utime + stime) / (hz > 0 ? hz : 100));
  return "state " + state + ", " + cpu + " s of CPU";
}

}  // namespace preadaptive_mrac
