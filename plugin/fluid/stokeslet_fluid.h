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
// The resistance depends on the body's shape only (a rigid motion in the
// plane z = 0, the generated models' root joints, is a symmetry of free
// space and of the wall), so it is computed in the root body's frame and
// kept until a joint (any but the root body's) has moved more than
// `shape_tolerance_rad` from the shape it was computed at (docs/FLUIDS.md
// measures the tolerance's effect on the swim).
//
// Settings: the program's (RftDragOverrides::stokeslets, from the scenario's
// fluid.stokeslet_* keys); the defaults come from the model's <custom>
// fields ipmc_strip_width_m and ipmc_rft_equivalent_radius_m.
#pragma once

#include <mujoco/mujoco.h>

#include <Eigen/Core>
#include <memory>
#include <vector>

#include "plugin/fluid/fluid_model.h"
#include "plugin/fluid/regularized_stokeslets.h"
#include "plugin/fluid/rft_drag.h"

namespace ipmc {

// `given` with its 0 fields filled from the model (the strip's width) and
// the segments (RFT's equivalent radius), checked. Throws
// std::invalid_argument naming the setting.
StokesletSettings StokesletSettingsFromModel(const mjModel* m, const RftDrag& segments,
                                             StokesletSettings given);

class StokesletFluid : public Fluid {
 public:
  // The segments' geoms, viscosity and equivalent radius are `segments`'
  // (the model's RFT fields); `stokeslets` sets the points (0 fields: the
  // defaults, StokesletSettingsFromModel). Throws std::invalid_argument on
  // bad settings.
  StokesletFluid(const mjModel* m, const RftDrag& segments, const StokesletSettings& stokeslets);
  // The registry's entry (fluid_model.h): chosen when the overrides carry
  // Stokeslet settings.
  static bool Chosen(const RftDrag& segments, const RftDragOverrides& overrides);
  static std::unique_ptr<Fluid> Make(const mjModel* m, const RftDrag& segments,
                                     const RftDragOverrides& overrides);

  void Apply(const mjModel* m, mjData* d) const override;
  // With the resistance last computed (the cache is not refreshed, so a
  // measurement does not change the run).
  double DissipatedPower_W(const mjModel* m, const mjData* d) const override;
  double TowingDrag_N(double speed_m_s) const override;
  // The resistance R over InteractingBodies() (see Fluid), the cached one
  // while the shape has moved less than the tolerance.
  const Eigen::MatrixXd* InteractionResistance(const mjModel* m, const mjData* d) const override;
  const std::vector<int>& InteractingBodies() const override { return bodies_; }
  const Eigen::MatrixXd& BodyResistance(const mjModel* m, const mjData* d) const {
    return *InteractionResistance(m, d);
  }

  const RftDrag& rft() const { return rft_; }
  // Resistances computed so far (the cache's misses).
  int recomputations() const { return recomputations_; }
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
  // R about the root body's origin in its frame for the current shape.
  void Recompute(const mjModel* m, const mjData* d) const;
  // The cached R, in the world frame about the subtree centre of mass.
  const Eigen::MatrixXd& WorldResistance(const mjData* d) const;
  // The generalised force of body wrenches W (6 per body of bodies_).
  void AddBodyWrenches(const mjModel* m, const mjData* d, const Eigen::VectorXd& wrench,
                       mjtNum* qfrc) const;
  Eigen::VectorXd BodyVelocities(const mjData* d) const;

  RftDrag rft_;
  StokesletSettings settings_;
  std::vector<int> bodies_;        // distinct bodies of the slender geoms
  std::vector<int> body_of_geom_;  // index into bodies_, per rft_ geom
  std::vector<int> shape_joints_;  // qpos addresses of the non-root hinges and slides
  int root_body_ = -1;
  mutable int points_ = 0;
  mutable std::vector<double> cached_shape_;
  mutable Eigen::MatrixXd root_resistance_;  // about the root's origin, root frame
  mutable Eigen::MatrixXd world_resistance_;
  mutable int recomputations_ = 0;
};

}  // namespace ipmc
