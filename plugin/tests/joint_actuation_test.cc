// The Stokes step's O(nu) actuation (plugin/dynamics/stokes_step.h,
// JointTransmission and JointActuation) against MuJoCo 2.2's own
// mj_transmission and mj_fwdActuation, which form the dense nu x nv moment
// matrix: the same lengths, moments, actuator forces and generalised
// forces, bit for bit, for the IPMC motors of a flexible flagellum and for
// servos with clamped controls and force limits.
#include <gtest/gtest.h>
#include <mujoco/mujoco.h>

#include <cmath>
#include <string>
#include <vector>

#include "plugin/dynamics/stokes_step.h"
#include "plugin/tests/test_model.h"

namespace ipmc {
namespace {

using testing::LoadXml;

using testing::FlexibleFlagellum;

// Sets qpos and ctrl to values that differ per dof and actuator (some
// controls beyond their ranges), then compares the two paths on copies.
void ExpectSameActuation(const mjModel* m, double ctrl_scale) {
  mjData* mujoco = mj_makeData(m);
  for (int i = 0; i < m->nq; ++i) mujoco->qpos[i] += 0.01 * std::sin(1.0 + i);
  for (int a = 0; a < m->nu; ++a) mujoco->ctrl[a] = ctrl_scale * std::sin(0.7 * a + 0.3);
  mj_kinematics(m, mujoco);
  mj_comPos(m, mujoco);
  mj_transmission(m, mujoco);
  mjData* ours = mj_copyData(nullptr, m, mujoco);
  mj_fwdActuation(m, mujoco);
  // Ours from a moment matrix that holds only its zeros and stale gears.
  for (int a = 0; a < m->nu; ++a) ours->actuator_length[a] = 0;
  JointTransmission(m, ours);
  JointActuation(m, ours);
  for (int a = 0; a < m->nu; ++a) {
    EXPECT_EQ(ours->actuator_length[a], mujoco->actuator_length[a]) << "actuator " << a;
    EXPECT_EQ(ours->actuator_force[a], mujoco->actuator_force[a]) << "actuator " << a;
  }
  for (int i = 0; i < m->nu * m->nv; ++i) {
    EXPECT_EQ(ours->actuator_moment[i], mujoco->actuator_moment[i]) << "moment entry " << i;
  }
  double largest = 0;
  for (int j = 0; j < m->nv; ++j) {
    EXPECT_EQ(ours->qfrc_actuator[j], mujoco->qfrc_actuator[j]) << "dof " << j;
    largest = std::max(largest, std::abs(mujoco->qfrc_actuator[j]));
  }
  EXPECT_GT(largest, 0.0);  // the comparison saw forces
  mj_deleteData(ours);
  mj_deleteData(mujoco);
}

TEST(JointActuationTest, FlexibleFlagellumMotorsMatchMujoco) {
  ModelPtr m = FlexibleFlagellum();
  ASSERT_TRUE(JointActuatorsOnly(m.get()));
  ASSERT_EQ(m->nu, 48 + 3);  // a motor per hinge, a servo per link
  ExpectSameActuation(m.get(), 1e-5);
}

TEST(JointActuationTest, ServosWithLimitsMatchMujoco) {
  ModelPtr m = LoadXml(R"(<mujoco><worldbody><body>
      <joint name="a" type="hinge" axis="0 0 1"/><geom type="box" size="0.01 0.001 0.001"/>
      <body pos="0.02 0 0"><joint name="b" type="slide" axis="1 0 0"/>
        <geom type="box" size="0.01 0.001 0.001"/></body></body></worldbody>
    <actuator>
      <position joint="a" kp="3" ctrllimited="true" ctrlrange="-0.5 0.5"/>
      <velocity joint="a" kv="0.2" forcelimited="true" forcerange="-0.1 0.1"/>
      <motor joint="b" gear="2.5" ctrllimited="true" ctrlrange="-1 2"/>
      <general joint="b" gaintype="affine" gainprm="1 0.5 0.1" biastype="affine" biasprm="0.2 -1 -0.3"/>
    </actuator></mujoco>)");
  ASSERT_TRUE(JointActuatorsOnly(m.get()));
  ExpectSameActuation(m.get(), 3.0);  // beyond every control range
}

TEST(JointActuationTest, OtherTransmissionsTakeMujocosPath) {
  ModelPtr m = LoadXml(R"(<mujoco><worldbody><body>
      <joint name="a" type="ball"/><geom type="box" size="0.01 0.001 0.001"/>
      </body></worldbody>
    <actuator><motor joint="a" gear="1 0 0 0 0 0"/></actuator></mujoco>)");
  EXPECT_FALSE(JointActuatorsOnly(m.get()));
  ModelPtr filtered = LoadXml(R"(<mujoco><worldbody><body>
      <joint name="a" type="hinge"/><geom type="box" size="0.01 0.001 0.001"/>
      </body></worldbody>
    <actuator><general joint="a" dyntype="filter" dynprm="0.1"/></actuator></mujoco>)");
  EXPECT_FALSE(JointActuatorsOnly(filtered.get()));
}

}  // namespace
}  // namespace ipmc
