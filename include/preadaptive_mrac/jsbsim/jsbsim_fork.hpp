#pragma once
/// \file jsbsim_fork.hpp
/// \brief fork() from one thread that lives as long as the process (POSIX + STL), so that a
/// child with PR_SET_PDEATHSIG dies exactly with the process that started it.

#include <sys/types.h>

#include <functional>

namespace preadaptive_mrac {

/// \brief fork() on the process's lasting fork thread; the child runs `child`
/// (async-signal-safe calls only, then exec or _exit). The child's pid, or -1 with errno set.
/// PR_SET_PDEATHSIG fires when the *thread* that forked the child ends, not its process: a
/// child forked by a thread that ends before the run (a nodelet's onInit served by a thread
/// that goes, a pool's worker) would be killed mid-run.
pid_t forkFromLastingThread(const std::function<void()>& child);

}  // namespace preadaptive_mrac
