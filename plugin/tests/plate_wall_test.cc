// Flat plates near a no-slip plane wall (plugin/fluid/plate_fluid.h: the
// nearest-neighbour method with the regularized image system of Ainley,
// Durkin, Embid, Boindala & Cortez, J. Comput. Phys. 227, 4600-4616, 2008).
//
// The far-field check: a body of mobility M_0 in free space, a height h
// above a wall, feels its own image, which, seen from the body, is a
// Stokeslet's reflection at distance 2h; for a body symmetric under
// x -> -x (no force dipole when it translates) the mobility is
//   M(h) = M_0 - 3 / (32 pi mu h)  parallel to the wall,
//   M(h) = M_0 - 3 / (16 pi mu h)  normal to it,
// up to O(a^2 / h^3): for a sphere, M_0 = 1 / (6 pi mu a), these are
// Faxen's 1 - 9 a / (16 h) (Happel & Brenner, Low Reynolds Number
// Hydrodynamics, 1965, eq. 7-4.28) and Lorentz's 1 - 9 a / (8 h) (eq.
// 7-4.39). The plates' disk, with M_0 its own free-space mobility at the
// same resolution, must follow them, the residual falling as (a / h)^2.
#include "plugin/fluid/plate_fluid.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <optional>

#include "sim/base/numbers.h"
#include "plugin/fluid/regularized_stokeslets.h"

namespace ipmc::testing {
namespace {

constexpr double kMu = 1e-3;  // Pa s
constexpr double kRadius = 1e-3;
constexpr int kRings = 6;

// The image part and the free-space kernel make the wall kernel.
TEST(PlateWallTest, ImagePlusFreeSpaceIsTheWallKernel) {
  const double wall_z = -2e-3, blob = 0.3e-3;
  const Eigen::Vector3d x(0.4e-3, -0.2e-3, 0.5e-3), y(-0.3e-3, 0.6e-3, -1.1e-3);
  const Eigen::Matrix3d wall = RegularizedWallStokeslet(x, y, wall_z, blob);
  const Eigen::Matrix3d sum =
      RegularizedStokeslet(x - y, blob) + RegularizedWallImage(x, y, wall_z, blob);
  EXPECT_LT((wall - sum).norm(), 1e-12 * wall.norm());
  // On the wall the two cancel up to the blob's O(eps^2) (Ainley et al.).
  const Eigen::Vector3d on_wall(0.1e-3, 0.2e-3, wall_z);
  const Eigen::Matrix3d at_wall = RegularizedWallStokeslet(on_wall, y, wall_z, blob);
  EXPECT_LT(at_wall.norm(), 1e-2 * RegularizedStokeslet(on_wall - y, blob).norm());
}

// The disk of radius a (kRings rings of cells, eps = h_f / 2), its normal
// turned by `rotation` from z, centred h above the wall z = -h (none: free
// space): R about its centre, without Richardson in eps. The image
// check is exact for the discrete body to first order (the image flow of
// the total force, uniform over the body, adds M_image to 1 / R), which
// 2 R(eps / 2) - R(eps), nonlinear in 1 / R, would blur at the 1e-3 level.
Eigen::MatrixXd Disk(const SurfaceMesh& mesh, const Eigen::Matrix3d& rotation,
                     std::optional<double> height_m) {
  PlacedSurface disk;
  disk.mesh = &mesh;
  disk.rotation = rotation;
  std::optional<double> wall_z;
  if (height_m) wall_z = -*height_m;
  return SurfaceResistance({disk}, 1, Eigen::Vector3d::Zero(), 0.5 * kRadius / kRings, kMu, {},
                           wall_z);
}

// Turns the disk's normal (z in DiskMesh) onto x.
Eigen::Matrix3d NormalAlongX() {
  Eigen::Matrix3d q;
  q << 0, 0, 1, 0, 1, 0, -1, 0, 0;
  return q;
}

struct WallCase {
  const char* name;
  Eigen::Matrix3d rotation;
  int axis;           // the velocity's component, 3 + (0, 1, 2)
  double image_mu_h;  // the image's mobility times mu h
};

// Measured (k = 6 rings, 113 force points): the residual of the
// translational mobility 1 / R_ii against M_0 + M_image, over M_image, at
// h / a = 4 / 8 / 16:
//   broadside, parallel to the wall (normal along x): -0.0006 / -0.0003 / -0.0001
//   edgewise, parallel (normal along z, along x):     -0.0192 / -0.0051 / -0.0013
//   broadside, normal to the wall (normal along z):   -0.0307 / -0.0081 / -0.0021
// falling as (a / h)^2 (by 3.8-3.9 per doubling of h where it is not at
// round-off). Asserted: within 0.05 of M_image at h = 4 a and 0.01 at 8 a
// and 16 a (about 1.5x the largest, whose expected size is set by the
// (a / h)^2 law, not by noise), falling by more than 3 per doubling where
// above 1e-3; so the wall's effect vanishes as 1 / h far from it.
TEST(PlateWallTest, DiskFollowsTheFaxenLorentzImageFarFromTheWall) {
  const SurfaceMesh mesh = DiskMesh(kRadius, kRings, 4);
  const WallCase cases[] = {
      {"broadside, parallel", NormalAlongX(), 3, -3.0 / (32.0 * kPi)},
      {"edgewise, parallel", Eigen::Matrix3d::Identity(), 3, -3.0 / (32.0 * kPi)},
      {"broadside, normal", Eigen::Matrix3d::Identity(), 5, -3.0 / (16.0 * kPi)},
  };
  for (const WallCase& c : cases) {
    SCOPED_TRACE(c.name);
    const double free_mobility = 1.0 / Disk(mesh, c.rotation, std::nullopt)(c.axis, c.axis);
    double previous = 0.0;
    for (double h_over_a : {4.0, 8.0, 16.0}) {
      const double h = h_over_a * kRadius;
      const double mobility = 1.0 / Disk(mesh, c.rotation, h)(c.axis, c.axis);
      const double image = c.image_mu_h / (kMu * h);
      const double residual = (mobility - free_mobility - image) / image;
      std::printf("%-20s h / a = %4.1f: mobility / free %.6f, residual / image %+.4f\n", c.name,
                  h_over_a, mobility / free_mobility, residual);
      EXPECT_LT(std::abs(residual), h_over_a == 4.0 ? 0.05 : 0.01);
      if (std::abs(previous) > 1e-3) EXPECT_LT(std::abs(residual), std::abs(previous) / 3.0);
      previous = residual;
    }
  }
}

// Richardson in eps near the wall: the image is regular on the plate (its
// singularities lie below the wall), so the wall's part of the mobility
// depends on eps only at O(eps^2) and the O(eps) error that
// 2 R(eps / 2) - R(eps) removes is the free-space kernel's alone. The disk
// (normal along x) 1.5 a above the wall, a gap of half its radius, at
// eps = h_f / 2, h_f / 4, h_f / 8: measured, the wall's part
// M_wall - M_free changes per halving of eps by 1.5e-4 / 2.2e-4 of itself
// moving parallel to the wall and 3.5e-3 / 1.5e-3 normal to it, while the
// free-space mobility itself changes by 1.4e-2 / -6.7e-4 and 4.5e-2 /
// 2.0e-2 (asserted: 1e-2, about 3x the largest, the free-space kernel's
// own change being of that size).
TEST(PlateWallTest, RichardsonInTheBlobHoldsNearTheWall) {
  const SurfaceMesh mesh = DiskMesh(kRadius, kRings, 4);
  const double h = 1.5 * kRadius;
  PlacedSurface disk;
  disk.mesh = &mesh;
  disk.rotation = NormalAlongX();
  const double eps = 0.5 * kRadius / kRings;
  for (int v : {3, 5}) {  // along x (parallel to the wall), along z (normal)
    const auto mobility = [&](double blob, std::optional<double> wall_z) {
      return 1.0 /
             SurfaceResistance({disk}, 1, Eigen::Vector3d::Zero(), blob, kMu, {}, wall_z)(v, v);
    };
    const auto wall_part = [&](double blob) {
      return mobility(blob, -h) - mobility(blob, std::nullopt);
    };
    double previous = wall_part(eps), previous_free = mobility(eps, std::nullopt);
    for (double blob : {0.5 * eps, 0.25 * eps}) {
      const double part = wall_part(blob), free = mobility(blob, std::nullopt);
      std::printf("v %d, eps %.3g m: the wall's part of the mobility %.6g, changed by %.2e; "
                  "the free-space mobility changed by %.2e\n",
                  v, blob, part, part / previous - 1.0, free / previous_free - 1.0);
      EXPECT_LT(std::abs(part / previous - 1.0), 1e-2);
      previous = part;
      previous_free = free;
    }
  }
}

}  // namespace
}  // namespace ipmc::testing
