#include "plugin/fluid/stokeslet_fluid.h"

#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>

namespace ipmc {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

void RequirePositive(double value, const char* what) {
  if (!(value > 0.0) || !std::isfinite(value)) {
    std::ostringstream msg;
    msg << "stokeslet fluid: " << what << " must be finite and > 0 (got " << value << ")";
    throw std::invalid_argument(msg.str());
  }
}

// A blob or point spacing longer than the body resolves nothing of it
// (and a huge blob overflows the kernel's eps^2).
void RequireWithinBody(double value_m, const char* what, const char* field, double body_m) {
  if (value_m > body_m) {
    std::ostringstream msg;
    msg << "stokeslet fluid: " << what << " (" << field << ") must be at most the body's length "
        << body_m << " m (got " << value_m << " m)";
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
  double body_m = 0.0;
  for (double length_m : segments.SegmentLengths_m()) body_m += length_m;
  RequireWithinBody(settings.blob_m, "the blob", "ipmc_fluid_stokeslet_blob_m", body_m);
  RequireWithinBody(settings.spacing_m, "the point spacing", "ipmc_fluid_stokeslet_points_per_m",
                    body_m);
  if (!(settings.shape_tolerance_rad >= 0.0) || !std::isfinite(settings.shape_tolerance_rad)) {
    throw std::invalid_argument("stokeslet fluid: the shape tolerance must be finite and >= 0");
  }
  if (!(settings.secant_reach_rad >= 0.0) || !std::isfinite(settings.secant_reach_rad)) {
    throw std::invalid_argument("stokeslet fluid: the secant's reach must be finite and >= 0");
  }
  if (!(settings.fit_tolerance >= 0.0) || !std::isfinite(settings.fit_tolerance)) {
    throw std::invalid_argument("stokeslet fluid: the fit's tolerance must be finite and >= 0");
  }
  if (settings.wall_distance_m) RequirePositive(*settings.wall_distance_m, "the wall distance");
  return settings;
}

namespace {

// The parameters (FluidParameter, fluid_model.h).
FluidParameter WidthPoints() {
  return SetsResolution(IntegerParameter(
      "stokeslet_width_points", "ipmc_fluid_stokeslet_width_points", 1, 1, kMaxWidthPoints, 4,
      "Stokeslet points across the strip's width (ipmc_strip_width_m): 1 puts them on the "
      "centreline; k > 1 makes the strip a sheet, a square grid w / k apart with the blob "
      "0.7 w / k (docs/FLUIDS.md, \"Ribbon calibration\")"));
}

FluidParameter PointsPerMm() {
  return SetsResolution(NumberParameter(
      "stokeslet_points_per_mm", "ipmc_fluid_stokeslet_points_per_m", "1/mm", 1e3, kNaN,
      "one per blob (1 / fluid.stokeslet_blob_mm)", 0.0, false, 2.0,
      "Stokeslet points per mm along each segment's centreline (each segment gets the "
      "smallest whole number of equal intervals at least this dense)"));
}

FluidParameter BlobMm() {
  return SetsResolution(NumberParameter(
      "stokeslet_blob_mm", "ipmc_fluid_stokeslet_blob_m", "mm", 1e-3, kNaN,
      "sqrt(e) a = 1.340 mm for the paper's strip (a the RFT equivalent radius)", 0.0, false,
      1.0,
      "Blob size eps of the regularized Stokeslets; sqrt(e) a makes the line of points the "
      "slender cylinder of radius a"));
}

// The Stokeslet resistance's cache parameters (dense_resistance_fluid.h).
const CacheParameters& Cache() {
  static const CacheParameters cache("stokeslet", "the Stokeslet resistance",
                                     "Stokeslet resolution, blob and the cached resistance");
  return cache;
}

// The settings the parameters give, defaults filled in and checked.
StokesletSettings SettingsFromParameters(const mjModel* m, const RftDrag& segments,
                                         const RftDragOverrides& overrides) {
  const auto value = [&](const FluidParameter& p) {
    return FluidParameterValue(m, overrides, "stokeslet fluid", p);
  };
  StokesletSettings settings;
  settings.width_points = static_cast<int>(*value(WidthPoints()));
  if (const std::optional<double> per_m = value(PointsPerMm())) settings.spacing_m = 1.0 / *per_m;
  settings.blob_m = value(BlobMm()).value_or(0.0);
  settings.shape_tolerance_rad = *value(Cache().ShapeToleranceRad());
  settings.secant_reach_rad = *value(Cache().SecantReachRad());
  settings.fit_tolerance = *value(Cache().FitTolerance());
  settings.wall_distance_m = WallDistance_m(segments);
  return StokesletSettingsFromModel(m, segments, settings);
}

}  // namespace

std::vector<FluidParameter> StokesletFluid::Parameters() {
  return {WidthPoints(), PointsPerMm(), BlobMm(), Cache().ShapeToleranceRad(),
          Cache().SecantReachRad(), Cache().FitTolerance()};
}

std::unique_ptr<Fluid> StokesletFluid::Make(const mjModel* m, const RftDrag& segments,
                                            const RftDragOverrides& overrides) {
  return std::make_unique<StokesletFluid>(m, segments,
                                          SettingsFromParameters(m, segments, overrides));
}

double StokesletFluid::ForcePoints(const mjModel* m, const RftDrag& segments,
                                   const RftDragOverrides& overrides) {
  const StokesletSettings settings = SettingsFromParameters(m, segments, overrides);
  double points = 0.0;
  for (double length_m : segments.SegmentLengths_m()) {
    points += SegmentIntervals(length_m, settings.spacing_m) * settings.width_points;
  }
  return points;
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
