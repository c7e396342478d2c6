// Resistive-force-theory drag coupled into MuJoCo through mjcb_passive
// (the segment integral and its invariants:
// plugin/tests/rft_segment_drag_test.cc).
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "ipmc_swim/ipmc_swim.h"
#include "tests/test_util.h"
#include "sim/base/numbers.h"

namespace ipmc::testing {
namespace {

// In MuJoCo: the generalised drag force the callback adds never does
// positive work along the motion (qfrc_drag . qvel <= 0).
TEST(RftDragTest, CallbackPowerIsNeverPositiveInMuJoCo) {
  FlagellumSpec spec;
  auto sim = MakeSimulation(spec);
  mjModel* m = sim->model();
  mjData* d = sim->data();
  std::mt19937 rng(3);
  std::normal_distribution<double> normal(0.0, 1.0);
  for (int trial = 0; trial < 200; ++trial) {
    for (int i = 0; i < m->nq; ++i) d->qpos[i] = 0.3 * normal(rng);
    for (int i = 0; i < m->nv; ++i) d->qvel[i] = 1e-3 * normal(rng);
    mj_forward(m, d);
    double power = 0.0;
    std::vector<double> with(d->qfrc_passive, d->qfrc_passive + m->nv);
    Detach(d);
    mj_forward(m, d);
    for (int i = 0; i < m->nv; ++i) {
      power += (with[i] - d->qfrc_passive[i]) * d->qvel[i];
    }
    ASSERT_TRUE(Attach(m, d));
    EXPECT_LE(power, 0.0);
  }
}

TEST(RftDragTest, ModelWithoutFieldsGetsNoDragAndNoCrash) {
  auto m = LoadModelString(R"(<mujoco><worldbody><body><joint type="slide" axis="1 0 0"/>
      <geom type="box" size="0.01 0.001 0.001"/></body></worldbody></mujoco>)");
  mjData* d = mj_makeData(m.get());
  EXPECT_FALSE(Attach(m.get(), d));
  d->qvel[0] = 1.0;
  for (int i = 0; i < 100; ++i) mj_step(m.get(), d);
  EXPECT_DOUBLE_EQ(d->qvel[0], 1.0);  // nothing slows it down
  mj_deleteData(d);
}

TEST(RftDragTest, AttachedFreeBodyDecaysAtTheRftRate) {
  // One free segment pushed along its axis: m dv/dt = -xi_t L v, so
  // v(t) = v0 exp(-xi_t L t / m).
  FlagellumSpec spec;
  spec.link_lengths_mm = {10.0};
  spec.head_length_mm = 0.0;
  spec.ipmc_actuators = false;  // no hinge to drive
  spec.timestep_s = 1e-5;
  spec.integrator = "RK4";
  auto sim = MakeSimulation(spec);
  mjModel* m = sim->model();
  mjData* d = sim->data();
  const double mass_kg = ComputeSegmentMechanics(spec, 0, 0).mass_kg;
  // Gray & Hancock (1955): xi_t = 2 pi mu / (ln(2 lambda / a) - 1/2), the
  // generator's mu = 1e-3 Pa s, a = 0.8125 mm, lambda = 32 mm.
  const double xi_t = 2 * kPi * 1e-3 / (std::log(2 * 32e-3 / 0.8125e-3) - 0.5);
  d->qvel[0] = 1e-3;
  for (int i = 0; i < 10000; ++i) mj_step(m, d);
  const double expected = 1e-3 * std::exp(-xi_t * 0.01 * d->time / mass_kg);
  EXPECT_NEAR(d->qvel[0] / expected, 1.0, 1e-6);  // RK4, tau / dt = 9e4
}

TEST(RftDragTest, MalformedFieldsAreRejectedWithTheFieldName) {
  const auto load = [](const std::string& custom) {
    return LoadModelString("<mujoco><custom>" + custom +
                           "</custom><worldbody><body><joint type=\"slide\" axis=\"1 0 0\"/>"
                           "<geom type=\"box\" size=\"0.01 0.001 0.001\"/></body></worldbody>"
                           "</mujoco>");
  };
  const auto attach_error = [&](const std::string& custom) -> std::string {
    auto m = load(custom);
    mjData* d = mj_makeData(m.get());
    std::string message;
    try {
      Attach(m.get(), d);
    } catch (const std::invalid_argument& e) {
      message = e.what();
    }
    Detach(d);
    mj_deleteData(d);
    return message;
  };
  EXPECT_NE(attach_error(R"(<numeric name="ipmc_rft_viscosity_Pa_s" data="-1"/>)")
                .find("ipmc_rft_viscosity_Pa_s must be finite and > 0"),
            std::string::npos);
  EXPECT_NE(attach_error(R"(<numeric name="ipmc_rft_wavelength_m" data="0.03"/>)")
                .find("ipmc_rft_viscosity_Pa_s is missing"),
            std::string::npos);
  EXPECT_NE(attach_error(R"(<numeric name="ipmc_rft_viscosity_Pa_s" data="1e-3"/>
                            <text name="ipmc_rft_coefficients" data="direct"/>
                            <numeric name="ipmc_rft_xi_normal_N_s_m2" data="nan"/>
                            <numeric name="ipmc_rft_xi_tangential_N_s_m2" data="1e-3"/>)")
                .find("ipmc_rft_xi_normal_N_s_m2' must be finite"),
            std::string::npos);
  EXPECT_NE(attach_error(R"(<numeric name="ipmc_rft_viscosity_Pa_s" data="1e-3"/>
                            <text name="ipmc_rft_coefficients" data="stokeslet"/>)")
                .find("gray_hancock, lighthill, near_wall, direct, ribbon or ribbon_fitted"),
            std::string::npos);
  EXPECT_NE(attach_error(R"(<numeric name="ipmc_rft_viscosity_Pa_s" data="1e-3"/>
                            <text name="ipmc_rft_geoms" data="tail"/>)")
                .find("names geom 'tail'"),
            std::string::npos);
}

}  // namespace
}  // namespace ipmc::testing
