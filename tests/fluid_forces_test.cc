// The library's forces and facts (ipmc_swim.h): a straight body towed
// along its axis and broadside feels RFT's analytic drag xi L U through
// FluidForces, in inertial and Stokes dynamics; FluidPower_W is F . U; the
// links' facts; SetFluidField changes the drag; a host's mjcb_passive is
// refused in Stokes dynamics.
#include <gtest/gtest.h>
#include <mujoco/mujoco.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "ipmc_swim/ipmc_swim.h"
#include "ipmc_swim/fields.h"
#include "sim/base/numbers.h"
#include "sim/core/model_generator.h"
#include "sim/core/simulation.h"
#include "sim/io/mjcf_edit.h"
#include "tests/test_util.h"

namespace ipmc::testing {
namespace {

constexpr double kViscosity_Pa_s = 1e-3;  // the generator's defaults
constexpr double kRadius_m = 0.8125e-3;
constexpr double kWavelength_m = 32e-3;

// Three straight 10 mm links, no head, no actuators, in `dynamics`.
std::unique_ptr<Simulation> StraightBody(Dynamics dynamics, bool actuators = false) {
  FlagellumSpec spec;
  spec.head_length_mm = actuators ? 1.0 : 0.0;
  spec.ipmc_actuators = actuators;
  const std::string xml = SetMjcfCustomField(GenerateFlagellumMjcf(spec), "text", kAttrDynamics,
                                              DynamicsName(dynamics));
  return std::make_unique<Simulation>(LoadModelString(xml), "straight");
}

// The sum of the fluid's forces on the bodies [N].
std::vector<double> TotalForce_N(const mjModel* m, const mjData* d) {
  std::vector<double> total(3, 0.0);
  for (const BodyFluidForce& body : FluidForces(m, d)) {
    for (int k = 0; k < 3; ++k) total[k] += body.force_N[k];
  }
  return total;
}

// The body's length L [m] and RFT's coefficients (Gray & Hancock 1955,
// the model's fields: docs/FLUID.md).
constexpr double kLength_m = 30e-3;
//   xi_n = 4 pi mu / (ln(2 lambda / a) + 1/2),  xi_t = 2 pi mu / (ln(2 lambda / a) - 1/2).
struct Coefficients {
  double normal_N_s_m2, tangential_N_s_m2;
};
Coefficients Xi() {
  const double log_term = std::log(2 * kWavelength_m / kRadius_m);
  return {4 * kPi * kViscosity_Pa_s / (log_term + 0.5),
          2 * kPi * kViscosity_Pa_s / (log_term - 0.5)};
}

TEST(FluidForcesTest, TowedStraightBodyFeelsXiLUInertial) {
  const auto sim = StraightBody(Dynamics::kInertial);
  const mjModel* m = sim->model();
  mjData* d = sim->data();
  const double speed_m_s = 1e-3;
  for (int axis : {0, 1}) {  // root_x: along the body; root_y: broadside
    mju_zero(d->qvel, m->nv);
    d->qvel[axis] = speed_m_s;
    const std::vector<double> total = TotalForce_N(m, d);
    const double xi = axis == 0 ? Xi().tangential_N_s_m2 : Xi().normal_N_s_m2;
    const double analytic_N = -xi * kLength_m * speed_m_s;
    std::printf("inertial, towed along %s: drag %.12g N, -xi L U %.12g N\n", axis ? "y" : "x",
                total[axis], analytic_N);
    EXPECT_NEAR(total[axis] / analytic_N, 1.0, 1e-12);  // measured 2e-16
    EXPECT_NEAR(total[1 - axis], 0.0, 1e-12 * std::abs(analytic_N));
    EXPECT_NEAR(FluidPower_W(m, d), -analytic_N * speed_m_s, 1e-12 * std::abs(analytic_N) * speed_m_s);
  }
}

TEST(FluidForcesTest, TowedStraightBodyFeelsXiLUStokes) {
  const auto sim = StraightBody(Dynamics::kStokes);
  const mjModel* m = sim->model();
  mjData* d = sim->data();
  const double tow_N = 1e-7;
  d->qfrc_applied[0] = tow_N;  // root_x
  ASSERT_TRUE(Step(m, d)) << LastError(d);
  const double speed_m_s = d->qvel[0];
  const std::vector<double> total = TotalForce_N(m, d);
  const double analytic_N = -Xi().tangential_N_s_m2 * kLength_m * speed_m_s;
  std::printf("stokes, towed by %g N: U %.12g m/s, drag %.12g N, -xi L U %.12g N\n", tow_N,
              speed_m_s, total[0], analytic_N);
  EXPECT_NEAR(total[0] / analytic_N, 1.0, 1e-12);
  EXPECT_NEAR(total[0] / -tow_N, 1.0, 1e-9);  // the balance the step solved
}

TEST(FluidForcesTest, SetFluidFieldScalesTheDrag) {
  const auto sim = StraightBody(Dynamics::kInertial);
  const mjModel* m = sim->model();
  mjData* d = sim->data();
  d->qvel[0] = 1e-3;
  const double before_N = TotalForce_N(m, d)[0];
  SetFluidField(d, "ipmc_rft_viscosity_Pa_s", 2 * kViscosity_Pa_s);
  EXPECT_NEAR(TotalForce_N(m, d)[0] / before_N, 2.0, 1e-12);
  ExpectInvalidArgument([&] { SetFluidField(d, "ipmc_rft_viscosity_Pa_s", -1.0); },
                        "ipmc_rft_viscosity_Pa_s must be finite and > 0");
  EXPECT_NEAR(TotalForce_N(m, d)[0] / before_N, 2.0, 1e-12);  // unchanged by the refusal
  ExpectInvalidArgument([&] { SetFluidField(d, "ipmc_links", 1.0); }, "ipmc_links");
}

TEST(FluidForcesTest, LinkFacts) {
  const auto sim = StraightBody(Dynamics::kInertial, true);
  const mjModel* m = sim->model();
  mjData* d = sim->data();
  ASSERT_EQ(LinkCount(d), 3);
  for (int q = 0; q < 3; ++q) {
    const std::vector<int> joints = LinkJoints(d, q);
    ASSERT_EQ(joints.size(), 1u);
    EXPECT_EQ(std::string(mj_id2name(m, mjOBJ_JOINT, joints[0])), "j" + std::to_string(q + 1));
  }
  const double volts[3] = {1.0, -2.0, 3.0};
  SetVoltages(d, volts, 3);
  for (int i = 0; i < 20; ++i) ASSERT_TRUE(Step(m, d)) << LastError(d);
  for (int q = 0; q < 3; ++q) {
    EXPECT_EQ(LinkVoltage_V(d, q), volts[q]);
    // The moment follows the voltage's sign (a0 > 0).
    EXPECT_GT(LinkActiveMoments_N_m(d, q)[0] * volts[q], 0.0);
  }
  ExpectInvalidArgument([&] { LinkVoltage_V(d, 3); }, "link 3 is outside [0, 2]");
}

void HostPassive(const mjModel*, mjData*) {}

TEST(FluidForcesTest, HostPassiveCallbackIsRefusedInStokesDynamics) {
  const auto sim = StraightBody(Dynamics::kStokes);
  const mjfGeneric coupling = mjcb_passive;
  mjcb_passive = HostPassive;
  EXPECT_FALSE(Step(sim->model(), sim->data()));
  mjcb_passive = coupling;
  EXPECT_NE(std::string(LastError(sim->data())).find("a host mjcb_passive is set"),
            std::string::npos)
      << LastError(sim->data());
  EXPECT_TRUE(Step(sim->model(), sim->data())) << LastError(sim->data());
}

}  // namespace
}  // namespace ipmc::testing
