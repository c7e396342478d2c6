// The hinges' damping of the inertial step (plugin/dynamics/step_model.h):
// c_eff = k h / (1 - exp(-k h / c)) against its two limits and against the
// exact relaxation c de/dt = -k e of a massless hinge.
#include "plugin/dynamics/step_model.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "plugin/tests/test_model.h"

namespace ipmc::testing {
namespace {

using testing::LoadXml;

// The paper's hinge (docs/ENERGY.md): k = 1.95e-4 N m/rad,
// c = 6.25e-7 N m s/rad.
constexpr double kStiffness = 1.95e-4, kDamping = 6.25e-7;

// k h / c << 1: c + k h / 2 + k^2 h^2 / (12 c) - ... (the series of
// x / (1 - e^-x) = 1 + x / 2 + x^2 / 12 - x^4 / 720 + ...): the trapezoid.
TEST(HingeDampingTest, SmallStepIsTheTrapezoid) {
  for (double x : {1e-6, 1e-3, 0.156}) {  // 0.156: the paper's h = 0.5 ms
    const double h_s = x * kDamping / kStiffness;
    const double c_eff = EulerHingeDamping(kDamping, kStiffness, h_s);
    const double trapezoid = kDamping + 0.5 * kStiffness * h_s;
    // The next term's bound and the rounding of 1 - exp(-x).
    EXPECT_NEAR(c_eff, trapezoid + kDamping * x * x / 12,
                kDamping * (x * x * x * x / 700 + 1e-14))
        << "k h / c = " << x;
  }
}

// k h / c >> 1: k h (backward Euler), up to k h exp(-k h / c).
TEST(HingeDampingTest, LargeStepIsBackwardEuler) {
  for (double x : {30.0, 1e3, 1e9}) {
    const double h_s = x * kDamping / kStiffness;
    EXPECT_NEAR(EulerHingeDamping(kDamping, kStiffness, h_s) / (kStiffness * h_s), 1.0,
                2 * std::exp(-x))
        << "k h / c = " << x;
  }
  EXPECT_DOUBLE_EQ(EulerHingeDamping(0.0, kStiffness, 1e-3), kStiffness * 1e-3);  // no damping
  EXPECT_DOUBLE_EQ(EulerHingeDamping(kDamping, 0.0, 1e-3), kDamping);            // no spring
}

// The booked damping (c_eff - k h / 2) v^2 h of a massless step
// e_(n+1) = r e_n, r = exp(-k h / c), v = (e_(n+1) - e_n) / h, is the
// elastic energy k e_n^2 (1 - r^2) / 2 it loses.
TEST(HingeDampingTest, BookedDampingIsTheElasticEnergyLost) {
  for (double x : {1e-3, 0.156, 1.0, 10.0, 100.0}) {
    const double h_s = x * kDamping / kStiffness, e_n = 0.1, r = std::exp(-x);
    const double v = (r - 1) * e_n / h_s;
    const double booked_J =
        EulerDissipatedDamping(EulerHingeDamping(kDamping, kStiffness, h_s), kStiffness, h_s) *
        v * v * h_s;
    const double lost_J = 0.5 * kStiffness * e_n * e_n * (1 - r * r);
    EXPECT_NEAR(booked_J / lost_J, 1.0, 1e-12) << "k h / c = " << x;
  }
}

// The massless step with c_eff, e_(n+1) = e_n - (k h / c_eff) e_n, is the
// exact relaxation e(t) = e_0 exp(-k t / c) at every step, for k h / c
// small, of order one and large.
TEST(HingeDampingTest, MasslessStepIsTheExactRelaxation) {
  for (double x : {1e-3, 0.156, 1.0, 15.6}) {
    const double h_s = x * kDamping / kStiffness;
    const double c_eff = EulerHingeDamping(kDamping, kStiffness, h_s);
    double e = 1.0;
    for (int n = 1; n <= 20; ++n) {
      e -= kStiffness * h_s / c_eff * e;
      // Rounding: 1 - k h / c_eff = exp(-x) loses 1e-16 / exp(-x) relative
      // per step (measured 1.5e-9 after 7 steps at x = 15.6).
      const double rounding = std::max(1e-12, 4e-16 * n * std::exp(x));
      EXPECT_NEAR(e / std::exp(-kStiffness * n * h_s / kDamping), 1.0, rounding)
          << "k h / c = " << x << ", step " << n;
    }
  }
}

// One hinge of (almost) no inertia, its spring's rest angle 0, let go at
// 0.1 rad and stepped by MuJoCo's Euler with c_eff. At h = 0.5 ms
// (k h / c = 0.156) the angle after 20 steps is 0.1 exp(-k t / c), the
// exact relaxation, up to the hinge's inertia J = 4e-14 kg m^2 against
// c_eff h = 3.4e-10 N m s^2/rad (measured 4.4e-5 relative). At h = 50 ms
// (k h / c = 15.6, where the Euler step with c would multiply the angle by
// 1 - 15.6 per step) the first step takes at least 0.999 of the angle and
// 20 steps leave below 1e-60 rad (measured 1.4e-72 rad: a factor
// J / (J + c_eff h) = 8e-8 every two steps, the inertia's own).
TEST(HingeDampingTest, MujocoEulerStepRelaxesAMasslessHinge) {
  const std::string xml = R"(<mujoco><option timestep="0.001" integrator="Euler" gravity="0 0 0"/>
    <worldbody><body><joint name="j" type="hinge" axis="0 0 1" stiffness="1.95e-4"
    damping="6.25e-7" armature="0"/><geom type="sphere" size="1e-2" mass="1e-9"/></body>
    </worldbody></mujoco>)";
  for (double h_s : {5e-4, 5e-2}) {
    ModelPtr file = LoadXml(xml);
    file->opt.timestep = h_s;
    const StepModel step = MakeStepModel(file.get(), Dynamics::kInertial);
    mjModel* model = step.model.get();
    const DataPtr data(mj_makeData(model));
    data->qpos[0] = 0.1;
    const int steps = 20;
    for (int i = 0; i < steps; ++i) {
      mj_step(model, data.get());
      if (h_s > 1e-2 && i == 0) {
        EXPECT_LT(std::abs(data->qpos[0]), 1e-4);
      }
    }
    if (h_s > 1e-2) {
      EXPECT_LT(std::abs(data->qpos[0]), 1e-60);
    }
    const double exact = 0.1 * std::exp(-kStiffness * steps * h_s / kDamping);
    std::printf("h = %g s: angle %.12e rad, exact %.12e rad\n", h_s, data->qpos[0], exact);
    if (h_s < 1e-3) {
      EXPECT_NEAR(data->qpos[0] / exact, 1.0, 5e-4);
    }
  }
  // The Stokes mode keeps c.
  ModelPtr model = LoadXml(xml);
  EXPECT_DOUBLE_EQ(MakeStepModel(model.get(), Dynamics::kStokes).model->dof_damping[0], kDamping);
}

}  // namespace
}  // namespace ipmc::testing
