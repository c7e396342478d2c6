// The sweep figure's script (renders/figures_sweep.cc): a logarithmic y
// axis spans the data, not whole decades around it, and the points whose
// runs warn (sim/runs/run_warnings.h) are circled and counted in the key.
#include <gtest/gtest.h>

#include <string>

#include "renders/figure_parts.h"
#include "sim/io/csv.h"

namespace ipmc {
namespace {

// Four points; points 2 and 3 warn (3 twice).
constexpr char kTable[] =
    "point,waveform.frequency_Hz,status,error,mean_speed_along_mm_s,warnings,warn_reynolds,"
    "warn_clamp,warn_tracking,warn_reach,warn_stepping\n"
    "0,0.005,ok,,0.045,0,0,0,0,0,0\n"
    "1,0.01,ok,,0.12,0,0,0,0,0,0\n"
    "2,0.02,ok,,0.3,1,0,1,0,0,0\n"
    "3,0.04,ok,,0.66,2,1,1,0,0,0\n";

std::string Script(bool log_y, FigureReport* report) {
  FigureOptions options;
  options.x_column = "waveform.frequency_Hz";
  options.y_column = "mean_speed_along_mm_s";
  options.log_x = true;
  options.log_y = log_y;
  const FigureScratch scratch;
  return figure_parts::SweepFigure(CsvTable::Parse(kTable, "t.csv"), "t.csv", options, scratch,
                                   *report)
      .commands;
}

TEST(FiguresSweepTest, LogYSpansTheDataWithTicsInsideIt) {
  FigureReport report;
  const std::string script = Script(true, &report);
  // 0.045-0.66 spans 1.17 decades; 5 % of them is a factor 1.144 each way.
  const size_t range = script.find("set yrange [");
  ASSERT_NE(range, std::string::npos) << script;
  const double low = std::stod(script.substr(range + 12));
  const double high = std::stod(script.substr(script.find(':', range) + 1));
  EXPECT_NEAR(low, 0.045 / 1.1436, 1e-4);
  EXPECT_NEAR(high, 0.66 * 1.1436, 1e-3);
  EXPECT_NE(script.find("set ytics ('0.05' 0.05, '0.1' 0.1, '0.2' 0.2, '0.5' 0.5)"),
            std::string::npos)
      << script;
  EXPECT_EQ(Script(false, &report).find("set yrange"), std::string::npos);
}

TEST(FiguresSweepTest, WarnedPointsAreCircledAndCounted) {
  FigureReport report;
  const std::string script = Script(false, &report);
  EXPECT_NE(script.find("pt 6"), std::string::npos) << script;
  EXPECT_NE(script.find("title 'circled: 2 with warnings'"), std::string::npos)
      << script;
  ASSERT_FALSE(report.notes.empty());
  EXPECT_EQ(report.notes.back(), "2 with warnings: Re > 1 (1), clamp > 25 % (2) (circled)");
}

}  // namespace
}  // namespace ipmc
