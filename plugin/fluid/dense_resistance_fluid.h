// The common part of the fluid models whose segments interact through the
// fluid (regularized Stokeslets, slender-ribbon theory, flat plates): one
// dense resistance R over the segments' bodies, 6 per body ([w; v] about
// the subtree centre of mass of the root, world frame; the bodies' drag
// wrenches are -R V of their velocities V).
//
// The resistance depends on the body's shape only (a rigid motion in the
// plane z = 0, the generated models' root joints, is a symmetry of free
// space and of a wall parallel to it), so it is kept in the root body's
// frame about the root's origin and recomputed (ComputeResistance) only
// when a joint below the root has moved more than the shape tolerance
// since it was last computed. docs/FLUIDS.md measures the tolerance's
// effect on the swim.
#pragma once

#include <mujoco/mujoco.h>

#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

#include "plugin/fluid/fluid_model.h"

namespace ipmc {

class RftDrag;

class DenseResistanceFluid : public Fluid {
 public:
  ~DenseResistanceFluid() override;

  void Apply(const mjModel* m, mjData* d) const override;
  // With the resistance last computed (the cache is not refreshed, so a
  // measurement does not change the run).
  double DissipatedPower_W(const mjModel* m, const mjData* d) const override;
  // The resistance R over InteractingBodies() (see Fluid), the cached one
  // while the shape has moved less than the tolerance.
  const Eigen::MatrixXd* InteractionResistance(const mjModel* m, const mjData* d) const override;
  const std::vector<int>& InteractingBodies() const override { return bodies_; }
  // The segments' (rft()'s): their lengths, the model's viscosity and
  // density, and RFT's rotational drag scale over them.
  std::vector<double> SegmentLengths_m() const override;
  double Viscosity_Pa_s() const override;
  double FluidDensity_kg_m3() const override;
  double RotationalDragScale_N_m_s() const override;

  // The segments' geoms, viscosity and coefficients (the model's RFT fields).
  const RftDrag& rft() const { return *rft_; }
  // Resistances computed so far (the cache's misses).
  int recomputations() const { return recomputations_; }

 protected:
  // `name` starts the error messages ("stokeslet fluid"). Throws
  // std::invalid_argument if the segments are not on one tree of bodies
  // moved by hinges and slides below its root.
  DenseResistanceFluid(const mjModel* m, const RftDrag& segments, const std::string& name);

  // R in the world frame about the root body's origin `origin_W`, for d's
  // positions; 6 rows and columns per body of InteractingBodies().
  // Symmetric (the reciprocal theorem).
  virtual Eigen::MatrixXd ComputeResistance(const mjModel* m, const mjData* d,
                                            const Eigen::Vector3d& origin_W) const = 0;
  virtual double shape_tolerance_rad() const = 0;
  // Index into InteractingBodies() of rft()'s geom g (in geom_ids() order).
  int body_of_geom(int g) const { return body_of_geom_[g]; }
  int body_count() const { return static_cast<int>(bodies_.size()); }

 private:
  void Recompute(const mjModel* m, const mjData* d) const;
  // The cached R, in the world frame about the subtree centre of mass.
  const Eigen::MatrixXd& WorldResistance(const mjData* d) const;
  // The generalised force of body wrenches W (6 per body of bodies_).
  void AddBodyWrenches(const mjModel* m, const mjData* d, const Eigen::VectorXd& wrench,
                       mjtNum* qfrc) const;
  Eigen::VectorXd BodyVelocities(const mjData* d) const;

  std::unique_ptr<const RftDrag> rft_;  // by pointer: rft_drag.h includes the models' headers
  std::vector<int> bodies_;        // distinct bodies of the slender geoms
  std::vector<int> body_of_geom_;  // index into bodies_, per rft_ geom
  std::vector<int> shape_joints_;  // qpos addresses of the non-root hinges and slides
  int root_body_ = -1;
  mutable std::vector<double> cached_shape_;
  mutable Eigen::MatrixXd root_resistance_;  // about the root's origin, root frame
  mutable Eigen::MatrixXd world_resistance_;
  mutable int recomputations_ = 0;
  // What world_resistance_ was made from: the root's rotation and offset
  // from the subtree centre of mass, and root_resistance_'s recomputation.
  // A further evaluation of the same state (within a step, or by a meter
  // after it) reuses it.
  mutable Eigen::Matrix3d world_rotation_;
  mutable Eigen::Vector3d world_offset_;
  mutable int world_of_recomputation_ = -1;
};

}  // namespace ipmc
