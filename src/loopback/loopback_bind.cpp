/// \file loopback_bind.cpp
/// \brief LD_PRELOAD shim: with PMRAC_LOOPBACK_BIND=1, bind() to the wildcard address
/// (0.0.0.0 or ::) becomes bind() to loopback (127.0.0.1 or ::1).
///
/// Why: roscpp's XML-RPC server (xmlrpcpp's XmlRpcSocket::bind) binds INADDR_ANY whatever
/// ROS_IP / ROS_HOSTNAME say, so every C++ node would otherwise listen on every address and
/// anyone reaching it could, e.g., call publisherUpdate and feed it a publisher of their own.
/// scripts/lib/ros_env preloads this only for single-machine runs (ROS_IP / ROS_HOSTNAME on
/// loopback); binds to a named address are left alone. docs/reference/ros.md "Network exposure".

#include <dlfcn.h>
#include <netinet/in.h>
#include <sys/socket.h>

#include <cstdlib>
#include <cstring>

namespace {
using BindFn = int (*)(int, const sockaddr*, socklen_t);

bool enabled() {
  const char* v = std::getenv("PMRAC_LOOPBACK_BIND");
  return v != nullptr && std::strcmp(v, "1") == 0;
}
}  // namespace

extern "C" int bind(int fd, const sockaddr* addr, socklen_t len) {
  static const BindFn real = reinterpret_cast<BindFn>(dlsym(RTLD_NEXT, "bind"));
  if (real == nullptr) return -1;
  if (addr != nullptr && enabled()) {
    if (addr->sa_family == AF_INET && len >= static_cast<socklen_t>(sizeof(sockaddr_in))) {
      sockaddr_in a;
      std::memcpy(&a, addr, sizeof a);
      if (a.sin_addr.s_addr == htonl(INADDR_ANY)) {
        a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
        return real(fd, reinterpret_cast<const sockaddr*>(&a), sizeof a);
      }
    } else if (addr->sa_family == AF_INET6 && len >= static_cast<socklen_t>(sizeof(sockaddr_in6))) {
      sockaddr_in6 a;
      std::memcpy(&a, addr, sizeof a);
      if (std::memcmp(&a.sin6_addr, &in6addr_any, sizeof in6addr_any) == 0) {
        a.sin6_addr = in6addr_loopback;
        return real(fd, reinterpret_cast<const sockaddr*>(&a), sizeof a);
      }
    }
  }
  return real(fd, addr, len);
}
