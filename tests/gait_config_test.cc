// Every check of a gait's configuration (sim/core/gait.h, the run options
// of sim/runs/gait_run.h) is a FieldError naming the field and its allowed
// range, so that each front end can put its own name in the field's place
// (the command line its flag, a sweep file its key).
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <string>

#include "sim/base/error.h"
#include "sim/core/gait.h"
#include "sim/runs/gait_run.h"

namespace ipmc {
namespace {

struct Refused {
  std::string field, allowed, message;
};

Refused RefusalOf(const std::function<void()>& check) {
  try {
    check();
  } catch (const FieldError& error) {
    return {error.field(), error.allowed(), error.what()};
  }
  ADD_FAILURE() << "no FieldError";
  return {};
}

void ExpectRefused(const std::function<void()>& check, const std::string& field,
                   const std::string& allowed) {
  const Refused refused = RefusalOf(check);
  EXPECT_EQ(refused.field, field) << refused.message;
  EXPECT_EQ(refused.allowed, allowed) << refused.message;
  EXPECT_EQ(refused.message.rfind("gait: ", 0), 0u) << refused.message;
  EXPECT_NE(refused.message.find(field), std::string::npos) << refused.message;
  EXPECT_EQ(refused.message.find('\n'), std::string::npos) << refused.message;
}

TEST(GaitConfig, SineGaitChecksNameTheFieldAndItsRange) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  for (double frequency_Hz : {0.0, -1.0, nan, inf}) {
    SineGaitConfig config = TravellingWave(3, frequency_Hz, 0.3, 2.0);
    ExpectRefused([&] { config.Validate(); }, "frequency_Hz", "finite and > 0");
  }
  SineGaitConfig empty;
  ExpectRefused([&] { empty.Validate(); }, "amplitude_rad", "one value per driven joint");
  SineGaitConfig phases = TravellingWave(3, 0.01, 0.3, 2.0);
  phases.phase_rad.pop_back();
  ExpectRefused([&] { phases.Validate(); }, "phase_rad", "3 values");
  for (double amplitude_rad : {4.0, -4.0, nan}) {
    SineGaitConfig config = TravellingWave(3, 0.01, amplitude_rad, 2.0);
    ExpectRefused([&] { MakeSineGait(config); }, "amplitude_rad", "finite, in [-pi, pi]");
  }
  SineGaitConfig phase = TravellingWave(3, 0.01, 0.3, 2.0);
  phase.phase_rad[1] = std::numeric_limits<double>::infinity();
  ExpectRefused([&] { phase.Validate(); }, "phase_rad", "finite");
  EXPECT_NO_THROW(TravellingWave(3, 0.01, 0.3, 2.0).Validate());
}

TEST(GaitConfig, SquareStrokeChecksNameTheFieldAndItsRange) {
  SquareStrokeConfig config;
  config.frequency_Hz = 0.0;
  ExpectRefused([&] { config.Validate(); }, "frequency_Hz", "finite and > 0");
  config.frequency_Hz = 0.01;
  for (double amplitude_rad : {0.0, -0.1, 3.5}) {
    config.amplitude_rad = amplitude_rad;
    ExpectRefused([&] { MakeSquareStroke(config); }, "amplitude_rad", "(0, pi]");
  }
  config.amplitude_rad = 0.5;
  config.joints = 0;
  ExpectRefused([&] { config.Validate(); }, "joints", ">= 1");
  config.joints = 2;
  EXPECT_NO_THROW(config.Validate());
}

TEST(GaitConfig, RunOptionChecksNameTheFieldAndItsRange) {
  GaitRunOptions options;
  options.cycles = 0;
  ExpectRefused([&] { options.Validate(); }, "cycles", ">= 1");
  options = GaitRunOptions();
  options.samples_per_cycle = 0;
  ExpectRefused([&] { options.Validate(); }, "samples_per_cycle", ">= 1");
  options = GaitRunOptions();
  options.servo_time_constant_steps = 1.0;
  ExpectRefused([&] { options.Validate(); }, "servo_time_constant_steps", ">= 2");
  options = GaitRunOptions();
  options.servo_damping_over_drag = 0.0;
  ExpectRefused([&] { options.Validate(); }, "servo_damping_over_drag", "> 0");
  EXPECT_NO_THROW(GaitRunOptions().Validate());
}

}  // namespace
}  // namespace ipmc
