// The three-state paths of the hot loop (small_ops.hpp, Plant::step, the sensitivity ODE,
// pa_robust's window sums and residual) give the bits of Eigen's generic expressions: on
// random inputs, and over whole closed-loop runs of every mode.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <map>
#include <random>
#include <string>

#include "preadaptive_mrac/core/closed_loop.hpp"
#include "preadaptive_mrac/core/controller/mode_registry.hpp"
#include "preadaptive_mrac/core/sim/plant.hpp"
#include "preadaptive_mrac/core/small_ops.hpp"
#include "test_helpers.hpp"

using namespace preadaptive_mrac;

namespace {

/// genericPathsOnly() set for the lifetime of the object.
struct GenericOnly {
  GenericOnly() { genericPathsOnly() = true; }
  ~GenericOnly() { genericPathsOnly() = false; }
};

bool sameBits(double a, double b) { return std::memcmp(&a, &b, sizeof(double)) == 0; }

bool sameBits(const Vec& a, const Vec& b) {
  return a.size() == b.size() &&
         std::memcmp(a.data(), b.data(), sizeof(double) * static_cast<size_t>(a.size())) == 0;
}

Vec randomVec(std::mt19937_64* gen, int n, double scale) {
  std::uniform_real_distribution<double> d(-scale, scale);
  Vec v(n);
  for (int i = 0; i < n; ++i) v[i] = d(*gen);
  return v;
}

// A value over many magnitudes, sometimes exactly zero (signed zeros and zero columns are
// where a different order of sums can still agree, or not).
double spread(std::mt19937_64* gen) {
  std::uniform_real_distribution<double> d(-1.0, 1.0);
  const double u = d(*gen);
  if (std::abs(u) < 0.05) return u < 0.0 ? -0.0 : 0.0;
  return u * std::pow(10.0, 3.0 * d(*gen));
}

PlantConfig randomPlant(std::mt19937_64* gen) {
  PlantConfig cfg;
  cfg.A = Eigen::MatrixXd::Zero(3, 3);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) cfg.A(i, j) = spread(gen);
  cfg.B = randomVec(gen, 3, 1.0);
  cfg.B1r = randomVec(gen, 3, 1.0);
  cfg.x0 = Eigen::VectorXd::Zero(3);
  return cfg;
}

}  // namespace

TEST(FastPaths, DotAndReferenceModelProductHaveEigensBits) {
  std::mt19937_64 gen(11);
  for (int k = 0; k < 20000; ++k) {
    Vec a(3), b(3), c(3);
    Mat M(3, 3);
    for (int i = 0; i < 3; ++i) {
      a[i] = spread(&gen);
      b[i] = spread(&gen);
      c[i] = spread(&gen);
      for (int j = 0; j < 3; ++j) M(i, j) = spread(&gen);
    }
    const double r = spread(&gen);
    ASSERT_TRUE(sameBits(dotOf(a, b), a.dot(b))) << "a " << a.transpose() << " b " << b.transpose();
    Vec want;
    want.noalias() = M.lazyProduct(a);
    want += c * r;
    Vec got;
    lazyProductPlus(M, a, c, r, &got);
    ASSERT_TRUE(sameBits(got, want)) << "got " << got.transpose() << " want " << want.transpose();
    lazyProductPlus(M, a, c, r, &a);  // in place
    ASSERT_TRUE(sameBits(a, want));
  }
}

TEST(FastPaths, PlantStepHasTheBitsOfTheGenericStep) {
  // The package's B-747 plant and random full ones (the B-747's zero first column of A makes
  // some orders of summation agree by chance).
  std::mt19937_64 gen(42);
  std::vector<PlantConfig> plants{test::packageConfig("1").plant};
  for (int p = 0; p < 4; ++p) plants.push_back(randomPlant(&gen));
  int compared = 0;
  for (const PlantConfig& cfg : plants) {
    Plant fast(cfg);
    Plant generic = [&] {
      GenericOnly g;
      return Plant(cfg);
    }();
    for (double dt : {0.001, 0.002, 0.0123}) {
      for (int k = 0; k < 2000; ++k) {
        Vec x(3), theta(3);
        for (int i = 0; i < 3; ++i) {
          x[i] = spread(&gen);
          theta[i] = spread(&gen);
        }
        const double u = spread(&gen), r = spread(&gen);
        fast.setState(x);
        generic.setState(x);
        fast.step(dt, theta, u, r);
        generic.step(dt, theta, u, r);
        ASSERT_TRUE(sameBits(fast.state(), generic.state()))
            << "dt " << dt << " x " << x.transpose() << " theta " << theta.transpose() << " u " << u
            << " r " << r << ": fast " << fast.state().transpose() << ", generic "
            << generic.state().transpose();
        ++compared;
      }
    }
  }
  EXPECT_EQ(compared, 5 * 3 * 2000);
}

TEST(FastPaths, PlantFollowsALongRunBitForBit) {
  std::mt19937_64 gen(7);
  PlantConfig cfg;
  cfg.A = Eigen::MatrixXd::Random(3, 3);
  cfg.A.diagonal().array() -= 2.0;
  cfg.B = Eigen::VectorXd::Random(3);
  cfg.B1r = Eigen::VectorXd::Random(3);
  cfg.x0 = Eigen::VectorXd::Random(3);
  Plant fast(cfg);
  Plant generic = [&] {
    GenericOnly g;
    return Plant(cfg);
  }();
  const Vec theta = randomVec(&gen, 3, 0.5);
  for (int k = 0; k < 20000; ++k) {
    const double u = std::sin(0.01 * k), r = 0.1;
    fast.step(0.001, theta, u, r);
    generic.step(0.001, theta, u, r);
    ASSERT_TRUE(sameBits(fast.state(), generic.state())) << "step " << k;
  }
}

namespace {

// The first difference between two runs, or "" when they agree bit for bit.
std::string firstDifference(const SimResult& a, const SimResult& b) {
  const Series &s = a.series, &g = b.series;
  if (s.t.size() != g.t.size()) return "lengths";
  for (size_t k = 0; k < s.t.size(); ++k) {
    const std::string at = " at t = " + std::to_string(s.t[k]);
    if (!sameBits(s.e[k], g.e[k]) || !sameBits(s.e_dot[k], g.e_dot[k])) return "e" + at;
    if (!sameBits(s.u[k], g.u[k]) || !sameBits(s.u_bl[k], g.u_bl[k]) ||
        !sameBits(s.u_ad[k], g.u_ad[k]))
      return "u" + at;
    if (!sameBits(s.x[k], g.x[k])) return "x" + at;
    if (!sameBits(s.x_r[k], g.x_r[k])) return "x_r" + at;
    if (!sameBits(s.theta_hat[k], g.theta_hat[k])) return "theta_hat" + at;
    if (s.phase[k] != g.phase[k] || s.saturated[k] != g.saturated[k]) return "phase" + at;
  }
  if (a.events.size() != b.events.size()) return "event count";
  for (size_t i = 0; i < a.events.size(); ++i) {
    const Event &x = a.events[i], &y = b.events[i];
    const std::string at = " of event " + std::to_string(i);
    if (x.type != y.type || !sameBits(x.t, y.t) || x.decision != y.decision) return "type" + at;
    if (!sameBits(x.theta_hat_after, y.theta_hat_after)) return "theta_hat_after" + at;
    if (!sameBits(x.cost, y.cost) || !sameBits(x.score, y.score)) return "cost/score" + at;
    if (!sameBits(x.grad, y.grad)) return "grad" + at;
  }
  if (!sameBits(a.metrics.iae, b.metrics.iae)) return "iae";
  return "";
}

}  // namespace

TEST(FastPaths, WholeRunsOfEveryModeHaveTheBitsOfTheGenericPaths) {
  // Scenario 3 in every mode; scenario 1 with every switch detected (so the learners learn),
  // measurement noise, elevator limits and projection (pa_robust's long window, decisions,
  // saturation and clamping all run).
  RunConfig s3 = test::packageConfig("3");
  RunConfig s1 = test::packageConfig("1");
  s1.controller.c_ed = 0.015;
  s1.plant.noise.std = Eigen::VectorXd::Constant(3, 1e-4);
  s1.plant.noise.std[0] = 0.0;
  s1.plant.noise.seed = 5;
  s1.plant.actuator.enabled = true;
  s1.controller.projection = true;
  s1.controller.theta_max = 6.0;
  // Hedged (the default) and unhedged: the hedged law keeps the error small enough that l1
  // sees no event on scenario 1, the unhedged one has them; every mode has events somewhere.
  RunConfig s1_unhedged = s1;
  s1_unhedged.controller.hedging = Hedging::kNone;
  std::map<std::string, size_t> events;
  for (const RunConfig* base : {&s3, &s1, &s1_unhedged}) {
    for (const std::string& m : modeNameList()) {
      RunConfig cfg = *base;
      cfg.controller.mode = m;
      const SimResult fast = test::simulate(cfg);
      SimResult generic;
      {
        GenericOnly g;
        generic = test::simulate(cfg);
      }
      events[m] += fast.events.size();
      EXPECT_EQ(firstDifference(fast, generic), "")
          << m << " on " << (base == &s3 ? "scenario 3" : "scenario 1 with options");
    }
  }
  for (const auto& [m, n] : events) EXPECT_GT(n, 0u) << m;
}
