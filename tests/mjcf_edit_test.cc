// Edits of MJCF text (sim/io/mjcf_edit.h): each changes what it names and
// leaves the rest of the text byte for byte, commented-out elements
// included; MuJoCo loads the result with the exact numbers.
#include "sim/io/mjcf_edit.h"

#include <gtest/gtest.h>
#include <mujoco/mujoco.h>

#include <string>

#include "sim/core/simulation.h"

namespace ipmc {
namespace {

const std::string kModel = R"(<mujoco model="m">
  <!-- <option timestep="9"/> <joint damping="9"/> <numeric name="a" data="9"/> -->
  <option timestep="0.001" gravity="0 0 0"/>
  <default><joint damping='0.25'/></default>
  <custom>
    <numeric name="a" size="1" data="1"/>
    <text name="t" data="old"/>
  </custom>
  <worldbody><body><joint name="j" type="hinge" damping="1e-7" stiffness="2"/>
    <geom type="sphere" size="0.01"/></body></worldbody>
</mujoco>
)";

TEST(MjcfEditTest, SetsTheOptionAndKeepsTheRest) {
  const std::string edited = SetMjcfOption(kModel, "timestep", "0.0005");
  EXPECT_NE(edited.find(R"(<option timestep="0.0005" gravity="0 0 0"/>)"), std::string::npos);
  EXPECT_NE(edited.find(R"(<!-- <option timestep="9"/>)"), std::string::npos);  // the comment
  const std::string added =
      SetMjcfOption("<mujoco>\n<worldbody/>\n</mujoco>", "integrator", "Euler");
  EXPECT_EQ(added, "<mujoco>\n  <option integrator=\"Euler\"/>\n<worldbody/>\n</mujoco>");
}

TEST(MjcfEditTest, ScalesEveryJointsDampingExactly) {
  const std::string edited = ScaleMjcfJointDamping(kModel, 3.0);
  EXPECT_NE(edited.find("<joint damping='0.75'/>"), std::string::npos);
  EXPECT_NE(edited.find(R"(damping="3e-07")"), std::string::npos);  // shortest form of 1e-7 * 3
  EXPECT_NE(edited.find(R"(<joint damping="9"/>)"), std::string::npos);  // the comment
  const ModelPtr m = LoadModelString(edited);
  EXPECT_EQ(m->dof_damping[0], 1e-7 * 3.0);  // the product, to the bit
}

TEST(MjcfEditTest, SetsAddsAndRemovesCustomFields) {
  std::string edited = SetMjcfCustomField(kModel, "numeric", "a", "0.1");
  EXPECT_NE(edited.find(R"(<numeric name="a" data="0.1"/>)"), std::string::npos);
  edited = SetMjcfCustomField(edited, "text", "t", "new");
  edited = SetMjcfCustomField(edited, "numeric", "b", "2.5");
  edited = RemoveMjcfCustomField(edited, "a");
  const ModelPtr m = LoadModelString(edited);
  ASSERT_EQ(m->nnumeric, 1);
  EXPECT_EQ(std::string(mj_id2name(m.get(), mjOBJ_NUMERIC, 0)), "b");
  EXPECT_EQ(m->numeric_data[0], 2.5);
  ASSERT_EQ(m->ntext, 1);
  EXPECT_EQ(std::string(m->text_data + m->text_adr[0]), "new");
}

}  // namespace
}  // namespace ipmc
