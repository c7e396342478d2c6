// Ribbon calibration: the strip is a 31 mm x 3 mm x 250 um ribbon, which
// RFT treats as a rod of equivalent radius a = (w + t) / 4 = 0.8125 mm
// (Batchelor, JFM 44, 419, 1970). A sheet of regularized Stokeslets drags
// more than that rod face-on (plugin/tests/ribbon_sheet_calibration_test.cc);
// here the paper's swimmer for one short cycle with RFT coefficients
// scaled by the ribbon's drag over the rod's.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "sim/base/numbers.h"
#include "sim/core/scenario.h"
#include "sim/runs/closed_loop_run.h"

namespace ipmc::testing {
namespace {

constexpr double kMu = 1e-3, kRadius = 0.8125e-3;

// The sheet's drag over the rod's at k = 8 points across (the middle of
// its bracket), face-on and axial, as
// plugin/tests/ribbon_sheet_calibration_test.cc measures them
// (RibbonCalibrationTest.SheetOfStokesletsGivesTheEquivalentRadius).
constexpr double kFaceOverRod = 1.107171, kAxialOverRod = 1.007065;

// RFT with Gray & Hancock's coefficients scaled by the ribbon's drag over
// the rod's (the middle of the k = 8 bracket), in the paper's model file.
TEST(RibbonCalibrationTest, CalibratedCoefficientsChangeTheSwim) {
  const double face = kFaceOverRod, axial = kAxialOverRod;
  // Gray & Hancock (1955), lambda = 32 mm:
  //   xi_n = 4 pi mu / (ln(2 lambda / a) + 1/2),  xi_t = 2 pi mu / (ln(2 lambda / a) - 1/2).
  const double log_term = std::log(2 * 32e-3 / kRadius);
  const struct {
    double normal_N_s_m2, tangential_N_s_m2;
  } gh = {4 * kPi * kMu / (log_term + 0.5), 2 * kPi * kMu / (log_term - 0.5)};
  std::ifstream in(std::string(IPMC_SWIM_SOURCE_DIR) + "/models/flagellum3.xml");
  std::stringstream text;
  text << in.rdbuf();
  std::string xml = text.str();
  const std::string coefficients = "<text name=\"ipmc_rft_coefficients\" data=\"gray_hancock\"/>";
  ASSERT_NE(xml.find(coefficients), std::string::npos);
  std::ostringstream direct;
  direct.precision(17);
  direct << "<text name=\"ipmc_rft_coefficients\" data=\"direct\"/>\n"
         << "    <numeric name=\"ipmc_rft_xi_normal_N_s_m2\" data=\"" << face * gh.normal_N_s_m2
         << "\"/>\n    <numeric name=\"ipmc_rft_xi_tangential_N_s_m2\" data=\""
         << axial * gh.tangential_N_s_m2 << "\"/>";
  xml.replace(xml.find(coefficients), coefficients.size(), direct.str());
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "ribbon_calibration";
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "ribbon.xml") << xml;
  const std::string run = "cycles = 1\ntimestep_s = 1e-3\ndynamics = \"stokes\"\n"
                          "[waveform]\nfrequency_Hz = 0.5\nwavelength_mm = 32.0\n";
  const std::string paper = std::string(IPMC_SWIM_SOURCE_DIR) + "/scenarios/paper.toml";
  const std::string rod_model = "model = \"../models/flagellum3.xml\"\n";
  const std::string ribbon_model = "model = \"" + (dir / "ribbon.xml").string() + "\"\n";
  const double rod =
      SimulateScenario(ParseScenario(rod_model + run, paper)).swim.per_cycle.at(0).com_along;
  const double ribbon =
      SimulateScenario(ParseScenario(ribbon_model + run, paper)).swim.per_cycle.at(0).com_along;
  std::filesystem::remove_all(dir);
  std::printf("xi_n x %.4f, xi_t x %.4f; per cycle: rod %.6g mm, ribbon %.6g mm, ratio %.4f\n",
              face, axial, rod, ribbon, ribbon / rod);
  // The ribbon's larger face-on drag raises xi_n / xi_t, which drives the
  // swim: the same direction, faster.
  EXPECT_GT(ribbon, rod);
  EXPECT_LT(ribbon / rod, 1.5);
}

}  // namespace
}  // namespace ipmc::testing
