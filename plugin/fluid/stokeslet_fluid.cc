#include "plugin/fluid/stokeslet_fluid.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

#include "plugin/mjcf/spatial_algebra.h"

namespace ipmc {
namespace {

// The last dof of body b's chain (its own or its nearest moving
// ancestor's), -1 if it is fixed to the world.
int LastDof(const mjModel* m, int body) {
  while (body > 0 && m->body_dofnum[body] == 0) body = m->body_parentid[body];
  return body > 0 ? m->body_dofadr[body] + m->body_dofnum[body] - 1 : -1;
}

void RequirePositive(double value, const char* what) {
  if (!(value > 0.0) || !std::isfinite(value)) {
    std::ostringstream msg;
    msg << "stokeslet fluid: " << what << " must be finite and > 0 (got " << value << ")";
    throw std::invalid_argument(msg.str());
  }
}

}  // namespace

StokesletSettings StokesletSettingsFromModel(const mjModel* m, const RftDrag& segments,
                                             StokesletSettings given) {
  StokesletSettings& settings = given;
  if (settings.width_points < 1 || settings.width_points > kMaxWidthPoints) {
    throw std::invalid_argument("stokeslet fluid: the points across the width must be in [1, " +
                                std::to_string(kMaxWidthPoints) + "] (got " +
                                std::to_string(settings.width_points) + ")");
  }
  if (settings.width_m == 0.0) settings.width_m = StripWidth_m(m);
  RequirePositive(settings.width_m, "the ribbon's width");
  if (settings.width_points == 1) {
    // A centreline: the slender cylinder of RFT's equivalent radius.
    const double radius_m = segments.config().equivalent_radius_m;
    if (settings.blob_m == 0.0) settings.blob_m = kBlobOverRadius * radius_m;
    if (settings.spacing_m == 0.0) settings.spacing_m = kSpacingOverBlob * settings.blob_m;
  } else {
    // A sheet: a square grid over the ribbon.
    if (settings.spacing_m == 0.0) settings.spacing_m = settings.width_m / settings.width_points;
    if (settings.blob_m == 0.0) settings.blob_m = kSheetBlobOverSpacing * settings.spacing_m;
  }
  RequirePositive(settings.blob_m, "the blob");
  RequirePositive(settings.spacing_m, "the point spacing");
  if (!(settings.shape_tolerance_rad >= 0.0) || !std::isfinite(settings.shape_tolerance_rad)) {
    throw std::invalid_argument("stokeslet fluid: the shape tolerance must be finite and >= 0");
  }
  if (settings.wall_distance_m) RequirePositive(*settings.wall_distance_m, "the wall distance");
  return settings;
}

bool StokesletFluid::Chosen(const RftDrag& /*segments*/, const RftDragOverrides& overrides) {
  return overrides.stokeslets.has_value();
}

std::unique_ptr<Fluid> StokesletFluid::Make(const mjModel* m, const RftDrag& segments,
                                            const RftDragOverrides& overrides) {
  return std::make_unique<StokesletFluid>(m, segments, *overrides.stokeslets);
}

StokesletFluid::StokesletFluid(const mjModel* m, const RftDrag& segments,
                               const StokesletSettings& stokeslets)
    : rft_(segments), settings_(StokesletSettingsFromModel(m, segments, stokeslets)) {
  for (int g : rft_.geom_ids()) {
    const int body = m->geom_bodyid[g];
    auto it = std::find(bodies_.begin(), bodies_.end(), body);
    body_of_geom_.push_back(static_cast<int>(it - bodies_.begin()));
    if (it == bodies_.end()) bodies_.push_back(body);
  }
  if (bodies_.empty()) throw std::invalid_argument("stokeslet fluid: the model has no segments");
  root_body_ = m->body_rootid[bodies_[0]];
  for (int body : bodies_) {
    if (m->body_rootid[body] != root_body_) {
      throw std::invalid_argument("stokeslet fluid: the segments must be on one tree of bodies");
    }
  }
  for (int j = 0; j < m->njnt; ++j) {
    const int type = m->jnt_type[j];
    if (m->jnt_bodyid[j] == root_body_) continue;
    if (type != mjJNT_HINGE && type != mjJNT_SLIDE) {
      throw std::invalid_argument("stokeslet fluid: only hinge and slide joints below the root");
    }
    shape_joints_.push_back(m->jnt_qposadr[j]);
  }
}

PointList StokesletFluid::Points(const Eigen::Vector3d& center, const Eigen::Vector3d& tangent,
                                 double length_m) const {
  // The width lies along z, normal to the plane the generated models beat in.
  return SegmentPoints(center, tangent, length_m, settings_.spacing_m, Eigen::Vector3d::UnitZ(),
                       settings_.width_m, settings_.width_points);
}

StokesletGeometry StokesletFluid::Geometry() const {
  StokesletGeometry geometry{settings_.blob_m, std::nullopt};
  if (settings_.wall_distance_m) geometry.wall_z_m = -*settings_.wall_distance_m;
  return geometry;
}

void StokesletFluid::Recompute(const mjModel* m, const mjData* d) const {
  const std::vector<Segment> segments = rft_.Segments(m, d);
  PointList points;
  std::vector<int> body_of_point;
  for (size_t i = 0; i < segments.size(); ++i) {
    const PointList along =
        Points(segments[i].center_W, segments[i].tangent_W, segments[i].length_m);
    points.insert(points.end(), along.begin(), along.end());
    body_of_point.insert(body_of_point.end(), along.size(), body_of_geom_[i]);
  }
  points_ = static_cast<int>(points.size());
  const Eigen::Vector3d origin(d->xpos + 3 * root_body_);
  const Eigen::MatrixXd world =
      RigidBodyResistance(points, body_of_point, static_cast<int>(bodies_.size()), origin,
                          Geometry(), rft_.config().viscosity_Pa_s);
  // Into the root's frame: R_root = Q6^T R Q6, Q6 = diag(Q, Q).
  const int n = static_cast<int>(world.rows());
  Eigen::MatrixXd q6 = Eigen::MatrixXd::Zero(n, n);
  const Eigen::Matrix3d q = BodyRotation(d, root_body_);
  for (int k = 0; k < n / 3; ++k) q6.block<3, 3>(3 * k, 3 * k) = q;
  root_resistance_ = q6.transpose() * world * q6;
  cached_shape_.resize(shape_joints_.size());
  for (size_t k = 0; k < shape_joints_.size(); ++k) cached_shape_[k] = d->qpos[shape_joints_[k]];
  ++recomputations_;
}

const Eigen::MatrixXd* StokesletFluid::InteractionResistance(const mjModel* m,
                                                             const mjData* d) const {
  bool stale = cached_shape_.size() != shape_joints_.size() || root_resistance_.size() == 0;
  for (size_t k = 0; !stale && k < shape_joints_.size(); ++k) {
    stale = std::abs(d->qpos[shape_joints_[k]] - cached_shape_[k]) > settings_.shape_tolerance_rad;
  }
  if (stale) Recompute(m, d);
  return &WorldResistance(d);
}

const Eigen::MatrixXd& StokesletFluid::WorldResistance(const mjData* d) const {
  // Back into the world and from the root's origin p to c: V_p = T V_c
  // with T = [I 0; -[p - c]x I], so R_c = T^T R_p T block by block.
  const Eigen::Matrix3d q = BodyRotation(d, root_body_);
  const Eigen::Vector3d r =
      Eigen::Vector3d(d->xpos + 3 * root_body_) - Eigen::Vector3d(d->subtree_com + 3 * root_body_);
  Matrix6 t = Matrix6::Identity();
  t.block<3, 3>(3, 0) = -CrossMatrix(r);
  Matrix6 q6 = Matrix6::Zero();
  q6.block<3, 3>(0, 0) = q;
  q6.block<3, 3>(3, 3) = q;
  const Matrix6 a = q6.transpose() * t;  // V_root-frame at p = a V_c
  const int bodies = static_cast<int>(bodies_.size());
  world_resistance_.resize(6 * bodies, 6 * bodies);
  for (int i = 0; i < bodies; ++i) {
    for (int j = 0; j < bodies; ++j) {
      world_resistance_.block<6, 6>(6 * i, 6 * j) =
          a.transpose() * root_resistance_.block<6, 6>(6 * i, 6 * j) * a;
    }
  }
  return world_resistance_;
}

Eigen::VectorXd StokesletFluid::BodyVelocities(const mjData* d) const {
  Eigen::VectorXd v(6 * bodies_.size());
  for (size_t i = 0; i < bodies_.size(); ++i) {
    v.segment<6>(6 * i) = Eigen::Map<const Vector6>(d->cvel + 6 * bodies_[i]);
  }
  return v;
}

void StokesletFluid::AddBodyWrenches(const mjModel* m, const mjData* d,
                                     const Eigen::VectorXd& wrench, mjtNum* qfrc) const {
  for (size_t i = 0; i < bodies_.size(); ++i) {
    const Vector6 w = wrench.segment<6>(6 * i);
    for (int j = LastDof(m, bodies_[i]); j >= 0; j = m->dof_parentid[j]) {
      qfrc[j] += Eigen::Map<const Vector6>(d->cdof + 6 * j).dot(w);
    }
  }
}

void StokesletFluid::Apply(const mjModel* m, mjData* d) const {
  const Eigen::VectorXd wrench = -(*InteractionResistance(m, d) * BodyVelocities(d));
  AddBodyWrenches(m, d, wrench, d->qfrc_passive);
}

double StokesletFluid::DissipatedPower_W(const mjModel* m, const mjData* d) const {
  // The resistance the drag was last applied with: measuring the power
  // must not refresh the cache (after a step d's positions are the next
  // step's while its kinematics are still this one's).
  if (root_resistance_.size() == 0) Recompute(m, d);
  const Eigen::VectorXd v = BodyVelocities(d);
  return v.dot(WorldResistance(d) * v);
}

double StokesletFluid::TowingDrag_N(double speed_m_s) const {
  // The segments end to end along x at z = 0, every point moving at U x.
  PointList points;
  double start_m = 0.0;
  for (double length_m : rft_.SegmentLengths_m()) {
    const PointList along =
        Points(Eigen::Vector3d(start_m + 0.5 * length_m, 0, 0), Eigen::Vector3d::UnitX(), length_m);
    points.insert(points.end(), along.begin(), along.end());
    start_m += length_m;
  }
  const MobilitySolver solver(StokesletMobility(points, Geometry(), rft_.config().viscosity_Pa_s));
  const Eigen::VectorXd f = solver.Forces(
      Eigen::Vector3d(speed_m_s, 0, 0).replicate(static_cast<int>(points.size()), 1));
  double drag_N = 0.0;
  for (size_t k = 0; k < points.size(); ++k) drag_N += f[3 * k];
  return drag_N;
}

}  // namespace ipmc
