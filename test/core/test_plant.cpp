// Plant: the unrolled three-state RK4 step gives the bits of the generic Eigen step.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>

#include "preadaptive_mrac/core/plant.hpp"
#include "test_helpers.hpp"

using namespace preadaptive_mrac;

namespace {
// The generic step as the plant wrote it before the three-state path (and still writes it for
// other n): Eigen's run-time sized expressions on Plant::derivative.
Vec referenceStep(const Plant& p, const Vec& x, double dt, const Vec& theta, double u, double r) {
  Vec k1, k2, k3, k4, tmp;
  p.derivative(x, theta, u, r, &k1);
  tmp = x + 0.5 * dt * k1;
  p.derivative(tmp, theta, u, r, &k2);
  tmp = x + 0.5 * dt * k2;
  p.derivative(tmp, theta, u, r, &k3);
  tmp = x + dt * k3;
  p.derivative(tmp, theta, u, r, &k4);
  Vec out = x;
  out += (dt / 6.0) * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
  return out;
}

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
}  // namespace

TEST(Plant, ThreeStateStepHasTheBitsOfTheGenericStep) {
  // The package's B-747 plant, and a full random one (the B-747's zeros in A's first column
  // make some orders of summation agree by chance).
  PlantConfig random;
  random.A = Eigen::MatrixXd::Random(3, 3);
  random.B = Eigen::VectorXd::Random(3);
  random.B1r = Eigen::VectorXd::Random(3);
  random.x0 = Eigen::VectorXd::Zero(3);
  int compared = 0;
  for (const PlantConfig& cfg : {test::packageConfig("1").plant, random}) {
    ASSERT_EQ(cfg.n(), 3);
    Plant plant(cfg);
    std::mt19937_64 gen(42);
    std::uniform_real_distribution<double> d(-1.0, 1.0);
    for (double dt : {0.001, 0.002, 0.01, 0.0123}) {
      for (int k = 0; k < 2000; ++k) {
        // States and inputs over many magnitudes, so rounding differs between orders of sums.
        const double mag = std::pow(10.0, d(gen) * 3.0);
        const Vec x = randomVec(&gen, 3, mag);
        const Vec theta = randomVec(&gen, 3, 10.0);
        const double u = d(gen) * mag, r = d(gen) * 0.2;
        const Vec want = referenceStep(plant, x, dt, theta, u, r);
        plant.setState(x);
        plant.step(dt, theta, u, r);
        ASSERT_TRUE(sameBits(plant.state(), want))
            << "dt " << dt << " x " << x.transpose() << " theta " << theta.transpose() << " u " << u
            << " r " << r << ": got " << plant.state().transpose() << ", want " << want.transpose();
        ++compared;
      }
    }
  }
  EXPECT_EQ(compared, 16000);
}

TEST(Plant, ThreeStateStepFollowsALongRunBitForBit) {
  // A closed trajectory of 20 000 steps with a random plant: the paths must not drift apart.
  std::mt19937_64 gen(7);
  PlantConfig cfg;
  cfg.A = Eigen::MatrixXd::Random(3, 3);
  cfg.A.diagonal().array() -= 2.0;
  cfg.B = Eigen::VectorXd::Random(3);
  cfg.B1r = Eigen::VectorXd::Random(3);
  cfg.x0 = Eigen::VectorXd::Random(3);
  Plant plant(cfg);
  Vec x = plant.state();
  const Vec theta = randomVec(&gen, 3, 0.5);
  for (int k = 0; k < 20000; ++k) {
    const double u = std::sin(0.01 * k), r = 0.1;
    x = referenceStep(plant, x, 0.001, theta, u, r);
    plant.step(0.001, theta, u, r);
    ASSERT_TRUE(sameBits(plant.state(), x)) << "step " << k;
  }
}

TEST(Plant, OtherSizesTakeTheGenericStep) {
  std::mt19937_64 gen(3);
  for (int n : {1, 2, 4, 5}) {
    PlantConfig cfg;
    cfg.A = Eigen::MatrixXd::Random(n, n);
    cfg.B = Eigen::VectorXd::Random(n);
    cfg.B1r = Eigen::VectorXd::Random(n);
    cfg.x0 = Eigen::VectorXd::Random(n);
    Plant plant(cfg);
    const Vec theta = randomVec(&gen, n, 1.0);
    const Vec want = referenceStep(plant, plant.state(), 0.001, theta, 0.3, 0.1);
    plant.step(0.001, theta, 0.3, 0.1);
    EXPECT_TRUE(sameBits(plant.state(), want)) << "n = " << n;
  }
}
