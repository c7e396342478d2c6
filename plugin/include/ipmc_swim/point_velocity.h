// The world-frame velocity of a point fixed to a body, from the data's
// spatial velocities (valid after mj_comVel, as in the passive callback).
#pragma once

#include <mujoco/mujoco.h>

namespace ipmc {

// MuJoCo gives body b's spatial velocity cvel = [w; v] at the subtree
// centre of mass c of b's root, so a point p of the body moves with
// v + w x (p - c): what mj_objectVelocity computes, without its frame
// rotations or the copy of the angular part.
inline void PointVelocity_W(const mjModel* m, const mjData* d, int body, const mjtNum point_W[3],
                            mjtNum velocity_W[3]) {
  const mjtNum* w = d->cvel + 6 * body;
  const mjtNum* v = w + 3;
  const mjtNum* c = d->subtree_com + 3 * m->body_rootid[body];
  const mjtNum r[3] = {point_W[0] - c[0], point_W[1] - c[1], point_W[2] - c[2]};
  velocity_W[0] = v[0] + (w[1] * r[2] - w[2] * r[1]);
  velocity_W[1] = v[1] + (w[2] * r[0] - w[0] * r[2]);
  velocity_W[2] = v[2] + (w[0] * r[1] - w[1] * r[0]);
}

}  // namespace ipmc
