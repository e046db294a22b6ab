#pragma once
/// \file jsbsim_lane_ring.hpp
/// \brief The shared-memory lane to JSBSim (POSIX + STL, header only): three one-way byte rings
/// in one mapped file, shared by this package's JSBSim client (jsbsim_lane.hpp) and the preload
/// library inside the JSBSim process (src/jsbsim/preload), which carries JSBSim's input-socket
/// and output-socket bytes through them instead of through loopback TCP.
///
/// The bytes are the same as on the sockets; only the way they travel changes. Each ring has
/// one writer and one reader. A reader that finds its ring empty spins for a short while and
/// then sleeps on the ring's futex word; a writer wakes it only when it sleeps.

#include <linux/futex.h>
#include <sched.h>
#include <sys/syscall.h>
#include <time.h>
#include <unistd.h>

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <cstring>

namespace preadaptive_mrac {
namespace lane {

/// "PMRL" and the layout's version: a file of another layout is not used.
constexpr std::uint32_t kMagic = 0x504d524c;
constexpr std::uint32_t kVersion = 1;
/// Bytes per ring (a power of two). A step's packet, its replies and its output lines are a
/// few hundred bytes; a trim's replies a few kilobytes.
constexpr std::size_t kRingBytes = std::size_t{1} << 18;

/// \brief One single-writer single-reader byte ring.
struct Ring {
  alignas(64) std::atomic<std::uint64_t> head{0};  ///< bytes written so far (writer)
  alignas(64) std::atomic<std::uint64_t> tail{0};  ///< bytes read so far (reader)
  alignas(64) std::atomic<std::uint32_t> seq{0};   ///< futex word: bumped after each write
  std::atomic<std::uint32_t> sleeping{0};          ///< the reader sleeps on seq
  std::atomic<std::uint32_t> space_seq{0};         ///< futex word: bumped after each read
  std::atomic<std::uint32_t> writer_sleeping{0};   ///< the writer waits for space
  char data[kRingBytes];
};

/// \brief The mapped file: a header and the three rings.
struct Shared {
  std::uint32_t magic;
  std::uint32_t version;
  std::atomic<std::int32_t> attached;  ///< the preload library's process id, once it has mapped
  Ring to_jsbsim;                      ///< commands (JSBSim's input socket, read side)
  Ring replies;                        ///< JSBSim's answers on its input socket
  Ring outputs;                        ///< JSBSim's output-socket lines
};

inline long futex(std::atomic<std::uint32_t>* word, int op, std::uint32_t val,
                  const timespec* timeout) {
  // FUTEX_WAIT/WAKE without PRIVATE: the word is shared between two processes.
  return ::syscall(SYS_futex, reinterpret_cast<std::uint32_t*>(word), op, val, timeout, nullptr, 0);
}

inline void wake(std::atomic<std::uint32_t>* word, std::atomic<std::uint32_t>* sleeping) {
  word->fetch_add(1);
  if (sleeping->load() != 0) futex(word, FUTEX_WAKE, 0x7fffffff, nullptr);
}

/// \brief Sleep on `word` until it moves from `seen` or `ns` nanoseconds pass.
inline void sleepOn(std::atomic<std::uint32_t>* word, std::atomic<std::uint32_t>* sleeping,
                    std::uint32_t seen, long ns) {
  timespec t{ns / 1000000000L, ns % 1000000000L};
  sleeping->store(1);
  if (word->load() == seen) futex(word, FUTEX_WAIT, seen, &t);
  sleeping->store(0);
}

inline std::size_t available(const Ring& r) {
  return static_cast<std::size_t>(r.head.load(std::memory_order_acquire) -
                                  r.tail.load(std::memory_order_relaxed));
}

/// \brief Copy up to `n` bytes out of `r` (the reader's side); the number copied.
inline std::size_t read(Ring* r, char* out, std::size_t n) {
  const std::uint64_t tail = r->tail.load(std::memory_order_relaxed);
  const std::size_t have = static_cast<std::size_t>(r->head.load(std::memory_order_acquire) - tail);
  const std::size_t take = have < n ? have : n;
  if (take == 0) return 0;
  const std::size_t at = static_cast<std::size_t>(tail % kRingBytes);
  const std::size_t first = take < kRingBytes - at ? take : kRingBytes - at;
  std::memcpy(out, r->data + at, first);
  std::memcpy(out + first, r->data, take - first);
  r->tail.store(tail + take, std::memory_order_release);
  wake(&r->space_seq, &r->writer_sleeping);
  return take;
}

/// \brief Copy what fits of `n` bytes into `r` (the writer's side) and wake a sleeping reader;
/// the number copied (0 when the ring is full).
inline std::size_t write(Ring* r, const char* in, std::size_t n) {
  const std::uint64_t head = r->head.load(std::memory_order_relaxed);
  const std::size_t room =
      kRingBytes - static_cast<std::size_t>(head - r->tail.load(std::memory_order_acquire));
  const std::size_t put = room < n ? room : n;
  if (put == 0) return 0;
  const std::size_t at = static_cast<std::size_t>(head % kRingBytes);
  const std::size_t first = put < kRingBytes - at ? put : kRingBytes - at;
  std::memcpy(r->data + at, in, first);
  std::memcpy(r->data, in + first, put - first);
  r->head.store(head + put, std::memory_order_release);
  wake(&r->seq, &r->sleeping);
  return put;
}

/// \brief Write all `n` bytes, sleeping while the reader frees room (at most `ns_each` per
/// sleep); false when `alive()` says the reader is gone.
template <class Alive>
bool writeAll(Ring* r, const char* in, std::size_t n, long ns_each, Alive alive) {
  while (n > 0) {
    const std::uint32_t seen = r->space_seq.load();
    const std::size_t put = write(r, in, n);
    in += put;
    n -= put;
    if (n == 0) break;
    if (!alive()) return false;
    if (put == 0) sleepOn(&r->space_seq, &r->writer_sleeping, seen, ns_each);
  }
  return true;
}

inline long nowNs() {
  timespec t{};
  ::clock_gettime(CLOCK_MONOTONIC, &t);
  return t.tv_sec * 1000000000L + t.tv_nsec;
}

/// How long either side spins for the other's bytes before it sleeps on the ring: a reply is
/// usually there within JSBSim's step (about 7 us), and JSBSim's next command within the
/// client's controller step, so a step costs no system call when the two sides keep pace.
constexpr long kSpinNs = 200000;

/// \brief One turn of a spin that has waited `spun_ns` so far: a pause, and after the first
/// kYieldAfterNs a yield of the core. With more spinning threads than cores (two JSBSim runs
/// on two cores) the one waited for may be queued behind the spinner on its core.
constexpr long kYieldAfterNs = 20000;
inline void relax(long spun_ns) {
  if (spun_ns > kYieldAfterNs) {
    ::sched_yield();
    return;
  }
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();
#endif
}

}  // namespace lane
}  // namespace preadaptive_mrac
