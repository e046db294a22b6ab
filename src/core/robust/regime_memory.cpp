#include "preadaptive_mrac/core/robust/regime_memory.hpp"

#include <algorithm>
#include <cmath>

namespace preadaptive_mrac {

std::int64_t RegimeMemory::nextStamp() const {
  std::int64_t s = 0;
  for (const auto& e : *entries_) s = std::max(s, e.last_used);
  return s + 1;
}

int RegimeMemory::evictIndex() const {
  int worst = 0;
  for (int i = 1; i < size(); ++i) {
    const RegimeEntry& a = at(i);
    const RegimeEntry& w = at(worst);
    if (a.uses < w.uses || (a.uses == w.uses && a.last_used < w.last_used)) worst = i;
  }
  return worst;
}

int RegimeMemory::remember(const Vec& theta, const Vec& direction, double merge_tol, double loss,
                           double loss_info) {
  const std::int64_t stamp = nextStamp();
  const double dn = direction.norm();
  int best = -1;
  double best_gap = 0.0;
  for (int i = 0; i < size(); ++i) {
    const Vec& t = at(i).theta;
    if (t.size() != theta.size()) continue;
    // Two estimates are one regime when they predict the same disturbance on the states the
    // plant visits (the identifiable part); along unexcited directions they may differ.
    const double gap = dn > 0.0 ? std::abs((t - theta).dot(direction)) : (t - theta).norm();
    if (gap <= merge_tol && (best < 0 || gap < best_gap)) {
      best = i;
      best_gap = gap;
    }
  }
  if (best >= 0) {
    RegimeEntry& e = (*entries_)[static_cast<size_t>(best)];
    e.theta = theta;
    if (loss_info > 0.0) {
      const double w = e.loss_info + loss_info;
      e.loss = (e.loss_info * e.loss + loss_info * loss) / w;
      e.loss_info = w;
    }
    ++e.uses;
    e.last_used = stamp;
    return best;
  }
  if (capacity_ <= 0) return -1;
  RegimeEntry fresh;
  fresh.theta = theta;
  fresh.uses = 1;
  fresh.last_used = stamp;
  fresh.loss = loss_info > 0.0 ? loss : 0.0;
  fresh.loss_info = std::max(loss_info, 0.0);
  if (size() >= capacity_) {
    const int victim = evictIndex();
    (*entries_)[static_cast<size_t>(victim)] = fresh;
    return victim;
  }
  entries_->push_back(fresh);
  return size() - 1;
}

void RegimeMemory::markUsed(int i) {
  if (i < 0 || i >= size()) return;
  const std::int64_t stamp = nextStamp();
  RegimeEntry& e = (*entries_)[static_cast<size_t>(i)];
  ++e.uses;
  e.last_used = stamp;
}

void RegimeMemory::trim() {
  while (size() > std::max(capacity_, 0)) entries_->erase(entries_->begin() + evictIndex());
}

}  // namespace preadaptive_mrac
