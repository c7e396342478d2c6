#include "plugin/fluid/regularized_stokeslets.h"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "sim/base/numbers.h"
#include "plugin/mjcf/spatial_algebra.h"

namespace ipmc {

Eigen::Matrix3d RegularizedStokeslet(const Eigen::Vector3d& r, double blob_m) {
  const double e2 = blob_m * blob_m;
  const double r2 = r.squaredNorm();
  const double inv3 = 1.0 / std::pow(r2 + e2, 1.5);
  Eigen::Matrix3d g = r * r.transpose() * inv3;
  g.diagonal().array() += (r2 + 2.0 * e2) * inv3;
  return g;
}

// Ainley et al. (2008), eq. (18) with Smith's (2009) signs, for the wall
// z = wall_z: with h the source's height above the wall, R = x - y* (y*
// the mirror of y), Delta = diag(1, 1, -1), H3 = (R^2 + eps^2)^(-3/2),
// H5 = (R^2 + eps^2)^(-5/2), the primary kernel at x - y minus the image
// kernel at R, and
//   blob:           -2 h^2 3 eps^2 H5 Delta_ij
//   potential dip.:  2 h^2 (Delta_ij H3 - 3 R_i R_j Delta_jj H5)
//   Stokes doublet:  2 h (delta_i3 R_j Delta_jj (R^2 + 4 eps^2) H5
//                         - Delta_ij R_3 H3 + delta_j3 R_i H3
//                         + 3 R_3 R_i R_j Delta_jj H5)
//   rotlet:         -6 h eps^2 H5 (delta_i3 R_j - delta_ij R_3)
// (i the velocity's component, j the force's; coordinates relative to the
// wall).
namespace {

// The image system's terms beyond the image Stokeslet -S_eps(R) (the list
// above), added into g, for R = x - y* and the source's height h.
void AddWallImageTerms(const Eigen::Vector3d& R, double h, double blob_m, Eigen::Matrix3d* g) {
  const double e2 = blob_m * blob_m;
  const double R2 = R.squaredNorm();
  const double h3 = 1.0 / std::pow(R2 + e2, 1.5);
  const double h5 = h3 / (R2 + e2);
  const double delta[3] = {1.0, 1.0, -1.0};
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      const double dij = i == j ? delta[i] : 0.0;
      const double kron = i == j ? 1.0 : 0.0;
      const double rr = R[i] * R[j] * delta[j];
      double term = -2.0 * h * h * 3.0 * e2 * h5 * dij;
      term += 2.0 * h * h * (dij * h3 - 3.0 * rr * h5);
      term += 2.0 * h *
              ((i == 2 ? R[j] * delta[j] * (R2 + 4.0 * e2) * h5 : 0.0) - dij * R[2] * h3 +
               (j == 2 ? R[i] * h3 : 0.0) + 3.0 * R[2] * rr * h5);
      term += -6.0 * h * e2 * h5 * ((i == 2 ? R[j] : 0.0) - kron * R[2]);
      (*g)(i, j) += term;
    }
  }
}

}  // namespace

Eigen::Matrix3d RegularizedWallStokeslet(const Eigen::Vector3d& x, const Eigen::Vector3d& y,
                                         double wall_z_m, double blob_m) {
  const Eigen::Vector3d offset(0.0, 0.0, wall_z_m);
  const Eigen::Vector3d xw = x - offset, yw = y - offset;
  const double h = yw.z();
  const Eigen::Vector3d mirror(yw.x(), yw.y(), -h);
  const Eigen::Vector3d R = xw - mirror;
  Eigen::Matrix3d g = RegularizedStokeslet(xw - yw, blob_m) - RegularizedStokeslet(R, blob_m);
  AddWallImageTerms(R, h, blob_m, &g);
  return g;
}

Eigen::Matrix3d RegularizedWallImage(const Eigen::Vector3d& x, const Eigen::Vector3d& y,
                                     double wall_z_m, double blob_m) {
  const Eigen::Vector3d offset(0.0, 0.0, wall_z_m);
  const Eigen::Vector3d xw = x - offset, yw = y - offset;
  const double h = yw.z();
  const Eigen::Vector3d R = xw - Eigen::Vector3d(yw.x(), yw.y(), -h);
  Eigen::Matrix3d g = -RegularizedStokeslet(R, blob_m);
  AddWallImageTerms(R, h, blob_m, &g);
  return g;
}

Eigen::MatrixXd StokesletMobility(const PointList& points, const StokesletGeometry& geometry,
                                  double viscosity_Pa_s) {
  const int n = static_cast<int>(points.size());
  Eigen::MatrixXd mobility(3 * n, 3 * n);
  const double scale = 1.0 / (8.0 * kPi * viscosity_Pa_s);
  for (int a = 0; a < n; ++a) {
    for (int b = 0; b < n; ++b) {
      mobility.block<3, 3>(3 * a, 3 * b) =
          scale * (geometry.wall_z_m ? RegularizedWallStokeslet(points[a], points[b],
                                                                *geometry.wall_z_m, geometry.blob_m)
                                     : RegularizedStokeslet(points[a] - points[b], geometry.blob_m));
    }
  }
  // The wall kernel is symmetric (Lorentz reciprocity) up to round-off.
  if (geometry.wall_z_m) mobility = 0.5 * (mobility + mobility.transpose()).eval();
  return mobility;
}

MobilitySolver::MobilitySolver(const Eigen::MatrixXd& mobility) {
  Eigen::LLT<Eigen::MatrixXd> llt(mobility);
  if (llt.info() == Eigen::Success) {
    factor_ = llt.matrixL();
    return;
  }
  Eigen::PartialPivLU<Eigen::MatrixXd> lu(mobility);
  cholesky_ = false;
  factor_ = lu.matrixLU();
  permutation_ = lu.permutationP().indices();
}

Eigen::VectorXd MobilitySolver::Forces(const Eigen::VectorXd& u) const {
  if (cholesky_) {
    const auto lower = factor_.triangularView<Eigen::Lower>();
    return lower.transpose().solve(lower.solve(u));
  }
  Eigen::VectorXd pu(u.size());
  for (int i = 0; i < u.size(); ++i) pu[i] = u[permutation_[i]];
  // P M = L U with unit lower L.
  const Eigen::VectorXd y = factor_.triangularView<Eigen::UnitLower>().solve(pu);
  return factor_.triangularView<Eigen::Upper>().solve(y);
}

Eigen::MatrixXd MobilitySolver::Inverse() const {
  const int n = static_cast<int>(factor_.rows());
  Eigen::MatrixXd inverse(n, n);
  for (int k = 0; k < n; ++k) inverse.col(k) = Forces(Eigen::VectorXd::Unit(n, k));
  return inverse;
}

double SegmentIntervals(double length_m, double spacing_m) {
  return std::max(1.0, std::ceil(length_m / spacing_m - 1e-9));
}

PointList SegmentPoints(const Eigen::Vector3d& center, const Eigen::Vector3d& tangent,
                        double length_m, double spacing_m, const Eigen::Vector3d& width_axis,
                        double width_m, int width_points) {
  if (!(spacing_m > 0) || !(length_m > 0) || width_points < 1) {
    throw std::invalid_argument("regularized stokeslets: need length, spacing > 0 and >= 1 point");
  }
  const int along = static_cast<int>(SegmentIntervals(length_m, spacing_m));
  PointList points;
  points.reserve(along * width_points);
  for (int i = 0; i < along; ++i) {
    const Eigen::Vector3d p = center + (-0.5 * length_m + (i + 0.5) * length_m / along) * tangent;
    for (int k = 0; k < width_points; ++k) {
      const double w = width_points == 1 ? 0.0 : (-0.5 + (k + 0.5) / width_points) * width_m;
      points.push_back(p + w * width_axis);
    }
  }
  return points;
}

Eigen::MatrixXd RigidBodyResistance(const PointList& points, const std::vector<int>& body_of_point,
                                    int bodies, const Eigen::Vector3d& c,
                                    const StokesletGeometry& geometry, double viscosity_Pa_s) {
  const int n = static_cast<int>(points.size());
  // B (3N x 6 bodies): point velocity = v_b + w_b x (x - c) = [-(x - c)x, I] V_b.
  Eigen::MatrixXd b = Eigen::MatrixXd::Zero(3 * n, 6 * bodies);
  for (int k = 0; k < n; ++k) {
    const Eigen::Vector3d r = points[k] - c;
    const int body = body_of_point[k];
    b.block<3, 3>(3 * k, 6 * body) = -CrossMatrix(r);
    b.block<3, 3>(3 * k, 6 * body + 3) = Eigen::Matrix3d::Identity();
  }
  const MobilitySolver solver(StokesletMobility(points, geometry, viscosity_Pa_s));
  Eigen::MatrixXd forces(3 * n, 6 * bodies);  // M^-1 B
  for (int col = 0; col < 6 * bodies; ++col) forces.col(col) = solver.Forces(b.col(col));
  // Wrench of the point forces [sum r x f; sum f] = B^T f.
  Eigen::MatrixXd resistance = b.transpose() * forces;
  return 0.5 * (resistance + resistance.transpose());
}

}  // namespace ipmc
