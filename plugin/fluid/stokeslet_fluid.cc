#include "plugin/fluid/stokeslet_fluid.h"

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

namespace ipmc {
namespace {

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
    : DenseResistanceFluid(m, segments, "stokeslet fluid"),
      settings_(StokesletSettingsFromModel(m, segments, stokeslets)) {}

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

Eigen::MatrixXd StokesletFluid::ComputeResistance(const mjModel* m, const mjData* d,
                                                  const Eigen::Vector3d& origin_W) const {
  const std::vector<Segment> segments = rft().Segments(m, d);
  PointList points;
  std::vector<int> body_of_point;
  for (size_t i = 0; i < segments.size(); ++i) {
    const PointList along =
        Points(segments[i].center_W, segments[i].tangent_W, segments[i].length_m);
    points.insert(points.end(), along.begin(), along.end());
    body_of_point.insert(body_of_point.end(), along.size(), body_of_geom(static_cast<int>(i)));
  }
  points_ = static_cast<int>(points.size());
  return RigidBodyResistance(points, body_of_point, body_count(), origin_W, Geometry(),
                             rft().config().viscosity_Pa_s);
}

double StokesletFluid::TowingDrag_N(double speed_m_s) const {
  // The segments end to end along x at z = 0, every point moving at U x.
  PointList points;
  double start_m = 0.0;
  for (double length_m : rft().SegmentLengths_m()) {
    const PointList along =
        Points(Eigen::Vector3d(start_m + 0.5 * length_m, 0, 0), Eigen::Vector3d::UnitX(), length_m);
    points.insert(points.end(), along.begin(), along.end());
    start_m += length_m;
  }
  const MobilitySolver solver(StokesletMobility(points, Geometry(), rft().config().viscosity_Pa_s));
  const Eigen::VectorXd f = solver.Forces(
      Eigen::Vector3d(speed_m_s, 0, 0).replicate(static_cast<int>(points.size()), 1));
  double drag_N = 0.0;
  for (size_t k = 0; k < points.size(); ++k) drag_N += f[3 * k];
  return drag_N;
}

}  // namespace ipmc
