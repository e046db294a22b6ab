// Riccati and Lyapunov solvers: residuals and every refusal.
#include <gtest/gtest.h>

#include <random>

#include "preadaptive_mrac/core/solvers.hpp"
#include "test_helpers.hpp"

using namespace preadaptive_mrac;

namespace {
Eigen::MatrixXd b747A() {
  Eigen::MatrixXd A(3, 3);
  A << 0, 1, 0, 0, -0.32, 0.86, 0, -0.93, -0.43;
  return A;
}
Eigen::VectorXd b747B() { return Eigen::Vector3d(0, -0.02, -1.16); }

std::string causeOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const SolverError& e) {
    EXPECT_FALSE(std::string(e.what()).empty());
    return e.cause();
  }
  return "no error";
}
}  // namespace

TEST(Solvers, B747RiccatiAndLyapunovResiduals) {
  const auto A = b747A();
  const auto B = b747B();
  const Eigen::MatrixXd Q = Eigen::MatrixXd::Identity(3, 3);
  const LqrSolution lqr = solveLqr(A, B, Q, 1.0);
  EXPECT_LT(careResidual(A, B, Q, 1.0, lqr.X), 1e-9);
  EXPECT_LT(lqr.relative_residual, 1e-9);
  // X symmetric positive definite, K = R^-1 B^T X.
  EXPECT_LT((lqr.X - lqr.X.transpose()).norm(), 1e-12);
  EXPECT_GT(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(lqr.X).eigenvalues().minCoeff(), 0.0);
  EXPECT_LT((lqr.K - B.transpose() * lqr.X).norm(), 1e-12);
  const ControllerDesign d = designController(A, B, Q, 1.0);
  EXPECT_TRUE(isHurwitz(d.Ar));
  EXPECT_LT(lyapunovResidual(d.Ar, Eigen::MatrixXd::Identity(3, 3), d.P), 1e-9);
  EXPECT_GT(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(d.P).eigenvalues().minCoeff(), 0.0);
}

TEST(Solvers, LqrGainIsOptimalAgainstPerturbations) {
  // The LQR cost x0^T X x0 must not exceed the cost of any nearby stabilising gain.
  const auto A = b747A();
  const auto B = b747B();
  const Eigen::MatrixXd Q = Eigen::MatrixXd::Identity(3, 3);
  const LqrSolution lqr = solveLqr(A, B, Q, 1.0);
  std::mt19937 gen(3);
  std::normal_distribution<double> nd(0.0, 0.05);
  int compared = 0;
  for (int trial = 0; trial < 20; ++trial) {
    Eigen::RowVectorXd K = lqr.K;
    for (int i = 0; i < 3; ++i) K[i] += nd(gen);
    const Eigen::MatrixXd Acl = A - B * K;
    if (!isHurwitz(Acl)) continue;
    const Eigen::MatrixXd Xk = solveLyapunov(Acl, Q + K.transpose() * K);
    EXPECT_GE(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(Xk - lqr.X).eigenvalues().minCoeff(),
              -1e-9);
    ++compared;
  }
  // Most perturbed gains still stabilise: a test that compared none would prove nothing.
  EXPECT_GE(compared, 15);
}

TEST(Solvers, RandomStabilisableSystems) {
  std::mt19937 gen(42);
  std::normal_distribution<double> nd(0.0, 1.0);
  int solved = 0;
  for (int trial = 0; trial < 60; ++trial) {
    const int n = 2 + trial % 6;
    Eigen::MatrixXd A(n, n), M(n, n);
    Eigen::VectorXd B(n);
    for (int i = 0; i < n; ++i) {
      B[i] = nd(gen);
      for (int j = 0; j < n; ++j) {
        A(i, j) = nd(gen);
        M(i, j) = nd(gen);
      }
    }
    // Q >= 0 of full rank half the time, rank one (still detectable in general) otherwise.
    Eigen::MatrixXd Q = (trial % 2 == 0) ? Eigen::MatrixXd(M * M.transpose())
                                         : Eigen::MatrixXd(M.col(0) * M.col(0).transpose());
    const double R = 0.1 + std::abs(nd(gen));
    ASSERT_TRUE(isStabilizable(A, B)) << "trial " << trial;
    const LqrSolution lqr = solveLqr(A, B, Q, R);
    EXPECT_LT(careResidual(A, B, Q, R, lqr.X), 1e-9) << "trial " << trial << " n " << n;
    EXPECT_TRUE(isHurwitz(A - B * lqr.K)) << "trial " << trial;
    const Eigen::MatrixXd Ar = A - B * lqr.K;
    const Eigen::MatrixXd I = Eigen::MatrixXd::Identity(n, n);
    EXPECT_LT(lyapunovResidual(Ar, I, solveLyapunov(Ar, I)), 1e-9) << "trial " << trial;
    ++solved;
  }
  EXPECT_EQ(solved, 60);
}

TEST(Solvers, RefusesNonStabilisable) {
  // An unstable mode (eigenvalue 1) that B cannot reach.
  Eigen::MatrixXd A(2, 2);
  A << 1, 0, 0, -1;
  const Eigen::VectorXd B = Eigen::Vector2d(0, 1);
  EXPECT_FALSE(isStabilizable(A, B));
  EXPECT_EQ(causeOf([&] { solveLqr(A, B, Eigen::MatrixXd::Identity(2, 2), 1.0); }),
            "not_stabilizable");
  // The same with a stable unreachable mode is fine.
  A(0, 0) = -2;
  EXPECT_TRUE(isStabilizable(A, B));
  EXPECT_NO_THROW(solveLqr(A, B, Eigen::MatrixXd::Identity(2, 2), 1.0));
}

TEST(Solvers, RefusesBadWeights) {
  const auto A = b747A();
  const auto B = b747B();
  Eigen::MatrixXd Q = Eigen::MatrixXd::Identity(3, 3);
  EXPECT_EQ(causeOf([&] { solveLqr(A, B, Q, 0.0); }), "r_not_positive");
  EXPECT_EQ(causeOf([&] { solveLqr(A, B, Q, -1.0); }), "r_not_positive");
  Q(0, 0) = -1.0;
  EXPECT_EQ(causeOf([&] { solveLqr(A, B, Q, 1.0); }), "q_not_psd");
  Q = Eigen::MatrixXd::Identity(3, 3);
  Q(0, 1) = 0.5;
  EXPECT_EQ(causeOf([&] { solveLqr(A, B, Q, 1.0); }), "q_not_symmetric");
  EXPECT_EQ(causeOf([&] { solveLqr(A, B, Eigen::MatrixXd::Identity(2, 2), 1.0); }), "dimension");
}

TEST(Solvers, RefusesImaginaryAxisHamiltonian) {
  // Undamped oscillator with Q = 0: the mode on the imaginary axis is unobservable in the cost.
  Eigen::MatrixXd A(2, 2);
  A << 0, 1, -1, 0;
  const Eigen::VectorXd B = Eigen::Vector2d(0, 1);
  EXPECT_EQ(causeOf([&] { solveLqr(A, B, Eigen::MatrixXd::Zero(2, 2), 1.0); }),
            "hamiltonian_imaginary_axis");
}

TEST(Solvers, RefusesNonHurwitzReferenceModelAndIndefiniteP) {
  const auto A = b747A();
  const auto B = b747B();
  // K = 0 leaves the integrator's eigenvalue at 0: A_r is not Hurwitz.
  EXPECT_EQ(causeOf([&] { designFromGain(A, B, Eigen::RowVectorXd::Zero(3)); }), "not_hurwitz");
  Eigen::MatrixXd P = Eigen::MatrixXd::Identity(3, 3);
  P(2, 2) = -0.1;
  EXPECT_EQ(causeOf([&] { requirePositiveDefinite(P, "P"); }), "p_not_positive_definite");
  EXPECT_EQ(causeOf([&] { requirePositiveDefinite(Eigen::MatrixXd::Identity(2, 2), "P"); }),
            "no error");
}

TEST(Solvers, LyapunovRefusesSingular) {
  Eigen::MatrixXd A(2, 2);
  A << 1, 0, 0, -1;  // lambda_1 + lambda_2 = 0
  EXPECT_EQ(causeOf([&] { solveLyapunov(A, Eigen::MatrixXd::Identity(2, 2)); }), "singular");
}

TEST(Solvers, Rk4HoldIsOneClassicRk4StepWithTheInputHeld) {
  std::mt19937 gen(3);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  for (int n = 1; n <= 5; ++n) {
    Eigen::MatrixXd A(n, n);
    Eigen::VectorXd x(n), b(n);
    for (int i = 0; i < n; ++i) {
      x[i] = u(gen);
      b[i] = u(gen);
      for (int j = 0; j < n; ++j) A(i, j) = u(gen);
    }
    const double dt = 0.05, w = u(gen);
    const auto f = [&](const Eigen::VectorXd& s) -> Eigen::VectorXd { return A * s + b * w; };
    const Eigen::VectorXd k1 = f(x), k2 = f(x + dt / 2 * k1), k3 = f(x + dt / 2 * k2),
                          k4 = f(x + dt * k3);
    const Eigen::VectorXd rk4 = x + dt / 6 * (k1 + 2 * k2 + 2 * k3 + k4);
    const Rk4Hold hold = rk4Hold(A, dt);
    EXPECT_LT((hold.Phi * x + hold.G * b * w - rk4).norm(), 1e-13 * (1.0 + rk4.norm())) << n;
  }
}
