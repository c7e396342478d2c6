// The regularized-Stokeslet fluid model (plugin/fluid/regularized_stokeslets.h
// has the kernel): points along each segment's centreline, spaced
// `spacing_m` (default the blob), blob eps (default sqrt(e) a, a RFT's
// equivalent radius), or, with `width_points` k > 1, on a sheet across the
// strip's width w (along z): a grid w / k apart, blob 0.7 w / k; with the
// image system of a no-slip wall z = -h when a wall distance h is set: the
// centreline is then h above the wall, which is parallel to the plane
// z = 0 the generated models beat and swim in. Every segment's velocity
// moves every other segment (hydrodynamic interaction): the resistance is
// one dense 6B x 6B matrix over the segments' B bodies.
//
// The resistance is kept while the shape moves less than
// `shape_tolerance_rad`, and extrapolated along the secant of the last two
// within `secant_reach_rad` or fitted in time within `fit_tolerance`
// (plugin/fluid/dense_resistance_fluid.h).
//
// Settings: the model's <custom> fields ipmc_fluid_stokeslet_* and the
// program's overrides of them (the scenario's fluid.stokeslet_* keys); the
// defaults come from the model's ipmc_strip_width_m and
// ipmc_rft_equivalent_radius_m.
#pragma once

#include <mujoco/mujoco.h>

#include <Eigen/Core>
#include <memory>
#include <vector>

#include "plugin/fluid/dense_resistance_fluid.h"
#include "plugin/fluid/regularized_stokeslets.h"
#include "plugin/fluid/rft_drag.h"

namespace ipmc {

// `given` with its 0 fields filled from the model (the strip's width) and
// the segments (RFT's equivalent radius), checked. Throws
// std::invalid_argument naming the setting.
StokesletSettings StokesletSettingsFromModel(const mjModel* m, const RftDrag& segments,
                                             StokesletSettings given);

class StokesletFluid : public DenseResistanceFluid {
 public:
  // The segments' geoms, viscosity and equivalent radius are `segments`'
  // (the model's RFT fields); `stokeslets` sets the points (0 fields: the
  // defaults, StokesletSettingsFromModel). Throws std::invalid_argument on
  // bad settings.
  StokesletFluid(const mjModel* m, const RftDrag& segments, const StokesletSettings& stokeslets);
  // The registry's entry (fluid_model.h): the settings' parameters
  // (ipmc_fluid_stokeslet_* fields, fluid.stokeslet_* keys), the model they
  // set, with the wall of the segments' near-wall coefficients, and its
  // points.
  static constexpr char kSummary[] =
      "regularized Stokeslets along the segments' centrelines (or on a sheet across the "
      "width), whose segments interact, with a wall's image system";
  static std::vector<FluidParameter> Parameters();
  static std::unique_ptr<Fluid> Make(const mjModel* m, const RftDrag& segments,
                                     const RftDragOverrides& overrides);
  static double ForcePoints(const mjModel* m, const RftDrag& segments,
                            const RftDragOverrides& overrides);

  double TowingDrag_N(double speed_m_s) const override;
  const Eigen::MatrixXd& BodyResistance(const mjModel* m, const mjData* d) const {
    return *InteractionResistance(m, d);
  }

  // The settings, defaults filled in.
  const StokesletSettings& settings() const { return settings_; }
  double blob_m() const { return settings_.blob_m; }
  double spacing_m() const { return settings_.spacing_m; }
  int points() const { return points_; }

 private:
  // The points of a straight segment (the centreline, or the sheet across
  // the width).
  PointList Points(const Eigen::Vector3d& center, const Eigen::Vector3d& tangent,
                   double length_m) const;
  StokesletGeometry Geometry() const;
  Eigen::MatrixXd ComputeResistance(const mjModel* m, const mjData* d,
                                    const Eigen::Vector3d& origin_W) const override;
  double shape_tolerance_rad() const override { return settings_.shape_tolerance_rad; }
  double secant_reach_rad() const override { return settings_.secant_reach_rad; }
  double fit_tolerance() const override { return settings_.fit_tolerance; }

  StokesletSettings settings_;
  mutable int points_ = 0;
};

}  // namespace ipmc
