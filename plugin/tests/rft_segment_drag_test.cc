// Resistive-force-theory drag (plugin/fluid/rft_drag.h): the segment
// integral and its invariants, the drag of all segments in one pass over
// MuJoCo's tree against mj_applyFT's per segment, the dissipated power,
// and the settings a program imposes over a model's fields. The library's
// drag through ipmc::Attach: tests/rft_drag_test.cc.
#include "plugin/fluid/rft_drag.h"

#include <gtest/gtest.h>
#include <mujoco/mujoco.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "plugin/tests/test_model.h"
#include "sim/base/numbers.h"

namespace ipmc::testing {
namespace {

const DragCoefficients kXi{2.6e-3, 1.6e-3};  // [N s/m^2], water-like

Segment RandomSegment(std::mt19937& rng) {
  std::normal_distribution<double> normal(0.0, 1.0);
  Segment s;
  s.center_W = Eigen::Vector3d(normal(rng), normal(rng), normal(rng)) * 1e-2;
  s.tangent_W = Eigen::Vector3d(normal(rng), normal(rng), normal(rng)).normalized();
  s.length_m = 1e-2 * (0.1 + std::abs(normal(rng)));
  s.velocity_center_W = Eigen::Vector3d(normal(rng), normal(rng), normal(rng)) * 1e-3;
  s.angular_velocity_W = Eigen::Vector3d(normal(rng), normal(rng), normal(rng));
  return s;
}

TEST(RftDragTest, GrayHancockAndLighthillCoefficients) {
  // Gray & Hancock (1955) with mu = 1e-3 Pa s, a = 0.8125 mm, lambda = 32 mm:
  // ln(2 lambda / a) = ln(78.769) = 4.36652, xi_n = 4 pi mu / 4.86652,
  // xi_t = 2 pi mu / 3.86652 (evaluated by hand).
  const DragCoefficients gh = GrayHancockCoefficients(1e-3, 0.8125e-3, 32e-3);
  EXPECT_NEAR(gh.normal_N_s_m2, 4 * kPi * 1e-3 / 4.866524, 1e-9);
  EXPECT_NEAR(gh.tangential_N_s_m2, 2 * kPi * 1e-3 / 3.866524, 1e-9);
  // Lighthill (1976): q = 0.09 lambda, ln(2 q / a) = ln(7.08923) = 1.958577.
  const DragCoefficients li = LighthillCoefficients(1e-3, 0.8125e-3, 32e-3);
  EXPECT_NEAR(li.normal_N_s_m2, 4 * kPi * 1e-3 / 2.458577, 1e-9);
  EXPECT_NEAR(li.tangential_N_s_m2, 2 * kPi * 1e-3 / 1.958577, 1e-9);
  // Both scale linearly with viscosity.
  const DragCoefficients gh2 = GrayHancockCoefficients(2e-3, 0.8125e-3, 32e-3);
  EXPECT_DOUBLE_EQ(gh2.normal_N_s_m2, 2 * gh.normal_N_s_m2);
}

TEST(RftDragTest, ZeroVelocityGivesZeroForce) {
  Segment s;
  s.center_W = Eigen::Vector3d(1, 2, 3);
  s.tangent_W = Eigen::Vector3d(0, 1, 0);
  s.length_m = 0.01;
  s.velocity_center_W.setZero();
  s.angular_velocity_W.setZero();
  const Wrench w = SegmentDragExact(s, kXi);
  EXPECT_EQ(w.force_W.norm(), 0.0);
  EXPECT_EQ(w.torque_center_W.norm(), 0.0);
}

TEST(RftDragTest, DragNeverDoesPositiveWork) {
  std::mt19937 rng(7);
  for (int i = 0; i < 10000; ++i) {
    const Segment s = RandomSegment(rng);
    EXPECT_LE(SegmentDragPower(s, SegmentDragExact(s, kXi)), 0.0);
  }
}

TEST(RftDragTest, ExactSegmentIntegralEqualsFineQuadrature) {
  std::mt19937 rng(11);
  for (int i = 0; i < 100; ++i) {
    const Segment s = RandomSegment(rng);
    const Wrench exact = SegmentDragExact(s, kXi);
    // The force integrand is linear in s: the midpoint rule is exact.
    const Wrench coarse = SegmentDragQuadrature(s, kXi, 10);
    const Wrench fine = SegmentDragQuadrature(s, kXi, 1000);
    EXPECT_LT((fine.force_W - exact.force_W).norm(), 1e-12 * exact.force_W.norm() + 1e-20);
    // The torque integrand is quadratic: midpoint error ~ 1/n^2, so 100x
    // more intervals cut it 1e4x (measured ratio 1.0e4).
    const double coarse_error = (coarse.torque_center_W - exact.torque_center_W).norm();
    const double fine_error = (fine.torque_center_W - exact.torque_center_W).norm();
    const double scale = exact.torque_center_W.norm();
    EXPECT_LT(fine_error, 1e-5 * scale);
    EXPECT_NEAR(coarse_error / fine_error, 1e4, 10.0);
  }
}

TEST(RftDragTest, SegmentAlongItsAxisFeelsTangentialCoefficientOnly) {
  Segment s;
  s.center_W.setZero();
  s.tangent_W = Eigen::Vector3d(1, 0, 0);
  s.length_m = 0.02;
  s.velocity_center_W = Eigen::Vector3d(1e-3, 0, 0);
  s.angular_velocity_W.setZero();
  EXPECT_NEAR(SegmentDragExact(s, kXi).force_W.x(), -kXi.tangential_N_s_m2 * 0.02 * 1e-3, 1e-18);
  s.velocity_center_W = Eigen::Vector3d(0, 1e-3, 0);
  EXPECT_NEAR(SegmentDragExact(s, kXi).force_W.y(), -kXi.normal_N_s_m2 * 0.02 * 1e-3, 1e-18);
  // Rotation about the centre: T = -xi_n L^3 / 12 w.
  s.velocity_center_W.setZero();
  s.angular_velocity_W = Eigen::Vector3d(0, 0, 2.0);
  EXPECT_NEAR(SegmentDragExact(s, kXi).torque_center_W.z(),
              -kXi.normal_N_s_m2 * std::pow(0.02, 3) / 12 * 2.0, 1e-20);
}

// The planar block the Stokes step assembles is rows and columns 2 to 4
// ([w_z; v_x; v_y]) of the whole spatial resistance, for any tangent and
// centre (out of the plane too): measured equal to the last bit on these
// 200 segments (the same products in the same order); the bound allows
// the compiler another order of the sums.
TEST(RftDragTest, PlanarResistanceIsTheWholeResistancesBlock) {
  std::mt19937 rng(13);
  std::normal_distribution<double> normal(0.0, 1.0);
  for (int trial = 0; trial < 200; ++trial) {
    const Segment s = RandomSegment(rng);
    const Eigen::Vector3d c = Eigen::Vector3d(normal(rng), normal(rng), normal(rng)) * 1e-2;
    const SpatialResistance whole = SegmentResistance(s.center_W, s.tangent_W, s.length_m, c, kXi);
    const Eigen::Matrix3d planar =
        SegmentPlanarResistance(s.center_W, s.tangent_W, s.length_m, c, kXi);
    EXPECT_LE((planar - whole.block<3, 3>(2, 2)).norm(), 1e-14 * whole.norm()) << trial;
  }
}

// The strip of three links of 3 sub-segments each: a deeper tree than the
// rigid links'.
ModelPtr SubSegmentedFlagellum(bool clamped) { return LoadXml(SubSegmentedStrip(3, clamped)); }

// A random pose (angles ~ 0.3 rad) and velocity (~ 1e-3), then mj_forward.
void RandomState(const mjModel* m, mjData* d, std::mt19937& rng) {
  std::normal_distribution<double> normal(0.0, 1.0);
  for (int i = 0; i < m->nq; ++i) d->qpos[i] = 0.3 * normal(rng);
  for (int i = 0; i < m->nv; ++i) d->qvel[i] = 1e-3 * normal(rng);
  mj_forward(m, d);
}

// RftDrag::Apply maps all segments' wrenches into generalised forces in
// one pass over the tree; MuJoCo's mj_applyFT does it one wrench at a time
// through the point's Jacobian. The two (and the segments' velocities and
// mj_objectVelocity's) agree on random states of a free
// and a clamped strip with sub-segments (a deeper tree), to rounding:
// measured 4.0e-16 / 4.2e-16 of the largest entry.
TEST(RftDragTest, OnePassEqualsMujocosApplyFtPerSegment) {
  for (bool clamped : {false, true}) {
    const ModelPtr model = SubSegmentedFlagellum(clamped);
    const mjModel* m = model.get();
    const DataPtr data = MakeData(m);
    mjData* d = data.get();
    const RftDrag drag(m, *RftDragConfig::FromModel(m));
    std::mt19937 rng(11);
    double worst = 0.0;
    for (int trial = 0; trial < 50; ++trial) {
      RandomState(m, d, rng);  // not attached: qfrc_passive holds MuJoCo's own forces
      std::vector<double> per_segment(d->qfrc_passive, d->qfrc_passive + m->nv);
      drag.Apply(m, d);  // adds the drag to them
      const std::vector<double> one_pass(d->qfrc_passive, d->qfrc_passive + m->nv);
      const std::vector<Segment> segments = drag.Segments(m, d);
      for (size_t k = 0; k < segments.size(); ++k) {
        const Wrench wrench = SegmentDragExact(segments[k], drag.coefficients());
        mjtNum force[3], torque[3], point[3];
        for (int i = 0; i < 3; ++i) {
          force[i] = wrench.force_W[i];
          torque[i] = wrench.torque_center_W[i];
          point[i] = segments[k].center_W[i];
        }
        mj_applyFT(m, d, force, torque, point, m->geom_bodyid[drag.geom_ids()[k]],
                   per_segment.data());
      }
      double largest = 0.0, difference = 0.0;
      for (int i = 0; i < m->nv; ++i) {
        largest = std::max(largest, std::abs(per_segment[i]));
        difference = std::max(difference, std::abs(one_pass[i] - per_segment[i]));
      }
      ASSERT_GT(largest, 0.0);
      worst = std::max(worst, difference / largest);
      // The segments' velocities, taken from the bodies' spatial
      // velocities, are mj_objectVelocity's at the geom centres: the same
      // operations, so the same numbers.
      for (size_t k = 0; k < segments.size(); ++k) {
        mjtNum velocity[6];  // [angular; linear], world frame
        mj_objectVelocity(m, d, mjOBJ_GEOM, drag.geom_ids()[k], velocity, 0);
        for (int i = 0; i < 3; ++i) {
          EXPECT_EQ(segments[k].angular_velocity_W[i], velocity[i]);
          EXPECT_EQ(segments[k].velocity_center_W[i], velocity[3 + i]);
        }
      }
    }
    std::printf("%s: one pass vs mj_applyFT, largest difference %.3g of the largest force\n",
                clamped ? "clamped" : "free", worst);
    EXPECT_LT(worst, 5e-15);
  }
}

// The power into the fluid from the segments (DissipatedPower_W, minus
// the sum of F . v_c + T_c . w) is minus the generalised drag force's
// power qfrc_drag . qvel (the wrenches' power is J^T's, the same number
// by duality), on random states of a chain with sub-segments: measured
// 4.8e-16 relative.
TEST(RftDragTest, DissipatedPowerIsMinusTheGeneralisedDragPower) {
  const ModelPtr model = SubSegmentedFlagellum(false);
  const mjModel* m = model.get();
  const DataPtr data = MakeData(m);
  mjData* d = data.get();
  const RftDrag drag(m, *RftDragConfig::FromModel(m));
  std::mt19937 rng(5);
  double worst = 0.0;
  for (int trial = 0; trial < 50; ++trial) {
    RandomState(m, d, rng);
    mju_zero(d->qfrc_passive, m->nv);
    drag.Apply(m, d);
    const double generalised_W = -mju_dot(d->qfrc_passive, d->qvel, m->nv);
    const double power_W = drag.DissipatedPower_W(m, d);
    ASSERT_GT(power_W, 0.0);
    worst = std::max(worst, std::abs(power_W - generalised_W) / power_W);
  }
  std::printf("dissipated power vs -qfrc_drag . qvel: largest difference %.3g relative\n", worst);
  EXPECT_LT(worst, 1e-13);
}

TEST(RftScenarioTest, OverridesReplaceTheModelsFields) {
  // A model with direct coefficients: the override to gray_hancock drops
  // them instead of refusing them.
  const ModelPtr model = LoadXml(R"(<mujoco><custom>
      <numeric name="ipmc_rft_viscosity_Pa_s" data="0.001"/>
      <text name="ipmc_rft_coefficients" data="direct"/>
      <numeric name="ipmc_rft_xi_normal_N_s_m2" data="0.002"/>
      <numeric name="ipmc_rft_xi_tangential_N_s_m2" data="0.001"/>
    </custom><worldbody><body><freejoint/><geom type="capsule" size="0.001 0.01"/></body>
    </worldbody></mujoco>)");
  EXPECT_EQ(RftDragConfig::FromModel(model.get())->model, CoefficientModel::kDirect);
  RftDragOverrides overrides;
  overrides.model = CoefficientModel::kGrayHancock;
  overrides.wavelength_m = 0.02;
  const RftDragConfig config = *RftDragConfig::FromModel(model.get(), overrides);
  EXPECT_EQ(config.model, CoefficientModel::kGrayHancock);
  EXPECT_DOUBLE_EQ(config.wavelength_m, 0.02);
}

}  // namespace
}  // namespace ipmc::testing
