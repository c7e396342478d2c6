// The flagellum models: geometry of Table 1, mechanics from the stated
// material assumptions, and the committed files equal the generator's.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "tests/test_util.h"

namespace ipmc::testing {
namespace {

std::string ReadFile(const std::string& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

const std::string kModels = std::string(IPMC_SWIM_SOURCE_DIR) + "/models/";

TEST(ModelsTest, CommittedFilesEqualTheGenerator) {
  FlagellumSpec free_spec;
  EXPECT_EQ(ReadFile(kModels + "flagellum3.xml"), GenerateFlagellumMjcf(free_spec));
  FlagellumSpec clamped = free_spec;
  clamped.clamped = true;
  clamped.name = "flagellum3_clamped";
  clamped.plants = "table2";  // the bench identifies each link's own Table 2 row
  clamped.timestep_s = 5e-4;  // docs/RUNS.md, "Time step and integrator": the bench's step
  EXPECT_EQ(ReadFile(kModels + "flagellum3_clamped.xml"), GenerateFlagellumMjcf(clamped));
}

TEST(ModelsTest, FlagellumGeometryFollowsTable1) {
  Simulation sim(LoadModelFile(kModels + "flagellum3.xml"), "flagellum3.xml");
  const mjModel* m = sim.model();
  const mjData* d = sim.data();
  // Link 1 starts at x = 0; tip 3 ends the 31 mm body (3 x 10 mm + 2 x 0.5 mm).
  const int tip3 = mj_name2id(m, mjOBJ_SITE, "tip3");
  EXPECT_NEAR(d->site_xpos[3 * tip3], 31e-3, 1e-12);
  for (int q = 1; q <= 3; ++q) {
    const int geom = mj_name2id(m, mjOBJ_GEOM, ("link" + std::to_string(q)).c_str());
    EXPECT_NEAR(m->geom_size[3 * geom], 5e-3, 1e-15);      // 10 mm long
    EXPECT_NEAR(m->geom_size[3 * geom + 1], 125e-6, 1e-15);  // 250 um thick
    EXPECT_NEAR(m->geom_size[3 * geom + 2], 1.5e-3, 1e-15);  // 3 mm wide
    // 2000 kg/m^3 x 10 x 3 x 0.25 mm^3 = 15 mg.
    EXPECT_NEAR(m->body_mass[m->geom_bodyid[geom]], 1.5e-5, 1e-15);
    // k = E I / (L / 2), I = w h^3 / 12: 0.25e9 x 3e-3 x (250e-6)^3 / (12 x 5e-3),
    // the root hinge's share being half the rigid link.
    const int joint = mj_name2id(m, mjOBJ_JOINT, ("j" + std::to_string(q)).c_str());
    EXPECT_NEAR(m->jnt_stiffness[joint], 1.953125e-4, 1e-15);
  }
  // Planar root, three hinges, one IPMC motor and one servo per hinge,
  // joint-angle and tip-position sensors.
  EXPECT_EQ(m->nq, 6);
  EXPECT_EQ(m->nu, 6);
  EXPECT_EQ(m->nsensor, 6);
  EXPECT_GE(mj_name2id(m, mjOBJ_JOINT, "root_yaw"), 0);
}

TEST(ModelsTest, ClampedModelHasOnlyTheHinges) {
  Simulation sim(LoadModelFile(kModels + "flagellum3_clamped.xml"), "flagellum3_clamped.xml");
  EXPECT_EQ(sim.model()->nq, 3);
  EXPECT_LT(mj_name2id(sim.model(), mjOBJ_JOINT, "root_x"), 0);
}

TEST(ModelsTest, GeneratorWritesAnyLinkCount) {
  FlagellumSpec spec;
  spec.link_lengths_mm = {4.0, 6.0, 8.0, 10.0, 12.0};
  spec.head_length_mm = 0.0;
  spec.ipmc_actuators = false;  // link 1 is the free root: no hinge for its IPMC
  Simulation sim(LoadModelString(GenerateFlagellumMjcf(spec)), "five links");
  const mjModel* m = sim.model();
  EXPECT_EQ(m->nq, 3 + 4);  // free root on link 1, four hinges
  const int tip5 = mj_name2id(m, mjOBJ_SITE, "tip5");
  EXPECT_NEAR(sim.data()->site_xpos[3 * tip5], (40.0 + 4 * 0.5) * 1e-3, 1e-12);
}

TEST(ModelsTest, GeneratorRejectsBadSpecs) {
  FlagellumSpec spec;
  spec.link_lengths_mm = {10.0, -1.0};
  EXPECT_THROW(GenerateFlagellumMjcf(spec), std::invalid_argument);
  spec = FlagellumSpec();
  spec.viscosity_Pa_s = std::nan("");
  EXPECT_THROW(GenerateFlagellumMjcf(spec), std::invalid_argument);
  spec = FlagellumSpec();
  spec.coefficients = "direct";  // without xi values
  EXPECT_THROW(GenerateFlagellumMjcf(spec), std::invalid_argument);
}

}  // namespace
}  // namespace ipmc::testing
