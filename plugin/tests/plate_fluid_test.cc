// Flat plates of regularized Stokeslets by the nearest-neighbour method
// (plugin/fluid/plate_fluid.h; Smith, J. Comput. Phys. 358, 88-102, 2018,
// with Richardson extrapolation in the blob, Gallagher & Smith, R. Soc.
// Open Sci. 8, 210108, 2021) against exact results: a disk's drag
// broadside (16 mu a U) and edgewise (32/3 mu a U) and its torque about a
// diameter (32/3 mu a^3 Omega) (Ray, Phil. Mag. 21, 546, 1936; Kim &
// Karrila, Microhydrodynamics, 1991, sec. 3.3, the limit of Oberbeck's
// ellipsoid); and the straight 31 x 3 mm strip's drags converging with
// the resolution.
#include "plugin/fluid/plate_fluid.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "sim/base/numbers.h"
#include "plugin/fluid/regularized_stokeslets.h"
#include "tests/oberbeck_drag.h"

namespace ipmc::testing {
namespace {

constexpr double kMu = 1e-3;  // Pa s

// R of one rigid surface about its centre, eps = h / 2, Richardson in eps.
Eigen::MatrixXd OneSurface(const SurfaceMesh& mesh, double spacing_m) {
  PlacedSurface surface;
  surface.mesh = &mesh;
  return ExtrapolatedResistance({surface}, 1, Eigen::Vector3d::Zero(), 0.5 * spacing_m, true, kMu);
}

// After Richardson in eps the remaining error is the piecewise-constant
// force's, first order in the spacing h = 1 / k (the tables below: the
// error times k is nearly constant), so two resolutions extrapolate to
// h = 0: F = (k2 F2 - k1 F1) / (k2 - k1).
double ExtrapolateInSpacing(int k1, double f1, int k2, double f2) {
  return (k2 * f2 - k1 * f1) / (k2 - k1);
}

// The disk of radius a in z = 0 with k rings of cells, against the exact
// drags. Measured (errors, Richardson in eps):
//   k = 6:  broadside -3.637 %, edgewise -3.082 %, torque -11.026 %
//   k = 8:  broadside -2.741 %, edgewise -2.320 %, torque  -8.297 %
//   k = 10: broadside -2.199 %, edgewise -1.860 %, torque  -6.652 %
// falling as 1 / k; extrapolated from k = 8 and 10 (ExtrapolateInSpacing):
// -0.033 %, -0.019 %, -0.073 %, asserted within 0.5 %.
TEST(PlateFluidTest, DiskMatchesTheExactDragsAndTorque) {
  const double a = 1e-3;
  const double broadside_exact = 16.0 * kMu * a;
  const double edgewise_exact = 32.0 / 3.0 * kMu * a;
  const double torque_exact = 32.0 / 3.0 * kMu * a * a * a;
  struct Row {
    int k;
    double broadside, edgewise, torque;
  };
  std::vector<Row> rows;
  for (int k : {6, 8, 10}) {
    const SurfaceMesh mesh = DiskMesh(a, k, 4);
    const Eigen::MatrixXd r = OneSurface(mesh, a / k);
    rows.push_back({k, r(5, 5) / broadside_exact - 1, r(3, 3) / edgewise_exact - 1,
                    r(0, 0) / torque_exact - 1});
    std::printf("k = %2d (%3zu force points): broadside %+.3f %%, edgewise %+.3f %%, torque %+.3f %%\n",
                k, mesh.force_points.size(), 100 * rows.back().broadside,
                100 * rows.back().edgewise, 100 * rows.back().torque);
  }
  for (size_t i = 1; i < rows.size(); ++i) {
    EXPECT_LT(std::abs(rows[i].broadside), std::abs(rows[i - 1].broadside));
    EXPECT_LT(std::abs(rows[i].edgewise), std::abs(rows[i - 1].edgewise));
    EXPECT_LT(std::abs(rows[i].torque), std::abs(rows[i - 1].torque));
  }
  const Row& p = rows[rows.size() - 2];
  const Row& q = rows.back();
  const double broadside = ExtrapolateInSpacing(p.k, p.broadside, q.k, q.broadside);
  const double edgewise = ExtrapolateInSpacing(p.k, p.edgewise, q.k, q.edgewise);
  const double torque = ExtrapolateInSpacing(p.k, p.torque, q.k, q.torque);
  std::printf("extrapolated from k = %d and %d: broadside %+.3f %%, edgewise %+.3f %%, torque %+.3f %%\n",
              p.k, q.k, 100 * broadside, 100 * edgewise, 100 * torque);
  EXPECT_LT(std::abs(broadside), 0.005);
  EXPECT_LT(std::abs(edgewise), 0.005);
  EXPECT_LT(std::abs(torque), 0.005);
}

// Oberbeck's exact drag (tests/oberbeck_drag.h) at this file's viscosity.
double OberbeckDrag(const Eigen::Vector3d& c, int axis) {
  return ipmc::testing::OberbeckEllipsoid(c, kMu).Drag_N_s_m(axis);
}

// The straight strip, 31 mm along x, 3 mm across z, in y = 0, with k force
// points across: the drags extrapolated from (4, 6) and from (6, 8) agree
// within 0.5 % (measured 0.04 %). Its broadside / axial ratio, about 1.71,
// is well above Gray & Hancock's 1.59 (the paper's RFT) and above the
// ratio of the flat ellipsoid of the same outline (Oberbeck), printed for
// comparison with the Stokeslets on the centreline (regularized_stokeslets.h).
TEST(PlateFluidTest, StraightStripDragConverges) {
  const double length = 31e-3, width = 3e-3;
  std::vector<int> ks = {4, 6, 8};
  std::vector<Eigen::Vector3d> drags;  // axial, broadside, edgewise [N s/m]
  for (int k : ks) {
    const SurfaceMesh mesh = RectangleMesh(length, width, k, 4);
    const Eigen::MatrixXd r = OneSurface(mesh, width / k);
    drags.emplace_back(r(3, 3), r(4, 4), r(5, 5));
    std::printf("k = %d (%3zu force points): axial %.6g, broadside %.6g, edgewise %.6g N s/m, "
                "broadside / axial %.4f\n",
                k, mesh.force_points.size(), r(3, 3), r(4, 4), r(5, 5), r(4, 4) / r(3, 3));
  }
  Eigen::Vector3d coarse, fine;
  for (int i = 0; i < 3; ++i) {
    coarse[i] = ExtrapolateInSpacing(ks[0], drags[0][i], ks[1], drags[1][i]);
    fine[i] = ExtrapolateInSpacing(ks[1], drags[1][i], ks[2], drags[2][i]);
    EXPECT_NEAR(fine[i] / coarse[i], 1.0, 0.005) << "axis " << i;
  }
  const double ratio = fine[1] / fine[0];
  std::printf("extrapolated: axial %.6g, broadside %.6g, edgewise %.6g N s/m, ratio %.4f\n",
              fine[0], fine[1], fine[2], ratio);
  // The flat ellipsoid of the same outline and the strip's thickness.
  const Eigen::Vector3d semi(0.5 * length, 0.125e-3, 0.5 * width);
  std::printf("Oberbeck's flat ellipsoid 15.5 x 1.5 x 0.125 mm: broadside / axial %.4f\n",
              OberbeckDrag(semi, 1) / OberbeckDrag(semi, 0));
  // The centreline of Stokeslets (sqrt(e) a, a = 0.8125 mm, one point per blob).
  const double blob = kBlobOverRadius * 0.8125e-3;
  const PointList line = SegmentPoints(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX(), length,
                                       blob, Eigen::Vector3d::UnitZ(), width, 1);
  const Eigen::MatrixXd rod = RigidBodyResistance(line, std::vector<int>(line.size(), 0), 1,
                                                  Eigen::Vector3d::Zero(), {blob, std::nullopt}, kMu);
  std::printf("Stokeslets on the centreline: broadside / axial %.4f\n", rod(4, 4) / rod(3, 3));
  EXPECT_GT(ratio, 1.59 * 1.05);  // Gray & Hancock's ratio, the paper's RFT
}

}  // namespace
}  // namespace ipmc::testing
