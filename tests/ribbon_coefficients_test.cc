// RFT calibrated on the flat plates (plugin/fluid/ribbon_coefficients.h,
// `fluid.rft_coefficients = "ribbon"`) against the plate model itself
// (plugin/fluid/plate_fluid.h, `fluid.model = "plates"`) on the same
// straight body: the paper's model in its reference pose, each segment a
// plate. The calibration solves its own plates (its meshes, placements and
// extrapolation); the plate model's dense resistance, read through the
// Fluid interface at 4 and 6 points across and extrapolated in 1 / k the
// same way, must give the same drags: the sum over the segments of xi_n L
// and xi_t L for the body translating broadside and along its axis, and a
// link's own rotational drag. The fitted set (`"ribbon_fitted"`) against
// the plates' swim and fluid power in the paper's default job.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "ipmc_swim/ipmc_swim.h"
#include "plugin/coupling.h"
#include "plugin/fluid/fluid_model.h"
#include "plugin/fluid/rft_drag.h"
#include "plugin/fluid/ribbon_coefficients.h"
#include "sim/core/scenario.h"
#include "sim/core/scenario_simulation.h"
#include "sim/core/simulation.h"
#include "sim/runs/closed_loop_run.h"

namespace ipmc::testing {
namespace {

const std::string kPaper = std::string(IPMC_SWIM_SOURCE_DIR) + "/scenarios/paper.toml";

std::unique_ptr<Simulation> Paper(const std::string& fluid) {
  return LoadScenarioSimulation(
      ParseScenario("model = \"../models/flagellum3.xml\"\n[fluid]\n" + fluid, kPaper));
}

// The plate model's drags of the straight body at k points across: total
// broadside force, total axial force (unit speed), and segment `turning`'s
// torque about its centre when it alone turns about z at unit rate.
Eigen::Vector3d PlateDrags(int k, int turning) {
  const std::unique_ptr<Simulation> sim =
      Paper("model = \"plates\"\nplate_points_across = " + std::to_string(k) + "\n");
  const mjModel* m = sim->model();
  mjData* d = sim->data();
  mj_resetData(m, d);
  mj_forward(m, d);  // the reference pose: straight along x
  const CouplingContext& coupling = *FindCoupling(d);
  const Eigen::MatrixXd& r = *coupling.fluid->InteractionResistance(m, d);
  const std::vector<int>& bodies = coupling.fluid->InteractingBodies();
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
  const int geom = coupling.drag->geom_ids()[turning];
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
  const std::unique_ptr<Simulation> sim = Paper("rft_coefficients = \"ribbon\"\n");
  const RftDrag& drag = *FindCoupling(sim->data())->drag;
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
  const std::unique_ptr<Simulation> calibrated = Paper("rft_coefficients = \"ribbon\"\n");
  const std::unique_ptr<Simulation> fitted = Paper("rft_coefficients = \"ribbon_fitted\"\n");
  const std::vector<DragCoefficients>& xi =
      FindCoupling(calibrated->data())->drag->segment_coefficients();
  const std::vector<DragCoefficients>& fit =
      FindCoupling(fitted->data())->drag->segment_coefficients();
  ASSERT_EQ(fit.size(), xi.size());
  for (size_t i = 0; i < xi.size(); ++i) {
    EXPECT_DOUBLE_EQ(fit[i].normal_N_s_m2, kFittedBroadsideScale * xi[i].normal_N_s_m2);
    EXPECT_DOUBLE_EQ(fit[i].tangential_N_s_m2, xi[i].tangential_N_s_m2);
    EXPECT_DOUBLE_EQ(fit[i].rotation_N_m_s, kFittedRotationScale * xi[i].rotation_N_m_s);
  }
}

// The paper's default job (three 100 s cycles), cycle 3, against the plates
// extrapolated in 1 / k from k = 4 and 5 (docs/FLUIDS.md, "Flat plates":
// 0.830256 mm and 1.59466e-12 W, themselves uncertain by about 0.5 % and
// 1 %, the distance to the extrapolations from k = 3 and 4 and from k = 5
// and 6: +0.47 % / -1.2 % and +0.42 % / -0.97 %). The factors
// were fitted to these to two figures, which leaves 0.2 % in the swim and
// -0.2 % in the power; 2 % is ten times that: a change in the calibration
// or the dynamics that moves the swim fails it.
TEST(RibbonCoefficientsTest, FittedSetSwimsAsThePlatesInThePaperRun) {
  constexpr double kPlatesSwim_mm = 0.830256, kPlatesFluidPower_W = 1.59466e-12;
  ScenarioConfig scenario = LoadScenario(kPaper);
  scenario.fluid.rft_coefficients = CoefficientModel::kRibbonFitted;
  const ClosedLoopResult result = SimulateScenario(scenario);
  const double swim_mm = result.swim.per_cycle.at(2).com_along;
  const double power_W = result.energy.per_cycle.at(2).fluid_power_W;
  std::printf("ribbon_fitted, default job, cycle 3: %.6g mm (plates %.6g), %.6g W (plates %.6g)\n",
              swim_mm, kPlatesSwim_mm, power_W, kPlatesFluidPower_W);
  EXPECT_NEAR(swim_mm / kPlatesSwim_mm, 1.0, 0.02);
  EXPECT_NEAR(power_W / kPlatesFluidPower_W, 1.0, 0.02);
}

}  // namespace
}  // namespace ipmc::testing
