#include "preadaptive_mrac/jsbsim/jsbsim_lane.hpp"

#include <dlfcn.h>
#include <fcntl.h>
#include <sys/mman.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <new>

#include "preadaptive_mrac/jsbsim/jsbsim_lane_ring.hpp"
#include "preadaptive_mrac/jsbsim/jsbsim_process.hpp"

namespace preadaptive_mrac {

namespace {

constexpr char kPreloadName[] = "libpmrac_jsbsim_lane.so";

}  // namespace

JsbsimLane::JsbsimLane(const std::string& path) : path_(path) {
  const int fd = ::open(path.c_str(), O_RDWR | O_CREAT | O_EXCL | O_CLOEXEC, 0600);
  if (fd < 0)
    throw JsbsimError("JSBSim: cannot make the shared-memory lane " + path + ": " +
                      std::strerror(errno));
  // Its blocks taken now: on a full disk a write into a mapped hole would be a SIGBUS later.
  if (const int e = ::posix_fallocate(fd, 0, sizeof(lane::Shared)); e != 0) {
    ::close(fd);
    ::unlink(path.c_str());
    throw JsbsimError("JSBSim: cannot make the shared-memory lane " + path + ": " +
                      std::strerror(e));
  }
  void* m = ::mmap(nullptr, sizeof(lane::Shared), PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0);
  const int e = errno;
  ::close(fd);
  if (m == MAP_FAILED) {
    ::unlink(path.c_str());
    throw JsbsimError("JSBSim: cannot map the shared-memory lane " + path + ": " +
                      std::strerror(e));
  }
  shared_ = new (m) lane::Shared;
  shared_->magic = lane::kMagic;
  shared_->version = lane::kVersion;
  shared_->attached.store(0);
}

std::unique_ptr<JsbsimLane> JsbsimLane::tryMake(const std::string& path) {
  try {
    return std::make_unique<JsbsimLane>(path);
  } catch (const JsbsimError&) {
    return nullptr;
  }
}

JsbsimLane::~JsbsimLane() {
  if (shared_ != nullptr) ::munmap(shared_, sizeof(lane::Shared));
  ::unlink(path_.c_str());
}

std::vector<std::string> JsbsimLane::childEnvironment(const JsbsimLane* lane,
                                                      const std::string& preload, int in_port,
                                                      int out_port) {
  std::vector<std::string> env;
  std::string old_preload;
  for (char** e = environ; *e != nullptr; ++e) {
    if (lane != nullptr && std::strncmp(*e, "LD_PRELOAD=", 11) == 0)
      old_preload = *e + 11;
    else if (std::strncmp(*e, "PMRAC_JSBSIM_LANE=", 18) != 0 &&
             std::strncmp(*e, "PMRAC_JSBSIM_LANE_IN=", 21) != 0 &&
             std::strncmp(*e, "PMRAC_JSBSIM_LANE_OUT=", 22) != 0)
      env.emplace_back(*e);
  }
  if (lane == nullptr) return env;
  env.push_back("LD_PRELOAD=" + preload + (old_preload.empty() ? "" : ":" + old_preload));
  env.push_back("PMRAC_JSBSIM_LANE=" + lane->path_);
  env.push_back("PMRAC_JSBSIM_LANE_IN=" + std::to_string(in_port));
  env.push_back("PMRAC_JSBSIM_LANE_OUT=" + std::to_string(out_port));
  return env;
}

bool JsbsimLane::attached() const { return shared_->attached.load() != 0; }

bool JsbsimLane::send(const char* data, size_t n, const std::function<bool()>& alive) {
  return lane::writeAll(&shared_->to_jsbsim, data, n, 20000000L, alive);
}

bool JsbsimLane::receive(bool outputs, std::string* into, int wait_ms) {
  lane::Ring* r = outputs ? &shared_->outputs : &shared_->replies;
  const long start = lane::nowNs();
  const long until = start + static_cast<long>(wait_ms) * 1000000L;
  for (;;) {
    const std::uint32_t seen = r->seq.load();
    const size_t have = lane::available(*r);
    if (have > 0) {
      const size_t at = into->size();
      into->resize(at + have);
      into->resize(at + lane::read(r, &(*into)[at], have));
      return true;
    }
    const long now = lane::nowNs();
    if (now >= until) return false;
    if (now - start < lane::kSpinNs)
      lane::relax(now - start);
    else
      lane::sleepOn(&r->seq, &r->sleeping, seen, until - now);
  }
}

std::string findJsbsimLanePreload() {
  namespace fs = std::filesystem;
  if (const char* env = std::getenv("PMRAC_JSBSIM_LANE_PRELOAD"))
    return fs::is_regular_file(env) ? std::string(env) : std::string();
  std::vector<fs::path> dirs;
  // Beside this code when it is a shared library (the nodes and nodelets), else (the batch
  // tools: devel/bin or bin, tests: devel/lib/preadaptive_mrac) the program's library folder.
  Dl_info info{};
  if (::dladdr(reinterpret_cast<void*>(&findJsbsimLanePreload), &info) != 0 &&
      info.dli_fname != nullptr)
    dirs.push_back(fs::path(info.dli_fname).parent_path());
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    dirs.push_back(exe.parent_path());
    dirs.push_back(exe.parent_path().parent_path());
    dirs.push_back(exe.parent_path().parent_path() / "lib");
  }
  for (const auto& d : dirs) {
    const fs::path p = d / kPreloadName;
    if (fs::is_regular_file(p, ec)) return fs::absolute(p).lexically_normal().string();
  }
  return {};
}

}  // namespace preadaptive_mrac
