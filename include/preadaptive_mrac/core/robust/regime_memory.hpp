#pragma once
/// \file regime_memory.hpp
/// \brief A bounded memory of the regimes (theta estimates) a plant has been in: what the
/// robust preadaptation recalls when the plant switches back (docs/research/robust.md).

#include <cstdint>
#include <vector>

#include "preadaptive_mrac/core/control/network.hpp"
#include "preadaptive_mrac/core/types.hpp"

namespace preadaptive_mrac {

/// \brief A view that keeps a list of regimes bounded: close entries merge, and when the list
/// is full the least used entry (the oldest among equals) makes room.
class RegimeMemory {
 public:
  RegimeMemory(std::vector<RegimeEntry>* entries, int capacity)
      : entries_(entries), capacity_(capacity) {}
  /// \brief Store theta. When an entry predicts the same disturbance theta^T d as theta on
  /// the state d (a typical state of the regime, e.g. the recent mean) to within merge_tol
  /// [rad, input-equivalent], that entry is replaced by theta (the newer estimate) and counted;
  /// otherwise theta is added, evicting first when full. Returns the entry's index, or -1 when
  /// the capacity is 0.
  /// The loss fit (loss, information) is pooled with the entry's by information.
  int remember(const Vec& theta, const Vec& direction, double merge_tol, double loss = 0.0,
               double loss_info = 0.0);
  /// \brief Count a recall of entry i.
  void markUsed(int i);
  int size() const { return static_cast<int>(entries_->size()); }
  int capacity() const { return capacity_; }
  const RegimeEntry& at(int i) const { return (*entries_)[static_cast<size_t>(i)]; }
  /// \brief Drop entries beyond the capacity (least used first), e.g. after a load.
  void trim();

 private:
  std::int64_t nextStamp() const;
  int evictIndex() const;
  std::vector<RegimeEntry>* entries_;
  int capacity_;
};

}  // namespace preadaptive_mrac
