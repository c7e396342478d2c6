// The fluid model's registry (plugin/fluid/fluid_model.h): RFT and the
// dense models behind one interface, built with the form of resistance
// each has, their settings from the model's fields or a program's
// overrides. The Stokeslets' cached resistance, moved with the root,
// equals one computed afresh (a rigid motion in the plane, with or
// without the wall parallel to it, changes nothing). On the paper's model
// (models/flagellum3.xml); its swims under the models:
// tests/fluid_model_test.cc.
#include <gtest/gtest.h>
#include <mujoco/mujoco.h>

#include <cmath>
#include <fstream>
#include <memory>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "plugin/fluid/fluid_model.h"
#include "plugin/fluid/plate_fluid.h"
#include "plugin/fluid/ribbon_fluid.h"
#include "plugin/fluid/rft_drag.h"
#include "plugin/fluid/stokeslet_fluid.h"
#include "plugin/tests/paper_fluid.h"
#include "plugin/tests/test_model.h"

namespace ipmc::testing {
namespace {

// A bent shape, the root moved and turned, velocities on every dof.
void Pose(const mjModel* m, mjData* d, double x, double y, double yaw) {
  for (int j = 0; j < m->nq; ++j) d->qpos[j] = 0.1 * std::sin(1.0 + j);
  d->qpos[0] = x, d->qpos[1] = y, d->qpos[2] = yaw;
  for (int j = 0; j < m->nv; ++j) d->qvel[j] = 1e-3 * std::cos(2.0 + j);
  mj_forward(m, d);
}

void ExpectCacheMovesWithTheRoot(RftDragOverrides overrides) {
  overrides.fluid_model = "stokeslets";
  const Paper paper(overrides);
  const mjModel* m = paper.model.get();
  mjData* d = paper.data.get();
  const auto* interacting = dynamic_cast<const StokesletFluid*>(paper.fluid.get());
  ASSERT_NE(interacting, nullptr);
  const StokesletFluid& model = *interacting;
  Pose(m, d, 0, 0, 0);
  model.BodyResistance(m, d);
  const int computed = model.recomputations();
  Pose(m, d, 3e-3, -2e-3, 0.7);
  const Eigen::MatrixXd moved = model.BodyResistance(m, d);
  EXPECT_EQ(model.recomputations(), computed);  // the shape has not changed
  const StokesletFluid fresh(m, model.rft(), model.settings());
  const Eigen::MatrixXd direct = fresh.BodyResistance(m, d);
  EXPECT_NEAR((moved - direct).norm() / direct.norm(), 0.0, 1e-10);
  // A joint moved beyond the tolerance makes a new resistance.
  d->qpos[4] += 2e-3;
  mj_forward(m, d);
  model.BodyResistance(m, d);
  EXPECT_EQ(model.recomputations(), computed + 1);
}

// The registry builds the model the overrides choose (Stokeslets when they
// carry Stokeslet settings, RFT otherwise), over the coupling's segments,
// and the Stokes step's two forms of resistance are each model's own: RFT
// a block per segment and no dense matrix, Stokeslets a dense matrix over
// its bodies and no blocks.
TEST(FluidModelTest, RegistryBuildsTheChosenModel) {
  const Paper paper({});
  const mjModel* m = paper.model.get();
  mjData* d = paper.data.get();
  Pose(m, d, 0, 0, 0);
  const RftDrag& segments = paper.segments;
  std::vector<std::string> names;
  for (const FluidModelEntry& entry : FluidModels()) names.push_back(entry.name);
  EXPECT_EQ(names, (std::vector<std::string>{"rft", "stokeslets", "ribbon", "plates"}));

  const std::unique_ptr<Fluid> rft = MakeFluid(m, segments, {});
  ASSERT_NE(dynamic_cast<const RftDrag*>(rft.get()), nullptr);
  BodyResistanceBlocks<6> blocks;
  rft->LocalResistances(m, d, &blocks);
  EXPECT_EQ(blocks.size(), segments.geom_ids().size());
  EXPECT_EQ(rft->InteractionResistance(m, d), nullptr);

  RftDragOverrides overrides;
  overrides.fluid_model = "stokeslets";
  const std::unique_ptr<Fluid> stokeslets = MakeFluid(m, segments, overrides);
  ASSERT_NE(dynamic_cast<const StokesletFluid*>(stokeslets.get()), nullptr);
  stokeslets->LocalResistances(m, d, &blocks);
  EXPECT_TRUE(blocks.empty());
  const Eigen::MatrixXd* dense = stokeslets->InteractionResistance(m, d);
  ASSERT_NE(dense, nullptr);
  EXPECT_EQ(dense->rows(), 6 * static_cast<int>(stokeslets->InteractingBodies().size()));
  EXPECT_FALSE(stokeslets->InteractingBodies().empty());

  RftDragOverrides ribbon_overrides;
  ribbon_overrides.fluid_model = "ribbon";
  const std::unique_ptr<Fluid> ribbon = MakeFluid(m, segments, ribbon_overrides);
  ASSERT_NE(dynamic_cast<const RibbonFluid*>(ribbon.get()), nullptr);
  ribbon->LocalResistances(m, d, &blocks);
  EXPECT_TRUE(blocks.empty());
  const Eigen::MatrixXd* ribbon_dense = ribbon->InteractionResistance(m, d);
  ASSERT_NE(ribbon_dense, nullptr);
  EXPECT_EQ(ribbon_dense->rows(), 6 * static_cast<int>(ribbon->InteractingBodies().size()));
}

TEST(FluidModelTest, CachedStokesletResistanceMovesWithTheRoot) {
  ExpectCacheMovesWithTheRoot({});
  // A 1 mm gap below the 3 mm strip: the wall 2.5 mm from the centreline.
  RftDragOverrides wall;
  wall.model = CoefficientModel::kNearWall;
  wall.wall_distance_m = 2.5e-3;
  ExpectCacheMovesWithTheRoot(wall);
  RftDragOverrides sheet;
  sheet.fluid_parameters["ipmc_fluid_stokeslet_width_points"] = 3;
  ExpectCacheMovesWithTheRoot(sheet);
}

// The paper's model file with `lines` added to its <custom> block.
std::string PaperModelWithCustom(const std::string& lines) {
  std::ifstream in(std::string(IPMC_SWIM_SOURCE_DIR) + "/models/flagellum3.xml");
  std::stringstream text;
  text << in.rdbuf();
  return std::regex_replace(text.str(), std::regex("<custom>"), "<custom>\n" + lines);
}

// A model file chooses its fluid model and sets its parameters by its own
// <custom> fields (ipmc_fluid_model, ipmc_fluid_plate_points_across; the
// others at their defaults); a program's choice of model wins over the
// file's.
TEST(FluidModelTest, ModelFileFieldsSetTheFluidsSettings) {
  const std::string plates_xml =
      PaperModelWithCustom("<text name=\"ipmc_fluid_model\" data=\"plates\"/>\n"
                           "<numeric name=\"ipmc_fluid_plate_points_across\" data=\"1\"/>\n");
  const Paper file({}, plates_xml);
  const auto* plates = dynamic_cast<const PlateFluid*>(file.fluid.get());
  ASSERT_NE(plates, nullptr);
  EXPECT_EQ(plates->settings().points_across, 1);
  EXPECT_EQ(plates->settings().quadrature_refinement, 4);  // the parameter's default
  EXPECT_TRUE(plates->settings().richardson);
  RftDragOverrides rft;
  rft.fluid_model = "rft";
  EXPECT_NE(dynamic_cast<const RftDrag*>(Paper(rft, plates_xml).fluid.get()), nullptr);
  // The Stokeslets' blob and spacing from their fields, in SI units.
  const Paper stokeslets({}, PaperModelWithCustom(
                                 "<text name=\"ipmc_fluid_model\" data=\"stokeslets\"/>\n"
                                 "<numeric name=\"ipmc_fluid_stokeslet_blob_m\" data=\"1.5e-3\"/>\n"
                                 "<numeric name=\"ipmc_fluid_stokeslet_points_per_m\" "
                                 "data=\"2000\"/>\n"));
  const auto* line = dynamic_cast<const StokesletFluid*>(stokeslets.fluid.get());
  ASSERT_NE(line, nullptr);
  EXPECT_EQ(line->blob_m(), 1.5e-3);
  EXPECT_EQ(line->spacing_m(), 0.5e-3);
}

}  // namespace
}  // namespace ipmc::testing
