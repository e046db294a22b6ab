#pragma once
/// \file jsbsim_process.hpp
/// \brief One JSBSim process driven through its input socket (POSIX + STL): started on a free
/// port, connected with retry, set / get / iterate / trim with the traps of the Debian 2020.3
/// binary handled (jsbsim/README.md), and ended whatever happens.

#include <sys/types.h>

#include <chrono>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "preadaptive_mrac/core/sim/plant_engine.hpp"
#include "preadaptive_mrac/jsbsim/jsbsim_lane.hpp"
#include "preadaptive_mrac/jsbsim/jsbsim_log.hpp"
#include "preadaptive_mrac/jsbsim/jsbsim_paths.hpp"

namespace preadaptive_mrac {

/// \brief Anything that goes wrong with JSBSim: the message says what and how to fix it.
class JsbsimError : public PlantEngineError {
 public:
  using PlantEngineError::PlantEngineError;
};

/// \brief How to start JSBSim.
struct JsbsimLaunch {
  std::string executable;  ///< empty: $PMRAC_JSBSIM, /usr/games/JSBSim, <build>/jsbsim/bin/JSBSim
  std::string root;        ///< JSBSim's --root; empty: the package's share/preadaptive_mrac/jsbsim
  std::string aircraft = "b747_pmrac";
  std::string initialize = "cruise_m080_h40k";  ///< the aircraft folder's initial-condition file
  double dt = 0.001;                            ///< JSBSim's frame [s]
  double timeout = 10.0;                        ///< start-up and reply timeout [s]
  /// Properties JSBSim sends through its output socket, one line after every model pass that
  /// is not held (empty: no output socket). Read with JsbsimProcess::readOutput().
  std::vector<std::string> outputs;
  /// The sockets' bytes through shared memory (jsbsim_lane.hpp) when the preload library is
  /// found; false, or no library: loopback TCP. The bytes, and so the run, are the same.
  bool shared_memory = true;
};

/// \brief One JSBSim process in socket lockstep, held between steps.
///
/// The process is forked with PR_SET_PDEATHSIG (SIGKILL) in its own process group from one
/// thread that lives as long as the process (the signal follows the forking thread, and a
/// nodelet's or a pool's thread may end before the run), so it dies with the process that
/// started it whatever ends that (an exception, Ctrl-C, SIGKILL); the destructor kills the
/// group and reaps it. One connection per process (the server
/// serves one client, once); a fresh free port per process (a port is not reusable at once).
/// With JsbsimLaunch::outputs, JSBSim also connects back to a loopback port this object listens
/// on (a `<output type="SOCKET">` directive given by `--logdirectivefile`) and sends those
/// properties as one line of 7 significant digits per model pass, in one send() each.
///
/// A JSBSim that cannot go on fails fast with the cause its output names (jsbsim_log.hpp): a
/// process that ends is seen at once, a refused property (after which JSBSim ignores the rest
/// of the packet and never answers it) at its reply, and JSBSim's fatal lines while a reply is
/// due are looked for every 200 ms; the timeout is left for a process alive and silent.
class JsbsimProcess {
 public:
  explicit JsbsimProcess(const JsbsimLaunch& launch);
  ~JsbsimProcess();
  JsbsimProcess(const JsbsimProcess&) = delete;
  JsbsimProcess& operator=(const JsbsimProcess&) = delete;

  /// \brief Send `packet` (lines ending in '\n') in one write and return the reply text of
  /// each of its `lines` commands (the text before each prompt).
  const std::vector<std::string>& transact(const std::string& packet, size_t lines);
  /// \brief Send `packet` in one write; its replies are read later with replies().
  void send(const std::string& packet);
  /// \brief The reply text of each of the next `lines` commands sent with send().
  const std::vector<std::string>& replies(size_t lines);
  /// \brief The next line of the output socket: JsbsimLaunch::outputs' values in their order
  /// (7 significant digits), without JSBSim's time column. While it waits, a command JSBSim
  /// refused (which drops the rest of its packet, so no frame may come) is an error.
  const std::vector<double>& readOutput();
  /// \brief Set a property (the value written with 17 significant digits).
  void set(const std::string& property, double value);
  /// \brief Read properties in one packet (6 significant digits: JSBSim's `get`).
  std::vector<double> get(const std::vector<std::string>& properties);
  /// \brief JSBSim's longitudinal trim (simulation/do_simple_trim 0) from the current ic/
  /// values; the process ends when it fails, which is reported as a JsbsimError saying so.
  void trim(const std::string& what);
  /// \brief Parse the reply to `get name` ("name = value").
  static double parseGet(const std::string& reply, const std::string& name);

  pid_t pid() const { return pid_; }
  /// \brief The bytes travel through the shared-memory lane (else through loopback TCP).
  bool sharedMemory() const { return lane_ != nullptr; }
  int port() const { return port_; }
  /// \brief The last lines of JSBSim's own output (for messages).
  std::string logTail(size_t max_lines = 8) const;
  /// \brief Kill the process group and reap it (idempotent).
  void stop();

 private:
  [[noreturn]] void failDead(const std::string& what);
  [[noreturn]] void failFor(const std::string& what, const std::string& how);
  void watchStart(std::chrono::steady_clock::time_point* next_watch);
  void watchSilence(int waited_ms, const std::string& waiting_for = "answer");
  void acceptOutput(int listener);
  void checkRefusals();
  /// Receive what `fd` has into `into`, waiting (poll, with the watch every 200 ms) if nothing.
  void receive(int fd, std::string* into);
  /// receive() through the lane: JSBSim's replies (`outputs` false) or output lines.
  void receiveLane(bool outputs, std::string* into);
  void takeRefusal(bool rest_dropped);
  std::string logSince(size_t from) const;
  void startOnce(const JsbsimLaunch& launch, const std::string& exe, const std::string& root);
  /// Read the replies of the `n` commands of one packet.
  void readPrompts(size_t n);
  bool takeOutputLine();
  void sendAll(const char* data, size_t size);
  bool exited(int* status, double wait_s);
  void removeDir();
  pid_t pid_ = -1;
  int fd_ = -1;
  int port_ = 0;
  int timeout_ms_ = 10000;
  std::string dir_, log_path_;
  JsbsimNames names_;
  size_t log_mark_ = 0;   ///< the log's length where the lines that may still matter start
  bool greeted_ = false;  ///< JSBSim has loaded and answered the connection
  std::string buf_;
  std::vector<std::string> replies_;
  int out_fd_ = -1;     ///< JSBSim's output socket (accepted), or -1
  size_t outputs_ = 0;  ///< values per output line (JsbsimLaunch::outputs)
  std::string out_buf_;
  std::vector<double> out_values_;
  std::unique_ptr<JsbsimLane> lane_;  ///< set once JSBSim's preload library has attached
};

}  // namespace preadaptive_mrac
