// RFT calibrated on the flat plates (plugin/fluid/ribbon_coefficients.h,
// ipmc_rft_coefficients = ribbon) against the plate model itself
// (plugin/fluid/plate_fluid.h, ipmc_fluid_model = plates) on the same
// straight body: the paper's model (models/flagellum3.xml) in its
// reference pose, each segment a plate. The calibration solves its own
// plates (its meshes, placements and extrapolation); the plate model's
// dense resistance, read through the Fluid interface at 4 and 6 points
// across and extrapolated in 1 / k the same way, must give the same drags:
// the sum over the segments of xi_n L and xi_t L for the body translating
// broadside and along its axis, and a link's own rotational drag. The
// fitted set (ribbon_fitted) scales the calibrated one; its swim against
// the plates': tests/ribbon_coefficients_test.cc.
#include <gtest/gtest.h>
#include <mujoco/mujoco.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "plugin/fluid/fluid_model.h"
#include "plugin/fluid/rft_drag.h"
#include "plugin/fluid/ribbon_coefficients.h"
#include "plugin/tests/paper_fluid.h"
#include "plugin/tests/test_model.h"

namespace ipmc::testing {
namespace {

RftDragOverrides Coefficients(CoefficientModel coefficients) {
  RftDragOverrides overrides;
  overrides.model = coefficients;
  return overrides;
}

// The plate model's drags of the straight body at k points across: total
// broadside force, total axial force (unit speed), and segment `turning`'s
// torque about its centre when it alone turns about z at unit rate.
Eigen::Vector3d PlateDrags(int k, int turning) {
  RftDragOverrides overrides;
  overrides.fluid_model = "plates";
  overrides.fluid_parameters["ipmc_fluid_plate_points_across"] = k;
  const Paper paper(overrides);
  const mjModel* m = paper.model.get();
  const mjData* d = paper.data.get();
  const Eigen::MatrixXd& r = *paper.fluid->InteractionResistance(m, d);
  const std::vector<int>& bodies = paper.fluid->InteractingBodies();
  const int n = static_cast<int>(bodies.size());
  const int root = m->body_rootid[bodies[0]];
  const Eigen::Vector3d c(d->subtree_com + 3 * root);  // R's reference point
  Eigen::VectorXd broadside = Eigen::VectorXd::Zero(6 * n), axial = Eigen::VectorXd::Zero(6 * n);
  for (int b = 0; b < n; ++b) {
    broadside[6 * b + 4] = 1.0;
    axial[6 * b + 3] = 1.0;
  }
  const Eigen::VectorXd fb = r * broadside, fa = r * axial;
  Eigen::Vector3d drags(0.0, 0.0, 0.0);
  for (int b = 0; b < n; ++b) drags[0] += fb[6 * b + 4], drags[1] += fa[6 * b + 3];
  // The turning segment's body and centre.
  const int geom = paper.segments.geom_ids()[turning];
  const Eigen::Vector3d p(d->geom_xpos + 3 * geom);
  int b = 0;
  while (bodies[b] != m->geom_bodyid[geom]) ++b;
  Eigen::Matrix<double, 6, 1> turn;
  turn << Eigen::Vector3d::UnitZ(), Eigen::Vector3d::UnitZ().cross(c - p);
  const Eigen::Matrix<double, 6, 1> wrench = r.block<6, 6>(6 * b, 6 * b) * turn;
  drags[2] = (wrench.head<3>() + (c - p).cross(Eigen::Vector3d(wrench.tail<3>()))).z();
  return drags;
}

TEST(RibbonCoefficientsTest, MatchThePlateModelOfTheStraightBody) {
  const Paper paper(Coefficients(CoefficientModel::kRibbon));
  const RftDrag& drag = paper.segments;
  const std::vector<DragCoefficients>& xi = drag.segment_coefficients();
  const std::vector<double> lengths = drag.SegmentLengths_m();
  ASSERT_EQ(xi.size(), 4u);  // the head and three links
  double broadside = 0.0, axial = 0.0;
  for (size_t i = 0; i < xi.size(); ++i) {
    broadside += xi[i].normal_N_s_m2 * lengths[i];
    axial += xi[i].tangential_N_s_m2 * lengths[i];
    std::printf("segment %zu (%.4g mm): xi_n %.6g, xi_t %.6g N s/m^2, ratio %.4f, rotation "
                "%.6g N m s (xi_n L^3 / 12 = %.6g)\n",
                i, 1e3 * lengths[i], xi[i].normal_N_s_m2, xi[i].tangential_N_s_m2,
                xi[i].normal_N_s_m2 / xi[i].tangential_N_s_m2, xi[i].rotation_N_m_s,
                xi[i].normal_N_s_m2 * lengths[i] * lengths[i] * lengths[i] / 12.0);
  }
  constexpr int kMiddleLink = 2;
  const Eigen::Vector3d coarse = PlateDrags(4, kMiddleLink), fine = PlateDrags(6, kMiddleLink);
  const Eigen::Vector3d plates = (6.0 * fine - 4.0 * coarse) / 2.0;
  std::printf("plates extrapolated: broadside %.6g, axial %.6g N s/m, link 2 turning %.6g N m s; "
              "calibrated RFT: %.6g, %.6g, %.6g\n",
              plates[0], plates[1], plates[2], broadside, axial, xi[kMiddleLink].rotation_N_m_s);
  // The two computations agree to the six digits printed (the same
  // equations through different code); 1e-6 is 10 times that.
  EXPECT_NEAR(broadside / plates[0], 1.0, 1e-6);
  EXPECT_NEAR(axial / plates[1], 1.0, 1e-6);
  EXPECT_NEAR(xi[kMiddleLink].rotation_N_m_s / plates[2], 1.0, 1e-6);
  // The ends carry more force per length than the screened middle, and a
  // 10 mm link turns harder than RFT's uniform xi_n L^3 / 12.
  EXPECT_GT(xi[3].normal_N_s_m2, xi[kMiddleLink].normal_N_s_m2);
  const double length = lengths[kMiddleLink];
  EXPECT_GT(xi[kMiddleLink].rotation_N_m_s,
            2.0 * xi[kMiddleLink].normal_N_s_m2 * length * length * length / 12.0);
  EXPECT_DOUBLE_EQ(drag.TowingDrag_N(1.0), axial);
}

TEST(RibbonCoefficientsTest, FittedSetScalesBroadsideAndRotationOnly) {
  const Paper calibrated(Coefficients(CoefficientModel::kRibbon));
  const Paper fitted(Coefficients(CoefficientModel::kRibbonFitted));
  const std::vector<DragCoefficients>& xi = calibrated.segments.segment_coefficients();
  const std::vector<DragCoefficients>& fit = fitted.segments.segment_coefficients();
  ASSERT_EQ(fit.size(), xi.size());
  for (size_t i = 0; i < xi.size(); ++i) {
    EXPECT_DOUBLE_EQ(fit[i].normal_N_s_m2, kFittedBroadsideScale * xi[i].normal_N_s_m2);
    EXPECT_DOUBLE_EQ(fit[i].tangential_N_s_m2, xi[i].tangential_N_s_m2);
    EXPECT_DOUBLE_EQ(fit[i].rotation_N_m_s, kFittedRotationScale * xi[i].rotation_N_m_s);
  }
}

}  // namespace
}  // namespace ipmc::testing
