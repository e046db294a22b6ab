#pragma once
/// \file jsbsim_fork.hpp
/// \brief fork() from one thread that lives as long as the process (POSIX + STL), so that a
/// child with PR_SET_PDEATHSIG dies exactly with the process that started it.

#include <sys/types.h>

#include <functional>
#include <string>

namespace preadaptive_mrac {

/// \brief fork() on the process's lasting fork thread; the child runs `child`
/// (async-signal-safe calls only, then exec or _exit). The child's pid, or -1 with errno set.
/// PR_SET_PDEATHSIG fires when the *thread* that forked the child ends, not its process: a
/// child forked by a thread that ends before the run (a nodelet's onInit served by a thread
/// that goes, a pool's worker) would be killed mid-run.
pid_t forkFromLastingThread(const std::function<void()>& child);

/// \brief What /proc says of a running process, for an error message: "state S, 2.31 s of
/// CPU" (R runs or waits for a core, S sleeps, T is stopped); empty when it cannot be read.
/// A process that did not answer tells so whether it was starved (R), waiting (S) or stopped.
std::string processState(pid_t pid);

}  // namespace preadaptive_mrac
