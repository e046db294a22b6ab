#include "preadaptive_mrac/jsbsim/jsbsim_linearise.hpp"

#include <cmath>
#include <vector>

namespace preadaptive_mrac {

namespace {

/// The input shape w(t): a doublet of 1 s each way from 0.2 s, then a 1.7 Hz square wave of
/// half its amplitude (excites the short period on both of its states).
double inputShape(double t) {
  double w = (t >= 0.2 && t < 1.2) ? 1.0 : ((t >= 1.2 && t < 2.2) ? -1.0 : 0.0);
  if (t >= 2.5) w += 0.5 * (std::sin(2.0 * M_PI * 1.7 * t) >= 0.0 ? 1.0 : -1.0);
  return w;
}

struct Run {
  std::vector<double> alpha, q, speed, pitch, w;
};

Run record(JsbsimPlant* plant, const LineariseOptions& opt, double sign, int steps) {
  Run run;
  plant->reset();
  const Vec theta = Vec::Zero(3);
  for (int k = 0; k <= steps; ++k) {
    run.alpha.push_back(plant->state()[1]);
    run.q.push_back(plant->state()[2]);
    run.speed.push_back(plant->flight().airspeed);
    run.pitch.push_back(plant->flight().pitch);
    const double w = inputShape(k * opt.dt);
    run.w.push_back(w);
    if (k < steps) plant->step(opt.dt, theta, sign * opt.amplitude * w, 0.0, 0.0);
  }
  return run;
}

}  // namespace

LinearModel lineariseJsbsim(JsbsimPlant* plant, const LineariseOptions& opt) {
  const int steps = static_cast<int>(std::lround(opt.duration / opt.dt));
  const Run up = record(plant, opt, 1.0, steps);
  const Run down = record(plant, opt, -1.0, steps);
  plant->reset();
  // Rows: samples k with the same input over [t_k-1, t_k+1] (the central difference then sees
  // one held input); columns: alpha, q, elevator, speed, pitch, 1.
  std::vector<Eigen::Matrix<double, 6, 1>> rows;
  std::vector<double> adot, qdot;
  auto half = [](const std::vector<double>& a, const std::vector<double>& b, int k) {
    return 0.5 * (a[static_cast<size_t>(k)] - b[static_cast<size_t>(k)]);
  };
  for (int k = 1; k < steps; ++k) {
    const auto i = static_cast<size_t>(k);
    if (up.w[i - 1] != up.w[i]) continue;
    Eigen::Matrix<double, 6, 1> row;
    row << half(up.alpha, down.alpha, k), half(up.q, down.q, k), opt.amplitude * up.w[i],
        half(up.speed, down.speed, k), half(up.pitch, down.pitch, k), 1.0;
    rows.push_back(row);
    adot.push_back((half(up.alpha, down.alpha, k + 1) - half(up.alpha, down.alpha, k - 1)) /
                   (2.0 * opt.dt));
    qdot.push_back((half(up.q, down.q, k + 1) - half(up.q, down.q, k - 1)) / (2.0 * opt.dt));
  }
  const auto m = static_cast<Eigen::Index>(rows.size());
  Eigen::MatrixXd X(m, 6);
  Eigen::VectorXd ya(m), yq(m);
  for (Eigen::Index i = 0; i < m; ++i) {
    X.row(i) = rows[static_cast<size_t>(i)].transpose();
    ya[i] = adot[static_cast<size_t>(i)];
    yq[i] = qdot[static_cast<size_t>(i)];
  }
  const auto qr = X.colPivHouseholderQr();
  const Eigen::VectorXd ca = qr.solve(ya), cq = qr.solve(yq);
  LinearModel lm;
  lm.A = Mat::Zero(3, 3);
  lm.A(0, 1) = 1.0;
  lm.A(1, 1) = ca[0];
  lm.A(1, 2) = ca[1];
  lm.A(2, 1) = cq[0];
  lm.A(2, 2) = cq[1];
  lm.B = Vec::Zero(3);
  lm.B[1] = ca[2];
  lm.B[2] = cq[2];
  lm.B1r = Vec::Zero(3);
  lm.B1r[0] = -1.0;
  auto rms = [](const Eigen::VectorXd& v) { return std::sqrt(v.squaredNorm() / v.size()); };
  lm.residual_alpha = rms(ya - X * ca);
  lm.residual_q = rms(yq - X * cq);
  lm.signal_alpha = rms(ya);
  lm.signal_q = rms(yq);
  return lm;
}

}  // namespace preadaptive_mrac
