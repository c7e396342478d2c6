// The fluid of a stepped model whose joints all move in the x-y plane
// (Fluid::set_in_plane_when_planar, plugin/fluid/fluid_model.h): the
// plates then solve their z-even half alone (plugin/fluid/plate_fluid.h),
// and the Stokes step, which on planar joints reads R's in-plane entries
// only, gives the same velocities and fluid power bit for bit as with the
// whole R, on links of 4 sub-segments driven off straight, the resistance
// exact at every step or cached; R's out-of-plane entries are then RFT's
// own blocks of each body (the local part), zero between bodies.
#include <gtest/gtest.h>
#include <mujoco/mujoco.h>

#include <cmath>
#include <memory>
#include <vector>

#include "plugin/dynamics/stokes_step.h"
#include "plugin/fluid/dense_resistance_fluid.h"
#include "plugin/fluid/fluid_model.h"
#include "plugin/fluid/rft_drag.h"
#include "plugin/tests/test_model.h"

namespace ipmc::testing {
namespace {

struct Run {
  DataPtr data;
  std::unique_ptr<Fluid> fluid;
  std::unique_ptr<StokesStepper> stepper;
};

Run Start(const mjModel* m, const RftDrag& segments, const RftDragOverrides& overrides,
          bool in_plane) {
  Run run{MakeData(m), MakeFluid(m, segments, overrides), std::make_unique<StokesStepper>(m)};
  run.fluid->set_in_plane_when_planar(in_plane);
  mjData* d = run.data.get();
  DriveHingesOffStraight(m, d);
  return run;
}

void ExpectTheSameSteps(double tolerance_rad) {
  const ModelPtr model = LoadXml(SubSegmentedStrip(4, false));
  mjModel* m = model.get();
  m->opt.timestep = 1e-3;
  RftDragOverrides overrides;
  overrides.fluid_model = "plates";
  overrides.fluid_parameters["ipmc_fluid_plate_shape_tolerance_rad"] = tolerance_rad;
  const RftDrag segments(m, *RftDragConfig::FromModel(m, overrides));
  Run whole = Start(m, segments, overrides, false);
  Run in_plane = Start(m, segments, overrides, true);
  for (int step = 0; step < 6; ++step) {
    ASSERT_TRUE(whole.stepper->Step(m, whole.data.get(), whole.fluid.get()));
    ASSERT_TRUE(in_plane.stepper->Step(m, in_plane.data.get(), in_plane.fluid.get()));
    for (int j = 0; j < m->nv; ++j) {
      ASSERT_EQ(in_plane.data->qvel[j], whole.data->qvel[j]) << "step " << step << ", dof " << j;
    }
    ASSERT_EQ(in_plane.stepper->fluid_power_W(), whole.stepper->fluid_power_W()) << step;
    ASSERT_GT(whole.stepper->fluid_power_W(), 0.0);
  }
  const auto& dense = dynamic_cast<const DenseResistanceFluid&>(*in_plane.fluid);
  EXPECT_EQ(dense.recomputations(),
            dynamic_cast<const DenseResistanceFluid&>(*whole.fluid).recomputations());
  // The out-of-plane entries: each body's own from RFT, none between bodies.
  mjData* d = in_plane.data.get();
  const Eigen::MatrixXd r = *in_plane.fluid->InteractionResistance(m, d);
  const Eigen::MatrixXd full = *whole.fluid->InteractionResistance(m, whole.data.get());
  const auto out_of_plane = [](Eigen::Index i) { return i % 6 < 2 || i % 6 == 5; };
  double in_plane_difference = 0.0;
  for (Eigen::Index j = 0; j < r.cols(); ++j) {
    for (Eigen::Index i = 0; i < r.rows(); ++i) {
      if (out_of_plane(i) || out_of_plane(j)) {
        if (i / 6 != j / 6) {
          EXPECT_EQ(r(i, j), 0.0) << i << ", " << j;
        }
      } else {
        in_plane_difference = std::max(in_plane_difference, std::abs(r(i, j) - full(i, j)));
      }
    }
  }
  EXPECT_EQ(in_plane_difference, 0.0);
  // RFT's out-of-plane resistance is not the plates': the whole R differs.
  EXPECT_GT((r - full).cwiseAbs().maxCoeff(), 0.0);
}

TEST(PlateInPlaneTest, ExactResistanceStepsTheSame) { ExpectTheSameSteps(0.0); }

TEST(PlateInPlaneTest, CachedResistanceStepsTheSame) { ExpectTheSameSteps(1e-3); }

// A joint out of the plane (the root's free joint): the whole R.
TEST(PlateInPlaneTest, AModelOutOfThePlaneGetsTheWholeResistance) {
  const ModelPtr model = LoadXml(SubSegmentedStrip(2, false));
  mjModel* m = model.get();
  RftDragOverrides overrides;
  overrides.fluid_model = "plates";
  const RftDrag segments(m, *RftDragConfig::FromModel(m, overrides));
  const std::unique_ptr<Fluid> flagged = MakeFluid(m, segments, overrides);
  flagged->set_in_plane_when_planar(true);
  const std::unique_ptr<Fluid> whole = MakeFluid(m, segments, overrides);
  const DataPtr data = MakeData(m);
  mjData* d = data.get();
  // Tilt the root's yaw axis off z: its joint no longer moves in the plane.
  m->jnt_axis[3 * 2 + 0] = 0.1;
  mj_kinematics(m, d);
  mj_comPos(m, d);
  const Eigen::MatrixXd a = *flagged->InteractionResistance(m, d);
  const Eigen::MatrixXd b = *whole->InteractionResistance(m, d);
  EXPECT_EQ((a - b).cwiseAbs().maxCoeff(), 0.0);
}

}  // namespace
}  // namespace ipmc::testing
