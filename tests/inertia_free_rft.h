// An inertia-free resistive-force-theory swimmer, independent of the
// simulator: what tests/propulsion_crosscheck_test.cc compares the
// closed-loop run with (its own checks: tests/inertia_free_rft_test.cc).
//
// The solver (Stokes limit, planar). Let B be the frame of the swimmer's
// root body (the head). The shape is the vector of hinge angles q(t); from
// the model's rest geometry it gives, in B, every drag segment's centre c,
// unit tangent t and length L, and every hinge's anchor p_j and axis a_j.
// B moves with the planar twist xi = (U_x, U_y, Omega), expressed in B. A
// point r of a segment carried by body b then moves through the still fluid
// with
//   u(r) = U + Omega e_z x r + sum_{j ancestor hinges of b} qdot_j a_j x (r - p_j)
// and feels the drag per unit length (Gray & Hancock 1955)
//   f = -xi_t (u.t) t - xi_n (u - (u.t) t),
// with each segment's coefficients from its own radius (or the model's
// global one where it sets ipmc_rft_equivalent_radius_m). A sphere of
// radius a (a head) whose centre moves with u_c and whose body turns with
// omega feels Stokes' (1851) force and torque about its centre
//   F = -6 pi mu a u_c,   T = -8 pi mu a^3 omega.
// Without inertia the total drag force and torque about B's origin vanish:
//   F = sum_seg int f ds = 0,   M_z = e_z . sum_seg int r x f ds = 0.
// Both are linear in (xi, qdot): R xi + b(q, qdot) = 0 with the 3x3
// resistance matrix R (column k: the wrench for xi = e_k, qdot = 0) and
// b the wrench for xi = 0. B's pose g = (x, y, yaw) in the world then
// follows dg/dt = g xi(t) on SE(2).
#pragma once

#include <mujoco/mujoco.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "sim/core/model_generator.h"
#include "sim/core/scenario.h"
#include "sim/core/simulation.h"
#include "tests/test_util.h"
#include "sim/base/numbers.h"

namespace ipmc::testing {

constexpr double kMToMm = 1e3;
// The swimmer's root: the first body under the world (sim/core/swim_meter.h).
constexpr int kRootBody = 1;

// ---------------------------------------------------------------------------
// Drag coefficients from the model's <custom> fields (docs/MODEL.md,
// "Resistive-force theory"), with the defaults docs/LIBRARY.md lists for
// absent fields.

inline std::optional<double> CustomNumber(const mjModel* m, const std::string& name) {
  const int id = mj_name2id(m, mjOBJ_NUMERIC, name.c_str());
  if (id < 0) return std::nullopt;
  return m->numeric_data[m->numeric_adr[id]];
}

inline double RequireCustomNumber(const mjModel* m, const std::string& name) {
  const std::optional<double> value = CustomNumber(m, name);
  if (!value) throw std::runtime_error("model has no <custom> numeric " + name);
  return *value;
}

inline std::optional<std::string> CustomText(const mjModel* m, const std::string& name) {
  const int id = mj_name2id(m, mjOBJ_TEXT, name.c_str());
  if (id < 0) return std::nullopt;
  return std::string(m->text_data + m->text_adr[id]);
}

struct RftCoefficients {
  double normal_N_s_m2 = 0.0;
  double tangential_N_s_m2 = 0.0;
};

// gray_hancock: xi_n = 4 pi mu / (ln(2 lambda / a) + 1/2),
//               xi_t = 2 pi mu / (ln(2 lambda / a) - 1/2)
// lighthill:    xi_n = 4 pi mu / (ln(2 q / a) + 1/2), xi_t = 2 pi mu / ln(2 q / a),
//               q = 0.09 lambda
// direct:       the two given values.
// a is the model's ipmc_rft_equivalent_radius_m where it sets one, else
// `own_radius_m` (a segment's own), else the paper's strip's 0.8125 mm.
inline RftCoefficients CoefficientsFromModel(const mjModel* m,
                                             std::optional<double> own_radius_m = {}) {
  const double mu_Pa_s = RequireCustomNumber(m, "ipmc_rft_viscosity_Pa_s");
  const std::string law = CustomText(m, "ipmc_rft_coefficients").value_or("gray_hancock");
  const double radius_m =
      CustomNumber(m, "ipmc_rft_equivalent_radius_m").value_or(own_radius_m.value_or(0.8125e-3));
  const double wavelength_m = CustomNumber(m, "ipmc_rft_wavelength_m").value_or(0.032);
  if (law == "direct") {
    return {RequireCustomNumber(m, "ipmc_rft_xi_normal_N_s_m2"),
            RequireCustomNumber(m, "ipmc_rft_xi_tangential_N_s_m2")};
  }
  if (law == "lighthill") {
    const double log_term = std::log(2.0 * 0.09 * wavelength_m / radius_m);
    return {4.0 * kPi * mu_Pa_s / (log_term + 0.5), 2.0 * kPi * mu_Pa_s / log_term};
  }
  if (law != "gray_hancock") throw std::runtime_error("unknown ipmc_rft_coefficients " + law);
  const double log_term = std::log(2.0 * wavelength_m / radius_m);
  return {4.0 * kPi * mu_Pa_s / (log_term + 0.5), 2.0 * kPi * mu_Pa_s / (log_term - 0.5)};
}

// ---------------------------------------------------------------------------
// The chain read from the model: every body of the root's subtree, every
// hinge below the root (the root's own joints are the free planar root),
// every drag geom.

struct Hinge {
  int joint_id = -1;
  int qpos_adr = -1;
  double qpos0_rad = 0.0;
  Eigen::Vector3d anchor_body_m;  // in the frame of the body it moves
  Eigen::Vector3d axis_body;      // unit
};

struct ChainBody {
  int body_id = -1;
  int parent = -1;                  // index in Chain::bodies; -1 for the root
  Eigen::Vector3d pos_in_parent_m;  // rest placement in the parent's frame
  Eigen::Matrix3d rot_in_parent;
  std::vector<int> hinges;           // its own, in the model's order (Chain::hinges)
  std::vector<int> ancestor_hinges;  // every hinge between the root and it, own included
  double mass_kg = 0.0;
  Eigen::Vector3d com_body_m;  // centre of mass in the body's frame
};

struct DragSegment {
  int geom_id = -1;
  int body = -1;  // index in Chain::bodies
  Eigen::Vector3d centre_body_m;
  Eigen::Vector3d tangent_body;  // box: local x; capsule, cylinder: local z
  double length_m = 0.0;
  // A box's (w + h) / 4 from its sides across x (Batchelor 1970), a
  // capsule's or cylinder's radius.
  double radius_m = 0.0;
  RftCoefficients xi;  // CoefficientsFromModel(m, radius_m)
};

struct DragSphere {
  int geom_id = -1;
  int body = -1;  // index in Chain::bodies
  Eigen::Vector3d centre_body_m;
  double radius_m = 0.0;
};

struct Chain {
  std::vector<ChainBody> bodies;
  std::vector<Hinge> hinges;
  std::vector<DragSegment> segments;
  std::vector<DragSphere> spheres;
  double viscosity_Pa_s = 0.0;
  // The coefficients of the model's global radius (the paper's strip's
  // where the model sets none); each segment drags with its own.
  RftCoefficients xi;
  double mass_kg = 0.0;
  double length_m = 0.0;  // sum of the segment lengths
  int Hinges() const { return static_cast<int>(hinges.size()); }
};

inline Eigen::Matrix3d RotationOfQuat(const mjtNum* quat_wxyz) {
  return Eigen::Quaterniond(quat_wxyz[0], quat_wxyz[1], quat_wxyz[2], quat_wxyz[3])
      .normalized()
      .toRotationMatrix();
}

inline bool IsSlenderGeomType(int type) {
  return type == mjGEOM_BOX || type == mjGEOM_CAPSULE || type == mjGEOM_CYLINDER;
}

inline Chain ChainFromModel(const mjModel* m) {
  if (m->nbody <= kRootBody || m->body_parentid[kRootBody] != 0) {
    throw std::runtime_error("the model has no root body under the world");
  }
  Chain chain;
  std::vector<int> index_of_body(m->nbody, -1);
  // MuJoCo numbers bodies depth first, so parents come before children.
  for (int b = kRootBody; b < m->nbody; ++b) {
    const int parent_body = m->body_parentid[b];
    if (b != kRootBody && index_of_body[parent_body] < 0) continue;  // not in the subtree
    ChainBody body;
    body.body_id = b;
    body.parent = b == kRootBody ? -1 : index_of_body[parent_body];
    body.pos_in_parent_m = Eigen::Vector3d(m->body_pos + 3 * b);
    body.rot_in_parent = RotationOfQuat(m->body_quat + 4 * b);
    body.mass_kg = m->body_mass[b];
    body.com_body_m = Eigen::Vector3d(m->body_ipos + 3 * b);
    if (body.parent >= 0) body.ancestor_hinges = chain.bodies[body.parent].ancestor_hinges;
    if (b != kRootBody) {
      for (int j = m->body_jntadr[b]; j < m->body_jntadr[b] + m->body_jntnum[b]; ++j) {
        if (m->jnt_type[j] != mjJNT_HINGE) {
          throw std::runtime_error("only hinges may join the bodies below the root");
        }
        Hinge hinge;
        hinge.joint_id = j;
        hinge.qpos_adr = m->jnt_qposadr[j];
        hinge.qpos0_rad = m->qpos0[hinge.qpos_adr];
        hinge.anchor_body_m = Eigen::Vector3d(m->jnt_pos + 3 * j);
        hinge.axis_body = Eigen::Vector3d(m->jnt_axis + 3 * j).normalized();
        body.hinges.push_back(chain.Hinges());
        body.ancestor_hinges.push_back(chain.Hinges());
        chain.hinges.push_back(hinge);
      }
    }
    index_of_body[b] = static_cast<int>(chain.bodies.size());
    chain.bodies.push_back(body);
    chain.mass_kg += body.mass_kg;
  }
  // Drag geoms: those named in ipmc_rft_geoms, else every box, capsule,
  // cylinder and sphere of the subtree.
  std::vector<int> geoms;
  if (const std::optional<std::string> names = CustomText(m, "ipmc_rft_geoms")) {
    std::istringstream words(*names);
    for (std::string name; words >> name;) {
      const int g = mj_name2id(m, mjOBJ_GEOM, name.c_str());
      if (g < 0) throw std::runtime_error("ipmc_rft_geoms names an unknown geom " + name);
      geoms.push_back(g);
    }
  } else {
    for (int g = 0; g < m->ngeom; ++g) {
      const bool dragged = IsSlenderGeomType(m->geom_type[g]) || m->geom_type[g] == mjGEOM_SPHERE;
      if (dragged && index_of_body[m->geom_bodyid[g]] >= 0) geoms.push_back(g);
    }
  }
  chain.viscosity_Pa_s = RequireCustomNumber(m, "ipmc_rft_viscosity_Pa_s");
  for (int g : geoms) {
    if (index_of_body[m->geom_bodyid[g]] >= 0 && m->geom_type[g] == mjGEOM_SPHERE) {
      DragSphere sphere;
      sphere.geom_id = g;
      sphere.body = index_of_body[m->geom_bodyid[g]];
      sphere.centre_body_m = Eigen::Vector3d(m->geom_pos + 3 * g);
      sphere.radius_m = m->geom_size[3 * g];
      chain.spheres.push_back(sphere);
      continue;
    }
    if (index_of_body[m->geom_bodyid[g]] < 0 || !IsSlenderGeomType(m->geom_type[g])) {
      throw std::runtime_error("a drag geom is outside the swimmer or not slender");
    }
    const bool box = m->geom_type[g] == mjGEOM_BOX;
    DragSegment segment;
    segment.geom_id = g;
    segment.body = index_of_body[m->geom_bodyid[g]];
    segment.centre_body_m = Eigen::Vector3d(m->geom_pos + 3 * g);
    segment.tangent_body = RotationOfQuat(m->geom_quat + 4 * g).col(box ? 0 : 2);
    segment.length_m = 2.0 * m->geom_size[3 * g + (box ? 0 : 1)];
    segment.radius_m =
        box ? 0.5 * (m->geom_size[3 * g + 1] + m->geom_size[3 * g + 2]) : m->geom_size[3 * g];
    segment.xi = CoefficientsFromModel(m, segment.radius_m);
    chain.segments.push_back(segment);
    chain.length_m += segment.length_m;
  }
  chain.xi = CoefficientsFromModel(m);
  return chain;
}

// The root's yaw hinge (about z) in qpos; the planar root of the generated
// models is slide x, slide y, hinge z at the root body's origin.
inline int RootYawQposAdr(const mjModel* m) {
  const int first = m->body_jntadr[kRootBody];
  for (int j = first; j < first + m->body_jntnum[kRootBody]; ++j) {
    if (m->jnt_type[j] == mjJNT_HINGE) return m->jnt_qposadr[j];
  }
  throw std::runtime_error("the root body has no yaw hinge");
}

inline double RootYaw_rad(const mjModel* m, const mjData* d) {
  const int adr = RootYawQposAdr(m);
  return d->qpos[adr] - m->qpos0[adr];
}

inline Eigen::VectorXd HingeAngles_rad(const Chain& chain, const mjData* d) {
  Eigen::VectorXd q(chain.Hinges());
  for (int j = 0; j < chain.Hinges(); ++j) q[j] = d->qpos[chain.hinges[j].qpos_adr];
  return q;
}

// ---------------------------------------------------------------------------
// Kinematics in B. For body b with parent P:
//   R_b = R_P R_rest,  p_b = p_P + R_P pos_rest,
// then for each of its hinges (anchor s, axis a in b's frame, angle q - q0):
//   anchor p_j = p_b + R_b s, axis a_j = R_b a,
//   R_b <- Rot(a_j, q - q0) R_b,  p_b <- p_j - R_b s   (the anchor stays put).

struct ChainShape {
  std::vector<Eigen::Matrix3d> body_rot;
  std::vector<Eigen::Vector3d> body_pos_m;
  std::vector<Eigen::Vector3d> hinge_anchor_m, hinge_axis;
  std::vector<Eigen::Vector3d> segment_centre_m, segment_tangent;
  std::vector<Eigen::Vector3d> sphere_centre_m;
};

inline ChainShape ShapeOf(const Chain& chain, const Eigen::VectorXd& angle_rad) {
  ChainShape shape;
  const size_t n = chain.bodies.size();
  shape.body_rot.resize(n);
  shape.body_pos_m.resize(n);
  shape.hinge_anchor_m.resize(chain.hinges.size());
  shape.hinge_axis.resize(chain.hinges.size());
  for (size_t b = 0; b < n; ++b) {
    const ChainBody& body = chain.bodies[b];
    Eigen::Matrix3d rot = Eigen::Matrix3d::Identity();
    Eigen::Vector3d pos = Eigen::Vector3d::Zero();
    if (body.parent >= 0) {
      const Eigen::Matrix3d& parent_rot = shape.body_rot[body.parent];
      rot = parent_rot * body.rot_in_parent;
      pos = shape.body_pos_m[body.parent] + parent_rot * body.pos_in_parent_m;
    }
    for (int j : body.hinges) {
      const Hinge& hinge = chain.hinges[j];
      const Eigen::Vector3d anchor = pos + rot * hinge.anchor_body_m;
      const Eigen::Vector3d axis = rot * hinge.axis_body;
      rot = Eigen::AngleAxisd(angle_rad[j] - hinge.qpos0_rad, axis).toRotationMatrix() * rot;
      pos = anchor - rot * hinge.anchor_body_m;
      shape.hinge_anchor_m[j] = anchor;
      shape.hinge_axis[j] = axis;
    }
    shape.body_rot[b] = rot;
    shape.body_pos_m[b] = pos;
  }
  for (const DragSegment& segment : chain.segments) {
    shape.segment_centre_m.push_back(shape.body_pos_m[segment.body] +
                                     shape.body_rot[segment.body] * segment.centre_body_m);
    shape.segment_tangent.push_back(shape.body_rot[segment.body] * segment.tangent_body);
  }
  for (const DragSphere& sphere : chain.spheres) {
    shape.sphere_centre_m.push_back(shape.body_pos_m[sphere.body] +
                                    shape.body_rot[sphere.body] * sphere.centre_body_m);
  }
  return shape;
}

// Centre of mass of the chain in B: sum_b m_b (p_b + R_b c_b) / sum_b m_b.
inline Eigen::Vector3d CentreOfMass_m(const Chain& chain, const ChainShape& shape) {
  Eigen::Vector3d weighted = Eigen::Vector3d::Zero();
  for (size_t b = 0; b < chain.bodies.size(); ++b) {
    weighted += chain.bodies[b].mass_kg *
                (shape.body_pos_m[b] + shape.body_rot[b] * chain.bodies[b].com_body_m);
  }
  return weighted / chain.mass_kg;
}

// ---------------------------------------------------------------------------
// RFT drag on the whole chain by Gauss-Legendre quadrature along each
// segment, r(s) = c + s t, s in [-L/2, L/2]:
//   int g(s) ds ~= L/2 sum_k w_k g(L/2 x_k).
// For a rigid segment f is linear in s and r x f quadratic, so two nodes
// would already be exact; three are used.
constexpr int kGaussNodes = 3;
const double kGaussX[kGaussNodes] = {-0.7745966692414834, 0.0, 0.7745966692414834};
const double kGaussW[kGaussNodes] = {5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0};

// (F_x, F_y, M_z about B's origin) [N, N, N m] on the chain with shape
// `shape`, hinge rates `rate_rad_s` and B's twist (U_x, U_y, Omega) in B.
inline Eigen::Vector3d DragWrench(const Chain& chain, const ChainShape& shape,
                           const Eigen::Vector3d& frame_twist, const Eigen::VectorXd& rate_rad_s) {
  const Eigen::Vector3d frame_velocity(frame_twist[0], frame_twist[1], 0.0);
  const Eigen::Vector3d frame_spin(0.0, 0.0, frame_twist[2]);
  Eigen::Vector3d force = Eigen::Vector3d::Zero(), torque = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < chain.segments.size(); ++i) {
    const DragSegment& segment = chain.segments[i];
    const Eigen::Vector3d& c = shape.segment_centre_m[i];
    const Eigen::Vector3d& t = shape.segment_tangent[i];
    const double half_m = 0.5 * segment.length_m;
    for (int k = 0; k < kGaussNodes; ++k) {
      const Eigen::Vector3d r = c + half_m * kGaussX[k] * t;
      Eigen::Vector3d u = frame_velocity + frame_spin.cross(r);
      for (int j : chain.bodies[segment.body].ancestor_hinges) {
        u += rate_rad_s[j] * shape.hinge_axis[j].cross(r - shape.hinge_anchor_m[j]);
      }
      const Eigen::Vector3d u_tangential = u.dot(t) * t;
      const Eigen::Vector3d f = -segment.xi.tangential_N_s_m2 * u_tangential -
                                segment.xi.normal_N_s_m2 * (u - u_tangential);
      const double weight_m = half_m * kGaussW[k];
      force += weight_m * f;
      torque += weight_m * r.cross(f);
    }
  }
  for (size_t i = 0; i < chain.spheres.size(); ++i) {
    const DragSphere& sphere = chain.spheres[i];
    const Eigen::Vector3d& c = shape.sphere_centre_m[i];
    Eigen::Vector3d u = frame_velocity + frame_spin.cross(c);
    Eigen::Vector3d spin = frame_spin;
    for (int j : chain.bodies[sphere.body].ancestor_hinges) {
      u += rate_rad_s[j] * shape.hinge_axis[j].cross(c - shape.hinge_anchor_m[j]);
      spin += rate_rad_s[j] * shape.hinge_axis[j];
    }
    const double a = sphere.radius_m, mu = chain.viscosity_Pa_s;
    const Eigen::Vector3d f = -6.0 * kPi * mu * a * u;
    force += f;
    torque += c.cross(f) - 8.0 * kPi * mu * a * a * a * spin;
  }
  return {force.x(), force.y(), torque.z()};
}

inline Eigen::Matrix3d ResistanceMatrix(const Chain& chain, const ChainShape& shape) {
  const Eigen::VectorXd still = Eigen::VectorXd::Zero(chain.Hinges());
  Eigen::Matrix3d resistance;
  for (int k = 0; k < 3; ++k) {
    resistance.col(k) = DragWrench(chain, shape, Eigen::Vector3d::Unit(k), still);
  }
  return resistance;
}

// The force- and torque-free twist of B: xi = -R^-1 b.
inline Eigen::Vector3d FreeSwimmingTwist(const Chain& chain, const Eigen::VectorXd& angle_rad,
                                  const Eigen::VectorXd& rate_rad_s) {
  const ChainShape shape = ShapeOf(chain, angle_rad);
  const Eigen::Vector3d shape_wrench =
      DragWrench(chain, shape, Eigen::Vector3d::Zero(), rate_rad_s);
  return ResistanceMatrix(chain, shape).partialPivLu().solve(-shape_wrench);
}

// ---------------------------------------------------------------------------
// Pose of B on SE(2): g = (origin, yaw). With a body-frame twist
// xi = (v, omega) held for unit time, g exp(xi) has
//   yaw' = yaw + omega,  origin' = origin + Rot(yaw) V(omega) v,
//   V(w) = [sin w / w, -(1 - cos w) / w; (1 - cos w) / w, sin w / w].

struct PlanarPose {
  Eigen::Vector2d origin_m = Eigen::Vector2d::Zero();
  double yaw_rad = 0.0;
  Eigen::Vector2d ToWorld(const Eigen::Vector3d& point_B) const {
    return origin_m + Eigen::Rotation2Dd(yaw_rad) * point_B.head<2>();
  }
};

inline PlanarPose TimesExp(const PlanarPose& g, const Eigen::Vector3d& twist) {
  const double w = twist[2];
  double sin_over_w = 1.0, one_minus_cos_over_w = 0.0;
  if (std::abs(w) > 1e-8) {
    sin_over_w = std::sin(w) / w;
    one_minus_cos_over_w = (1.0 - std::cos(w)) / w;
  } else {  // series to O(w^3)
    sin_over_w = 1.0 - w * w / 6.0;
    one_minus_cos_over_w = w / 2.0 - w * w * w / 24.0;
  }
  Eigen::Matrix2d v_of_w;
  v_of_w << sin_over_w, -one_minus_cos_over_w, one_minus_cos_over_w, sin_over_w;
  PlanarPose next;
  next.origin_m = g.origin_m + Eigen::Rotation2Dd(g.yaw_rad) * (v_of_w * twist.head<2>());
  next.yaw_rad = g.yaw_rad + w;
  return next;
}

// Shape (hinge angles and rates) as a function of time.
struct ShapeSample {
  Eigen::VectorXd angle_rad, rate_rad_s;
};
using Stroke = std::function<ShapeSample(double t_s)>;

// dg/dt = g xi(t): fourth-order Magnus step with the Gauss points
// t_1,2 = t + h (1/2 -+ sqrt(3)/6),
//   g(t + h) = g(t) exp(h/2 (xi_1 + xi_2) + sqrt(3)/12 h^2 [xi_1, xi_2]),
// with the se(2) bracket [xi_a, xi_b] = (w_a J v_b - w_b J v_a, 0),
// J v = (-v_y, v_x). The step is time-symmetric: run over the mirrored
// interval with the shape played backwards (xi_1 -> -xi_2, xi_2 -> -xi_1)
// it gives exactly the inverse motion.
inline PlanarPose MagnusStep(const Chain& chain, const Stroke& stroke, const PlanarPose& g, double t_s,
                      double h_s) {
  constexpr double kNode = 0.28867513459481287;  // sqrt(3) / 6
  const ShapeSample s1 = stroke(t_s + h_s * (0.5 - kNode));
  const ShapeSample s2 = stroke(t_s + h_s * (0.5 + kNode));
  const Eigen::Vector3d xi1 = FreeSwimmingTwist(chain, s1.angle_rad, s1.rate_rad_s);
  const Eigen::Vector3d xi2 = FreeSwimmingTwist(chain, s2.angle_rad, s2.rate_rad_s);
  const auto perp = [](const Eigen::Vector3d& xi) { return Eigen::Vector2d(-xi[1], xi[0]); };
  Eigen::Vector3d bracket = Eigen::Vector3d::Zero();
  bracket.head<2>() = xi1[2] * perp(xi2) - xi2[2] * perp(xi1);
  const Eigen::Vector3d exponent =
      0.5 * h_s * (xi1 + xi2) + (std::sqrt(3.0) / 12.0) * h_s * h_s * bracket;
  return TimesExp(g, exponent);
}

struct Swim {
  PlanarPose start, end;  // of B
  // Net displacement along the swimming axis -x (positive = head first)
  // and across it (+y) [m]; rotation of B [rad].
  double com_along_m = 0.0, com_across_m = 0.0;
  double head_along_m = 0.0, head_across_m = 0.0;
  double yaw_rad = 0.0;
};

// B's motion over [t0, t1] in `steps` equal Magnus steps, from `start`.
inline Swim SwimOver(const Chain& chain, const Stroke& stroke, double t0_s, double t1_s, int steps,
              const PlanarPose& start) {
  const double h_s = (t1_s - t0_s) / steps;
  PlanarPose g = start;
  for (int k = 0; k < steps; ++k) g = MagnusStep(chain, stroke, g, t0_s + k * h_s, h_s);
  const Eigen::Vector2d com0 =
      start.ToWorld(CentreOfMass_m(chain, ShapeOf(chain, stroke(t0_s).angle_rad)));
  const Eigen::Vector2d com1 =
      g.ToWorld(CentreOfMass_m(chain, ShapeOf(chain, stroke(t1_s).angle_rad)));
  Swim swim;
  swim.start = start;
  swim.end = g;
  swim.com_along_m = -(com1.x() - com0.x());
  swim.com_across_m = com1.y() - com0.y();
  swim.head_along_m = -(g.origin_m.x() - start.origin_m.x());
  swim.head_across_m = g.origin_m.y() - start.origin_m.y();
  swim.yaw_rad = g.yaw_rad - start.yaw_rad;
  return swim;
}


// Synthetic strokes: q_j(t) = A_j sin(w t + phi_j) (+ A2_j sin(2 w t) if given).
inline Stroke SineStroke(const Eigen::VectorXd& amplitude_rad, const Eigen::VectorXd& phase_rad,
                  double frequency_Hz, const Eigen::VectorXd& second_harmonic_rad = {}) {
  const double w = 2.0 * kPi * frequency_Hz;
  return [=](double t) {
    ShapeSample s;
    s.angle_rad = s.rate_rad_s = Eigen::VectorXd::Zero(amplitude_rad.size());
    for (int j = 0; j < amplitude_rad.size(); ++j) {
      s.angle_rad[j] = amplitude_rad[j] * std::sin(w * t + phase_rad[j]);
      s.rate_rad_s[j] = amplitude_rad[j] * w * std::cos(w * t + phase_rad[j]);
      if (second_harmonic_rad.size() > 0) {
        s.angle_rad[j] += second_harmonic_rad[j] * std::sin(2.0 * w * t);
        s.rate_rad_s[j] += second_harmonic_rad[j] * 2.0 * w * std::cos(2.0 * w * t);
      }
    }
    return s;
  };
}

// ---------------------------------------------------------------------------
// Natural cubic spline through recorded angles (all hinges share the
// knots). On [t_i, t_i+1], h = t_i+1 - t_i, A = (t_i+1 - t) / h, B = 1 - A:
//   y  = A y_i + B y_i+1 + ((A^3 - A) M_i + (B^3 - B) M_i+1) h^2 / 6
//   y' = (y_i+1 - y_i) / h - (3 A^2 - 1) h M_i / 6 + (3 B^2 - 1) h M_i+1 / 6
// with the second derivatives M from
//   h_i-1 M_i-1 + 2 (h_i-1 + h_i) M_i + h_i M_i+1
//     = 6 ((y_i+1 - y_i) / h_i - (y_i - y_i-1) / h_i-1),  M_0 = M_n = 0.
class AngleSpline {
 public:
  AngleSpline(std::vector<double> t_s, std::vector<Eigen::VectorXd> angle_rad)
      : t_(std::move(t_s)), y_(std::move(angle_rad)) {
    const size_t n = t_.size();
    if (n < 3) throw std::runtime_error("a spline needs at least 3 samples");
    const Eigen::VectorXd zero = Eigen::VectorXd::Zero(y_[0].size());
    m_.assign(n, zero);
    // Thomas algorithm on the interior equations.
    std::vector<double> diag(n, 1.0), upper(n, 0.0);
    std::vector<Eigen::VectorXd> rhs(n, zero);
    for (size_t i = 1; i + 1 < n; ++i) {
      const double h0 = t_[i] - t_[i - 1], h1 = t_[i + 1] - t_[i];
      rhs[i] = 6.0 * ((y_[i + 1] - y_[i]) / h1 - (y_[i] - y_[i - 1]) / h0);
      diag[i] = 2.0 * (h0 + h1);
      upper[i] = h1;
      if (i > 1) {
        const double factor = h0 / diag[i - 1];
        diag[i] -= factor * upper[i - 1];
        rhs[i] -= factor * rhs[i - 1];
      }
    }
    for (size_t i = n - 2; i >= 1; --i) {
      m_[i] = (rhs[i] - upper[i] * m_[i + 1]) / diag[i];
    }
  }

  ShapeSample operator()(double t_s) const {
    const size_t i = std::min<size_t>(
        t_.size() - 2,
        std::max<std::ptrdiff_t>(0, std::upper_bound(t_.begin(), t_.end(), t_s) - t_.begin() - 1));
    const double h = t_[i + 1] - t_[i];
    const double a = (t_[i + 1] - t_s) / h, b = 1.0 - a;
    ShapeSample sample;
    sample.angle_rad = a * y_[i] + b * y_[i + 1] +
                       ((a * a * a - a) * m_[i] + (b * b * b - b) * m_[i + 1]) * (h * h / 6.0);
    sample.rate_rad_s = (y_[i + 1] - y_[i]) / h - ((3.0 * a * a - 1.0) * h / 6.0) * m_[i] +
                        ((3.0 * b * b - 1.0) * h / 6.0) * m_[i + 1];
    return sample;
  }

 private:
  std::vector<double> t_;
  std::vector<Eigen::VectorXd> y_, m_;
};

// Hinge angles recorded at the run's samples.
struct Recording {
  std::vector<double> t_s;
  std::vector<Eigen::VectorXd> angle_rad;
  std::vector<double> root_yaw_rad;

  // Every `stride`-th sample.
  Recording Thinned(int stride) const {
    Recording thin;
    for (size_t i = 0; i < t_s.size(); i += stride) {
      thin.t_s.push_back(t_s[i]);
      thin.angle_rad.push_back(angle_rad[i]);
      thin.root_yaw_rad.push_back(root_yaw_rad[i]);
    }
    return thin;
  }
  // Played backwards: sample i at t_first + t_last - t_i.
  Recording Reversed() const {
    Recording reversed;
    for (size_t i = t_s.size(); i-- > 0;) {
      reversed.t_s.push_back(t_s.front() + t_s.back() - t_s[i]);
      reversed.angle_rad.push_back(angle_rad[i]);
      reversed.root_yaw_rad.push_back(root_yaw_rad[i]);
    }
    return reversed;
  }
  size_t IndexNear(double t) const {
    return std::min_element(t_s.begin(), t_s.end(),
                            [t](double a, double b) { return std::abs(a - t) < std::abs(b - t); }) -
           t_s.begin();
  }
};

// The solver over [t0, t1] of a recording, one Magnus step per sample
// interval, B starting at the origin with yaw `yaw0`.
inline Swim SwimRecorded(const Chain& chain, const Recording& rec, double t0_s, double t1_s,
                  double yaw0_rad) {
  const AngleSpline spline(rec.t_s, rec.angle_rad);
  const size_t i0 = rec.IndexNear(t0_s), i1 = rec.IndexNear(t1_s);
  PlanarPose start;
  start.yaw_rad = yaw0_rad;
  return SwimOver(
      chain, [&spline](double t) { return spline(t); }, rec.t_s[i0], rec.t_s[i1],
      static_cast<int>(i1 - i0), start);
}

inline ModelPtr PaperModel() {
  return LoadModelFile(std::string(IPMC_SWIM_SOURCE_DIR) + "/models/flagellum3.xml");
}

}  // namespace ipmc::testing
