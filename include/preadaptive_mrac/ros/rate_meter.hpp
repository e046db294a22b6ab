#pragma once
/// \file rate_meter.hpp
/// \brief The rate of a counter between two diagnostics reports. ROS-free.

#include <cstdint>

namespace preadaptive_mrac {
namespace ros1 {

/// \brief Counts per second of a growing counter since the previous update().
class RateMeter {
 public:
  /// \brief Rate [1/s] of `count` since the previous call (0 on the first call or when no
  /// time passed); `now` in seconds on any one clock.
  double update(std::int64_t count, double now) {
    const double span = have_ ? now - last_time_ : 0.0;
    const double rate = span > 0.0 ? static_cast<double>(count - last_count_) / span : 0.0;
    have_ = true;
    last_time_ = now;
    last_count_ = count;
    return rate;
  }

 private:
  bool have_ = false;
  std::int64_t last_count_ = 0;
  double last_time_ = 0.0;
};

}  // namespace ros1
}  // namespace preadaptive_mrac
