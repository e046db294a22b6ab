#include "preadaptive_mrac/core/robust/chunk_sums.hpp"

#include <algorithm>

namespace preadaptive_mrac {

void ChunkSums::clear(Eigen::Index n) {
  G.setZero(n, n);
  h.setZero(n);
  c = 0.0;
  loss = LossSums();
  loss.hv.setZero(n);
}

void ChunkSums::add(const IdentificationWindow& win, int j0, int len, bool with_loss) {
  Vec Phi;
  double Y = 0.0;
  win.sums(j0, len, &Phi, &Y);
  G.noalias() += Phi * Phi.transpose();
  h += Y * Phi;
  c += Y * Y;
  if (with_loss) {
    const double V = win.vSum(j0, len);
    loss.hv += V * Phi;
    loss.yv += Y * V;
    loss.vv += V * V;
    loss.v += V;
  }
}

void ChunkSums::scale(double f) {
  G *= f;
  h *= f;
  c *= f;
  loss.hv *= f;
  loss.yv *= f;
  loss.vv *= f;
  loss.v *= f;
}

double ChunkSums::error(const Vec& th) const {
  return std::max(0.0, c - 2.0 * th.dot(h) + th.dot(G * th));
}

double ChunkSums::error(const Vec& th, double nu) const {
  if (nu <= 0.0) return error(th);
  const double rw = loss.yv - th.dot(loss.hv) - th.dot(h) + th.dot(G * th);
  const double ww = loss.vv - 2.0 * th.dot(loss.hv) + th.dot(G * th);
  return std::max(0.0, error(th) - 2.0 * nu * rw + nu * nu * ww);
}

Vec ChunkSums::hFixed(double nu) const {
  return nu > 0.0 ? Vec((h - nu * loss.hv) / (1.0 - nu)) : h;
}

Vec ridgeFit(const Mat& G, const Vec& h, const Vec& base, double sigma, double prior_std,
             double ridge) {
  Mat Gl = G;
  const double lambda = sigma * sigma / (prior_std * prior_std) + ridge * std::max(G.trace(), 0.0);
  for (Eigen::Index i = 0; i < G.rows(); ++i) Gl(i, i) += lambda;
  return base + Gl.ldlt().solve(h - G * base);
}

}  // namespace preadaptive_mrac
