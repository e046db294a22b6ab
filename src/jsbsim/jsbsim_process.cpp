#include "preadaptive_mrac/jsbsim/jsbsim_process.hpp"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/socket.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <mutex>
#include <sstream>
#include <thread>

namespace preadaptive_mrac {

namespace {

constexpr char kPrompt[] = "JSBSim> ";
// How often a wait for JSBSim looks at its process and output [ms].
constexpr int kWatchMs = 200;
constexpr size_t kPromptLen = sizeof(kPrompt) - 1;

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

int freePort() {
  const int s = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (s < 0) throw JsbsimError(std::string("JSBSim: socket(): ") + std::strerror(errno));
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  a.sin_port = 0;
  socklen_t len = sizeof a;
  if (::bind(s, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0 ||
      ::getsockname(s, reinterpret_cast<sockaddr*>(&a), &len) != 0) {
    const int e = errno;
    ::close(s);
    throw JsbsimError(std::string("JSBSim: no free local port: ") + std::strerror(e));
  }
  ::close(s);
  return ntohs(a.sin_port);
}

void quickAck(int fd) {
  // Linux clears TCP_QUICKACK again after a while: set it around every read, or the delayed
  // ACK holds JSBSim's separately sent prompt back by ~40 ms (Nagle on its side).
  const int one = 1;
  ::setsockopt(fd, IPPROTO_TCP, TCP_QUICKACK, &one, sizeof one);
}

std::string readFile(const std::string& path) {
  std::ifstream f(path);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

std::string endedHow(int status) {
  return WIFEXITED(status) ? "it ended with exit code " + std::to_string(WEXITSTATUS(status))
                           : "it was killed by signal " + std::to_string(WTERMSIG(status));
}

/// Thrown inside the start-up when JSBSim could not bind the port (taken meanwhile): a fresh
/// port is tried.
struct PortTaken {};

}  // namespace

JsbsimProcess::JsbsimProcess(const JsbsimLaunch& launch) {
  const std::string exe = findJsbsimExecutable(launch.executable);
  const std::string root = findJsbsimRoot(launch.root, launch.aircraft);
  names_ = {launch.aircraft, launch.initialize, root};
  timeout_ms_ = static_cast<int>(launch.timeout * 1000.0);
  for (int attempt = 0;; ++attempt) {
    try {
      startOnce(launch, exe, root);
      return;
    } catch (const PortTaken&) {
      stop();
      if (attempt == 4) {
        const std::string tail = logTail(3);
        removeDir();
        throw JsbsimError(
            "JSBSim could not bind a free local port in 5 attempts (its log: " + tail + ")");
      }
    } catch (...) {
      stop();
      removeDir();
      throw;
    }
  }
}

JsbsimProcess::~JsbsimProcess() {
  stop();
  removeDir();
}

void JsbsimProcess::removeDir() {
  if (dir_.empty()) return;
  std::error_code ec;
  std::filesystem::remove_all(dir_, ec);
  dir_.clear();
  log_path_.clear();
}

void JsbsimProcess::startOnce(const JsbsimLaunch& launch, const std::string& exe,
                              const std::string& root) {
  port_ = freePort();
  log_mark_ = 0;
  greeted_ = false;
  if (dir_.empty()) dir_ = makeJsbsimTempDir("pmrac_jsbsim_");
  const std::string script = dir_ + "/lockstep.xml";
  log_path_ = dir_ + "/jsbsim.log";
  {
    std::ofstream f(script);
    char dt[64];
    std::snprintf(dt, sizeof dt, "%.17g", launch.dt);
    f << "<?xml version=\"1.0\"?>\n<runscript name=\"pmrac-lockstep\">\n  <use aircraft=\""
      << launch.aircraft << "\" initialize=\"" << launch.initialize << "\"/>\n  <input port=\""
      << port_ << "\"/>\n  <run start=\"0.0\" end=\"1.0e9\" dt=\"" << dt
      << "\">\n  </run>\n</runscript>\n";
    if (!f) throw JsbsimError("JSBSim: cannot write " + script);
  }
  // Everything the child needs, prepared before fork (only async-signal-safe calls after it).
  std::vector<std::string> args = {
      exe, "--root=" + root, "--script=" + script, "--nohighlight", "--suspend", "--nice=0"};
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  int errpipe[2];
  if (::pipe2(errpipe, O_CLOEXEC) != 0)
    throw JsbsimError(std::string("JSBSim: pipe(): ") + std::strerror(errno));
  const pid_t parent = ::getpid();
  // The child: dies with the process that started it (PR_SET_PDEATHSIG from ForkThread's
  // thread, which ends only with the process), in its own process group, output to the log,
  // no descriptor of the parent's but the exec-error pipe.
  const std::function<void()> child = [&] {
    ::prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (::getppid() != parent) ::_exit(127);
    ::setpgid(0, 0);
    sigset_t none;
    sigemptyset(&none);
    ::sigprocmask(SIG_SETMASK, &none, nullptr);
    for (int s : {SIGINT, SIGTERM, SIGPIPE, SIGHUP}) ::signal(s, SIG_DFL);
    const int in = ::open("/dev/null", O_RDONLY);
    const int out = ::open(log_path_.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (in >= 0) ::dup2(in, 0);
    if (out >= 0) {
      ::dup2(out, 1);
      ::dup2(out, 2);
    }
    if (::chdir(dir_.c_str()) != 0) ::_exit(127);
#ifdef SYS_close_range
    if (errpipe[1] > 3) ::syscall(SYS_close_range, 3u, static_cast<unsigned>(errpipe[1] - 1), 0u);
    ::syscall(SYS_close_range, static_cast<unsigned>(errpipe[1] + 1), ~0u, 0u);
#endif
    ::execv(argv[0], argv.data());
    const int e = errno;
    ssize_t w = ::write(errpipe[1], &e, sizeof e);
    (void)w;
    ::_exit(127);
  };
  const pid_t pid = ForkThread::instance().fork(child);
  if (pid < 0) {
    const int e = errno;
    ::close(errpipe[0]);
    ::close(errpipe[1]);
    throw JsbsimError(std::string("JSBSim: fork(): ") + std::strerror(e));
  }
  pid_ = pid;
  ::setpgid(pid, pid);  // (also in the child: whichever runs first)
  ::close(errpipe[1]);
  int exec_errno = 0;
  ssize_t got;
  do {
    got = ::read(errpipe[0], &exec_errno, sizeof exec_errno);
  } while (got < 0 && errno == EINTR);
  ::close(errpipe[0]);
  if (got == static_cast<ssize_t>(sizeof exec_errno))
    throw JsbsimError("JSBSim: cannot run " + exe + ": " + std::strerror(exec_errno) + "; " +
                      kJsbsimInstallHint);

  // Connect with retry until JSBSim listens (it loads the aircraft first: ~10 ms).
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms_);
  auto next_watch = std::chrono::steady_clock::now() + std::chrono::milliseconds(kWatchMs);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  a.sin_port = htons(static_cast<uint16_t>(port_));
  for (;;) {
    fd_ = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
    if (fd_ < 0) throw JsbsimError(std::string("JSBSim: socket(): ") + std::strerror(errno));
    if (::connect(fd_, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0) break;
    ::close(fd_);
    fd_ = -1;
    int status = 0;
    if (exited(&status, 0.0)) {
      pid_ = -1;
      failFor("ended while starting: the aircraft '" + launch.aircraft +
                  "' or its initial condition '" + launch.initialize + "' under " + root +
                  " did not load (check plant.jsbsim.aircraft, plant.jsbsim.initialize, "
                  "plant.jsbsim.root)",
              endedHow(status));
    }
    if (readFile(log_path_).find("Could not bind") != std::string::npos) throw PortTaken{};
    watchStart(&next_watch);
    if (std::chrono::steady_clock::now() > deadline)
      throw JsbsimError("JSBSim did not open its input socket on port " + std::to_string(port_) +
                        " within " + std::to_string(timeout_ms_) +
                        " ms (plant.jsbsim.timeout); JSBSim said: " + logTail());
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  const int one = 1;
  ::setsockopt(fd_, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
  buf_.clear();
  readPrompts(1);
  if (replies_[0].find("Connected to JSBSim server") == std::string::npos)
    throw JsbsimError("JSBSim on port " + std::to_string(port_) +
                      " greeted with an unexpected text: '" + replies_[0] + "'");
  // What it printed while loading has been read: from here on only the newer lines matter.
  log_mark_ = readFile(log_path_).size();
  greeted_ = true;
}

void JsbsimProcess::watchStart(std::chrono::steady_clock::time_point* next_watch) {
  // Every fatal message of a load is followed by JSBSim's exit, seen above within 2 ms; this
  // catches one that is not. A failed property lookup alone does not count here: while
  // loading, only the exit that follows it says it was fatal.
  const auto now = std::chrono::steady_clock::now();
  if (now < *next_watch) return;
  *next_watch = now + std::chrono::milliseconds(kWatchMs);
  if (diagnoseJsbsimLog(readFile(log_path_), names_).certain)
    failFor("did not load", "it was still running, killed now");
}

void JsbsimProcess::watchSilence(int waited_ms) {
  int status = 0;
  if (exited(&status, 0.0)) {
    pid_ = -1;
    failFor("ended while a reply was due", endedHow(status));
  }
  // While loading (before the greeting) a failed property lookup alone does not count: the
  // exit that follows a fatal one says so.
  const JsbsimFault fault = diagnoseJsbsimLog(logSince(log_mark_), names_);
  if (fault.certain || (fault.found() && greeted_))
    failFor("cannot go on", "it was still running, killed now");
  if (waited_ms >= timeout_ms_)
    failDead("did not answer within " + std::to_string(timeout_ms_) + " ms (plant.jsbsim.timeout)");
}

void JsbsimProcess::takeRefusal(bool rest_dropped) {
  // JSBSim ignores the rest of a packet after a command it refused for its property: with
  // replies still due nothing more will come. A refusal that ends its packet is the caller's
  // to handle; the lookup it logged no longer counts against a later wait.
  if (rest_dropped)
    failFor("refused a property and ignored the rest of the packet ('" + replies_.back() + "')",
            "it was still running, killed now");
  log_mark_ = readFile(log_path_).size();
}

std::string JsbsimProcess::logSince(size_t from) const {
  if (log_path_.empty()) return {};
  const std::string text = readFile(log_path_);
  return from < text.size() ? text.substr(from) : std::string();
}

bool JsbsimProcess::exited(int* status, double wait_s) {
  if (pid_ <= 0) return true;
  const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(wait_s);
  for (;;) {
    const pid_t r = ::waitpid(pid_, status, WNOHANG);
    if (r == pid_) return true;
    if (r < 0) return true;  // not our child any more
    if (std::chrono::steady_clock::now() >= until) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
}

void JsbsimProcess::failDead(const std::string& what) {
  int status = 0;
  std::string how = "it was still running, killed now";
  if (exited(&status, 1.0)) {
    pid_ = -1;
    how = endedHow(status);
  }
  failFor(what, how);
}

void JsbsimProcess::failFor(const std::string& what, const std::string& how) {
  // The cause JSBSim printed, when it printed one, is the headline; else what was seen.
  const JsbsimFault fault = diagnoseJsbsimLog(logSince(log_mark_), names_);
  const std::string tail = logTail();
  stop();
  if (fault.found()) throw JsbsimError(fault.message() + " (" + how + ")");
  throw JsbsimError("JSBSim " + what + " (" + how + "); JSBSim said: " + tail);
}

void JsbsimProcess::readPrompts(size_t n, size_t packet_end) {
  if (packet_end == 0) packet_end = n;
  replies_.clear();
  char chunk[65536];
  size_t pos = 0;
  while (replies_.size() < n) {
    const size_t i = buf_.find(kPrompt, pos);
    if (i != std::string::npos) {
      replies_.emplace_back(buf_, pos, i - pos);
      pos = i + kPromptLen;
      if (jsbsimRefusedProperty(replies_.back())) {
        const size_t r = replies_.size();
        takeRefusal(r < packet_end || (r > packet_end && r < n));
      }
      continue;
    }
    buf_.erase(0, pos);
    pos = 0;
    // (A read that spins on a non-blocking socket for the next chunk is slower on a loaded
    // 2-core machine: the spinning client takes the CPU from JSBSim.)
    ssize_t got = -1;
    int waited_ms = 0;
    for (;;) {
      quickAck(fd_);
      got = ::recv(fd_, chunk, sizeof chunk, MSG_DONTWAIT);
      if (got >= 0 || (errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR)) break;
      pollfd p{fd_, POLLIN, 0};
      const int slice = std::max(1, std::min(kWatchMs, timeout_ms_ - waited_ms));
      int pr;
      do {
        pr = ::poll(&p, 1, slice);
      } while (pr < 0 && errno == EINTR);
      if (pr == 0) {
        waited_ms += slice;
        watchSilence(waited_ms);
      }
    }
    quickAck(fd_);
    if (got <= 0) failDead("closed the connection mid-run (the process ended or was killed)");
    buf_.append(chunk, static_cast<size_t>(got));
  }
  buf_.erase(0, pos);
}

void JsbsimProcess::sendAll(const char* data, size_t size) {
  if (fd_ < 0) throw JsbsimError("JSBSim: not connected (the process was stopped)");
  size_t sent = 0;
  while (sent < size) {
    const ssize_t w = ::send(fd_, data + sent, size - sent, MSG_NOSIGNAL);
    if (w < 0 && errno == EINTR) continue;
    if (w <= 0) failDead(std::string("refused a command: ") + std::strerror(errno));
    sent += static_cast<size_t>(w);
  }
}

const std::vector<std::string>& JsbsimProcess::transact(const std::string& packet, size_t lines) {
  sendAll(packet.data(), packet.size());
  readPrompts(lines);
  return replies_;
}

const std::vector<std::string>& JsbsimProcess::transact2(const std::string& first, size_t lines1,
                                                         const char* second, size_t lines2) {
  sendAll(first.data(), first.size());
  // The first reply's arrival says JSBSim's input pass has taken `first` (the step runs next):
  // `second` then reaches the pass after it, or the one in its middle.
  readPrompts(1, lines1);
  std::string head = replies_[0];
  sendAll(second, std::strlen(second));
  readPrompts(lines1 + lines2 - 1, lines1 - 1);
  replies_.insert(replies_.begin(), std::move(head));
  return replies_;
}

void JsbsimProcess::set(const std::string& property, double value) {
  char line[512];
  std::snprintf(line, sizeof line, "set %s %.17g\n", property.c_str(), value);
  const auto& r = transact(line, 1);
  if (r[0].find("set successful") == std::string::npos)
    throw JsbsimError("JSBSim refused 'set " + property + "': " + r[0]);
}

double JsbsimProcess::parseGet(const std::string& reply, const std::string& name) {
  const size_t eq = reply.find(" = ");
  if (eq == std::string::npos || reply.compare(0, name.size(), name) != 0)
    throw JsbsimError("JSBSim: no value for '" + name + "' (the aircraft file has no such " +
                      "property?): it answered '" + reply.substr(0, reply.find('\n')) + "'");
  char* end = nullptr;
  const double v = std::strtod(reply.c_str() + eq + 3, &end);
  if (end == reply.c_str() + eq + 3)
    throw JsbsimError("JSBSim: unreadable value for '" + name + "': '" + reply + "'");
  return v;
}

std::vector<double> JsbsimProcess::get(const std::vector<std::string>& properties) {
  std::string packet;
  for (const auto& p : properties) packet += "get " + p + "\n";
  const auto& r = transact(packet, properties.size());
  std::vector<double> out;
  out.reserve(properties.size());
  for (size_t i = 0; i < properties.size(); ++i) out.push_back(parseGet(r[i], properties[i]));
  return out;
}

void JsbsimProcess::trim(const std::string& what) {
  // Sent held, the trim cannot move the aircraft: resume, trim and hold in one packet (all
  // handled in the same input pass, so no frame runs in between).
  if (fd_ < 0) throw JsbsimError("JSBSim: not connected (the process was stopped)");
  const std::string packet = "resume\nset simulation/do_simple_trim 0\nhold\n";
  try {
    transact(packet, 3);
  } catch (const JsbsimError& e) {
    throw JsbsimError("JSBSim's trim failed at " + what +
                      " and ended the process: choose an operating point the aircraft can fly "
                      "(plant.jsbsim.mach, plant.jsbsim.altitude_ft); " +
                      e.what());
  }
}

std::string JsbsimProcess::logTail(size_t max_lines) const {
  if (log_path_.empty()) return "(no output)";
  const std::string text = readFile(log_path_);
  std::vector<std::string> lines;
  std::stringstream ss(text);
  std::string line;
  while (std::getline(ss, line)) {
    // (JSBSim's banner and blank lines say nothing about the problem)
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    lines.push_back(line);
  }
  std::string out;
  const size_t from = lines.size() > max_lines ? lines.size() - max_lines : 0;
  for (size_t i = from; i < lines.size(); ++i) out += (out.empty() ? "" : " | ") + lines[i];
  return out.empty() ? "(no output)" : out;
}

void JsbsimProcess::stop() {
  if (fd_ >= 0) {
    ::close(fd_);
    fd_ = -1;
  }
  if (pid_ > 0) {
    ::kill(-pid_, SIGKILL);
    ::kill(pid_, SIGKILL);
    int status = 0;
    while (::waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
    }
    pid_ = -1;
  }
}

}  // namespace preadaptive_mrac
