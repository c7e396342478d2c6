// The small spatial algebra the fluid models and the Stokes stepper share:
// 6-vectors of motion [w; v] and force [torque; force] (Featherstone,
// "Rigid Body Dynamics Algorithms", 2008, ch. 2), the cross-product
// matrix and a body's rotation from MuJoCo's data.
#pragma once

#include <mujoco/mujoco.h>

#include <Eigen/Core>

namespace ipmc {

using Vector6 = Eigen::Matrix<double, 6, 1>;  // a motion or force vector (cdof, cvel)
using Matrix6 = Eigen::Matrix<double, 6, 6>;

// [r]x, the matrix of the cross product with r: [r]x a = r x a.
inline Eigen::Matrix3d CrossMatrix(const Eigen::Vector3d& r) {
  Eigen::Matrix3d rx;
  rx << 0, -r.z(), r.y(), r.z(), 0, -r.x(), -r.y(), r.x(), 0;
  return rx;
}

// The rotation of body `body` (body frame to world) from d->xmat.
inline Eigen::Matrix3d BodyRotation(const mjData* d, int body) {
  Eigen::Matrix3d q;
  const mjtNum* x = d->xmat + 9 * body;  // row-major
  q << x[0], x[1], x[2], x[3], x[4], x[5], x[6], x[7], x[8];
  return q;
}

}  // namespace ipmc
