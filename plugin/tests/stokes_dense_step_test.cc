// The Stokes step with a dense fluid (plugin/dynamics/stokes_step.h):
// its velocity and fluid power are those of the dense system
// (J^T R J + diag(h K + C)) v = f formed as written, J (6 bodies x nv) the
// bodies' chains of dof motions and R the fluid's resistance, both at the
// step's midpoint (3/2 of this step's, -1/2 of the last one's), solved by
// LDL^T: within 1e-12 over steps on flexible links under the ribbon,
// its resistance exact, cached or fitted in time.
#include <gtest/gtest.h>
#include <mujoco/mujoco.h>

#include <Eigen/Cholesky>
#include <memory>
#include <string>
#include <vector>

#include "plugin/dynamics/stokes_step.h"
#include "plugin/fluid/dense_resistance_fluid.h"
#include "plugin/fluid/fluid_model.h"
#include "plugin/fluid/rft_drag.h"
#include "plugin/tests/test_model.h"

namespace ipmc::testing {
namespace {

// J: body i's rows hold the motions (cdof) of the dofs on its chain.
Eigen::MatrixXd Jacobian(const mjModel* m, const std::vector<int>& bodies,
                         const Eigen::VectorXd& cdof) {
  Eigen::MatrixXd jacobian = Eigen::MatrixXd::Zero(6 * bodies.size(), m->nv);
  for (size_t i = 0; i < bodies.size(); ++i) {
    int body = bodies[i];
    while (body > 0 && m->body_dofnum[body] == 0) body = m->body_parentid[body];
    if (body <= 0) continue;
    for (int j = m->body_dofadr[body] + m->body_dofnum[body] - 1; j >= 0; j = m->dof_parentid[j]) {
      jacobian.block(6 * i, j, 6, 1) = cdof.segment<6>(6 * j);
    }
  }
  return jacobian;
}

// Links of 4 sub-segments under the ribbon with the shape tolerance
// `tolerance_rad` (and the fit in time's tolerance `fit_tolerance`),
// driven off straight; `steps` steps of 1 ms. Returns the fluid's fitted
// evaluations.
int ExpectTheDenseSystemAsFormed(double tolerance_rad, double fit_tolerance = 0.0,
                                 int steps = 4) {
  const ModelPtr model = LoadXml(SubSegmentedStrip(4, false));
  mjModel* m = model.get();
  m->opt.timestep = 1e-3;
  const DataPtr data = MakeData(m);
  mjData* d = data.get();
  RftDragOverrides overrides;
  overrides.fluid_model = "ribbon";
  overrides.fluid_parameters["ipmc_fluid_ribbon_shape_tolerance_rad"] = tolerance_rad;
  overrides.fluid_parameters["ipmc_fluid_ribbon_fit_tolerance"] = fit_tolerance;
  const RftDrag segments(m, *RftDragConfig::FromModel(m, overrides));
  const std::unique_ptr<Fluid> ribbon = MakeFluid(m, segments, overrides);
  const Fluid& fluid = *ribbon;
  const std::vector<int>& bodies = fluid.InteractingBodies();
  DriveHingesOffStraight(m, d);
  StokesStepper stepper(m);
  const double h = m->opt.timestep;
  Eigen::MatrixXd last_resistance;
  Eigen::VectorXd last_cdof;
  double largest_velocity = 0.0;
  for (int step = 0; step < steps; ++step) {
    mj_kinematics(m, d);
    StokesComPos(m, d);
    const Eigen::MatrixXd resistance = *fluid.InteractionResistance(m, d);
    const Eigen::VectorXd cdof = Eigen::Map<const Eigen::VectorXd>(d->cdof, 6 * m->nv);
    const bool extrapolate = step > 0;
    const Eigen::MatrixXd midpoint_r =
        extrapolate ? Eigen::MatrixXd(1.5 * resistance - 0.5 * last_resistance) : resistance;
    const Eigen::VectorXd midpoint_cdof =
        extrapolate ? Eigen::VectorXd(1.5 * cdof - 0.5 * last_cdof) : cdof;
    const bool stepped = stepper.Step(m, d, &fluid);
    EXPECT_TRUE(stepped) << "step " << step;
    if (!stepped) return 0;
    const Eigen::Map<const Eigen::VectorXd> v(d->qvel, m->nv);
    // After the step qfrc_* hold the forces at zero velocity, so f is
    // theirs; the diagonal is the hinges' damping and h times their
    // stiffness (the strip has no actuators).
    const Eigen::VectorXd f = Eigen::Map<const Eigen::VectorXd>(d->qfrc_passive, m->nv) +
                              Eigen::Map<const Eigen::VectorXd>(d->qfrc_actuator, m->nv) +
                              Eigen::Map<const Eigen::VectorXd>(d->qfrc_applied, m->nv);
    const Eigen::MatrixXd jacobian = Jacobian(m, bodies, midpoint_cdof);
    Eigen::MatrixXd system = jacobian.transpose() * midpoint_r * jacobian;
    for (int j = 0; j < m->nv; ++j) {
      system(j, j) += m->dof_damping[j] + h * m->jnt_stiffness[m->dof_jntid[j]];
    }
    const Eigen::VectorXd expected = system.ldlt().solve(f);
    const Eigen::VectorXd body_velocity = jacobian * expected;
    const double expected_power_W = body_velocity.dot(midpoint_r * body_velocity);
    // Measured: at most 3.9e-15 (velocity) and 3.9e-14 (power), the two orders of the
    // same sums.
    EXPECT_LT((v - expected).lpNorm<Eigen::Infinity>(), 1e-12 * expected.lpNorm<Eigen::Infinity>())
        << "step " << step;
    EXPECT_NEAR(stepper.fluid_power_W(), expected_power_W, 1e-12 * expected_power_W)
        << "step " << step;
    largest_velocity = std::max(largest_velocity, expected.lpNorm<Eigen::Infinity>());
    last_resistance = resistance;
    last_cdof = cdof;
  }
  EXPECT_GT(largest_velocity, 0.0);  // the comparison saw a motion
  return dynamic_cast<const DenseResistanceFluid&>(fluid).fits();
}

// Every evaluation exact: R changes at every step.
TEST(StokesDenseStepTest, ChainSumsSolveTheDenseSystemAsFormed) {
  ExpectTheDenseSystemAsFormed(0.0);
}

// A cached resistance (tolerance 1 rad): R in the root's frame is kept over the steps and
// only the frame moves (the chain sums reused).
TEST(StokesDenseStepTest, ReusedChainSumsSolveTheDenseSystemAsFormed) {
  ExpectTheDenseSystemAsFormed(1.0);
}

// The fit in time: the step sums the chains of the cubic's coefficients
// and of the local part (Fluid::FrameResistanceCubic), the reference the
// chains of the R the fluid forms from them. 20 steps, the first four
// exact.
TEST(StokesDenseStepTest, FittedChainSumsSolveTheDenseSystemAsFormed) {
  EXPECT_GT(ExpectTheDenseSystemAsFormed(1e-3, 1e-4, 20), 0);  // the fit served steps
}

}  // namespace
}  // namespace ipmc::testing
