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
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <thread>

#include "preadaptive_mrac/jsbsim/jsbsim_fork.hpp"

namespace preadaptive_mrac {

namespace {

constexpr char kPrompt[] = "JSBSim> ";
// How often a wait for JSBSim looks at its process and output [ms].
constexpr int kWatchMs = 200;
constexpr size_t kPromptLen = sizeof(kPrompt) - 1;

/// A socket listening on a free loopback port (returned in `port`), for JSBSim's output socket.
int listenLoopback(int* port) {
  const int s = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (s < 0) throw JsbsimError(std::string("JSBSim: socket(): ") + std::strerror(errno));
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  socklen_t len = sizeof a;
  if (::bind(s, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0 || ::listen(s, 1) != 0 ||
      ::getsockname(s, reinterpret_cast<sockaddr*>(&a), &len) != 0) {
    const int e = errno;
    ::close(s);
    throw JsbsimError(std::string("JSBSim: cannot listen on a local port: ") + std::strerror(e));
  }
  *port = ntohs(a.sin_port);
  return s;
}

/// A free local port (for JSBSim's input socket: JSBSim binds it).
int freePort() {
  int port = 0;
  ::close(listenLoopback(&port));
  return port;
}

/// Closes a descriptor when the scope ends.
struct FdCloser {
  int fd;
  ~FdCloser() {
    if (fd >= 0) ::close(fd);
  }
};

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
  const std::string directives = dir_ + "/outputs.xml";
  log_path_ = dir_ + "/jsbsim.log";
  FdCloser listener{-1};
  outputs_ = launch.outputs.size();
  int out_port = 0;
  if (outputs_ > 0) {
    // JSBSim connects to this port when it reads the directive (as a client: the socket is
    // ours, so no other process can hold the port). rate 1000 Hz (JSBSim's largest) is every
    // model pass at dt >= 1 ms.
    listener.fd = listenLoopback(&out_port);
    std::ofstream f(directives);
    f << "<?xml version=\"1.0\"?>\n<output name=\"localhost\" type=\"SOCKET\" protocol=\"TCP\" "
         "port=\""
      << out_port << "\" rate=\"1000\">\n";
    for (const auto& p : launch.outputs) f << "  <property> " << p << " </property>\n";
    f << "</output>\n";
    if (!f) throw JsbsimError("JSBSim: cannot write " + directives);
  }
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
  if (outputs_ > 0) args.push_back("--logdirectivefile=" + directives);
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  lane_.reset();  // (a retry's: its file goes with it)
  const std::string preload = launch.shared_memory ? findJsbsimLanePreload() : std::string();
  if (!preload.empty()) lane_ = JsbsimLane::tryMake(dir_ + "/lane");
  std::vector<std::string> env =
      JsbsimLane::childEnvironment(lane_.get(), preload, port_, out_port);
  std::vector<char*> envp;
  for (auto& e : env) envp.push_back(e.data());
  envp.push_back(nullptr);
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
    ::execve(argv[0], argv.data(), envp.data());
    const int e = errno;
    ssize_t w = ::write(errpipe[1], &e, sizeof e);
    (void)w;
    ::_exit(127);
  };
  const pid_t pid = forkFromLastingThread(child);
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
  // The preload library attaches before JSBSim's main() (so before it listens): not attached
  // now, it is not there (the bytes then come through the sockets).
  if (lane_ && !lane_->attached()) lane_.reset();
  buf_.clear();
  readPrompts(1);
  if (replies_[0].find("Connected to JSBSim server") == std::string::npos)
    throw JsbsimError("JSBSim on port " + std::to_string(port_) +
                      " greeted with an unexpected text: '" + replies_[0] + "'");
  if (outputs_ > 0) acceptOutput(listener.fd);
  // What it printed while loading has been read: from here on only the newer lines matter.
  log_mark_ = readFile(log_path_).size();
  greeted_ = true;
}

void JsbsimProcess::acceptOutput(int listener) {
  // JSBSim connected while loading (before it answered on its input socket) or never: it
  // says which in its output.
  int waited_ms = 0;
  for (;;) {
    pollfd p{listener, POLLIN, 0};
    const int slice = std::max(1, std::min(kWatchMs, timeout_ms_ - waited_ms));
    const int pr = ::poll(&p, 1, slice);
    if (pr > 0) {
      out_fd_ = ::accept4(listener, nullptr, nullptr, SOCK_CLOEXEC);
      if (out_fd_ >= 0) break;
    } else if (pr == 0) {
      waited_ms += slice;
      const std::string log = logSince(0);
      if (log.find("Could not connect to socket for output") != std::string::npos ||
          log.find("Could not get host net address") != std::string::npos)
        failFor("could not connect its output socket to this process (loopback, 'localhost')",
                "it was still running, killed now");
      watchSilence(waited_ms, "connect its output socket");
    } else if (errno != EINTR) {
      throw JsbsimError(std::string("JSBSim: poll(): ") + std::strerror(errno));
    }
  }
  out_buf_.clear();
  // The first line names the columns: "<LABELS> ,Time," then one per property. JSBSim leaves
  // out a property it does not have (saying so in its log) and sends the others.
  while (out_buf_.find('\n') == std::string::npos) receive(out_fd_, &out_buf_);
  const std::string labels = out_buf_.substr(0, out_buf_.find('\n'));
  if (labels.compare(0, 8, "<LABELS>") != 0)
    failFor("sent an unexpected first line on its output socket: '" + labels + "'",
            "it was still running, killed now");
  if (static_cast<size_t>(std::count(labels.begin(), labels.end(), ',')) != outputs_ + 1)
    failFor("does not have every property the package reads from its output socket (" +
                std::to_string(outputs_) + " asked for, its columns: '" + labels + "')",
            "it was still running, killed now");
  out_buf_.erase(0, labels.size() + 1);
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

void JsbsimProcess::watchSilence(int waited_ms, const std::string& waiting_for) {
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
    failDead("did not " + waiting_for + " within " + std::to_string(timeout_ms_) +
             " ms (plant.jsbsim.timeout)");
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
  const std::string state = processState(pid_);
  std::string how =
      "it was still running" + (state.empty() ? "" : " (" + state + ")") + ", killed now";
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

void JsbsimProcess::readPrompts(size_t n) {
  replies_.clear();
  size_t pos = 0;
  while (replies_.size() < n) {
    const size_t i = buf_.find(kPrompt, pos);
    if (i != std::string::npos) {
      replies_.emplace_back(buf_, pos, i - pos);
      pos = i + kPromptLen;
      if (jsbsimRefusedProperty(replies_.back())) takeRefusal(replies_.size() < n);
      continue;
    }
    buf_.erase(0, pos);
    pos = 0;
    receive(fd_, &buf_);
  }
  buf_.erase(0, pos);
}

void JsbsimProcess::receiveLane(bool outputs, std::string* into) {
  // In slices of 20 ms: a JSBSim that ended is seen within one (a socket sees it at once).
  for (int waited_ms = 20, status = 0; !lane_->receive(outputs, into, 20); waited_ms += 20) {
    if (waited_ms % kWatchMs != 0 && exited(&status, 0.0)) {
      pid_ = -1;
      failFor("ended while a reply was due", endedHow(status));
    } else if (waited_ms % kWatchMs == 0) {
      if (outputs) checkRefusals();
      watchSilence(waited_ms);
    }
  }
}

void JsbsimProcess::receive(int fd, std::string* into) {
  if (lane_ && (fd == fd_ || fd == out_fd_)) return receiveLane(fd == out_fd_, into);
  // (A read that spun on a non-blocking socket for the next chunk was slower on this loaded
  // 2-core machine: the spinning client takes the CPU from JSBSim.)
  char chunk[65536];
  ssize_t got = -1;
  int waited_ms = 0;
  for (;;) {
    quickAck(fd);
    got = ::recv(fd, chunk, sizeof chunk, MSG_DONTWAIT);
    if (got >= 0 || (errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR)) break;
    pollfd p{fd, POLLIN, 0};
    const int slice = std::max(1, std::min(kWatchMs, timeout_ms_ - waited_ms));
    int pr;
    do {
      pr = ::poll(&p, 1, slice);
    } while (pr < 0 && errno == EINTR);
    if (pr == 0) {
      waited_ms += slice;
      if (fd == out_fd_) checkRefusals();
      watchSilence(waited_ms);
    }
  }
  quickAck(fd);
  if (got <= 0) failDead("closed the connection mid-run (the process ended or was killed)");
  into->append(chunk, static_cast<size_t>(got));
}

void JsbsimProcess::checkRefusals() {
  // The replies that have come so far (without waiting): a refused command drops the rest of
  // its packet, `iterate` with it, so the frame waited for would never come.
  if (lane_) {
    lane_->receive(false, &buf_, 0);
  } else {
    char chunk[65536];
    ssize_t got;
    while ((got = ::recv(fd_, chunk, sizeof chunk, MSG_DONTWAIT)) > 0)
      buf_.append(chunk, static_cast<size_t>(got));
  }
  for (size_t pos = 0, i; (i = buf_.find(kPrompt, pos)) != std::string::npos;
       pos = i + kPromptLen) {
    replies_.assign(1, buf_.substr(pos, i - pos));
    if (jsbsimRefusedProperty(replies_[0])) takeRefusal(true);
  }
}

bool JsbsimProcess::takeOutputLine() {
  const size_t nl = out_buf_.find('\n');
  if (nl == std::string::npos) return false;
  // "time,v1,...,vn": numbers of at least 12 characters (setw(12), setprecision(7)).
  out_values_.clear();
  const char* p = out_buf_.c_str();
  const char* const end = p + nl;
  for (size_t k = 0; k <= outputs_; ++k) {
    char* after = nullptr;
    const double v = std::strtod(p, &after);
    if (after == p || after > end || (k < outputs_ ? *after != ',' : after != end))
      failFor("sent an unreadable line on its output socket (" + std::to_string(outputs_ + 1) +
                  " numbers expected): '" + out_buf_.substr(0, nl) + "'",
              "it was still running, killed now");
    if (k > 0) out_values_.push_back(v);
    p = after + 1;
  }
  out_buf_.erase(0, nl + 1);
  return true;
}

const std::vector<double>& JsbsimProcess::readOutput() {
  if (out_fd_ < 0)
    throw JsbsimError("JSBSim: no output socket (not started with outputs, or stopped)");
  while (!takeOutputLine()) receive(out_fd_, &out_buf_);
  return out_values_;
}

void JsbsimProcess::sendAll(const char* data, size_t size) {
  if (fd_ < 0) throw JsbsimError("JSBSim: not connected (the process was stopped)");
  if (lane_) {
    int status = 0;
    if (!lane_->send(data, size, [&] { return !exited(&status, 0.0); }))
      failDead("stopped reading its commands");
    return;
  }
  size_t sent = 0;
  while (sent < size) {
    const ssize_t w = ::send(fd_, data + sent, size - sent, MSG_NOSIGNAL);
    if (w < 0 && errno == EINTR) continue;
    if (w <= 0) failDead(std::string("refused a command: ") + std::strerror(errno));
    sent += static_cast<size_t>(w);
  }
}

const std::vector<std::string>& JsbsimProcess::transact(const std::string& packet, size_t lines) {
  send(packet);
  return replies(lines);
}

void JsbsimProcess::send(const std::string& packet) { sendAll(packet.data(), packet.size()); }

const std::vector<std::string>& JsbsimProcess::replies(size_t lines) {
  readPrompts(lines);
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
  return log_path_.empty() ? "(no output)" : jsbsimLogTail(readFile(log_path_), max_lines);
}

void JsbsimProcess::stop() {
  lane_.reset();
  if (fd_ >= 0) {
    ::close(fd_);
    fd_ = -1;
  }
  if (out_fd_ >= 0) {
    ::close(out_fd_);
    out_fd_ = -1;
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
