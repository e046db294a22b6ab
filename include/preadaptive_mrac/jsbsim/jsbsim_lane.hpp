#pragma once
/// \file jsbsim_lane.hpp
/// \brief The client's end of the shared-memory lane to JSBSim (jsbsim_lane_ring.hpp): the
/// mapped file, the preload library that serves JSBSim's end, and byte-wise reads and writes
/// that wait the way a socket read would.

#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace preadaptive_mrac {

namespace lane {
struct Shared;
}

/// \brief One lane: made before JSBSim starts, used once JSBSim's preload library attached.
class JsbsimLane {
 public:
  /// \brief Make the lane's file `path` (in a folder of this process's own) and map it.
  explicit JsbsimLane(const std::string& path);
  /// \brief The lane, or null when its file cannot be made (a full disk: the sockets then).
  static std::unique_ptr<JsbsimLane> tryMake(const std::string& path);
  ~JsbsimLane();
  JsbsimLane(const JsbsimLane&) = delete;
  JsbsimLane& operator=(const JsbsimLane&) = delete;

  /// \brief The environment to start JSBSim with: this process's, and with a `lane` the
  /// entries that make JSBSim serve it (`preload` first in LD_PRELOAD, the lane's file, JSBSim's
  /// input port and the port its output socket connects to). Without one, no lane entries.
  static std::vector<std::string> childEnvironment(const JsbsimLane* lane,
                                                   const std::string& preload, int in_port,
                                                   int out_port);
  /// \brief JSBSim's preload library has mapped the lane: its socket bytes now travel here.
  bool attached() const;
  /// \brief Send `n` bytes to JSBSim's input, waiting while the ring is full; false when
  /// `alive()` says JSBSim is gone first.
  bool send(const char* data, size_t n, const std::function<bool()>& alive);
  /// \brief Append what JSBSim has answered (`outputs` false) or sent on its output socket
  /// (`outputs` true) to `into`, waiting up to `wait_ms` for something; false when nothing came.
  bool receive(bool outputs, std::string* into, int wait_ms);

 private:
  std::string path_;
  lane::Shared* shared_ = nullptr;
};

/// \brief The preload library JSBSim needs for the lane (libpmrac_jsbsim_lane.so): from
/// $PMRAC_JSBSIM_LANE_PRELOAD, else beside this library or the running program's library
/// folder; empty when not found (the sockets are used then).
std::string findJsbsimLanePreload();

}  // namespace preadaptive_mrac
