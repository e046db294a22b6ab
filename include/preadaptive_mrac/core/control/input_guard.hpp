#pragma once
/// \file input_guard.hpp
/// \brief Guards between a transport (ROS topics) and the controller or plant: rejects
/// malformed samples, counts them, and tells when the last valid sample is too old.

#include <cstddef>
#include <cstdint>
#include <string>

namespace preadaptive_mrac {

/// \brief What a stale controller sends instead of its adaptive command. Its names, parser and
/// reading are generated from params/nodes.yaml's ~stale_policy row (parseChoice, choiceName in
/// preadaptive_mrac/params/nodes_params.hpp, which names this header as its `enum_header`).
enum class StalePolicy {
  kBaselineHold,  ///< u = -K x_last: the LQR baseline from the last valid state
  kZero,          ///< u = 0 (trim)
};

/// \brief Validates samples of a fixed-size vector and tracks their age.
///
/// A rejected sample (wrong size, NaN or Inf) changes nothing but the counters: it does not
/// refresh the staleness timer and must not reach the controller.
class InputGuard {
 public:
  /// \brief `size`: entries a sample must have; `timeout` [s]: age after which input is stale.
  InputGuard(std::size_t size, double timeout) : size_(size), timeout_(timeout) {}

  /// \brief Why a sample is unusable ("x has 2 entries, expected 3", "x[1] is nan"), or "".
  std::string check(const double* x, std::size_t size, const char* field = "x") const;
  /// \brief Check and, when valid, record it as the latest at time `now` [s].
  /// Returns false (and sets *why) for a rejected sample.
  bool accept(double now, const double* x, std::size_t size, std::string* why = nullptr,
              const char* field = "x");
  /// \brief No valid sample yet, or the last one is older than the timeout at `now`.
  bool stale(double now) const { return !have_ || now - last_valid_ > timeout_; }
  /// \brief Seconds since the last valid sample (infinity before the first).
  double age(double now) const;
  bool haveValid() const { return have_; }

  std::uint64_t accepted() const { return accepted_; }
  std::uint64_t rejected() const { return rejected_; }
  const std::string& lastRejection() const { return last_reason_; }
  double timeout() const { return timeout_; }

 private:
  std::size_t size_;
  double timeout_;
  bool have_ = false;
  double last_valid_ = 0.0;
  std::uint64_t accepted_ = 0, rejected_ = 0;
  std::string last_reason_;
};

}  // namespace preadaptive_mrac
