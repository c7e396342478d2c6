// Which way a slender geom lies, read from the model alone (shared by the
// fluid models, which put a segment along it, and the IPMC actuators, which
// take a link's length from it).
//
// A capsule or cylinder lies along its local z (length 2 size[1]). A box
// lies along the local axis its centre is offset along from its body's
// origin (the joint a link hangs from: the chain's direction, whichever
// axis the model builds it along), and a box centred on its body's origin
// along its longest side; its other two sides are the ribbon's width and
// thickness.
#pragma once

#include <mujoco/mujoco.h>

#include <cmath>

namespace ipmc {

// The local axis (0, 1 or 2) of geom g's segment, or -1 for a geom that is
// not a box, capsule or cylinder, or a box centred on its body whose two
// longest sides are equal (no direction to take).
inline int SlenderAxis(const mjModel* m, int g) {
  const int type = m->geom_type[g];
  if (type == mjGEOM_CAPSULE || type == mjGEOM_CYLINDER) return 2;
  if (type != mjGEOM_BOX) return -1;
  const mjtNum* size = m->geom_size + 3 * g;
  // The body's origin seen from the geom's centre, in the geom's frame.
  mjtNum inverse[4], offset[3];
  mju_negQuat(inverse, m->geom_quat + 4 * g);
  mju_rotVecQuat(offset, m->geom_pos + 3 * g, inverse);
  const double scale = size[0] + size[1] + size[2];
  int axis = -1;
  double largest = 1e-9 * scale;  // a smaller offset is rounding: centred
  for (int i = 0; i < 3; ++i) {
    if (std::abs(offset[i]) > largest) {
      largest = std::abs(offset[i]);
      axis = i;
    }
  }
  if (axis >= 0) return axis;
  for (int i = 0; i < 3; ++i) {
    if (axis < 0 || size[i] > size[axis]) axis = i;
  }
  for (int i = 0; i < 3; ++i) {
    if (i != axis && size[i] == size[axis]) return -1;
  }
  return axis;
}

// The length [m] of geom g's segment along SlenderAxis(m, g) = axis.
inline double SlenderLength_m(const mjModel* m, int g, int axis) {
  const mjtNum* size = m->geom_size + 3 * g;
  return m->geom_type[g] == mjGEOM_BOX ? 2.0 * size[axis] : 2.0 * size[1];
}

// The radius [m] of the slender body geom g is: a capsule's or cylinder's
// own; a box's (w + h) / 4 from its two sides across the axis (Batchelor
// 1970: an elliptical section of semi-axes w/2 and h/2 has the equivalent
// radius of their mean; a flat ribbon of width w, w/4).
inline double SlenderRadius_m(const mjModel* m, int g, int axis) {
  const mjtNum* size = m->geom_size + 3 * g;
  if (m->geom_type[g] != mjGEOM_BOX) return size[0];
  return 0.5 * (size[(axis + 1) % 3] + size[(axis + 2) % 3]);
}

}  // namespace ipmc
