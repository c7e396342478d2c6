// The sampled PID of eq. 12 (controllers/pid.h): its defaults, its
// discrete recursions, its continuous response and derivative filter, the
// clamp with conditional integration, and bad configurations.
//
// Independent references used below: closed forms (the discrete PID
// recursions), and docs/VALIDATION.md, "The paper's numbers, computed
// independently" (numpy/scipy/mpmath, rounded).
#include <algorithm>
#include <cmath>
#include <complex>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "tests/test_util.h"
#include "tests/controller_test_util.h"
#include "controllers/pid.h"
#include "sim/base/numbers.h"

namespace ipmc {
namespace {

using ::ipmc::testing::ExpectThrowMentioning;
using ::ipmc::testing::Db;
using ::ipmc::testing::Deg;
using ::ipmc::testing::LinearPid;
using Complex = std::complex<double>;

TEST(PidTest, DefaultsAreEquation12) {
  const PidController::Config config;
  EXPECT_EQ(config.kp, 8.12);
  EXPECT_EQ(config.ki, 53.36);
  EXPECT_EQ(config.kd, 0.61);
  EXPECT_EQ(config.sample_period_s, 1e-3);
  EXPECT_TRUE(config.clamp_enabled);
  EXPECT_EQ(config.v_max, 6.0);
}

TEST(PidTest, ConstantErrorFollowsTheDiscreteRecursions) {
  // Backward-Euler integral and backward-difference derivative, from rest:
  // u_0 = Kp + Ki T + Kd / T, u_k = Kp + Ki T (k + 1) for k >= 1.
  const double period = 1e-3;
  PidController pid(LinearPid(period));
  for (int k = 0; k < 100; ++k) {
    const double expected =
        8.12 + 53.36 * period * (k + 1) + (k == 0 ? 0.61 / period : 0.0);
    EXPECT_NEAR(pid.Update(1.0), expected, 1e-12) << "k = " << k;
  }
  // Filtered derivative: D_k = Kd / (Tf + T) (Tf / (Tf + T))^k.
  PidController::Config config = LinearPid(period);
  config.kp = 0;
  config.ki = 0;
  config.derivative_filter_time_s = 4e-3;
  PidController filtered(config);
  const double tf = config.derivative_filter_time_s;
  for (int k = 0; k < 50; ++k) {
    EXPECT_NEAR(filtered.Update(2.0),
                2.0 * 0.61 / (tf + period) * std::pow(tf / (tf + period), k),
                1e-12);
  }
}

TEST(PidTest, ContinuousResponseAndFilterFromN) {
  PidController::Config config;
  const PidController ideal(config);
  const Complex s(0.0, 5.0);
  EXPECT_NEAR(std::abs(ideal.Evaluate(s) - (8.12 + 53.36 / s + 0.61 * s)), 0.0,
              1e-13);
  // docs/VALIDATION.md: PID(j5) 20.94 dB, -43.19 deg (measured 20.9352, -43.1880).
  EXPECT_NEAR(Db(ideal.Evaluate(s)), 20.94, 0.01);
  EXPECT_NEAR(Deg(ideal.Evaluate(s)), -43.19, 0.01);

  config.derivative_filter_time_s =
      PidController::DerivativeFilterTimeFromN(8.12, 0.61, 10.0);
  EXPECT_NEAR(config.derivative_filter_time_s, 0.61 / (8.12 * 10.0), 1e-18);
  const PidController filtered(config);
  // The derivative gain levels off at Kd / Tf = N Kp.
  const Complex high(0.0, 1e9);
  EXPECT_NEAR(filtered.Evaluate(high).real(), 8.12 + 10.0 * 8.12, 1e-6);
  ExpectThrowMentioning<std::invalid_argument>(
      [] { PidController::DerivativeFilterTimeFromN(0.0, 0.61, 10.0); }, "kp");
  ExpectThrowMentioning<std::invalid_argument>(
      [] { PidController::DerivativeFilterTimeFromN(8.12, 0.61, 0.0); }, "n");
}

TEST(PidTest, ClampWithConditionalIntegration) {
  PidController::Config config;  // clamp at 6 V, eq. 12 gains
  config.kd = 0;
  PidController pid(config);
  // e = 0.5 mm: Kp e = 4.06 V; the integral adds 26.68 V/s until the
  // output reaches 6 V (about 73 ms), then stops exactly at the limit.
  double u = 0;
  for (int k = 0; k < 2000; ++k) {
    u = pid.Update(0.5);
    EXPECT_LE(u, 6.0);
  }
  EXPECT_EQ(u, 6.0);
  EXPECT_NEAR(pid.integral(), 6.0 - 8.12 * 0.5, 1e-12);
  // The error reverses: no wound-up integral, the output leaves the limit
  // at once (Kp * -0.1 + ~1.94 V).
  u = pid.Update(-0.1);
  EXPECT_LT(u, 6.0);
  EXPECT_NEAR(u, -0.812 + pid.integral(), 1e-12);
  EXPECT_NEAR(u, 1.13, 0.03);

  // Negative saturation is symmetric.
  pid.Reset();
  for (int k = 0; k < 2000; ++k) u = pid.Update(-0.5);
  EXPECT_EQ(u, -6.0);
  EXPECT_NEAR(pid.integral(), -(6.0 - 8.12 * 0.5), 1e-12);
  // With P alone beyond the limit, the integral holds.
  pid.Reset();
  for (int k = 0; k < 100; ++k) u = pid.Update(1.0);
  EXPECT_EQ(u, 6.0);
  EXPECT_EQ(pid.integral(), 0.0);

  // Without the clamp the integral keeps growing (linear controller).
  PidController linear(LinearPid());
  for (int k = 0; k < 2000; ++k) u = linear.Update(0.5);
  EXPECT_NEAR(u, 8.12 * 0.5 + 53.36 * 2.0 * 0.5, 1e-9);
}

TEST(PidTest, ResetRestoresRest) {
  PidController pid(PidController::Config{});
  std::vector<double> first;
  for (int k = 0; k < 50; ++k) first.push_back(pid.Update(std::sin(0.1 * k)));
  pid.Reset();
  EXPECT_EQ(pid.integral(), 0.0);
  for (int k = 0; k < 50; ++k) {
    EXPECT_EQ(pid.Update(std::sin(0.1 * k)), first[k]);  // bit-identical
  }
}

TEST(PidTest, RejectsBadConfiguration) {
  const auto expect_field =
      [](const std::function<void(PidController::Config&)>& edit,
         const std::string& field) {
        PidController::Config config;
        edit(config);
        ExpectThrowMentioning<std::invalid_argument>(
            [&] { PidController pid(config); }, field);
      };
  expect_field([](auto& c) { c.kp = -1; }, "kp");
  expect_field([](auto& c) { c.ki = -1e-3; }, "ki");
  expect_field([](auto& c) { c.kd = -0.61; }, "kd");
  expect_field([](auto& c) { c.kd = std::nan(""); }, "kd");
  expect_field([](auto& c) { c.derivative_filter_time_s = -1e-3; },
               "derivative_filter_time_s");
  expect_field([](auto& c) { c.sample_period_s = 0; }, "sample_period_s");
  expect_field([](auto& c) { c.sample_period_s = -1e-3; }, "sample_period_s");
  expect_field([](auto& c) { c.v_max = 0; }, "v_max");
  expect_field([](auto& c) { c.v_max = -6; }, "v_max");
  // V_max is not used, so not checked, without the clamp.
  PidController::Config unclamped;
  unclamped.clamp_enabled = false;
  unclamped.v_max = 0;
  EXPECT_NO_THROW(PidController pid(unclamped));
  // The message is one line and states the allowed range.
  try {
    PidController::Config config;
    config.kp = -1;
    PidController pid(config);
  } catch (const std::invalid_argument& error) {
    const std::string message = error.what();
    EXPECT_EQ(message.find('\n'), std::string::npos);
    EXPECT_NE(message.find(">= 0"), std::string::npos) << message;
  }
  PidController pid(PidController::Config{});
  ExpectThrowMentioning<std::invalid_argument>(
      [&] { pid.Update(std::nan("")); }, "error");
}

}  // namespace
}  // namespace ipmc
