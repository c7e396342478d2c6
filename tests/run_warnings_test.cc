// The checks a closed-loop run's numbers are read with
// (sim/runs/run_warnings.h), on results made to sit just either side of
// each limit, and their table columns and counts.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "sim/runs/run_warnings.h"

namespace ipmc {
namespace {

// Three driven links well inside every limit.
ClosedLoopResult Clean() {
  ClosedLoopResult result;
  result.actuation = Actuation::kDistributed;
  result.links.resize(3);
  for (LinkTracking& link : result.links) {
    link.max_abs_reference_mm = 5.0;
    link.max_abs_error_mm = 0.01;
    link.clamped_fraction = 0.0;
  }
  result.swim.reynolds_tip = 0.789;  // the default job's: below 1, no warning
  // The default job's cycle 3 (docs/ENERGY.md): stepping 4.6e-10 of the work.
  result.energy.actuator_power_W_total = 1.78e-9;
  result.energy.stepping_power_W = 8.1e-19;
  return result;
}

std::vector<bool> Failed(const ClosedLoopResult& result) {
  const RunWarnings warnings = ClosedLoopWarnings(result);
  return std::vector<bool>(std::begin(warnings.failed), std::end(warnings.failed));
}

TEST(RunWarningsTest, EachCheckFailsJustAboveItsLimitOnly) {
  EXPECT_EQ(ClosedLoopWarnings(Clean()).Count(), 0);
  EXPECT_TRUE(ClosedLoopWarnings(Clean()).messages.empty());
  const std::vector<bool> none(kRunWarningCheckCount, false);
  const auto only = [&](int check) {
    std::vector<bool> failed = none;
    failed[check] = true;
    return failed;
  };
  ClosedLoopResult result = Clean();
  result.swim.reynolds_swim = 1.0;  // at the limit: no warning
  EXPECT_EQ(Failed(result), none);
  result.swim.reynolds_swim = 1.01;
  EXPECT_EQ(Failed(result), only(0));

  result = Clean();
  result.links[2].clamped_fraction = 0.25;
  EXPECT_EQ(Failed(result), none);
  result.links[2].clamped_fraction = 0.2501;
  EXPECT_EQ(Failed(result), only(1));
  EXPECT_NE(ClosedLoopWarnings(result).messages.at(0).find("link 3 is at the clamp in 25 %"),
            std::string::npos)
      << ClosedLoopWarnings(result).messages.at(0);

  result = Clean();
  result.links[0].max_abs_error_mm = 5.001;
  EXPECT_EQ(Failed(result), only(2));
  // A passive link of single actuation tracks nothing: no warning.
  result.actuation = Actuation::kSingle;
  result.links[0].max_abs_error_mm = 0.01;
  result.links[1].max_abs_error_mm = 50.0;
  result.links[1].clamped_fraction = 1.0;
  EXPECT_EQ(Failed(result), none);

  result = Clean();
  result.reach_clamps = 1;
  EXPECT_EQ(Failed(result), only(3));

  result = Clean();
  result.energy.stepping_power_W = -0.26 * result.energy.actuator_power_W_total;
  EXPECT_EQ(Failed(result), only(4));

  result = Clean();
  result.swim.step.explicit_drag = true;
  result.swim.step.timestep_s = 5e-4;
  result.swim.step.drag_relaxation_s = 5e-4 / kMaxStepPerDragRelaxation;
  result.swim.step.swim_error = kMaxSwimStepError;
  EXPECT_EQ(Failed(result), none);
  result.swim.step.swim_error = 1.01 * kMaxSwimStepError;
  EXPECT_EQ(Failed(result), only(5));
  result.swim.step.swim_error = 0.0;
  result.swim.step.drag_relaxation_s *= 0.99;
  EXPECT_EQ(Failed(result), only(5));
}

TEST(RunWarningsTest, TableCellsAreReadBackAndCounted) {
  const std::vector<std::string> columns = RunWarningColumns();
  ASSERT_EQ(columns.size(), 1u + kRunWarningCheckCount);
  EXPECT_EQ(columns[0], "warnings");
  ClosedLoopResult hot = Clean();
  hot.swim.reynolds_tip = 4.9;
  hot.links[1].clamped_fraction = 0.85;
  const std::vector<std::string> hot_row = RunWarningCells(ClosedLoopWarnings(hot));
  EXPECT_EQ(hot_row, (std::vector<std::string>{"2", "1", "1", "0", "0", "0", "0"}));
  ClosedLoopResult fast = Clean();
  fast.swim.reynolds_tip = 1.2;
  const std::vector<std::string> fast_row = RunWarningCells(ClosedLoopWarnings(fast));
  const std::vector<std::string> clean_row = RunWarningCells(ClosedLoopWarnings(Clean()));
  EXPECT_EQ(FailedChecks(columns, hot_row), (std::vector<int>{0, 1}));
  EXPECT_TRUE(FailedChecks(columns, clean_row).empty());
  EXPECT_TRUE(FailedChecks(columns, std::vector<std::string>(columns.size(), "")).empty());
  EXPECT_EQ(WarningCountsText(columns, {hot_row, clean_row, fast_row}),
            "2 with warnings: Re > 1 (2), clamp > 25 % (1)");
  EXPECT_EQ(WarningCountsText(columns, {clean_row}), "none with warnings");
  EXPECT_EQ(WarningCountsText({"point", "status"}, {{"0", "ok"}}), "");
}

}  // namespace
}  // namespace ipmc
