// Slender-ribbon theory (plugin/fluid/ribbon_fluid.h) against exact and
// published drags: the flat ellipsoid of Oberbeck (1876) in translation
// along its three axes and in rotation (Kim & Karrila, Microhydrodynamics,
// 1991, sec. 3.3), as Koens & Lauga (Phys. Fluids 28, 013101, 2016) test
// it, with the error falling as the ribbon gets slender; the leading-order
// drags of a flat ellipse (Koens & Lauga, Phys. Rev. Fluids 2, 084101,
// 2017); and a sheet of regularized Stokeslets on the straight strip.
#include "plugin/fluid/ribbon_fluid.h"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "sim/base/numbers.h"
#include "plugin/fluid/regularized_stokeslets.h"
#include "tests/oberbeck_drag.h"

namespace ipmc::testing {
namespace {

constexpr double kMu = 1e-3;  // Pa s
// The strip: 1 mm head and three 10 mm links, 3 mm wide.
const std::vector<double> kStripPieces_m = {1e-3, 10e-3, 10e-3, 10e-3};
constexpr double kStripWidth_m = 3e-3;

// Oberbeck's exact ellipsoid (tests/oberbeck_drag.h) at this file's viscosity.
struct Oberbeck {
  explicit Oberbeck(const Eigen::Vector3d& semi_axes) : exact(semi_axes, kMu) {}
  double Force(int i) const { return exact.Drag_N_s_m(i); }
  double Torque(int i) const { return exact.RotationalDrag_N_m_s(i); }
  ipmc::testing::OberbeckEllipsoid exact;
};

// The flat ellipse of semi-axes a (along x) and bw (across, along z) as a
// ribbon: one straight piece whose caps make the whole length elliptic.
Eigen::MatrixXd EllipseResistance(double a, double bw, int modes) {
  RibbonSettings settings;
  settings.modes = modes;
  settings.width_m = 2.0 * bw;
  settings.end_cap_m = a;
  std::vector<RibbonPiece> pieces = StraightRibbon({2.0 * a});
  return RibbonBodyResistance(pieces, 1, Eigen::Vector3d(a, 0, 0), settings, kMu);
}

// The ribbon's errors against Oberbeck's flat ellipsoid (thin axis along y,
// 1e-4 of the width): axial (x), broadside (y), edgewise (z) translation,
// rotation about the width (z, the strip's beat) and about the thin axis (y).
struct EllipsoidErrors {
  double axial, broadside, edgewise, rotation_width, rotation_thin;
};
EllipsoidErrors ErrorsAgainstOberbeck(double a, double bw) {
  const Oberbeck exact(Eigen::Vector3d(a, 1e-4 * bw, bw));
  const Eigen::MatrixXd r = EllipseResistance(a, bw, 6);  // [w; v]
  return {r(3, 3) / exact.Force(0) - 1.0, r(4, 4) / exact.Force(1) - 1.0,
          r(5, 5) / exact.Force(2) - 1.0, r(2, 2) / exact.Torque(2) - 1.0,
          r(1, 1) / exact.Torque(1) - 1.0};
}

TEST(RibbonFluidTest, OberbeckTorqueIsStokesForASphere) {
  const double a = 1e-3;
  const Oberbeck sphere(Eigen::Vector3d(a, a, a));
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(sphere.Torque(i) / (8 * kPi * kMu * a * a * a), 1.0, 1e-10);
    EXPECT_NEAR(sphere.Force(i) / (6 * kPi * kMu * a), 1.0, 1e-10);
  }
}

// The flat ellipsoid of the strip's size (semi-axes 15.5 x 1.5 mm, b = 0.097)
// and a stubby one (b = 0.3); SRT's error is O(b^2) (Koens & Lauga 2016).
// Measured (printed), axial / broadside / edgewise / rotation about the
// width: b = 0.097: +0.359 / +0.172 / -0.091 / +0.622 %; b = 0.3: +3.10 /
// +1.45 / -0.49 / +5.82 %; b = 0.03: +0.035 / +0.018 / -0.014 / +0.062 %.
// Bounds: twice the strip's errors, and the shrinking from b = 0.3.
TEST(RibbonFluidTest, FlatEllipsoidMatchesOberbeckAndImprovesAsItGetsSlender) {
  const double a = 15.5e-3;
  std::printf("half-width / half-length, axial, broadside, edgewise, rotation about the width, "
              "rotation about the thin axis [%% against Oberbeck]\n");
  EllipsoidErrors strip{}, stubby{};
  for (double b : {0.03, 1.5 / 15.5, 0.3}) {
    const EllipsoidErrors e = ErrorsAgainstOberbeck(a, b * a);
    std::printf("%.4f %+.3f %+.3f %+.3f %+.3f %+.3f\n", b, 100 * e.axial, 100 * e.broadside,
                100 * e.edgewise, 100 * e.rotation_width, 100 * e.rotation_thin);
    if (b == 0.3) stubby = e;
    if (b != 0.3 && b != 0.03) strip = e;
  }
  EXPECT_LT(std::abs(strip.axial), 0.008);
  EXPECT_LT(std::abs(strip.broadside), 0.004);
  EXPECT_LT(std::abs(strip.edgewise), 0.002);
  EXPECT_LT(std::abs(strip.rotation_width), 0.013);
  EXPECT_LT(std::abs(strip.axial), std::abs(stubby.axial));
  EXPECT_LT(std::abs(strip.broadside), std::abs(stubby.broadside));
  EXPECT_LT(std::abs(strip.edgewise), std::abs(stubby.edgewise));
  EXPECT_LT(std::abs(strip.rotation_width), std::abs(stubby.rotation_width));
}

// The leading order for a flat ellipse (Koens & Lauga 2017), Lambda =
// ln(4 L / w) with L and w the full length and width: axial
// 4 pi mu L / (2 Lambda - 1), broadside 4 pi mu L / Lambda, edgewise
// 4 pi mu L / (Lambda + 1). The uniform force density solves SRT's
// equation exactly on the straight ellipse, so the discretisation must
// give them to round-off.
TEST(RibbonFluidTest, FlatEllipseGivesTheLeadingOrderDrags) {
  const double a = 15.5e-3, bw = 0.01 * a;
  const double length = 2 * a, lambda = std::log(4.0 * a / bw);
  const Eigen::MatrixXd r = EllipseResistance(a, bw, 6);
  EXPECT_NEAR(r(3, 3) / (4 * kPi * kMu * length / (2 * lambda - 1)), 1.0, 1e-9);
  EXPECT_NEAR(r(4, 4) / (4 * kPi * kMu * length / lambda), 1.0, 1e-9);
  EXPECT_NEAR(r(5, 5) / (4 * kPi * kMu * length / (lambda + 1)), 1.0, 1e-9);
}

// The straight strip (1 + 3 x 10 mm, 3 mm wide, rectangular with the model's
// elliptic caps of half the width) against a sheet of regularized Stokeslets
// k = 6 points across (the ribbon rule of regularized_stokeslets.h), whose
// own error on the flat ellipsoid is -1.3 % face-on and +3.0 % axially
// (regularized_stokeslets_test). Measured, ribbon / sheet - 1: axial
// -5.52 %, broadside -0.37 %, edgewise -8.84 %, rotation about the width
// -1.36 %; bounds: about twice these.
TEST(RibbonFluidTest, StraightStripAgreesWithTheStokesletSheet) {
  RibbonSettings settings;
  settings.width_m = kStripWidth_m;
  settings.end_cap_m = 0.5 * kStripWidth_m;
  const Eigen::MatrixXd ribbon = RibbonBodyResistance(StraightRibbon(kStripPieces_m), 1,
                                                      Eigen::Vector3d::Zero(), settings, kMu);
  const int k = 6;
  const double ds = kStripWidth_m / k;
  PointList points;
  double start = 0.0;
  for (double length : kStripPieces_m) {
    const PointList piece =
        SegmentPoints(Eigen::Vector3d(start + 0.5 * length, 0, 0), Eigen::Vector3d::UnitX(),
                      length, ds, Eigen::Vector3d::UnitZ(), kStripWidth_m, k);
    points.insert(points.end(), piece.begin(), piece.end());
    start += length;
  }
  const Eigen::MatrixXd sheet =
      RigidBodyResistance(points, std::vector<int>(points.size(), 0), 1, Eigen::Vector3d::Zero(),
                          {kSheetBlobOverSpacing * ds, std::nullopt}, kMu);
  const double axial = ribbon(3, 3) / sheet(3, 3) - 1.0;
  const double broadside = ribbon(4, 4) / sheet(4, 4) - 1.0;
  const double edgewise = ribbon(5, 5) / sheet(5, 5) - 1.0;
  const double rotation = ribbon(2, 2) / sheet(2, 2) - 1.0;
  std::printf("ribbon / sheet - 1: axial %+.2f %%, broadside %+.2f %%, edgewise %+.2f %%, "
              "rotation about the width %+.2f %%\n",
              100 * axial, 100 * broadside, 100 * edgewise, 100 * rotation);
  EXPECT_LT(std::abs(axial), 0.12);
  EXPECT_LT(std::abs(broadside), 0.008);
  EXPECT_LT(std::abs(edgewise), 0.18);
  EXPECT_LT(std::abs(rotation), 0.03);
}

TEST(RibbonFluidTest, RefusesModesOutOfRange) {
  RibbonSettings settings;
  settings.width_m = settings.end_cap_m = 1e-3;
  settings.modes = kMaxRibbonModes + 1;
  EXPECT_THROW(settings.Validate(), std::invalid_argument);
  settings.modes = 0;
  EXPECT_THROW(settings.Validate(), std::invalid_argument);
}

}  // namespace
}  // namespace ipmc::testing
