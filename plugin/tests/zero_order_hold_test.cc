// Exact zero-order-hold integration of the IPMC link models
// (plugin/actuators/zero_order_hold.h) against CVODE at tight tolerances
// (plugin/actuators/ipmc_actuator_bank.h, ActuatorIntegration::kCvode):
// the two solve the same linear ODE with the voltages held between the
// changes, so they agree to CVODE's own error; then the coupling's model
// field ipmc_actuator_integration, and the clamped flagellum driven by
// both.
#include "plugin/actuators/zero_order_hold.h"

#include <gtest/gtest.h>
#include <mujoco/mujoco.h>

#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

#include "ipmc_swim/ipmc_swim.h"
#include "plugin/actuators/ipmc_actuator_bank.h"
#include "plugin/actuators/ipmc_actuators.h"
#include "plugin/tests/test_model.h"
#include "sim/linear/ipmc_link_model.h"
#include "sim/base/numbers.h"

namespace ipmc {
namespace {

using testing::LoadXml;

std::vector<IpmcLinkParams> PaperLinks(IpmcModelKind kind) {
  return {PaperLinkParams(1, kind), PaperLinkParams(2, kind), PaperLinkParams(3, kind)};
}

// Voltages changed every 1 ms as by the 1 kHz controllers (a slow sine and
// a 37 Hz one, different on each link), the banks advanced every 0.5 ms as
// by the paper's MuJoCo step, for 2 s, then held for 0.5 s: the largest
// |y_exact - y_cvode| over all links and samples relative to the largest
// |y_cvode|.
double ExactAgainstCvode(IpmcModelKind kind, double rel_tol) {
  CvodeOptions tight;
  tight.rel_tol = rel_tol;
  tight.abs_tol_mm = 1e-2 * rel_tol;
  auto cvode = IpmcActuatorBank::Create(PaperLinks(kind), tight, ActuatorIntegration::kCvode);
  auto exact = IpmcActuatorBank::Create(PaperLinks(kind), tight, ActuatorIntegration::kExact);
  constexpr double kStep_s = 5e-4;
  double max_abs = 0, max_err = 0;
  for (long i = 0; i < 5000; ++i) {
    if (i % 2 == 0 && i < 4000) {
      const double t = i * kStep_s;
      const double v = 4.0 * std::sin(2 * kPi * 0.5 * t) + 0.3 * std::sin(2 * kPi * 37.0 * t);
      cvode->SetVoltages({v, 0.5 * v, -v});
      exact->SetVoltages({v, 0.5 * v, -v});
    }
    cvode->AdvanceTo((i + 1) * kStep_s);
    exact->AdvanceTo((i + 1) * kStep_s);
    for (int q = 0; q < 3; ++q) {
      const double y = cvode->FreeTipDeflection_mm(q);
      max_abs = std::max(max_abs, std::abs(y));
      max_err = std::max(max_err, std::abs(exact->FreeTipDeflection_mm(q) - y));
    }
  }
  EXPECT_EQ(exact->Reinitialisations(), 0);
  EXPECT_EQ(exact->InternalSteps(), 5000);
  return max_err / max_abs;
}

TEST(ZeroOrderHoldTest, AgreesWithCvodeToItsTolerance) {
  // The difference is CVODE's error and shrinks with its tolerance
  // (measured: G1 2.1e-8 at rel_tol 1e-8, 3.1e-10 at 1e-10, 6.8e-12 at
  // 1e-12; G2 1.9e-11 at 1e-12), so the exact advance is the limit CVODE
  // converges to. Bounds: 10x the measured gaps.
  struct Case {
    IpmcModelKind kind;
    double rel_tol, bound;
  };
  double last = 1.0;
  for (const Case& c :
       {Case{IpmcModelKind::kG1, 1e-8, 2e-7}, Case{IpmcModelKind::kG1, 1e-10, 3e-9},
        Case{IpmcModelKind::kG1, 1e-12, 7e-11}, Case{IpmcModelKind::kG2, 1e-12, 2e-10}}) {
    const double error = ExactAgainstCvode(c.kind, c.rel_tol);
    std::printf("%s, CVODE rel_tol %.0e: exact - cvode relative %.3g\n",
                c.kind == IpmcModelKind::kG1 ? "G1" : "G2", c.rel_tol, error);
    EXPECT_LT(error, c.bound);
    if (c.kind == IpmcModelKind::kG1) {
      EXPECT_LT(error, 0.1 * last) << "the gap must shrink with CVODE's tolerance";
      last = error;
    }
  }
}

TEST(ZeroOrderHoldTest, OneIntervalEqualsItsHalves) {
  // Phi(2h) = Phi(h)^2 and Gamma(2h) = Phi(h) Gamma(h) + Gamma(h): the
  // advance over 1 ms in one call and in two of 0.5 ms agree to rounding.
  auto whole =
      IpmcActuatorBank::Create(PaperLinks(IpmcModelKind::kG1), {}, ActuatorIntegration::kExact);
  auto halves =
      IpmcActuatorBank::Create(PaperLinks(IpmcModelKind::kG1), {}, ActuatorIntegration::kExact);
  double max_abs = 0, max_err = 0;
  for (int i = 0; i < 1000; ++i) {
    const std::vector<double> u = {std::sin(0.01 * i), 2.0, -3.0 * std::cos(0.02 * i)};
    whole->SetVoltages(u);
    halves->SetVoltages(u);
    whole->AdvanceTo(1e-3 * (i + 1));
    halves->AdvanceTo(1e-3 * i + 5e-4);
    halves->AdvanceTo(1e-3 * (i + 1));
    for (int q = 0; q < 3; ++q) {
      max_abs = std::max(max_abs, std::abs(whole->FreeTipDeflection_mm(q)));
      max_err = std::max(
          max_err, std::abs(whole->FreeTipDeflection_mm(q) - halves->FreeTipDeflection_mm(q)));
    }
  }
  std::printf("1 ms against 2 x 0.5 ms: relative %.3g\n", max_err / max_abs);
  EXPECT_LT(max_err / max_abs, 2e-13);  // measured 2.2e-14
}

TEST(ZeroOrderHoldTest, RoundedIntervalKeepsFortyBits) {
  EXPECT_EQ(ZeroOrderHold::RoundedInterval_s(0.0), 0.0);
  EXPECT_EQ(ZeroOrderHold::RoundedInterval_s(0.5), 0.5);
  const double h = 1e-3;
  // Steps that differ in their last bits (d->time accumulated) share a key.
  EXPECT_EQ(ZeroOrderHold::RoundedInterval_s(h), ZeroOrderHold::RoundedInterval_s(h * (1 + 1e-15)));
  EXPECT_NEAR(ZeroOrderHold::RoundedInterval_s(h), h, h * std::ldexp(1.0, -40));
  EXPECT_NE(ZeroOrderHold::RoundedInterval_s(h), ZeroOrderHold::RoundedInterval_s(h * (1 + 1e-9)));
}

TEST(ZeroOrderHoldTest, MismatchedBlocksAreRefused) {
  EXPECT_THROW(ZeroOrderHold({Eigen::MatrixXd::Zero(2, 2)}, {Eigen::VectorXd::Zero(3)}),
               std::invalid_argument);
  EXPECT_THROW(ZeroOrderHold({Eigen::MatrixXd::Zero(2, 2)}, {}), std::invalid_argument);
}

std::string ClampedModelWith(const std::string& custom_line) {
  std::string xml = testing::SourceFileText("models/flagellum3_clamped.xml");
  const size_t at = xml.find("</custom>");
  EXPECT_NE(at, std::string::npos);
  return xml.insert(at, custom_line);
}

// The clamped flagellum's three hinge angles after 2 s of 3 V sines at
// 1 Hz (links 2 and 3 shifted), new every 1 ms, at the model's 0.5 ms step.
std::vector<double> ClampedAngles(const std::string& custom_line) {
  ModelPtr m = LoadXml(ClampedModelWith(custom_line));
  mjData* d = mj_makeData(m.get());
  EXPECT_TRUE(Attach(m.get(), d));
  for (int i = 0; i < 4000; ++i) {
    if (i % 2 == 0) {
      const double t = d->time;
      const double v[3] = {3 * std::sin(2 * kPi * t), 3 * std::sin(2 * kPi * t + 1),
                           3 * std::sin(2 * kPi * t + 2)};
      SetVoltages(d, v, 3);
    }
    mj_step(m.get(), d);
  }
  std::vector<double> angles(d->qpos, d->qpos + m->nq);
  Detach(d);
  mj_deleteData(d);
  return angles;
}

TEST(ZeroOrderHoldTest, CoupledRunsAgreeAndTheFieldIsChecked) {
  const std::vector<double> exact = ClampedAngles("");  // the default
  const std::vector<double> cvode = ClampedAngles(
      "<text name=\"ipmc_actuator_integration\" data=\"cvode\"/>"
      "<numeric name=\"ipmc_cvode_rel_tol\" data=\"1e-10\"/>");
  const std::vector<double> named =
      ClampedAngles("<text name=\"ipmc_actuator_integration\" data=\"exact\"/>");
  ASSERT_EQ(exact.size(), cvode.size());
  double scale = 0, gap = 0;
  for (size_t j = 0; j < exact.size(); ++j) {
    scale = std::max(scale, std::abs(cvode[j]));
    gap = std::max(gap, std::abs(exact[j] - cvode[j]));
    EXPECT_EQ(exact[j], named[j]);
  }
  std::printf("clamped hinge angles, exact against CVODE at 1e-10: relative %.3g\n", gap / scale);
  EXPECT_GT(scale, 1e-3);
  EXPECT_LT(gap / scale, 1e-9);  // measured 9.5e-11

  ModelPtr bad = LoadXml(
      ClampedModelWith("<text name=\"ipmc_actuator_integration\" data=\"euler\"/>"));
  mjData* d = mj_makeData(bad.get());
  try {
    Attach(bad.get(), d);
    ADD_FAILURE() << "ipmc_actuator_integration = euler was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("ipmc_actuator_integration must be exact or cvode"),
              std::string::npos)
        << e.what();
  }
  Detach(d);
  mj_deleteData(d);
}

}  // namespace
}  // namespace ipmc
