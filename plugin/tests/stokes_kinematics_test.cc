// The Stokes step's centre-of-mass stage (plugin/dynamics/stokes_step.h,
// StokesComPos and StokesComVel) against MuJoCo 2.2's mj_comPos and
// mj_comVel: the same subtree centres of mass, dof motions cdof and body
// velocities cvel, bit for bit, on the flexible flagellum (a planar chain
// of hinges under two slides) and on a chain of hinges and slides along
// skew axes out of any plane.
#include <gtest/gtest.h>
#include <mujoco/mujoco.h>

#include <cmath>
#include <string>

#include "plugin/dynamics/stokes_step.h"
#include "plugin/tests/test_model.h"

namespace ipmc {
namespace {

using testing::LoadXml;

using testing::FlexibleFlagellum;

void ExpectSameComStages(const mjModel* m) {
  ASSERT_TRUE(HingesAndSlidesOnly(m));
  mjData* mujoco = mj_makeData(m);
  for (int i = 0; i < m->nq; ++i) mujoco->qpos[i] += 0.3 * std::sin(1.0 + i);
  for (int i = 0; i < m->nv; ++i) mujoco->qvel[i] = 0.2 * std::cos(0.4 + 1.3 * i);
  mj_kinematics(m, mujoco);
  mjData* ours = mj_copyData(nullptr, m, mujoco);
  mj_comPos(m, mujoco);
  mj_comVel(m, mujoco);
  StokesComPos(m, ours);
  StokesComVel(m, ours);
  for (int i = 0; i < 3 * m->nbody; ++i) {
    EXPECT_EQ(ours->subtree_com[i], mujoco->subtree_com[i]) << "subtree_com entry " << i;
  }
  double largest = 0;
  for (int i = 0; i < 6 * m->nv; ++i) {
    EXPECT_EQ(ours->cdof[i], mujoco->cdof[i]) << "cdof entry " << i;
  }
  for (int i = 0; i < 6 * m->nbody; ++i) {
    EXPECT_EQ(ours->cvel[i], mujoco->cvel[i]) << "cvel entry " << i;
    largest = std::max(largest, std::abs(mujoco->cvel[i]));
  }
  EXPECT_GT(largest, 0.0);  // the comparison saw velocities
  mj_deleteData(ours);
  mj_deleteData(mujoco);
}

TEST(StokesKinematicsTest, FlexibleFlagellumMatchesMujoco) {
  ModelPtr m = FlexibleFlagellum();
  ExpectSameComStages(m.get());
}

TEST(StokesKinematicsTest, SkewChainOfHingesAndSlidesMatchesMujoco) {
  const std::string xml = R"(<mujoco>
  <option><flag contact="disable"/></option>
  <worldbody>
    <body name="a" pos="0.1 0.2 0.3">
      <joint type="slide" axis="1 0.2 0"/>
      <joint type="hinge" axis="0.3 1 0.5" pos="0.01 0 0"/>
      <geom type="box" size="0.02 0.01 0.005" pos="0.02 0 0" density="1000"/>
      <body name="b" pos="0.04 0 0" euler="0.1 0.2 0.3">
        <joint type="hinge" axis="0 0.2 1"/>
        <geom type="capsule" fromto="0 0 0 0.03 0.01 0" size="0.004" density="1000"/>
        <body name="c" pos="0.03 0.01 0">
          <joint type="slide" axis="0 0 1"/>
          <joint type="hinge" axis="1 0 0" pos="0 0.002 0"/>
          <geom type="box" size="0.01 0.003 0.002" pos="0.01 0 0" density="1000"/>
        </body>
      </body>
    </body>
  </worldbody>
</mujoco>
)";
  ModelPtr m = LoadXml(xml);
  ExpectSameComStages(m.get());
}

}  // namespace
}  // namespace ipmc
