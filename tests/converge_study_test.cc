// ipmc-swim converge's studies and references (sim/runs/converge_study.h)
// on a fast case: the two-link strip of docs/OWN_ROBOT.md
// (scenarios/own_two_link.toml, Stokes dynamics at 1 ms, 1 Hz), one cycle.
#include "sim/runs/converge_study.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>

namespace ipmc {
namespace {

namespace fs = std::filesystem;

const ConvergeStudy& StudyNamed(const ConvergeOutcome& outcome, const std::string& name) {
  for (const ConvergeStudy& study : outcome.studies) {
    if (study.name == name) return study;
  }
  throw std::runtime_error("no study " + name);
}

TEST(ConvergeStudyTest, ExtrapolatesTheSegmentsAtSecondOrderAndTheStokesStepAtItsObservedOrder) {
  ConvergeCommand command;
  command.scenario = (fs::path(IPMC_SWIM_SOURCE_DIR) / "scenarios" / "own_two_link.toml").string();
  command.max_segments = 8;
  command.halvings = 2;
  command.max_plates_k = 0;
  command.cycles = 1;
  const ConvergeOutcome outcome = RunConvergeCommand(command);
  ASSERT_EQ(outcome.studies.size(), 2u);

  const ConvergeStudy& segments = StudyNamed(outcome, "segments");
  ASSERT_EQ(segments.runs.size(), 4u);  // n = 1, 2, 4, 8
  const double s2 = segments.runs[1].swim_mm, s4 = segments.runs[2].swim_mm,
               s8 = segments.runs[3].swim_mm;
  // Richardson at order 2 from n = 4 and 8; its uncertainty the distance
  // to the same from n = 2 and 4.
  const double reference = s8 + (s8 - s4) / 3.0;
  EXPECT_DOUBLE_EQ(segments.swim.value, reference);
  EXPECT_DOUBLE_EQ(segments.swim.uncertainty, std::abs(reference - (s4 + (s4 - s2) / 3.0)));
  EXPECT_DOUBLE_EQ(ConvergeError(s8, segments.swim), (s8 - reference) / reference);
  // The rigid link (n = 1) is the scenario as given.
  EXPECT_EQ(segments.runs[0].swim_mm, outcome.scenario.swim_mm);

  const ConvergeStudy& timestep = StudyNamed(outcome, "timestep");
  ASSERT_EQ(timestep.runs.size(), 3u);  // 1, 0.5, 0.25 ms
  EXPECT_EQ(timestep.runs[2].setting, "timestep_s=0.00025");
  // The Stokes step's observed order on this strip: 1.22 in this one
  // cycle (docs/RUNS.md: 1.0 on the mean over cycles 2-3), between the
  // held inputs' first order and the midpoint drag's second.
  const double h0 = timestep.runs[0].swim_mm, h1 = timestep.runs[1].swim_mm,
               h2 = timestep.runs[2].swim_mm;
  const double order = std::log2((h1 - h0) / (h2 - h1));
  EXPECT_NEAR(order, 1.22, 0.05);
  EXPECT_NEAR(timestep.swim.value, h2 + (h2 - h1) / (std::pow(2.0, order) - 1.0),
              1e-12 * std::abs(h2));
  // The step is converged: every step within 1 % of the reference.
  for (const ConvergeRun& run : timestep.runs) {
    EXPECT_LT(std::abs(ConvergeError(run.swim_mm, timestep.swim)), kConvergedError) << run.setting;
  }
  // No files without out.
  EXPECT_TRUE(outcome.table_path.empty());
}

}  // namespace
}  // namespace ipmc
