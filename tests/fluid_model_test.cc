// The fluid model (plugin/fluid/fluid_model.h): RFT and regularized
// Stokeslets behind one interface. The Stokeslets' cached resistance,
// moved with the root, equals one computed afresh (a rigid motion in the
// plane, with or without the wall parallel to it, changes nothing); the
// drag callback's power is the model's dissipated power; and the paper's
// swimmer swims the same way under both models, Stokeslets within a
// measured band of RFT.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <string>

#include "ipmc_swim/ipmc_swim.h"
#include "plugin/coupling.h"
#include "plugin/fluid/fluid_model.h"
#include "sim/core/scenario.h"
#include "sim/core/simulation.h"
#include "sim/runs/closed_loop_run.h"

namespace ipmc::testing {
namespace {

const std::string kPaper = std::string(IPMC_SWIM_SOURCE_DIR) + "/scenarios/paper.toml";

ScenarioConfig PaperWith(const std::string& extra) {
  return ParseScenario("model = \"../models/flagellum3.xml\"\n" + extra, kPaper);
}

// A bent shape, the root moved and turned, velocities on every dof.
void Pose(const mjModel* m, mjData* d, double x, double y, double yaw) {
  for (int j = 0; j < m->nq; ++j) d->qpos[j] = 0.1 * std::sin(1.0 + j);
  d->qpos[0] = x, d->qpos[1] = y, d->qpos[2] = yaw;
  for (int j = 0; j < m->nv; ++j) d->qvel[j] = 1e-3 * std::cos(2.0 + j);
  mj_forward(m, d);
}

void ExpectCacheMovesWithTheRoot(const std::string& fluid) {
  const std::unique_ptr<Simulation> sim =
      LoadScenarioSimulation(PaperWith("[fluid]\nmodel = \"stokeslets\"\n" + fluid));
  const mjModel* m = sim->model();
  mjData* d = sim->data();
  const FluidModel& model = *FindCoupling(d)->fluid;
  ASSERT_TRUE(model.nonlocal());
  Pose(m, d, 0, 0, 0);
  model.BodyResistance(m, d);
  const int computed = model.recomputations();
  Pose(m, d, 3e-3, -2e-3, 0.7);
  const Eigen::MatrixXd moved = model.BodyResistance(m, d);
  EXPECT_EQ(model.recomputations(), computed);  // the shape has not changed
  const FluidModel fresh(m, model.rft(), model.settings());
  const Eigen::MatrixXd direct = fresh.BodyResistance(m, d);
  EXPECT_NEAR((moved - direct).norm() / direct.norm(), 0.0, 1e-10);
  // A joint moved beyond the tolerance makes a new resistance.
  d->qpos[4] += 2e-3;
  mj_forward(m, d);
  model.BodyResistance(m, d);
  EXPECT_EQ(model.recomputations(), computed + 1);
}

TEST(FluidModelTest, CachedStokesletResistanceMovesWithTheRoot) {
  ExpectCacheMovesWithTheRoot("");
  ExpectCacheMovesWithTheRoot("wall_gap_mm = 1.0\n");
}

// mjcb_passive adds -J^T R J qvel: its power qfrc . qvel is minus the
// dissipated power V^T R V, for both models.
TEST(FluidModelTest, CallbackPowerIsTheDissipatedPower) {
  for (const std::string model : {"rft", "stokeslets"}) {
    SCOPED_TRACE(model);
    const std::unique_ptr<Simulation> sim =
        LoadScenarioSimulation(PaperWith("[fluid]\nmodel = \"" + model + "\"\n"));
    const mjModel* m = sim->model();
    mjData* d = sim->data();
    Pose(m, d, 1e-3, 0, 0.2);
    const FluidModel& fluid = *FindCoupling(d)->fluid;
    std::vector<mjtNum> before(d->qfrc_passive, d->qfrc_passive + m->nv);
    mju_zero(d->qfrc_passive, m->nv);
    fluid.Apply(m, d);
    const double power = mju_dot(d->qfrc_passive, d->qvel, m->nv);
    const double dissipated = fluid.DissipatedPower_W(m, d);
    EXPECT_GT(dissipated, 0.0);
    EXPECT_NEAR(power, -dissipated, 1e-9 * dissipated);
  }
}

// The paper's swimmer for one short cycle (0.5 Hz, Stokes dynamics):
// RFT (Gray-Hancock) and Stokeslets swim the same way. Measured: see the
// printout; docs/FLUIDS.md has the full runs. The band is the models'
// difference, not a tolerance on either: Stokeslets resolve the links'
// interaction and the ends, which RFT leaves out (slender-body theory puts
// the difference at O(1 / ln(L / a)) ~ 30 % at most).
TEST(FluidModelTest, StokesletsAndRftSwimAlike) {
  const std::string run = "cycles = 1\ntimestep_s = 1e-3\ndynamics = \"stokes\"\n"
                          "[waveform]\nfrequency_Hz = 0.5\n";
  const double rft = RunScenario(PaperWith(run)).swim.per_cycle.at(0).com_along;
  const double stokeslets =
      RunScenario(PaperWith(run + "[fluid]\nmodel = \"stokeslets\"\n")).swim.per_cycle.at(0).com_along;
  std::printf("per cycle: rft %.6g mm, stokeslets %.6g mm, ratio %.4f\n", rft, stokeslets,
              stokeslets / rft);
  EXPECT_GT(rft * stokeslets, 0.0);
  EXPECT_NEAR(stokeslets / rft, 1.0, 0.3);
  // Snapshot: measured 0.9222 (0.0227701 and 0.020998 mm; the run is
  // deterministic). The band, 0.02, is twice the ratio's change when the
  // Stokeslet resistance is recomputed at every step instead of within the
  // default 1e-3 rad of shape (0.9131: 0.0207914 mm), so that a change of
  // either model larger than the cache's own effect shows.
  EXPECT_NEAR(stokeslets / rft, 0.9222, 0.02);
}

}  // namespace
}  // namespace ipmc::testing
