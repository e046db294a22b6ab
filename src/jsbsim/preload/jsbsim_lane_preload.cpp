/// \file jsbsim_lane_preload.cpp
/// \brief LD_PRELOAD library for the JSBSim process: with PMRAC_JSBSIM_LANE set (a file the
/// package's client made, jsbsim_lane_ring.hpp), the bytes of JSBSim's input socket (the
/// connection accepted on port PMRAC_JSBSIM_LANE_IN) and of its output socket (the connection
/// it makes to port PMRAC_JSBSIM_LANE_OUT) travel through shared memory instead of loopback TCP.
///
/// Why: in lockstep every step is a command to JSBSim and a line back. Through loopback TCP
/// that costs two socket wake-ups a step (about 300 us on a virtual machine), 50 times JSBSim's
/// own 7 us step. The connections themselves are still made (JSBSim sees its sockets as
/// always); only recv() and send() on those two descriptors are served from the rings.
/// Nothing else of JSBSim is touched. Without PMRAC_JSBSIM_LANE the library does nothing.

#include <arpa/inet.h>
#include <dlfcn.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <sys/mman.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>

#include "preadaptive_mrac/jsbsim/jsbsim_lane_ring.hpp"

namespace {

namespace lane = preadaptive_mrac::lane;

// JSBSim's main loop reads its input socket once per pass, also while held between steps.
// After a command it reads on until the socket is empty, and a step's second pass follows at
// once: a short wait must not sleep. Only an input silent for lane::kSpinNs sleeps (woken by
// the next command, or after kSleepNs to let JSBSim's loop go round).
constexpr long kSleepNs = 2000000;

lane::Shared* g_lane = nullptr;
int g_in_port = -1;
int g_out_port = -1;
int g_in_fd = -1;
int g_out_fd = -1;
long g_empty_since = 0;
bool g_was_empty = false;

template <class Fn>
Fn real(const char* name) {
  return reinterpret_cast<Fn>(dlsym(RTLD_NEXT, name));
}

int portFromEnv(const char* name) {
  const char* v = std::getenv(name);
  return v != nullptr && *v != '\0' ? std::atoi(v) : -1;
}

int localPort(int fd) {
  sockaddr_in a{};
  socklen_t len = sizeof a;
  if (::getsockname(fd, reinterpret_cast<sockaddr*>(&a), &len) != 0 || a.sin_family != AF_INET)
    return -1;
  return ntohs(a.sin_port);
}

__attribute__((constructor)) void attachLane() {
  const char* path = std::getenv("PMRAC_JSBSIM_LANE");
  if (path == nullptr || *path == '\0') return;
  const int fd = ::open(path, O_RDWR | O_CLOEXEC);
  if (fd < 0) return;
  void* m = ::mmap(nullptr, sizeof(lane::Shared), PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0);
  ::close(fd);
  if (m == MAP_FAILED) return;
  auto* s = static_cast<lane::Shared*>(m);
  if (s->magic != lane::kMagic || s->version != lane::kVersion) {
    ::munmap(m, sizeof(lane::Shared));
    return;
  }
  g_in_port = portFromEnv("PMRAC_JSBSIM_LANE_IN");
  g_out_port = portFromEnv("PMRAC_JSBSIM_LANE_OUT");
  g_lane = s;
  // A process JSBSim starts (none does in lockstep) must not take the lane over.
  ::unsetenv("PMRAC_JSBSIM_LANE");
  s->attached.store(static_cast<std::int32_t>(::getpid()));
}

bool clientAlive() { return ::getppid() != 1; }

ssize_t laneRecv(void* buf, size_t n) {
  const size_t got = lane::read(&g_lane->to_jsbsim, static_cast<char*>(buf), n);
  if (got > 0) {
    g_was_empty = false;
    return static_cast<ssize_t>(got);
  }
  const long now = lane::nowNs();
  if (!g_was_empty) {
    g_was_empty = true;
    g_empty_since = now;
  } else if (now - g_empty_since > lane::kSpinNs) {
    lane::Ring* r = &g_lane->to_jsbsim;
    lane::sleepOn(&r->seq, &r->sleeping, r->seq.load(), kSleepNs);
    const size_t late = lane::read(r, static_cast<char*>(buf), n);
    if (late > 0) {
      g_was_empty = false;
      return static_cast<ssize_t>(late);
    }
  } else {
    lane::relax(now - g_empty_since);
  }
  errno = EAGAIN;
  return -1;
}

ssize_t laneSend(lane::Ring* r, const void* buf, size_t n) {
  if (!lane::writeAll(r, static_cast<const char*>(buf), n, kSleepNs, clientAlive)) {
    errno = EPIPE;
    return -1;
  }
  return static_cast<ssize_t>(n);
}

}  // namespace

extern "C" int accept(int fd, sockaddr* addr, socklen_t* len) {
  static const auto fn = real<int (*)(int, sockaddr*, socklen_t*)>("accept");
  const int r = fn(fd, addr, len);
  if (r >= 0 && g_lane != nullptr && g_in_fd < 0 && localPort(fd) == g_in_port) g_in_fd = r;
  return r;
}

extern "C" int connect(int fd, const sockaddr* addr, socklen_t len) {
  static const auto fn = real<int (*)(int, const sockaddr*, socklen_t)>("connect");
  const int r = fn(fd, addr, len);
  if (r == 0 && g_lane != nullptr && g_out_port > 0 && addr != nullptr &&
      addr->sa_family == AF_INET && len >= static_cast<socklen_t>(sizeof(sockaddr_in)) &&
      ntohs(reinterpret_cast<const sockaddr_in*>(addr)->sin_port) == g_out_port)
    g_out_fd = fd;
  return r;
}

extern "C" ssize_t recv(int fd, void* buf, size_t n, int flags) {
  static const auto fn = real<ssize_t (*)(int, void*, size_t, int)>("recv");
  if (g_lane != nullptr && fd == g_in_fd) return laneRecv(buf, n);
  return fn(fd, buf, n, flags);
}

extern "C" ssize_t send(int fd, const void* buf, size_t n, int flags) {
  static const auto fn = real<ssize_t (*)(int, const void*, size_t, int)>("send");
  if (g_lane != nullptr && fd == g_in_fd) return laneSend(&g_lane->replies, buf, n);
  if (g_lane != nullptr && fd == g_out_fd) return laneSend(&g_lane->outputs, buf, n);
  return fn(fd, buf, n, flags);
}

// JSBSim started with --nice=0 asks for a sleep of 0 s on every pass of its loop: a system call
// that costs more than the step itself on a virtual machine. With the lane, the wait for input
// is the lane's (laneRecv), so a sleep of nothing is skipped; any other sleep is kept.
extern "C" int nanosleep(const timespec* req, timespec* rem) {
  static const auto fn = real<int (*)(const timespec*, timespec*)>("nanosleep");
  if (g_lane != nullptr && g_in_fd >= 0 && req != nullptr && req->tv_sec == 0 && req->tv_nsec == 0)
    return 0;
  return fn(req, rem);
}

extern "C" int close(int fd) {
  static const auto fn = real<int (*)(int)>("close");
  if (fd == g_in_fd) g_in_fd = -1;
  if (fd == g_out_fd) g_out_fd = -1;
  return fn(fd);
}
