#pragma once
/// \file solvers.hpp
/// \brief Start-up solvers: LQR gain from the continuous algebraic Riccati equation and P
/// from the Lyapunov equation. Each refuses bad input with a SolverError naming the cause.

#include <Eigen/Dense>
#include <stdexcept>
#include <string>

namespace preadaptive_mrac {

/// \brief Why a solver refused. `cause` is a stable short code for tests and tools.
class SolverError : public std::runtime_error {
 public:
  SolverError(std::string cause, const std::string& message)
      : std::runtime_error(message), cause_(std::move(cause)) {}
  /// \brief One of: not_stabilizable, q_not_psd, q_not_symmetric, r_not_positive,
  /// hamiltonian_imaginary_axis, not_hurwitz, p_not_positive_definite, dimension, singular.
  const std::string& cause() const { return cause_; }

 private:
  std::string cause_;
};

/// \brief Solution of the CARE A^T X + X A - X B R^-1 B^T X + Q = 0.
struct LqrSolution {
  Eigen::MatrixXd X;     ///< stabilising solution (n x n, symmetric, >= 0)
  Eigen::RowVectorXd K;  ///< gain K = R^-1 B^T X (1 x n), u = -K x
  double relative_residual = 0.0;
};

/// \brief LQR for single-input (A, B): matrix-sign-function solve of the Hamiltonian,
/// polished by Newton-Kleinman steps. Requires Q symmetric >= 0, R > 0, (A, B) stabilisable.
LqrSolution solveLqr(const Eigen::MatrixXd& A, const Eigen::VectorXd& B, const Eigen::MatrixXd& Q,
                     double R);

/// \brief Solve A^T X + X A = -Q (A Hurwitz). Kronecker form, meant for small n.
Eigen::MatrixXd solveLyapunov(const Eigen::MatrixXd& A, const Eigen::MatrixXd& Q);

/// \brief Relative residual ||A^T X + X A - X B R^-1 B^T X + Q|| / (sum of term norms).
double careResidual(const Eigen::MatrixXd& A, const Eigen::VectorXd& B, const Eigen::MatrixXd& Q,
                    double R, const Eigen::MatrixXd& X);
/// \brief Relative residual ||A^T X + X A + Q|| / (||A^T X|| + ||X A|| + ||Q||).
double lyapunovResidual(const Eigen::MatrixXd& A, const Eigen::MatrixXd& Q,
                        const Eigen::MatrixXd& X);

/// \brief PBH test: every eigenvalue with Re >= 0 is controllable.
bool isStabilizable(const Eigen::MatrixXd& A, const Eigen::VectorXd& B, double tol = 1e-9);
/// \brief All eigenvalues strictly in the left half plane.
bool isHurwitz(const Eigen::MatrixXd& A);
/// \brief Largest real part of the eigenvalues of A.
double spectralAbscissa(const Eigen::MatrixXd& A);

/// \brief Everything the controller derives at start-up from (A, B, Q, R).
struct ControllerDesign {
  Eigen::RowVectorXd K;  ///< LQR gain
  Eigen::MatrixXd Ar;    ///< A - B K
  Eigen::MatrixXd P;     ///< A_r^T P + P A_r = -I
  double care_residual = 0.0;
  double lyapunov_residual = 0.0;
};

/// \brief K from the CARE, then designFromGain().
ControllerDesign designController(const Eigen::MatrixXd& A, const Eigen::VectorXd& B,
                                  const Eigen::MatrixXd& Q, double R);
/// \brief A_r = A - B K and P from A_r^T P + P A_r = -I for a given gain; refuses (SolverError
/// not_hurwitz / p_not_positive_definite) when A_r is not Hurwitz or P is not positive definite.
ControllerDesign designFromGain(const Eigen::MatrixXd& A, const Eigen::VectorXd& B,
                                const Eigen::RowVectorXd& K);
/// \brief Throw SolverError p_not_positive_definite unless the symmetric matrix is > 0.
void requirePositiveDefinite(const Eigen::MatrixXd& P, const std::string& name);

/// \brief Classic RK4 over one sample of x' = A x + b w with the input w held over the sample
/// is exactly x_{k+1} = Phi x_k + G b w_k with M = A dt,
/// Phi = I + M + M^2/2 + M^3/6 + M^4/24 and G = dt (I + M/2 + M^2/6 + M^3/24).
struct Rk4Hold {
  Eigen::MatrixXd Phi;  ///< transition over dt
  Eigen::MatrixXd G;    ///< G b: the input vector of b over dt [s]
};
/// \brief The RK4-hold discretisation of A over dt [s]: the reference model, the L1 predictor
/// and the attention thresholds' step response are stepped with it alike.
Rk4Hold rk4Hold(const Eigen::MatrixXd& A, double dt);

}  // namespace preadaptive_mrac
