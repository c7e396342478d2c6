// The fluid model the body's segments feel: the one place the drag
// callback (mjcb_passive, inertial dynamics), the Stokes stepper
// (plugin/fluid/stokes_step.h) and the energy terms ask for the segments'
// forces and resistance.
//
//   rft         resistive-force theory (plugin/fluid/rft_drag.h): each
//               segment's resistance is its own (local), a 6 x 6 block per
//               segment; the numbers are RftDrag's, unchanged.
//   stokeslets  regularized Stokeslets (plugin/fluid/regularized_stokeslets.h)
//               at points along each segment's centreline, spaced
//               `spacing_m` (default the blob), blob eps (default
//               sqrt(e) a, a RFT's equivalent radius), or, with
//               `width_points` k > 1, on a sheet across the strip's width
//               w (along z): a grid w / k apart, blob 0.7 w / k; with the image
//               system of a no-slip wall z = -h when a wall distance h is
//               set: the centreline is then h above the wall, which is
//               parallel to the plane z = 0 the generated models beat and
//               swim in. Every segment's velocity moves every other
//               segment (hydrodynamic interaction): the resistance is one
//               dense 6B x 6B matrix over the segments' B bodies.
//
// The Stokeslet resistance depends on the body's shape only (a rigid
// motion in the plane z = 0, the generated models' root joints, is a
// symmetry of free space and of the wall), so it is computed in the root
// body's frame and kept until a joint (any but the root body's) has moved
// more than `shape_tolerance_rad` from the shape it was computed at
// (docs/FLUIDS.md measures the tolerance's effect on the swim).
#pragma once

#include <mujoco/mujoco.h>

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "plugin/fluid/regularized_stokeslets.h"
#include "plugin/fluid/rft_drag.h"

namespace ipmc {

enum class FluidModelKind { kRft, kStokeslets };
// "rft" or "stokeslets"; throws std::invalid_argument naming the allowed set.
FluidModelKind ParseFluidModelKind(const std::string& text);

class FluidModel {
 public:
  // rft's geoms, viscosity and equivalent radius are the model's; with
  // kStokeslets `stokeslets` sets the points (0 fields: the defaults
  // above). Throws std::invalid_argument on bad settings.
  FluidModel(const mjModel* m, const RftDrag& rft, const StokesletSettings& stokeslets);
  explicit FluidModel(const RftDrag& rft);  // the RFT model

  FluidModelKind kind() const { return kind_; }
  const RftDrag& rft() const { return rft_; }
  // True if the segments interact (stokeslets): use BodyResistance.
  bool nonlocal() const { return kind_ == FluidModelKind::kStokeslets; }

  // Adds the drag into d->qfrc_passive (positions and velocities from d).
  void Apply(const mjModel* m, mjData* d) const;
  // rft: the segments' own resistances (RftDrag::Resistances), whole or
  // their planar blocks.
  template <int Dim>  // 6 or 3
  void LocalResistances(const mjModel* m, const mjData* d,
                        RftDrag::BodyResistanceBlocks<Dim>* out) const {
    rft_.Resistances(m, d, out);
  }
  // stokeslets: the resistance R over bodies() about the subtree centre of
  // mass of the root (where MuJoCo gives cdof and cvel), world frame, from
  // d's positions (after mj_comPos): the drag wrenches [torque; force] of
  // the bodies are -R [w; v] of their spatial velocities.
  const Eigen::MatrixXd& BodyResistance(const mjModel* m, const mjData* d) const;
  const std::vector<int>& bodies() const { return bodies_; }
  // The power the body loses to the fluid [W], never negative: stokeslets
  // with the resistance last computed (the cache is not refreshed, so a
  // measurement does not change the run).
  double DissipatedPower_W(const mjModel* m, const mjData* d) const;
  // The drag [N] on the body laid straight along x and towed along it.
  double TowingDrag_N(double speed_m_s) const;
  // Stokeslet resistances computed so far (the cache's misses).
  int recomputations() const { return recomputations_; }
  // The Stokeslets' settings, defaults filled in.
  const StokesletSettings& settings() const { return settings_; }
  double blob_m() const { return settings_.blob_m; }
  double spacing_m() const { return settings_.spacing_m; }
  int points() const { return points_; }

 private:
  // The points of a straight segment (the centreline, or the sheet across
  // the width).
  PointList Points(const Eigen::Vector3d& center, const Eigen::Vector3d& tangent,
                   double length_m) const;
  // R about the root body's origin in its frame for the current shape.
  void Recompute(const mjModel* m, const mjData* d) const;
  // The cached R, in the world frame about the subtree centre of mass.
  const Eigen::MatrixXd& WorldResistance(const mjData* d) const;
  // The generalised force of body wrenches W (6 per body of bodies_).
  void AddBodyWrenches(const mjModel* m, const mjData* d, const Eigen::VectorXd& wrench,
                       mjtNum* qfrc) const;
  Eigen::VectorXd BodyVelocities(const mjModel* m, const mjData* d) const;

  FluidModelKind kind_ = FluidModelKind::kRft;
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
