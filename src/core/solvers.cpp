#include "preadaptive_mrac/core/solvers.hpp"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <sstream>

namespace preadaptive_mrac {

namespace {
std::string matStr(const Eigen::MatrixXd& M) {
  std::ostringstream os;
  os.precision(6);
  os << '[';
  for (int i = 0; i < M.rows(); ++i) {
    if (i) os << ", ";
    os << '[';
    for (int j = 0; j < M.cols(); ++j) os << (j ? ", " : "") << M(i, j);
    os << ']';
  }
  os << ']';
  return os.str();
}

void requireSquare(const Eigen::MatrixXd& A, const char* what) {
  if (A.rows() != A.cols() || A.rows() == 0)
    throw SolverError("dimension", std::string(what) + " must be square and non-empty, got " +
                                       std::to_string(A.rows()) + " x " + std::to_string(A.cols()));
}
}  // namespace

double spectralAbscissa(const Eigen::MatrixXd& A) {
  Eigen::EigenSolver<Eigen::MatrixXd> es(A, false);
  return es.eigenvalues().real().maxCoeff();
}

bool isHurwitz(const Eigen::MatrixXd& A) { return spectralAbscissa(A) < 0.0; }

bool isStabilizable(const Eigen::MatrixXd& A, const Eigen::VectorXd& B, double tol) {
  const int n = static_cast<int>(A.rows());
  Eigen::EigenSolver<Eigen::MatrixXd> es(A, false);
  Eigen::MatrixXd AB(n, n + 1);
  AB << A, B;
  const double scale = std::max(1.0, AB.norm());
  for (int i = 0; i < n; ++i) {
    const std::complex<double> lambda = es.eigenvalues()[i];
    if (lambda.real() < -tol * scale) continue;
    Eigen::MatrixXcd M(n, n + 1);
    M.leftCols(n) = A.cast<std::complex<double>>() - lambda * Eigen::MatrixXcd::Identity(n, n);
    M.col(n) = B.cast<std::complex<double>>();
    Eigen::JacobiSVD<Eigen::MatrixXcd> svd(M);
    if (svd.singularValues()(n - 1) <= tol * scale * 1e3) return false;
  }
  return true;
}

Eigen::MatrixXd solveLyapunov(const Eigen::MatrixXd& A, const Eigen::MatrixXd& Q) {
  requireSquare(A, "A");
  const int n = static_cast<int>(A.rows());
  if (Q.rows() != n || Q.cols() != n)
    throw SolverError("dimension", "Q must be " + std::to_string(n) + " x " + std::to_string(n));
  const int m = n * n;
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(m, m);
  const Eigen::MatrixXd At = A.transpose();
  // vec(A^T X) = (I kron A^T) vec(X); vec(X A) = (A^T kron I) vec(X) (column-major vec).
  for (int j = 0; j < n; ++j) M.block(j * n, j * n, n, n) += At;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) M.block(i * n, j * n, n, n).diagonal().array() += At(i, j);
  Eigen::FullPivLU<Eigen::MatrixXd> lu(M);
  if (!lu.isInvertible())
    throw SolverError(
        "singular",
        "Lyapunov equation is singular: A has eigenvalues lambda_i + lambda_j = 0, A = " +
            matStr(A));
  Eigen::VectorXd q = Eigen::Map<const Eigen::VectorXd>(Q.data(), m);
  Eigen::VectorXd x = lu.solve(-q);
  // Iterative refinement: ill-conditioned A (eigenvalues of very different size) leaves a
  // residual well above round-off after one solve; two corrections bring it down.
  for (int it = 0; it < 3; ++it) {
    const Eigen::VectorXd res = M * x + q;
    if (res.norm() <= 1e-15 * q.norm()) break;
    x -= lu.solve(res);
  }
  Eigen::MatrixXd X = Eigen::Map<Eigen::MatrixXd>(x.data(), n, n);
  return 0.5 * (X + X.transpose());
}

double lyapunovResidual(const Eigen::MatrixXd& A, const Eigen::MatrixXd& Q,
                        const Eigen::MatrixXd& X) {
  const Eigen::MatrixXd AtX = A.transpose() * X, XA = X * A;
  const double den = AtX.norm() + XA.norm() + Q.norm();
  return (AtX + XA + Q).norm() / (den > 0 ? den : 1.0);
}

double careResidual(const Eigen::MatrixXd& A, const Eigen::VectorXd& B, const Eigen::MatrixXd& Q,
                    double R, const Eigen::MatrixXd& X) {
  const Eigen::MatrixXd AtX = A.transpose() * X, XA = X * A;
  const Eigen::VectorXd XB = X * B;
  const Eigen::MatrixXd XBBX = XB * XB.transpose() / R;
  const double den = AtX.norm() + XA.norm() + XBBX.norm() + Q.norm();
  return (AtX + XA - XBBX + Q).norm() / (den > 0 ? den : 1.0);
}

LqrSolution solveLqr(const Eigen::MatrixXd& A, const Eigen::VectorXd& B, const Eigen::MatrixXd& Q,
                     double R) {
  requireSquare(A, "A");
  const int n = static_cast<int>(A.rows());
  if (B.size() != n)
    throw SolverError("dimension", "B must have " + std::to_string(n) + " entries, got " +
                                       std::to_string(B.size()));
  if (Q.rows() != n || Q.cols() != n)
    throw SolverError("dimension", "Q must be " + std::to_string(n) + " x " + std::to_string(n) +
                                       ", got " + std::to_string(Q.rows()) + " x " +
                                       std::to_string(Q.cols()));
  if (!A.allFinite() || !B.allFinite() || !Q.allFinite() || !std::isfinite(R))
    throw SolverError("dimension", "A, B, Q and R must be finite");
  if (!(R > 0.0)) throw SolverError("r_not_positive", "R must be > 0, got " + std::to_string(R));
  const double qscale = std::max(1.0, Q.norm());
  if ((Q - Q.transpose()).norm() > 1e-12 * qscale)
    throw SolverError("q_not_symmetric", "Q must be symmetric, got " + matStr(Q));
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> qe(Q);
  if (qe.eigenvalues().minCoeff() < -1e-12 * qscale)
    throw SolverError("q_not_psd", "Q must be positive semi-definite; its smallest eigenvalue is " +
                                       std::to_string(qe.eigenvalues().minCoeff()));
  if (!isStabilizable(A, B))
    throw SolverError("not_stabilizable",
                      "(A, B) is not stabilisable: an unstable mode of A = " + matStr(A) +
                          " cannot be reached from B = " + matStr(B.transpose()));

  // Hamiltonian and its matrix sign function (determinant-scaled Newton iteration).
  Eigen::MatrixXd H(2 * n, 2 * n);
  H << A, -(B * B.transpose()) / R, -Q, -A.transpose();
  Eigen::MatrixXd Z = H;
  bool converged = false;
  for (int it = 0; it < 100; ++it) {
    Eigen::PartialPivLU<Eigen::MatrixXd> lu(Z);
    const double det = std::abs(lu.determinant());
    const Eigen::MatrixXd Zi = lu.inverse();
    if (!(det > 0.0) || !Zi.allFinite()) break;
    const double c = std::pow(det, -1.0 / (2.0 * n));
    const Eigen::MatrixXd Zn = 0.5 * (c * Z + Zi / c);
    const double change = (Zn - Z).norm() / std::max(1.0, Z.norm());
    Z = Zn;
    if (change < 1e-13) {
      converged = true;
      break;
    }
  }
  if (!converged || !Z.allFinite())
    throw SolverError("hamiltonian_imaginary_axis",
                      "the Hamiltonian has eigenvalues on the imaginary axis: (Q, A) has an "
                      "unobservable mode on the imaginary axis, no stabilising solution exists");
  Eigen::MatrixXd lhs(2 * n, n), rhs(2 * n, n);
  lhs << Z.topRightCorner(n, n), Z.bottomRightCorner(n, n) + Eigen::MatrixXd::Identity(n, n);
  rhs << Z.topLeftCorner(n, n) + Eigen::MatrixXd::Identity(n, n), Z.bottomLeftCorner(n, n);
  Eigen::MatrixXd X = lhs.colPivHouseholderQr().solve(-rhs);
  X = 0.5 * (X + X.transpose());

  // Newton-Kleinman polishing: each step solves a Lyapunov equation of the closed loop.
  double res = careResidual(A, B, Q, R, X);
  for (int it = 0; it < 8 && res > 1e-15; ++it) {
    const Eigen::RowVectorXd K = (B.transpose() * X) / R;
    const Eigen::MatrixXd Acl = A - B * K;
    if (!isHurwitz(Acl)) break;
    const Eigen::MatrixXd Xn = solveLyapunov(Acl, Q + K.transpose() * R * K);
    const double rn = careResidual(A, B, Q, R, Xn);
    if (!(rn < res)) break;
    X = Xn;
    res = rn;
  }
  LqrSolution sol;
  sol.X = X;
  sol.K = (B.transpose() * X) / R;
  sol.relative_residual = res;
  if (!isHurwitz(A - B * sol.K))
    throw SolverError("not_hurwitz",
                      "the LQR closed loop A - B K is not Hurwitz (spectral abscissa " +
                          std::to_string(spectralAbscissa(A - B * sol.K)) + ")");
  return sol;
}

void requirePositiveDefinite(const Eigen::MatrixXd& P, const std::string& name) {
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> pe(0.5 * (P + P.transpose()));
  if (!(pe.eigenvalues().minCoeff() > 0.0))
    throw SolverError("p_not_positive_definite",
                      name + " is not positive definite (smallest eigenvalue " +
                          std::to_string(pe.eigenvalues().minCoeff()) + ")");
}

ControllerDesign designFromGain(const Eigen::MatrixXd& A, const Eigen::VectorXd& B,
                                const Eigen::RowVectorXd& K) {
  ControllerDesign d;
  d.K = K;
  d.Ar = A - B * K;
  if (!isHurwitz(d.Ar))
    throw SolverError("not_hurwitz", "A_r = A - B K is not Hurwitz (spectral abscissa " +
                                         std::to_string(spectralAbscissa(d.Ar)) + ")");
  const int n = static_cast<int>(A.rows());
  const Eigen::MatrixXd I = Eigen::MatrixXd::Identity(n, n);
  d.P = solveLyapunov(d.Ar, I);
  d.lyapunov_residual = lyapunovResidual(d.Ar, I, d.P);
  requirePositiveDefinite(d.P, "P from A_r^T P + P A_r = -I");
  return d;
}

Rk4Hold rk4Hold(const Eigen::MatrixXd& A, double dt) {
  const Eigen::MatrixXd M = A * dt;
  const Eigen::MatrixXd I = Eigen::MatrixXd::Identity(A.rows(), A.rows());
  const Eigen::MatrixXd M2 = M * M, M3 = M2 * M, M4 = M3 * M;
  Rk4Hold h;
  h.Phi = I + M + M2 / 2.0 + M3 / 6.0 + M4 / 24.0;
  h.G = dt * (I + M / 2.0 + M2 / 6.0 + M3 / 24.0);
  return h;
}

ControllerDesign designController(const Eigen::MatrixXd& A, const Eigen::VectorXd& B,
                                  const Eigen::MatrixXd& Q, double R) {
  const LqrSolution lqr = solveLqr(A, B, Q, R);
  ControllerDesign d = designFromGain(A, B, lqr.K);
  d.care_residual = lqr.relative_residual;
  return d;
}

}  // namespace preadaptive_mrac
