#include "preadaptive_mrac/core/control/network.hpp"

#include <random>

namespace preadaptive_mrac {

namespace {
double logistic(double a) { return 1.0 / (1.0 + std::exp(-a)); }
}  // namespace

PreadaptNetwork::PreadaptNetwork(int hidden, int outputs, std::uint64_t seed, double scale) {
  std::mt19937_64 gen(seed);
  // mt19937_64's output sequence is fixed by the standard; map it to [-scale, scale] by hand
  // (uniform_real_distribution is implementation-defined), so weights are portable.
  auto draw = [&] {
    const double u = static_cast<double>(gen() >> 11) * (1.0 / 9007199254740992.0);
    return scale * (2.0 * u - 1.0);
  };
  s_.V.resize(kNetInputs, hidden);
  s_.W.resize(hidden, outputs);
  for (int k = 0; k < kNetInputs; ++k)
    for (int j = 0; j < hidden; ++j) s_.V(k, j) = draw();
  for (int j = 0; j < hidden; ++j)
    for (int i = 0; i < outputs; ++i) s_.W(j, i) = draw();
  s_.seed = seed;
  s_.init_scale = scale;
  s_.episodes = 0;
}

void PreadaptNetwork::forward(const NetInput& z, Vec* theta_I, HiddenVec* hidden) const {
  HiddenVec s(s_.hidden());
  for (int j = 0; j < s_.hidden(); ++j) s[j] = logistic(s_.V.col(j).dot(z));
  theta_I->noalias() = s_.W.transpose() * s;
  if (hidden != nullptr) *hidden = s;
}

void PreadaptNetwork::gradients(const NetInput& z, const Vec& g, NetW* dW, NetV* dV) const {
  HiddenVec s(s_.hidden());
  for (int j = 0; j < s_.hidden(); ++j) s[j] = logistic(s_.V.col(j).dot(z));
  // dE/dW[j,i] = s_j g_i ; dE/dV[k,j] = z_k s_j (1 - s_j) sum_i W[j,i] g_i
  dW->noalias() = s * g.transpose();
  HiddenVec back(s_.hidden());
  back.noalias() = s_.W * g;
  dV->resize(kNetInputs, s_.hidden());
  for (int j = 0; j < s_.hidden(); ++j) dV->col(j) = z * (s[j] * (1.0 - s[j]) * back[j]);
}

void PreadaptNetwork::learn(const NetInput& z, const Vec& g, double rate) {
  NetW dW;
  NetV dV;
  gradients(z, g, &dW, &dV);
  s_.W -= rate * dW;
  s_.V -= rate * dV;
  ++s_.episodes;
}

}  // namespace preadaptive_mrac
