#include "plugin/fluid/rft_drag.h"

#include <Eigen/Geometry>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "plugin/fluid/near_wall_rft.h"
#include "plugin/fluid/ribbon_coefficients.h"
#include "plugin/mjcf/custom_fields.h"
#include "plugin/mjcf/geom_axes.h"
#include "ipmc_swim/point_velocity.h"
#include "sim/base/numbers.h"
#include "plugin/mjcf/spatial_algebra.h"

namespace ipmc {
namespace {

// Lighthill's (1976) effective distance q = 0.09 lambda.
constexpr double kLighthillDistanceOverWavelength = 0.09;

void RequirePositive(double value, const std::string& field) {
  if (!(value > 0.0) || !std::isfinite(value)) {
    std::ostringstream msg;
    msg << "rft drag: " << field << " must be finite and > 0 (got " << value << ")";
    throw std::invalid_argument(msg.str());
  }
}

// Applied drag per unit length for velocity u on a tangent t.
Eigen::Vector3d DragPerLength(const Eigen::Vector3d& u, const Eigen::Vector3d& t,
                              const DragCoefficients& xi) {
  const Eigen::Vector3d u_tangential = u.dot(t) * t;
  return -xi.tangential_N_s_m2 * u_tangential - xi.normal_N_s_m2 * (u - u_tangential);
}

}  // namespace

namespace {
constexpr CoefficientModel kCoefficientModels[] = {
    CoefficientModel::kGrayHancock, CoefficientModel::kLighthill, CoefficientModel::kNearWall,
    CoefficientModel::kDirect,      CoefficientModel::kRibbon,    CoefficientModel::kRibbonFitted};
}  // namespace

const char* CoefficientModelName(CoefficientModel model) {
  switch (model) {
    case CoefficientModel::kGrayHancock: return "gray_hancock";
    case CoefficientModel::kLighthill: return "lighthill";
    case CoefficientModel::kNearWall: return "near_wall";
    case CoefficientModel::kDirect: return "direct";
    case CoefficientModel::kRibbon: return "ribbon";
    case CoefficientModel::kRibbonFitted: return "ribbon_fitted";
  }
  return "";
}

CoefficientModel ParseCoefficientModel(const std::string& text) {
  for (CoefficientModel model : kCoefficientModels) {
    if (text == CoefficientModelName(model)) return model;
  }
  throw std::invalid_argument(
      std::string("rft drag: ") + kAttrCoefficients +
      " must be gray_hancock, lighthill, near_wall, direct, ribbon or ribbon_fitted (got '" + text +
      "')");
}

DragCoefficients GrayHancockCoefficients(double viscosity_Pa_s, double radius_m,
                                         double wavelength_m) {
  const double log_term = std::log(2.0 * wavelength_m / radius_m);
  return {4.0 * kPi * viscosity_Pa_s / (log_term + 0.5),
          2.0 * kPi * viscosity_Pa_s / (log_term - 0.5)};
}

DragCoefficients LighthillCoefficients(double viscosity_Pa_s, double radius_m,
                                       double wavelength_m) {
  const double log_term =
      std::log(2.0 * kLighthillDistanceOverWavelength * wavelength_m / radius_m);
  return {4.0 * kPi * viscosity_Pa_s / (log_term + 0.5), 2.0 * kPi * viscosity_Pa_s / log_term};
}

std::optional<RftDragConfig> RftDragConfig::FromModel(const mjModel* m,
                                                     const RftDragOverrides& overrides) {
  const std::optional<double> viscosity = FindCustomScalar(m, kAttrViscosity);
  if (!viscosity) {
    if (HasCustomFieldWithPrefix(m, "ipmc_rft_")) {
      throw std::invalid_argument(std::string("rft drag: ") + kAttrViscosity +
                                  " is missing (required with any ipmc_rft_ field; > 0 Pa s)");
    }
    return std::nullopt;
  }
  RftDragConfig config;
  config.viscosity_Pa_s = *viscosity;
  if (auto text = FindCustomText(m, kAttrCoefficients)) config.model = ParseCoefficientModel(*text);
  if (overrides.model) config.model = *overrides.model;
  if (auto radius = FindCustomScalar(m, kAttrEquivalentRadius)) {
    config.equivalent_radius_m = *radius;
  } else {
    config.radius_from_geoms = true;
  }
  if (auto wavelength = FindCustomScalar(m, kAttrWavelength)) config.wavelength_m = *wavelength;
  if (overrides.wavelength_m) config.wavelength_m = *overrides.wavelength_m;
  if (auto wall = FindCustomScalar(m, kAttrWallDistance)) config.wall_distance_m = *wall;
  if (overrides.wall_distance_m) {
    config.wall_distance_m = *overrides.wall_distance_m;
    config.model = CoefficientModel::kNearWall;
  }
  if (auto density = FindCustomScalar(m, kAttrFluidDensity)) config.fluid_density_kg_m3 = *density;
  const std::optional<double> xi_n = FindCustomScalar(m, kAttrXiNormal);
  const std::optional<double> xi_t = FindCustomScalar(m, kAttrXiTangential);
  if (config.model == CoefficientModel::kDirect) {
    if (!xi_n || !xi_t) {
      throw std::invalid_argument(std::string("rft drag: coefficients = direct needs ") +
                                  kAttrXiNormal + " and " + kAttrXiTangential + " (> 0 N s/m^2)");
    }
    config.direct = {*xi_n, *xi_t};
  } else if ((xi_n || xi_t) && !overrides.model) {
    throw std::invalid_argument(std::string("rft drag: ") + kAttrXiNormal + "/" +
                                kAttrXiTangential + " are only allowed with " + kAttrCoefficients +
                                " = direct");
  }
  if (auto geoms = FindCustomText(m, kAttrGeoms)) config.geom_names = SplitWords(*geoms);
  config.Validate();
  return config;
}

void RftDragConfig::Validate() const {
  RequirePositive(viscosity_Pa_s, kAttrViscosity);
  if (!(fluid_density_kg_m3 >= 0.0) || !std::isfinite(fluid_density_kg_m3)) {
    std::ostringstream msg;
    msg << "rft drag: " << kAttrFluidDensity << " must be finite and >= 0 (got "
        << fluid_density_kg_m3 << ")";
    throw std::invalid_argument(msg.str());
  }
  if (model == CoefficientModel::kDirect) {
    RequirePositive(direct.normal_N_s_m2, kAttrXiNormal);
    RequirePositive(direct.tangential_N_s_m2, kAttrXiTangential);
    return;
  }
  if (radius_from_geoms) {
    // Each segment's own radius is checked as RftDrag reads it.
    if (model != CoefficientModel::kNearWall) RequirePositive(wavelength_m, kAttrWavelength);
    return;
  }
  ValidateRadius(equivalent_radius_m, kAttrEquivalentRadius);
}

void CheckRftSegment(const std::string& coefficients, double radius_m, double wavelength_m) {
  RftDragConfig config;
  config.model = ParseCoefficientModel(coefficients);
  config.equivalent_radius_m = radius_m;
  config.wavelength_m = wavelength_m;
  config.ValidateRadius(radius_m, kAttrEquivalentRadius);
}

void RftDragConfig::ValidateRadius(double radius_m, const std::string& what) const {
  if (model == CoefficientModel::kDirect) return;
  RequirePositive(radius_m, what);
  if (model == CoefficientModel::kNearWall) {
    ValidateNearWallDistance(wall_distance_m, radius_m);
    return;
  }
  RequirePositive(wavelength_m, kAttrWavelength);
  // Both formulas need a positive tangential log term.
  const double distance_m = model == CoefficientModel::kLighthill
                                ? kLighthillDistanceOverWavelength * wavelength_m
                                : wavelength_m;
  const double log_term = std::log(2.0 * distance_m / radius_m);
  const double min_log = model == CoefficientModel::kLighthill ? 0.0 : 0.5;
  if (!(log_term > min_log)) {
    std::ostringstream msg;
    msg << "rft drag: " << kAttrWavelength << " too short for " << what << " = " << radius_m
        << " m (need ln(2 " << (min_log > 0 ? "lambda" : "0.09 lambda") << " / a) > " << min_log
        << ")";
    throw std::invalid_argument(msg.str());
  }
}

DragCoefficients RftDragConfig::CoefficientsForRadius(double radius_m) const {
  RftDragConfig own = *this;
  own.equivalent_radius_m = radius_m;
  return own.Coefficients();
}

DragCoefficients RftDragConfig::Coefficients() const {
  switch (model) {
    case CoefficientModel::kGrayHancock:
      return GrayHancockCoefficients(viscosity_Pa_s, equivalent_radius_m, wavelength_m);
    case CoefficientModel::kLighthill:
      return LighthillCoefficients(viscosity_Pa_s, equivalent_radius_m, wavelength_m);
    case CoefficientModel::kNearWall:
      return NearWallCoefficients(viscosity_Pa_s, equivalent_radius_m, wall_distance_m);
    case CoefficientModel::kDirect:
    case CoefficientModel::kRibbon:  // set by RftDrag, which knows the strip's length
    case CoefficientModel::kRibbonFitted:
      return direct;
  }
  return direct;
}

double RotationalDrag_N_m_s(const DragCoefficients& xi, double length_m) {
  if (xi.rotation_N_m_s > 0.0) return xi.rotation_N_m_s;
  return xi.normal_N_s_m2 * length_m * length_m * length_m / 12.0;
}

Wrench SegmentDragExact(const Segment& segment, const DragCoefficients& xi) {
  const Eigen::Vector3d& t = segment.tangent_W;
  const double length = segment.length_m;
  const Eigen::Vector3d w_normal =
      segment.angular_velocity_W - segment.angular_velocity_W.dot(t) * t;
  Wrench wrench;
  wrench.force_W = length * DragPerLength(segment.velocity_center_W, t, xi);
  wrench.torque_center_W = -RotationalDrag_N_m_s(xi, length) * w_normal;
  return wrench;
}

SpatialResistance SegmentResistance(const Eigen::Vector3d& center_W,
                                    const Eigen::Vector3d& tangent_W, double length_m,
                                    const Eigen::Vector3d& c_W, const DragCoefficients& xi) {
  const Eigen::Matrix3d tt = tangent_W * tangent_W.transpose();
  const Eigen::Matrix3d normal = Eigen::Matrix3d::Identity() - tt;
  const Eigen::Matrix3d lr = length_m * (xi.tangential_N_s_m2 * tt + xi.normal_N_s_m2 * normal);
  const Eigen::Matrix3d rx = CrossMatrix(center_W - c_W);
  const Eigen::Matrix3d rx_lr = rx * lr;
  SpatialResistance s;
  s.topLeftCorner<3, 3>() = RotationalDrag_N_m_s(xi, length_m) * normal - rx_lr * rx;
  s.topRightCorner<3, 3>() = rx_lr;
  s.bottomLeftCorner<3, 3>() = rx_lr.transpose();
  s.bottomRightCorner<3, 3>() = lr;
  return s;
}

// Rows and columns 2 to 4 of SegmentResistance's S, computed as it
// computes them, without the entries that a planar motion does not read:
// with r = centre - c, [r]x's row 2 is (-r_y, r_x, 0) and its column 2
// (r_y, -r_x, 0), so the block needs lr's upper-left 2 x 2 only.
Eigen::Matrix3d SegmentPlanarResistance(const Eigen::Vector3d& center_W,
                                        const Eigen::Vector3d& tangent_W, double length_m,
                                        const Eigen::Vector3d& c_W, const DragCoefficients& xi) {
  const Eigen::Vector3d& t = tangent_W;
  const Eigen::Vector3d r = center_W - c_W;
  Eigen::Matrix2d lr;  // length (xi_t t t^T + xi_n (1 - t t^T)), x-y block
  for (int i = 0; i < 2; ++i) {
    for (int j = 0; j < 2; ++j) {
      const double tt = t[i] * t[j];
      lr(i, j) = length_m * (xi.tangential_N_s_m2 * tt + xi.normal_N_s_m2 * ((i == j) - tt));
    }
  }
  // Row 2 of [r]x lr: the coupling of w_z with v_x and v_y.
  const double coupling_x = -r.y() * lr(0, 0) + r.x() * lr(1, 0);
  const double coupling_y = -r.y() * lr(0, 1) + r.x() * lr(1, 1);
  Eigen::Matrix3d s;
  s(0, 0) = RotationalDrag_N_m_s(xi, length_m) * (1.0 - t.z() * t.z()) -
            (coupling_x * r.y() - coupling_y * r.x());
  s(0, 1) = s(1, 0) = coupling_x;
  s(0, 2) = s(2, 0) = coupling_y;
  s.bottomRightCorner<2, 2>() = lr;
  return s;
}

Wrench SegmentDragQuadrature(const Segment& segment, const DragCoefficients& xi, int intervals) {
  if (intervals < 1) throw std::invalid_argument("rft drag: quadrature intervals must be >= 1");
  const Eigen::Vector3d& t = segment.tangent_W;
  const double ds = segment.length_m / intervals;
  Wrench wrench;
  for (int i = 0; i < intervals; ++i) {
    const double s = -0.5 * segment.length_m + (i + 0.5) * ds;  // midpoint rule
    const Eigen::Vector3d u =
        segment.velocity_center_W + s * segment.angular_velocity_W.cross(t);
    const Eigen::Vector3d f = DragPerLength(u, t, xi) * ds;
    wrench.force_W += f;
    wrench.torque_center_W += (s * t).cross(f);
  }
  return wrench;
}

double SegmentDragPower(const Segment& segment, const Wrench& wrench) {
  return wrench.force_W.dot(segment.velocity_center_W) +
         wrench.torque_center_W.dot(segment.angular_velocity_W);
}

std::unique_ptr<Fluid> RftDrag::Make(const mjModel* /*m*/, const RftDrag& segments,
                                     const RftDragOverrides& /*overrides*/) {
  return std::make_unique<RftDrag>(segments);
}

RftDrag::RftDrag(const mjModel* m, const RftDragConfig& config)
    : config_(config), coefficients_(config.Coefficients()) {
  config_.Validate();
  if (config_.geom_names.empty()) {
    for (int g = 0; g < m->ngeom; ++g) {
      if (m->geom_bodyid[g] != 0) AddGeom(m, g);
    }
  } else {
    for (const std::string& name : config_.geom_names) {
      const int g = mj_name2id(m, mjOBJ_GEOM, name.c_str());
      if (g < 0) {
        throw std::invalid_argument(std::string("rft drag: ") + kAttrGeoms + " names geom '" +
                                    name + "', which the model does not have");
      }
      AddGeom(m, g);
    }
  }
  if (config_.radius_from_geoms && !slender_.empty()) {
    double length_m = 0.0, radius_length_m2 = 0.0;
    for (const SlenderGeom& geom : slender_) {
      length_m += geom.length_m;
      radius_length_m2 += geom.radius_m * geom.length_m;
    }
    config_.equivalent_radius_m = radius_length_m2 / length_m;
    coefficients_ = config_.Coefficients();
  }
  for (const SlenderGeom& geom : slender_) {
    segment_coefficients_.push_back(SegmentCoefficients(geom));
  }
  if (!heads_.empty()) {
    mjData* d = mj_makeData(m);
    mj_kinematics(m, d);
    for (const HeadGeom& head : heads_) {
      const mjtNum* xmat = d->geom_xmat + 9 * head.geom_id;  // row-major: row 0 is x's
      for (int i = 0; i < 3; ++i) {
        heads_tow_N_s_m_ += head.principal.translation_N_s_m[i] * xmat[i] * xmat[i];
      }
    }
    mj_deleteData(d);
  }
  if (config_.model == CoefficientModel::kRibbon ||
      config_.model == CoefficientModel::kRibbonFitted) {
    // The plates' calibration in the model's reference pose (qpos0).
    mjData* d = mj_makeData(m);
    mj_kinematics(m, d);
    const std::vector<Segment> reference = Segments(m, d);
    mj_deleteData(d);
    segment_coefficients_ =
        PlateCalibratedCoefficients(config_.viscosity_Pa_s, reference, StripWidth_m(m));
    if (config_.model == CoefficientModel::kRibbonFitted) {
      segment_coefficients_ = FittedToPaperSwim(segment_coefficients_);
    }
    // coefficients(): the body's mean drag per length.
    double length_m = 0.0, broadside_N_s_m = 0.0, axial_N_s_m = 0.0;
    for (size_t i = 0; i < slender_.size(); ++i) {
      length_m += slender_[i].length_m;
      broadside_N_s_m += segment_coefficients_[i].normal_N_s_m2 * slender_[i].length_m;
      axial_N_s_m += segment_coefficients_[i].tangential_N_s_m2 * slender_[i].length_m;
    }
    coefficients_ = {broadside_N_s_m / length_m, axial_N_s_m / length_m};
  }
}

namespace {

std::string GeomName(const mjModel* m, int g) {
  const char* name = mj_id2name(m, mjOBJ_GEOM, g);
  return name ? "'" + std::string(name) + "'" : "#" + std::to_string(g);
}

const char* GeomKind(int type) {
  switch (type) {
    case mjGEOM_PLANE: return "plane";
    case mjGEOM_HFIELD: return "height field";
    case mjGEOM_SPHERE: return "sphere";
    case mjGEOM_CAPSULE: return "capsule";
    case mjGEOM_ELLIPSOID: return "ellipsoid";
    case mjGEOM_CYLINDER: return "cylinder";
    case mjGEOM_BOX: return "box";
    case mjGEOM_MESH: return "mesh";
    default: return "geom of another kind";
  }
}

}  // namespace

void RftDrag::AddGeom(const mjModel* m, int g) {
  const int type = m->geom_type[g];
  const mjtNum* size = m->geom_size + 3 * g;
  if (type == mjGEOM_SPHERE || type == mjGEOM_ELLIPSOID) {
    if (config_.model == CoefficientModel::kNearWall) {
      throw std::invalid_argument("rft drag: geom " + GeomName(m, g) + " is a " + GeomKind(type) +
                                  ", whose drag is known in free space only, not with " +
                                  kAttrCoefficients + " = near_wall");
    }
    const Eigen::Vector3d semi_axes_m = type == mjGEOM_SPHERE
                                            ? Eigen::Vector3d::Constant(size[0])
                                            : Eigen::Vector3d(size[0], size[1], size[2]);
    heads_.push_back({g, EllipsoidResistance(semi_axes_m, config_.viscosity_Pa_s)});
    return;
  }
  const int axis = SlenderAxis(m, g);
  if (axis < 0) {
    const std::string reason =
        type == mjGEOM_BOX
            ? "a box centred on its body with two equal longest sides, so no axis to lie along"
            : std::string("a ") + GeomKind(type) +
                  "; the fluid represents boxes, capsules, cylinders, spheres and ellipsoids "
                  "(list the geoms it acts on in " + kAttrGeoms + ")";
    throw std::invalid_argument("rft drag: geom " + GeomName(m, g) + " is " + reason);
  }
  const double radius_m = SlenderRadius_m(m, g, axis);
  if (config_.radius_from_geoms) config_.ValidateRadius(radius_m, "geom " + GeomName(m, g) + "'s radius");
  slender_.push_back({g, axis, SlenderLength_m(m, g, axis), radius_m});
  geom_ids_.push_back(g);
}

DragCoefficients RftDrag::SegmentCoefficients(const SlenderGeom& geom) const {
  return config_.radius_from_geoms ? config_.CoefficientsForRadius(geom.radius_m) : coefficients_;
}

std::vector<int> RftDrag::head_geom_ids() const {
  std::vector<int> ids;
  for (const HeadGeom& head : heads_) ids.push_back(head.geom_id);
  return ids;
}

Segment RftDrag::SegmentOf(const mjModel* m, const mjData* d, const SlenderGeom& geom) {
  const int body = m->geom_bodyid[geom.geom_id];
  const mjtNum* center = d->geom_xpos + 3 * geom.geom_id;
  const mjtNum* xmat = d->geom_xmat + 9 * geom.geom_id;  // row-major
  mjtNum velocity_W[3];
  PointVelocity_W(m, d, body, center, velocity_W);
  Segment segment;
  segment.center_W = Eigen::Vector3d(center);
  segment.tangent_W = Eigen::Vector3d(xmat[geom.axis], xmat[3 + geom.axis], xmat[6 + geom.axis]);
  segment.length_m = geom.length_m;
  segment.angular_velocity_W = Eigen::Vector3d(d->cvel + 6 * body);
  segment.velocity_center_W = Eigen::Vector3d(velocity_W);
  return segment;
}

std::vector<Segment> RftDrag::Segments(const mjModel* m, const mjData* d) const {
  std::vector<Segment> segments;
  segments.reserve(slender_.size());
  for (const SlenderGeom& geom : slender_) segments.push_back(SegmentOf(m, d, geom));
  return segments;
}

double RftDrag::DissipatedPower_W(const mjModel* m, const mjData* d) const {
  double power_W = 0.0;
  for (size_t i = 0; i < slender_.size(); ++i) {
    const Segment segment = SegmentOf(m, d, slender_[i]);
    power_W -= SegmentDragPower(segment, SegmentDragExact(segment, segment_coefficients_[i]));
  }
  for (const HeadGeom& head : heads_) {
    const BodyResistanceBlock<6> block = HeadResistanceOf(m, d, head);
    const Eigen::Map<const Vector6> velocity(d->cvel + 6 * block.body);
    power_W += velocity.dot(block.resistance * velocity);
  }
  return power_W;
}

double RftDrag::TowingDrag_N(double speed_m_s) const {
  double drag_N = 0.0;
  for (size_t i = 0; i < slender_.size(); ++i) {
    Segment segment;
    segment.center_W = Eigen::Vector3d::Zero();
    segment.tangent_W = Eigen::Vector3d::UnitX();
    segment.length_m = slender_[i].length_m;
    segment.velocity_center_W = Eigen::Vector3d(speed_m_s, 0.0, 0.0);
    segment.angular_velocity_W = Eigen::Vector3d::Zero();
    drag_N -= SegmentDragExact(segment, segment_coefficients_[i]).force_W.x();
  }
  return drag_N + heads_tow_N_s_m_ * speed_m_s;
}

std::vector<double> RftDrag::SegmentLengths_m() const {
  std::vector<double> lengths;
  for (const SlenderGeom& geom : slender_) lengths.push_back(geom.length_m);
  return lengths;
}

double RftDrag::RotationalDragScale_N_m_s() const {
  double length = 0.0;
  for (const SlenderGeom& geom : slender_) length += geom.length_m;
  return coefficients_.normal_N_s_m2 * length * length * length / 3.0;
}

// The spatial resistance (or its planar block) of one slender geom at the
// subtree centre of mass of its body's root (where MuJoCo gives cdof and
// cvel).
template <int Dim>
BodyResistanceBlock<Dim> RftDrag::ResistanceOf(const mjModel* m, const mjData* d,
                                                const SlenderGeom& geom,
                                                const DragCoefficients& xi) const {
  const int body = m->geom_bodyid[geom.geom_id];
  const mjtNum* xmat = d->geom_xmat + 9 * geom.geom_id;  // row-major
  const Eigen::Vector3d tangent(xmat[geom.axis], xmat[3 + geom.axis], xmat[6 + geom.axis]);
  const Eigen::Vector3d center(d->geom_xpos + 3 * geom.geom_id);
  const Eigen::Vector3d c(d->subtree_com + 3 * m->body_rootid[body]);
  if constexpr (Dim == 6) {
    return {body, SegmentResistance(center, tangent, geom.length_m, c, xi)};
  } else {
    return {body, SegmentPlanarResistance(center, tangent, geom.length_m, c, xi)};
  }
}

BodyResistanceBlock<6> RftDrag::HeadResistanceOf(const mjModel* m, const mjData* d,
                                                 const HeadGeom& head) {
  const int body = m->geom_bodyid[head.geom_id];
  const mjtNum* x = d->geom_xmat + 9 * head.geom_id;  // row-major; columns: the local axes
  Eigen::Matrix3d axes;
  axes << x[0], x[1], x[2], x[3], x[4], x[5], x[6], x[7], x[8];
  const Eigen::Vector3d center(d->geom_xpos + 3 * head.geom_id);
  const Eigen::Vector3d c(d->subtree_com + 3 * m->body_rootid[body]);
  return {body, PrincipalResistanceAbout(head.principal, center, axes, c)};
}

template <int Dim>
void RftDrag::Resistances(const mjModel* m, const mjData* d,
                          BodyResistanceBlocks<Dim>* out) const {
  out->clear();
  for (size_t i = 0; i < slender_.size(); ++i) {
    out->push_back(ResistanceOf<Dim>(m, d, slender_[i], segment_coefficients_[i]));
  }
  for (const HeadGeom& head : heads_) {
    const BodyResistanceBlock<6> block = HeadResistanceOf(m, d, head);
    if constexpr (Dim == 6) {
      out->push_back(block);
    } else {
      // [w_z; v_x; v_y]: rows and columns 2 to 4.
      out->push_back({block.body, block.resistance.template block<3, 3>(2, 2)});
    }
  }
}
template void RftDrag::Resistances<6>(const mjModel*, const mjData*,
                                      BodyResistanceBlocks<6>*) const;
template void RftDrag::Resistances<3>(const mjModel*, const mjData*,
                                      BodyResistanceBlocks<3>*) const;

// J^T of every segment's wrench in one pass over the tree, what
// mj_applyFT computes one wrench at a time (through a Jacobian per
// segment). MuJoCo's dof motions cdof = [w_j; v_j] are given at the
// subtree centre of mass c of each body's root, as is the body's spatial
// velocity cvel = [w; v]; the drag wrench at c is -S cvel (S from
// SegmentResistance), and the generalised force of dof j is
// cdof_j . (the sum of the wrenches on the subtree of its body), summed
// leaf to root.
void RftDrag::Apply(const mjModel* m, mjData* d) const {
  mjMARKSTACK
  mjtNum* wrench_c = mj_stackAlloc(d, 6 * m->nbody);  // [torque; force] at c, per body
  mju_zero(wrench_c, 6 * m->nbody);
  for (size_t i = 0; i < slender_.size(); ++i) {
    const BodyResistanceBlock<6> segment =
        ResistanceOf<6>(m, d, slender_[i], segment_coefficients_[i]);
    Eigen::Map<Vector6> target(wrench_c + 6 * segment.body);
    target.noalias() -= segment.resistance *
                        Eigen::Map<const Vector6>(d->cvel + 6 * segment.body);
  }
  for (const HeadGeom& head : heads_) {
    const BodyResistanceBlock<6> block = HeadResistanceOf(m, d, head);
    Eigen::Map<Vector6> target(wrench_c + 6 * block.body);
    target.noalias() -= block.resistance * Eigen::Map<const Vector6>(d->cvel + 6 * block.body);
  }
  // Bodies are numbered parents first; a tree's wrenches stop at its root.
  for (int body = m->nbody - 1; body > 0; --body) {
    const int parent = m->body_parentid[body];
    if (parent == 0 || m->body_rootid[parent] != m->body_rootid[body]) continue;
    for (int i = 0; i < 6; ++i) wrench_c[6 * parent + i] += wrench_c[6 * body + i];
  }
  for (int dof = 0; dof < m->nv; ++dof) {
    d->qfrc_passive[dof] += mju_dot(d->cdof + 6 * dof, wrench_c + 6 * m->dof_bodyid[dof], 6);
  }
  mjFREESTACK
}

double StripWidth_m(const mjModel* m) {
  if (const std::optional<double> width = FindCustomScalar(m, kStripWidthField)) return *width;
  const std::optional<double> radius_m = FindCustomScalar(m, kAttrEquivalentRadius);
  return 2.0 * radius_m.value_or(RftDragConfig().equivalent_radius_m);
}

}  // namespace ipmc
