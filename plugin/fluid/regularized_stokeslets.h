// Regularized Stokeslets: the nonlocal Stokes-flow drag of a body made of
// points, every point's force felt at every other point, so that the links
// of a swimmer interact through the fluid.
//
// Kernel (Cortez 2001; Cortez, Fauci & Medovikov, Phys. Fluids 17, 031504,
// 2005, eq. 10a, blob phi = 15 eps^4 / (8 pi (r^2 + eps^2)^(7/2))): a force
// f at y moves the fluid at x = y + r with
//   8 pi mu u = [ (r^2 + 2 eps^2) I + r r^T ] / (r^2 + eps^2)^(3/2) f,
// finite at r = 0. N points give u = M f with the dense, symmetric,
// positive definite 3N x 3N mobility M; the forces that make given
// velocities are f = M^-1 u (Cholesky, LU if round-off spoils it), and
// the drag on the body is -f.
//
// Near a no-slip plane wall z = z_w the kernel is the regularized image
// system of Ainley, Durkin, Embid, Boindala & Cortez (J. Comput. Phys. 227,
// 4600, 2008; with the sign correction of Smith, Proc. R. Soc. A 465, 3605,
// 2009): image Stokeslet, potential dipole, Stokes doublet and rotlet at
// the mirror point, which makes u = 0 on the wall.
//
// Blob and spacing (docs/FLUIDS.md): a straight line of regularized
// Stokeslets of density f has, a distance s_1 behind and s_2 ahead of a
// point (both >> eps), the local velocity
//   8 pi mu u_n = f_n [ln(4 s_1 s_2 / eps^2) + 2],
//   8 pi mu u_t = f_t  2 ln(4 s_1 s_2 / eps^2),
// and slender-body theory for a cylinder of radius a (Lighthill 1976;
// Keller & Rubinow 1976) has ln(4 s_1 s_2 / a^2) + 1 and
// 2 ln(4 s_1 s_2 / a^2) - 2: both agree for eps = sqrt(e) a = 1.6487 a.
// So a centreline of points with that blob is the slender cylinder of
// radius a; the points are spaced eps apart (the straight strip then
// drags 1.020 (broadside) and 1.026 (axial) times slender-body theory's
// total; closer points creep up by about 1.4 % per halving, as the
// first-kind solve concentrates force at the ends, so the spacing is tied
// to the blob; docs/FLUIDS.md has the table).
//
// Across the ribbon's width (an option, k = `width_points` > 1) the strip
// is a sheet: a square grid of points, ds = w / k apart along and across,
// each with the blob eps = 0.7 ds. The rule is calibrated on the exact drag
// of a flat ellipsoid (Oberbeck 1876; Kim & Karrila, Microhydrodynamics,
// 1991, sec. 3.3), the body Koens & Lauga (Phys. Fluids 28, 013101, 2016)
// test slender-ribbon theory on: semi-axes 15.5 x 1.5 x 0.125 mm, the
// strip's, drag 1.7 / 1.3 / 1.1 % below exact face-on and 5.0 / 3.0 / 2.0 %
// above axially for k = 4 / 6 / 8, converging with k
// (regularized_stokeslets_test, FlatEllipsoidSheetConvergesToOberbeck).
#pragma once

#include <Eigen/Core>
#include <optional>
#include <vector>

namespace ipmc {

// eps / a of a centreline that behaves like a cylinder of radius a.
constexpr double kBlobOverRadius = 1.6487212707001282;  // sqrt(e)
// Point spacing over eps.
constexpr double kSpacingOverBlob = 1.0;
// A sheet's eps over its grid spacing ds = w / width_points.
constexpr double kSheetBlobOverSpacing = 0.7;
// Points across the width: at most this many (k^2 L / w points in all).
constexpr int kMaxWidthPoints = 16;

using PointList = std::vector<Eigen::Vector3d>;

// 8 pi mu times the velocity at y + r per unit force at y.
Eigen::Matrix3d RegularizedStokeslet(const Eigen::Vector3d& r, double blob_m);
// The same near the no-slip wall z = wall_z (both points above it): the
// velocity at x per unit force at y, times 8 pi mu.
Eigen::Matrix3d RegularizedWallStokeslet(const Eigen::Vector3d& x, const Eigen::Vector3d& y,
                                         double wall_z_m, double blob_m);
// The wall's part of it alone, the image system at the mirror point:
// RegularizedWallStokeslet(x, y) - RegularizedStokeslet(x - y), without
// the free-space kernel's singular part near y (the plates' cached own
// blocks, plugin/fluid/plate_fluid.h, add it to their free-space part).
Eigen::Matrix3d RegularizedWallImage(const Eigen::Vector3d& x, const Eigen::Vector3d& y,
                                     double wall_z_m, double blob_m);

// The Stokeslet fluid model's settings (plugin/fluid/fluid_model.h); a
// field left at 0 takes its default there.
struct StokesletSettings {
  int width_points = 1;       // k across the ribbon's width, [1, kMaxWidthPoints]
  double width_m = 0.0;       // the ribbon's width w; default the model's strip width
  double blob_m = 0.0;        // eps; default sqrt(e) a (k = 1), 0.7 ds (k > 1)
  double spacing_m = 0.0;     // between points along a segment; default eps (k = 1), w / k
  std::optional<double> wall_distance_m;  // the centreline's height over a wall
  double shape_tolerance_rad = 1e-3;      // recompute beyond this joint motion
  double secant_reach_rad = 0.0;          // extrapolate within this (0: none)
  double fit_tolerance = 0.0;             // the fit in time's (0: none)
};

struct StokesletGeometry {
  double blob_m = 0.0;
  std::optional<double> wall_z_m;  // a no-slip wall z = wall_z below every point
};

// The mobility u = M f of the points [m/s per N].
Eigen::MatrixXd StokesletMobility(const PointList& points, const StokesletGeometry& geometry,
                                  double viscosity_Pa_s);

// A dense symmetric positive definite matrix, factored once.
class MobilitySolver {
 public:
  explicit MobilitySolver(const Eigen::MatrixXd& mobility);
  // The forces on the fluid that give the point velocities u: M f = u.
  Eigen::VectorXd Forces(const Eigen::VectorXd& u) const;
  // M^-1 (the point resistance).
  Eigen::MatrixXd Inverse() const;

 private:
  Eigen::MatrixXd factor_;  // Cholesky factor L (M = L L^T), or LU
  Eigen::VectorXi permutation_;
  bool cholesky_ = true;
};

// The intervals along a segment that SegmentPoints places its points in:
// ceil(length / spacing), at least 1 (a double, so that a count no int
// holds is not wrapped).
double SegmentIntervals(double length_m, double spacing_m);
// Points along a straight segment: the midpoints of ceil(length / spacing)
// equal intervals, each repeated `width_points` times across `width_m`
// along width_axis (unit; ignored for one point).
PointList SegmentPoints(const Eigen::Vector3d& center, const Eigen::Vector3d& tangent,
                        double length_m, double spacing_m, const Eigen::Vector3d& width_axis,
                        double width_m, int width_points);

// The resistance of rigid bodies made of points: body_of_point[k] in
// [0, bodies) names the body of point k; R (6 bodies x 6 bodies) maps the
// bodies' spatial velocities [w; v] (v that of the body point at c) to
// minus their drag wrenches [torque about c; force]: wrench = -R V.
Eigen::MatrixXd RigidBodyResistance(const PointList& points, const std::vector<int>& body_of_point,
                                    int bodies, const Eigen::Vector3d& c,
                                    const StokesletGeometry& geometry, double viscosity_Pa_s);

}  // namespace ipmc
