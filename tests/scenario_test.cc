// Scenario files: the paper's two scenarios load with the paper's values,
// and every class of bad input gives one line naming the file, line and
// key.
#include "sim/core/scenario.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

#include "controllers/pid.h"
#include "sim/base/error.h"
#include "tests/test_util.h"

namespace ipmc {
namespace {

namespace fs = std::filesystem;

const fs::path kSourceDir = IPMC_SWIM_SOURCE_DIR;

// A fresh directory holding a dummy model, "m.xml"; scenarios parsed with
// a source in it resolve "m.xml" to that model.
class ScenarioErrorTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / (std::string("ipmc_scenario_test_") + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    std::ofstream(dir_ / "m.xml") << "<mujoco/>\n";
    source_ = (dir_ / "paper.toml").string();
  }
  void TearDown() override { fs::remove_all(dir_); }

  ScenarioConfig Parse(const std::string& text) const { return ParseScenario(text, source_); }

  // The message of the error `text` raises, or "" (with a failure).
  std::string ErrorOf(const std::string& text) const {
    return ipmc::testing::OneLineErrorOf([&] { Parse(text); }, text);
  }

  // Fails unless `text` raises exactly source + `suffix`.
  void ExpectError(const std::string& text, const std::string& suffix) const {
    EXPECT_EQ(ErrorOf(text), source_ + suffix) << "for:\n" << text;
  }

  fs::path dir_;
  std::string source_;
};

constexpr char kModelLine[] = "model = \"m.xml\"\n";

TEST(ScenarioTest, PaperScenarioHasThePapersValues) {
  const std::string path = (kSourceDir / "scenarios" / "paper.toml").string();
  const ScenarioConfig config = LoadScenario(path);
  EXPECT_EQ(config.source, path);
  EXPECT_EQ(fs::path(config.model.path), fs::canonical(kSourceDir / "models" / "flagellum3.xml"));
  EXPECT_EQ(config.actuation, Actuation::kDistributed);
  EXPECT_EQ(config.run.cycles, 3);
  ASSERT_TRUE(config.run.timestep_s.has_value());
  EXPECT_DOUBLE_EQ(*config.run.timestep_s, 5e-4);
  EXPECT_EQ(config.controller.kind, ControllerKind::kPid);
  EXPECT_DOUBLE_EQ(config.controller.sample_rate_Hz, 1000.0);
  EXPECT_DOUBLE_EQ(config.controller.pid.kp, 8.12);
  EXPECT_DOUBLE_EQ(config.controller.pid.ki, 53.36);
  EXPECT_DOUBLE_EQ(config.controller.pid.kd, 0.61);
  EXPECT_DOUBLE_EQ(config.controller.pid.derivative_filter_time_s, 0.0);
  EXPECT_DOUBLE_EQ(config.controller.pid.sample_period_s, 1e-3);
  EXPECT_TRUE(config.controller.pid.clamp_enabled);
  EXPECT_DOUBLE_EQ(config.controller.pid.v_max, 6.0);
  EXPECT_EQ(config.waveform.kind, WaveformKind::kPolynomial);
  EXPECT_DOUBLE_EQ(config.waveform.c0_um, 0.0);
  EXPECT_DOUBLE_EQ(config.waveform.c1_um_per_mm, 200.0);
  EXPECT_DOUBLE_EQ(config.waveform.c2_um_per_mm2, 0.0);
  EXPECT_DOUBLE_EQ(config.waveform.frequency_Hz, 0.01);
  EXPECT_DOUBLE_EQ(config.waveform.wavelength_mm, 32.0);
  // Table 4 read as um per mm: 6.2 mm at the tip, 31 mm from the head.
  EXPECT_NEAR(config.waveform.c1_um_per_mm * 31.0 * 1e-3, 6.2, 1e-12);
  ASSERT_TRUE(config.fluid.viscosity_Pa_s.has_value());
  EXPECT_DOUBLE_EQ(*config.fluid.viscosity_Pa_s, 1e-3);
  EXPECT_EQ(config.output.dir, "out/paper");
  EXPECT_EQ(config.output.samples_per_cycle, 200);
}

TEST(ScenarioTest, PaperFractionalScenarioHasEquation15) {
  const ScenarioConfig config =
      LoadScenario((kSourceDir / "scenarios" / "paper_fractional.toml").string());
  EXPECT_EQ(fs::path(config.model.path), fs::canonical(kSourceDir / "models" / "flagellum3.xml"));
  EXPECT_EQ(config.actuation, Actuation::kDistributed);
  EXPECT_EQ(config.run.cycles, 3);
  ASSERT_TRUE(config.run.timestep_s.has_value());
  EXPECT_DOUBLE_EQ(*config.run.timestep_s, 5e-4);
  EXPECT_EQ(config.controller.kind, ControllerKind::kFractional);
  EXPECT_DOUBLE_EQ(config.controller.fractional.gain, 15.62);
  EXPECT_DOUBLE_EQ(config.controller.fractional.order, 0.62);
  EXPECT_EQ(config.controller.fractional.oustaloup_n, 4);
  EXPECT_DOUBLE_EQ(config.controller.fractional.w_low_rad_s, 1e-3);
  EXPECT_DOUBLE_EQ(config.controller.fractional.w_high_rad_s, 1e2);
  EXPECT_DOUBLE_EQ(config.controller.fractional.sample_period_s, 1e-3);
  EXPECT_TRUE(config.controller.fractional.clamp_enabled);
  EXPECT_DOUBLE_EQ(config.controller.fractional.v_max, 6.0);
  EXPECT_EQ(config.waveform.kind, WaveformKind::kPolynomial);
  EXPECT_DOUBLE_EQ(config.waveform.c1_um_per_mm, 200.0);
  EXPECT_DOUBLE_EQ(config.waveform.frequency_Hz, 0.01);
  EXPECT_DOUBLE_EQ(config.waveform.wavelength_mm, 32.0);
  EXPECT_EQ(config.output.dir, "out/paper_fractional");
}

TEST_F(ScenarioErrorTest, OnlyTheModelGivesTheDefaults) {
  const ScenarioConfig config = Parse(kModelLine);
  EXPECT_EQ(config.source, source_);
  EXPECT_EQ(config.model.path, (dir_ / "m.xml").string());
  EXPECT_EQ(config.actuation, Actuation::kDistributed);
  EXPECT_EQ(config.run.cycles, 3);
  EXPECT_FALSE(config.run.timestep_s.has_value());
  EXPECT_EQ(config.controller.kind, ControllerKind::kPid);
  EXPECT_DOUBLE_EQ(config.controller.pid.sample_period_s, 1e-3);
  EXPECT_DOUBLE_EQ(config.controller.fractional.sample_period_s, 1e-3);
  EXPECT_FALSE(config.fluid.viscosity_Pa_s.has_value());
  EXPECT_EQ(config.output.dir, "");
  EXPECT_EQ(config.output.samples_per_cycle, 200);
}

TEST_F(ScenarioErrorTest, ModelResolvesAgainstTheScenarioDirectory) {
  fs::create_directories(dir_ / "sub");
  const ScenarioConfig config =
      ParseScenario("model = \"../m.xml\"\n", (dir_ / "sub" / "s.toml").string());
  EXPECT_EQ(config.model.path, (dir_ / "m.xml").string());
  const ScenarioConfig absolute =
      ParseScenario("model = \"" + (dir_ / "m.xml").string() + "\"\n", "elsewhere/s.toml");
  EXPECT_EQ(absolute.model.path, (dir_ / "m.xml").string());
}

TEST_F(ScenarioErrorTest, IntegersAreAcceptedForFloats) {
  const ScenarioConfig config = Parse(std::string(kModelLine) +
                                      "[controller]\n"
                                      "sample_rate_Hz = 500\n"
                                      "v_max_V = 5\n"
                                      "kp = 8\nki = 53\nkd = 1\nderivative_filter_s = 0\n"
                                      "[waveform]\nc1_um_per_mm = 150\nwavelength_mm = 30\n"
                                      "frequency_Hz = 1\n"
                                      "[fluid]\nviscosity_Pa_s = 1\n");
  EXPECT_DOUBLE_EQ(config.controller.sample_rate_Hz, 500.0);
  EXPECT_DOUBLE_EQ(config.controller.pid.sample_period_s, 2e-3);
  EXPECT_DOUBLE_EQ(config.controller.pid.v_max, 5.0);
  EXPECT_DOUBLE_EQ(config.controller.pid.kp, 8.0);
  EXPECT_DOUBLE_EQ(config.controller.pid.ki, 53.0);
  EXPECT_DOUBLE_EQ(config.controller.pid.kd, 1.0);
  EXPECT_DOUBLE_EQ(config.waveform.c1_um_per_mm, 150.0);
  EXPECT_DOUBLE_EQ(config.waveform.wavelength_mm, 30.0);
  EXPECT_DOUBLE_EQ(config.waveform.frequency_Hz, 1.0);
  EXPECT_DOUBLE_EQ(*config.fluid.viscosity_Pa_s, 1.0);

  const ScenarioConfig fractional =
      Parse(std::string(kModelLine) +
            "[controller]\nkind = \"fractional\"\n"
            "gain = 15\norder = 1\nband_rad_s = [1, 100]\n"
            "[waveform]\nkind = \"fractional\"\nc_um = 1000\nalpha = 1\n");
  EXPECT_DOUBLE_EQ(fractional.controller.fractional.gain, 15.0);
  EXPECT_DOUBLE_EQ(fractional.controller.fractional.order, 1.0);
  EXPECT_DOUBLE_EQ(fractional.controller.fractional.w_low_rad_s, 1.0);
  EXPECT_DOUBLE_EQ(fractional.controller.fractional.w_high_rad_s, 100.0);
  EXPECT_EQ(fractional.waveform.kind, WaveformKind::kFractional);
  EXPECT_DOUBLE_EQ(fractional.waveform.c_um, 1000.0);
  EXPECT_DOUBLE_EQ(fractional.waveform.alpha, 1.0);
}

TEST_F(ScenarioErrorTest, SyntaxErrorsGiveLineAndColumn) {
  // FILE:LINE:COL: message
  const std::string message = ErrorOf(std::string(kModelLine) + "cycles = = 3\n");
  const std::string prefix = source_ + ":2:";
  ASSERT_EQ(message.rfind(prefix, 0), 0u) << message;
  const std::size_t column_end = message.find(": ", prefix.size());
  ASSERT_NE(column_end, std::string::npos) << message;
  const std::string column = message.substr(prefix.size(), column_end - prefix.size());
  EXPECT_FALSE(column.empty()) << message;
  EXPECT_EQ(column.find_first_not_of("0123456789"), std::string::npos) << message;
  EXPECT_GT(message.size(), column_end + 2) << message;
}

TEST_F(ScenarioErrorTest, UnknownKeysNameTheKeyAndTheAllowedOnes) {
  ExpectError(std::string(kModelLine) + "cycles = 3\n\n\n\n\ncontroler = 1\n",
              ":7: unknown key 'controler' (allowed: include, model, link_lengths_mm, segments_per_link, plants, actuation, dynamics, hinge_damping_scale, cycles, timestep_s, "
              "strip, plant, controller, waveform, drive, fluid, metrics, electrical, output)");
  ExpectError(
      std::string(kModelLine) + "[controller]\nkp = 1.0\nkpp = 2.0\n",
      ":4: unknown key 'controller.kpp' (allowed: kind, sample_rate_Hz, v_max_V, clamp, kp, "
      "ki, kd, link_kp, link_ki, link_kd, derivative_filter_s, gain, order, link_gain, "
      "link_order, oustaloup_n, band_rad_s, realisation)");
  ExpectError(
      std::string(kModelLine) + "[waveform]\nc3_um = 1.0\n",
      ":3: unknown key 'waveform.c3_um' (allowed: kind, c0_um, c1_um_per_mm, c2_um_per_mm2, "
      "c_um, alpha, frequency_Hz, wavelength_mm, start_ramp_cycles)");
  ExpectError(std::string(kModelLine) + "[fluid]\ndensity = 1000\n",
              ":3: unknown key 'fluid.density' (allowed: viscosity_Pa_s, rft_coefficients, "
              "rft_wavelength_mm, wall_gap_mm, model, stokeslet_width_points, "
              "stokeslet_points_per_mm, stokeslet_blob_mm, stokeslet_shape_tolerance_rad, "
              "stokeslet_secant_reach_rad, stokeslet_fit_tolerance, ribbon_modes, "
              "ribbon_shape_tolerance_rad, ribbon_secant_reach_rad, ribbon_fit_tolerance, "
              "plate_points_across, plate_quadrature_refinement, plate_richardson, "
              "plate_shape_tolerance_rad, plate_secant_reach_rad, plate_fit_tolerance)");
  ExpectError(std::string(kModelLine) + "[output]\ndir = \"x\"\nformat = \"csv\"\n",
              ":4: unknown key 'output.format' (allowed: dir, samples_per_cycle)");
  // The earliest of several.
  ExpectError(std::string(kModelLine) + "zz = 1\naa = 2\n",
              ":2: unknown key 'zz' (allowed: include, model, link_lengths_mm, segments_per_link, plants, actuation, dynamics, hinge_damping_scale, cycles, timestep_s, strip, plant, controller, "
              "waveform, drive, fluid, metrics, electrical, output)");
  // Dotted keys are walked like tables.
  ExpectError(
      std::string(kModelLine) + "controller.kq = 1\n",
      ":2: unknown key 'controller.kq' (allowed: kind, sample_rate_Hz, v_max_V, clamp, kp, ki, "
      "kd, link_kp, link_ki, link_kd, derivative_filter_s, gain, order, link_gain, link_order, "
      "oustaloup_n, band_rad_s, realisation)");
}

TEST_F(ScenarioErrorTest, WrongTypesNameTheKeyAndTheType) {
  ExpectError(
      std::string(kModelLine) + "[controller]\nkind = \"pid\"\n\n\n\n\n\n\n\n\nkp = \"8\"\n",
      ":12: controller.kp must be a number (got string)");
  ExpectError("model = 3\n", ":1: model must be a string (got integer)");
  ExpectError(std::string(kModelLine) + "cycles = 2.5\n",
              ":2: cycles must be an integer (got float)");
  ExpectError(std::string(kModelLine) + "cycles = 3.0\n",
              ":2: cycles must be an integer (got float)");
  ExpectError(std::string(kModelLine) + "timestep_s = true\n",
              ":2: timestep_s must be a number (got boolean)");
  ExpectError(std::string(kModelLine) + "actuation = 1\n",
              ":2: actuation must be a string (got integer)");
  ExpectError(std::string(kModelLine) + "[controller]\nclamp = 1\n",
              ":3: controller.clamp must be a boolean (got integer)");
  ExpectError(std::string(kModelLine) + "[controller]\noustaloup_n = 4.0\nkind = \"fractional\"\n",
              ":3: controller.oustaloup_n must be an integer (got float)");
  ExpectError(std::string(kModelLine) + "[output]\nsamples_per_cycle = \"200\"\n",
              ":3: output.samples_per_cycle must be an integer (got string)");
  ExpectError(std::string(kModelLine) + "[output]\ndir = [\"out\"]\n",
              ":3: output.dir must be a string (got array)");
  ExpectError(std::string(kModelLine) + "[waveform]\nfrequency_Hz = \"0.01\"\n",
              ":3: waveform.frequency_Hz must be a number (got string)");
  ExpectError(std::string(kModelLine) + "controller = 3\n",
              ":2: controller must be a table (got integer)");
  ExpectError(std::string(kModelLine) + "[[fluid]]\nviscosity_Pa_s = 1e-3\n",
              ":2: fluid must be a table (got array)");
  ExpectError(std::string(kModelLine) + "[controller]\nkp = inf\n",
              ":3: controller.kp must be finite (got inf)");
  ExpectError(std::string(kModelLine) + "[fluid]\nviscosity_Pa_s = nan\n",
              ":3: fluid.viscosity_Pa_s must be finite (got nan)");
}

TEST_F(ScenarioErrorTest, OutOfRangeValuesNameTheBound) {
  const std::string model = kModelLine;
  ExpectError(model + "cycles = 0\n", ":2: cycles must be >= 1 (got 0)");
  ExpectError(model + "cycles = 2\n[waveform]\nstart_ramp_cycles = 3\n",
              ":4: waveform.start_ramp_cycles must be in [0, cycles] = [0, 2] (got 3)");
  ExpectError(model + "cycles = 3000000000\n", ":2: cycles must be <= 2147483647 (got 3000000000)");
  ExpectError(model + "timestep_s = 0\n", ":2: timestep_s must be > 0 (got 0)");
  ExpectError(model + "timestep_s = -1e-4\n", ":2: timestep_s must be > 0 (got -0.0001)");
  ExpectError(model + "timestep_s = 2e-3\n", ":2: timestep_s must be <= 0.001 (got 0.002)");
  ExpectError(model + "[controller]\nsample_rate_Hz = 0\n",
              ":3: controller.sample_rate_Hz must be > 0 (got 0)");
  ExpectError(model + "[controller]\nv_max_V = 0\n", ":3: controller.v_max_V must be > 0 (got 0)");
  ExpectError(model + "[controller]\n\n\n\n\n\n\n\n\n\nkp = -1\n",
              ":12: controller.kp must be >= 0 (got -1)");
  ExpectError(model + "[controller]\nki = -0.5\n", ":3: controller.ki must be >= 0 (got -0.5)");
  ExpectError(model + "[controller]\nkd = -2\n", ":3: controller.kd must be >= 0 (got -2)");
  ExpectError(model + "[controller]\nderivative_filter_s = -0.01\n",
              ":3: controller.derivative_filter_s must be >= 0 (got -0.01)");
  const std::string fractional = model + "[controller]\nkind = \"fractional\"\n";
  ExpectError(fractional + "gain = -1\n", ":4: controller.gain must be >= 0 (got -1)");
  ExpectError(fractional + "order = 0\n", ":4: controller.order must be > 0 (got 0)");
  ExpectError(fractional + "order = 1.5\n", ":4: controller.order must be <= 1 (got 1.5)");
  ExpectError(fractional + "oustaloup_n = 0\n", ":4: controller.oustaloup_n must be >= 1 (got 0)");
  ExpectError(fractional + "oustaloup_n = 65\n",
              ":4: controller.oustaloup_n must be <= 64 (got 65)");
  ExpectError(model + "[fluid]\nviscosity_Pa_s = 0\n",
              ":3: fluid.viscosity_Pa_s must be > 0 (got 0)");
  ExpectError(model + "[output]\nsamples_per_cycle = 0\n",
              ":3: output.samples_per_cycle must be >= 1 (got 0)");
}

TEST_F(ScenarioErrorTest, BandIsTwoIncreasingPositiveNumbers) {
  const std::string fractional = std::string(kModelLine) + "[controller]\nkind = \"fractional\"\n";
  ExpectError(fractional + "band_rad_s = [1e-3]\n",
              ":4: controller.band_rad_s must be an array of two numbers [w_b, w_h] (got 1)");
  ExpectError(fractional + "band_rad_s = [1e-3, 1e1, 1e2]\n",
              ":4: controller.band_rad_s must be an array of two numbers [w_b, w_h] (got 3)");
  ExpectError(fractional + "band_rad_s = []\n",
              ":4: controller.band_rad_s must be an array of two numbers [w_b, w_h] (got 0)");
  ExpectError(fractional + "band_rad_s = 100\n",
              ":4: controller.band_rad_s must be an array of two numbers [w_b, w_h] (got integer)");
  ExpectError(fractional + "band_rad_s = [1e-3, \"100\"]\n",
              ":4: controller.band_rad_s[1] must be a number (got string)");
  ExpectError(fractional + "band_rad_s = [0, 100]\n",
              ":4: controller.band_rad_s[0] must be > 0 (got 0)");
  ExpectError(fractional + "band_rad_s = [100, 1e-3]\n",
              ":4: controller.band_rad_s must have w_b < w_h (got [100, 0.001])");
  ExpectError(fractional + "band_rad_s = [10, 10]\n",
              ":4: controller.band_rad_s must have w_b < w_h (got [10, 10])");
  // An element on its own line is reported there.
  ExpectError(fractional + "band_rad_s = [\n  1e-3,\n  -5,\n]\n",
              ":6: controller.band_rad_s[1] must be > 0 (got -5)");
}

TEST_F(ScenarioErrorTest, EnumsListTheChoices) {
  const std::string model = kModelLine;
  ExpectError(model + "actuation = \"dual\"\n",
              ":2: actuation must be \"distributed\" or \"single\" (got \"dual\")");
  ExpectError(model + "[controller]\nkind = \"PID\"\n",
              ":3: controller.kind must be \"pid\" or \"fractional\" (got \"PID\")");
  ExpectError(model + "[waveform]\nkind = \"sine\"\n",
              ":3: waveform.kind must be \"polynomial\" or \"fractional\" (got \"sine\")");
  EXPECT_EQ(Parse(model + "actuation = \"single\"\n").actuation, Actuation::kSingle);
}

TEST_F(ScenarioErrorTest, KeysOfTheOtherKindAreRejected) {
  const std::string model = kModelLine;
  ExpectError(model + "[controller]\nkind = \"fractional\"\nkp = 8.12\n",
              ":4: controller.kp applies only to kind = \"pid\" (kind is \"fractional\")");
  ExpectError(model + "[controller]\ngain = 15.62\n",
              ":3: controller.gain applies only to kind = \"fractional\" (kind is \"pid\")");
  ExpectError(model + "[waveform]\nalpha = 0.5\n",
              ":3: waveform.alpha applies only to kind = \"fractional\" (kind is \"polynomial\")");
  ExpectError(
      model + "[waveform]\nkind = \"fractional\"\nc1_um_per_mm = 200\n",
      ":4: waveform.c1_um_per_mm applies only to kind = \"polynomial\" (kind is \"fractional\")");
}

// controller.realisation chooses how the fractional integrator runs:
// "oustaloup" (the default, so existing scenarios keep their results) or
// the paper's printed eq. 15, which fixes gain, order and band.
TEST_F(ScenarioErrorTest, FractionalRealisationKey) {
  const std::string fractional = std::string(kModelLine) + "[controller]\nkind = \"fractional\"\n";
  EXPECT_EQ(Parse(fractional).controller.fractional.realisation, FractionalRealisation::kOustaloup);
  EXPECT_EQ(Parse(fractional + "realisation = \"oustaloup\"\ngain = 10\n")
                .controller.fractional.realisation,
            FractionalRealisation::kOustaloup);
  EXPECT_EQ(Parse(fractional + "realisation = \"eq15\"\n").controller.fractional.realisation,
            FractionalRealisation::kEq15);
  ExpectError(fractional + "realisation = \"Eq15\"\n",
              ":4: controller.realisation must be \"oustaloup\" or \"eq15\" (got \"Eq15\")");
  ExpectError(fractional + "realisation = 15\n",
              ":4: controller.realisation must be a string (got integer)");
  ExpectError(std::string(kModelLine) + "[controller]\nrealisation = \"eq15\"\n",
              ":3: controller.realisation applies only to kind = \"fractional\" (kind is "
              "\"pid\")");
  for (const char* key : {"gain = 15.62", "order = 0.62", "oustaloup_n = 4",
                          "band_rad_s = [1e-3, 1e2]"}) {
    const std::string name = std::string(key).substr(0, std::string(key).find(' '));
    ExpectError(fractional + "realisation = \"eq15\"\n" + key + "\n",
                ":5: controller." + name +
                    " applies only to realisation = \"oustaloup\" (realisation is \"eq15\")");
  }
}

TEST_F(ScenarioErrorTest, ModelIsRequiredAndMustExist) {
  ExpectError("cycles = 3\n", ": model is required (or link_lengths_mm)");
  ExpectError("", ": model is required (or link_lengths_mm)");
  ExpectError("model = \"missing.xml\"\n",
              ":1: model: cannot open '" + (dir_ / "missing.xml").string() + "'");
  ExpectError("\nmodel = \"sub/../missing.xml\"\n",
              ":2: model: cannot open '" + (dir_ / "missing.xml").string() + "'");
  ExpectError("model = \".\"\n", ":1: model: cannot open '" + (dir_ / "").string() + "'");
}

TEST_F(ScenarioErrorTest, WaveformIsValidatedByWaveformConfig) {
  const std::string model = kModelLine;
  std::string message = ErrorOf(model + "[waveform]\nc1_um_per_mm = 200\n\nfrequency_Hz = 0\n");
  EXPECT_EQ(message.rfind(source_ + ":5: waveform", 0), 0u) << message;
  EXPECT_NE(message.find("frequency_Hz"), std::string::npos) << message;

  message = ErrorOf(model + "[waveform]\nwavelength_mm = -32\n");
  EXPECT_EQ(message.rfind(source_ + ":3: waveform", 0), 0u) << message;
  EXPECT_NE(message.find("wavelength_mm"), std::string::npos) << message;

  message = ErrorOf(model + "[waveform]\nkind = \"fractional\"\nc_um = 1000\nalpha = 0\n");
  EXPECT_EQ(message.rfind(source_ + ":5: waveform", 0), 0u) << message;
  EXPECT_NE(message.find("alpha"), std::string::npos) << message;

  // A negative frequency (a wave from tail to head) is allowed.
  EXPECT_DOUBLE_EQ(Parse(model + "[waveform]\nfrequency_Hz = -0.01\n").waveform.frequency_Hz,
                   -0.01);
}

TEST_F(ScenarioErrorTest, SamplePeriodIsAWholeNumberOfTimesteps) {
  const std::string model = kModelLine;
  EXPECT_DOUBLE_EQ(
      *Parse(model + "timestep_s = 2.5e-4\n[controller]\nsample_rate_Hz = 1000\n").run.timestep_s,
      2.5e-4);
  ExpectError(
      model + "timestep_s = 3e-4\n[controller]\nsample_rate_Hz = 1000\n",
      ":4: controller.sample_rate_Hz must make the sample period a whole number of timesteps "
      "(1 / (1000 Hz x 0.0003 s) = 3.3333333333333335)");
  // Sampling faster than the physics steps.
  ExpectError(
      model + "timestep_s = 1e-3\n[controller]\nsample_rate_Hz = 2000\n",
      ":4: controller.sample_rate_Hz must make the sample period a whole number of timesteps "
      "(1 / (2000 Hz x 0.001 s) = 0.5)");
  // With the default rate the timestep is the key to blame, and named.
  ExpectError(model + "timestep_s = 3e-4\n",
              ":2: timestep_s must make a controller sample (controller.sample_rate_Hz = 1000 "
              "Hz, its default) a whole number of timesteps (1 / (1000 Hz x 0.0003 s) = "
              "3.3333333333333335), e.g. timestep_s = 0.00025");
}

TEST_F(ScenarioErrorTest, LoadScenarioReportsAMissingFile) {
  const std::string path = (dir_ / "none.toml").string();
  try {
    LoadScenario(path);
    ADD_FAILURE() << "no error";
  } catch (const std::runtime_error& error) {
    EXPECT_EQ(std::string(error.what()), path + ": cannot open the scenario file");
  }
  std::ofstream(source_) << kModelLine << "cycles = 2\n";
  EXPECT_EQ(LoadScenario(source_).run.cycles, 2);
}

// The errors carry what the sweeps decide by: the problem, the dotted key
// and the line, as the reader found them (not read back from the text).
TEST_F(ScenarioErrorTest, ErrorsCarryTheirProblemKeyAndLine) {
  struct Case {
    std::string text;
    InputProblem problem;
    std::string key;
    std::uint32_t line;
  };
  const Case cases[] = {
      {std::string(kModelLine) + "[controller]\nfoo = 1\n", InputProblem::kUnknownKey,
       "controller.foo", 3},
      {std::string(kModelLine) + "cycles = 1.5\n", InputProblem::kWrongType, "cycles", 2},
      {std::string(kModelLine) + "[controller]\nkp = -1\n", InputProblem::kBadValue,
       "controller.kp", 3},
      {std::string(kModelLine) + "[controller]\nkind = \"fractional\"\nkp = 1\n",
       InputProblem::kOtherKind, "controller.kp", 4},
      // Found by WaveformConfig::Validate, placed on its key's line.
      {std::string(kModelLine) + "[waveform]\nc1_um_per_mm = 1\nfrequency_Hz = 0\n",
       InputProblem::kBadValue, "waveform.frequency_Hz", 4},
      {std::string(kModelLine) + "link_lengths_mm = [1, -2]\n", InputProblem::kBadValue,
       "link_lengths_mm", 2},
      {"cycles = 2\n", InputProblem::kMissing, "model", 0},
  };
  for (const Case& c : cases) {
    try {
      Parse(c.text);
      ADD_FAILURE() << "no error for:\n" << c.text;
    } catch (const InputError& error) {
      EXPECT_EQ(error.problem(), c.problem) << error.what();
      EXPECT_EQ(error.key(), c.key) << error.what();
      EXPECT_EQ(error.where().file, source_);
      EXPECT_EQ(error.where().line, c.line) << error.what();
      // what() is the location followed by the message.
      const std::string what = error.what();
      ASSERT_GE(what.size(), error.message().size());
      EXPECT_EQ(what.substr(what.size() - error.message().size()), error.message());
    }
  }
}

// A Config's Validate() names the failing field apart from its message.
TEST(FieldErrorTest, ValidateNamesTheField) {
  PidController::Config config;
  config.kd = -1;
  try {
    config.Validate();
    ADD_FAILURE() << "no error";
  } catch (const FieldError& error) {
    EXPECT_EQ(error.field(), "kd");
    EXPECT_EQ(error.allowed(), "finite and >= 0");
    EXPECT_STREQ(error.what(), "PidController.Config.kd must be finite and >= 0, got -1");
  }
}

}  // namespace
}  // namespace ipmc
