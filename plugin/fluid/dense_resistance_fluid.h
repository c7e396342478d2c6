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
//
// With a secant reach r > 0, beyond the last exact evaluation the
// resistance is extrapolated along the secant of the last two, at the
// shapes q_a and q_b (the joints' angles and slides):
//   R(q) = R_b + alpha (R_b - R_a),  alpha = (q - q_b).(q_b - q_a) / |q_b - q_a|^2,
// as long as no joint is more than r from q_b and the motion off the
// secant, |q - q_b - alpha (q_b - q_a)| (max over the joints), is within
// 0.05 r; otherwise the shape tolerance decides as above. The error is
// second order in r (the cached R's is first order in the tolerance): at
// r = 1e-3 rad the swim of the paper's strip with flexible links is within
// 0.1 % of the exact evaluation's (docs/FLUIDS.md, "Cost on flexible
// links"). A shape tolerance of 0 computes every evaluation exactly,
// whatever the reach.
//
// With a fit tolerance e > 0, once four exact evaluations at increasing
// times t_0 > t_1 > t_2 > t_3 (newest first) are at hand, the resistance
// between exact evaluations is its local part L(q), RFT's resistance of
// each body's own segments at the shape q of the moment, plus R - L
// following the cubic through the four evaluations' R - L in time
// (Newton's divided differences): L takes the fast part of the segments'
// turning, which the hinges' closed-loop motion puts in on a scale of tens
// of milliseconds, so the cubic follows what the segments' interactions
// add, a smoother function of time. For t up to an interval h past t_0 and
// while no joint is more than the shape tolerance off the same cubic
// through the shapes (a run that jumps, or goes back in time, evaluates
// exactly). At each exact evaluation the fit's error there is measured,
//   err = max_ij |R_fit,ij - R_ij| / (T s_i s_j)  (L cancels),
// T the largest translational diagonal entry of R, s_i = 1 for a
// velocity and L, the body's length, for a rotation, and, as it is fourth
// order in the interval, the next interval is
// h' = min(2 max(h, tau), 0.9 tau (e / err)^(1/4)), tau the time since the
// last exact evaluation; the first interval is the last spacing of the
// four. Until there are four, every evaluation is exact. docs/FLUIDS.md,
// "Cost on flexible links", measures the fit against the exact evaluation:
// at e = 1e-4 the swim and the fluid power of the paper's strip with
// flexible links are within 0.1 % of it (0.04 % at 16 sub-segments).
//
// The cache belongs to the fluid, not to an mjData: a copy of the data
// (mj_copyData) that goes its own way gets a resistance within the
// tolerances of the exact one at its own shape, made from whichever exact
// evaluations came before, so not bit for bit the one the original would
// have had; with the shape tolerance 0 it is.
#pragma once

#include <mujoco/mujoco.h>

#include <Eigen/Core>
#include <array>
#include <memory>
#include <string>
#include <vector>

#include "plugin/fluid/fluid_model.h"
#include "plugin/mjcf/spatial_algebra.h"

namespace ipmc {

// The secant's reach by default [rad]: none, the cached resistance as it
// is (docs/FLUIDS.md, "Cost on flexible links", measures the secant).
constexpr double kDefaultSecantReachRad = 0.0;
// The fit's tolerance by default: the paper's strip swims, rigid or
// flexible, within 0.1 % of the exact evaluation at every step, its fluid
// power within 0.002 % (docs/FLUIDS.md, "Cost on flexible links", measures
// it, and a small-stroke strip where it errs more).
constexpr double kDefaultFitTolerance = 1e-4;

class RftDrag;

// The two parameters of a dense model's cached resistance (FluidParameter,
// fluid_model.h), under the model's name: `<model>_shape_tolerance_rad`
// `<model>_secant_reach_rad` and `<model>_fit_tolerance` (fields
// ipmc_fluid_<model>_...), their
// help naming the model's `resistance` ("the ribbon's resistance") and
// docs/FLUIDS.md's `section` on the tolerance. Owns the texts the
// parameters point to: keep it for as long as they are used (a static
// const of the model's registry entry).
class CacheParameters {
 public:
  CacheParameters(const std::string& model, const std::string& resistance,
                  const std::string& section);
  FluidParameter ShapeToleranceRad() const;
  FluidParameter SecantReachRad() const;
  FluidParameter FitTolerance() const;

 private:
  std::string tolerance_key_, tolerance_field_, tolerance_meaning_;
  std::string reach_key_, reach_field_, reach_meaning_;
  std::string fit_key_, fit_field_, fit_meaning_;
};

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
  // The same, in the root body's frame about its origin (the cache's own;
  // no change of frame on the whole matrix), its version bumped whenever
  // the cached resistance changes.
  const Eigen::MatrixXd* FrameResistance(const mjModel* m, const mjData* d,
                                         Eigen::Matrix<double, 6, 6>* frame,
                                         long* version) const override;
  // While the fit in time serves d's shape: its cubic, in FrameResistance's
  // frame (the Stokes step sums its own sums of the four coefficients).
  bool FrameResistanceCubic(const mjModel* m, const mjData* d, Eigen::Matrix<double, 6, 6>* frame,
                            ResistanceCubic* cubic) const override;
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
  // Evaluations served by the secant between exact ones.
  int extrapolations() const { return extrapolations_; }
  // Evaluations served by the fit in time between exact ones.
  int fits() const { return fits_; }
  // The fit's error measured at the last exact evaluation (0: none yet).
  double last_fit_error() const { return last_fit_error_; }

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
  // The same when only its in-plane part [w_z; v_x; v_y] can act (every
  // joint of d planar): a model may then leave the rows and columns of
  // the out-of-plane motions zero and say so in *out_of_plane_left_out.
  // By default the whole R.
  virtual Eigen::MatrixXd ComputeInPlaneResistance(const mjModel* m, const mjData* d,
                                                   const Eigen::Vector3d& origin_W,
                                                   bool* out_of_plane_left_out) const;
  virtual double shape_tolerance_rad() const = 0;
  // 0: the cached resistance is used as it is (no secant).
  virtual double secant_reach_rad() const = 0;
  // 0: no fit in time.
  virtual double fit_tolerance() const = 0;
  // Index into InteractingBodies() of rft()'s geom g (in geom_ids() order).
  int body_of_geom(int g) const { return body_of_geom_[g]; }
  int body_count() const { return static_cast<int>(bodies_.size()); }

 private:
  // The fit's points: a cubic in time.
  static constexpr int kFitPoints = 4;

  void Recompute(const mjModel* m, const mjData* d) const;
  // R's rows and columns of the out-of-plane motions, which a model left
  // out, from the local part `local` (LocalPart: RFT's own blocks of each
  // body): what a caller asking for them reads; the drag on planar joints
  // never does.
  static void FillOutOfPlane(const std::vector<Matrix6>& local, Eigen::MatrixXd* root_resistance);
  // Brings root_resistance_ to d's shape: the same shape's, the secant's,
  // the cached or a new exact one (the tolerances).
  void UpdateRootResistance(const mjModel* m, const mjData* d) const;
  // root_resistance_, the fit's made at its tau first if it is one not
  // yet made (a caller that takes the cubic never needs the sum).
  const Eigen::MatrixXd& RootResistance() const;
  // G of FrameResistance in d.
  void RootFrame(const mjData* d, Eigen::Matrix<double, 6, 6>* frame) const;
  // The root's rotation Q and its origin's offset from the root's subtree
  // centre of mass r = p - c in d.
  Eigen::Matrix3d RootRotation(const mjData* d) const;
  Eigen::Vector3d RootOffset(const mjData* d) const;
  // The shape (non-root joint positions) of d.
  void Shape(const mjData* d, std::vector<double>* shape) const;
  // Sets root_resistance_ to the secant's extrapolation to `shape` and
  // returns true, or returns false if the shape is beyond its reach or off
  // it (or there is no secant).
  bool Extrapolate(const std::vector<double>& shape) const;
  // Sets root_resistance_ to the fit in time at `time_s` and returns true,
  // or returns false if `time_s` is outside its interval or `shape` off
  // the fit's.
  bool Fit(const mjModel* m, const mjData* d, const std::vector<double>& shape) const;
  // The fit in time is on (a shape tolerance and a fit tolerance).
  bool Fitting() const;
  // *local = the resistance's local part at d's shape: per body of
  // bodies_, RFT's resistance of its segments (rft()'s coefficients), in
  // the root's frame about its origin; R's diagonal blocks hold it.
  void LocalPart(const mjModel* m, const mjData* d, std::vector<Matrix6>* local) const;
  // resistance's diagonal blocks += weight local.
  static void AddLocalPart(const std::vector<Matrix6>& local, double weight,
                           Eigen::MatrixXd* resistance);
  // After a new exact evaluation at exact_[0]: the fit through the newest
  // kFitPoints, if their times increase.
  void BuildFit() const;
  // The fit's error against the exact evaluation `exact` of what it fits
  // at `time_s` (err above, against the whole `resistance` R's T) and the
  // next interval.
  void UpdateFitInterval(double time_s, const Eigen::MatrixXd& exact,
                         const Eigen::MatrixXd& resistance) const;
  // *value = sum_k fit[k] tau^k.
  template <typename Value>
  static void FitAt(const std::array<Value, kFitPoints>& fit, double tau_s, Value* value);
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
  double body_length_m_ = 0.0;  // the segments' lengths summed
  // The last kFitPoints exact evaluations (time, shape, R about the root's
  // origin in the root's frame), newest first; an empty shape: none yet.
  struct Exact {
    double time_s = 0.0;
    std::vector<double> shape;
    Eigen::MatrixXd root_resistance;
  };
  mutable std::array<Exact, kFitPoints> exact_;
  // The fit in time through them (BuildFit), valid while fit_ready_: the
  // monomials' coefficients of R and of the shape in tau = t - fit_time_s_,
  // and the interval past fit_time_s_ it serves [s].
  mutable bool fit_ready_ = false;
  mutable std::array<Eigen::MatrixXd, kFitPoints> fit_;
  mutable std::array<Eigen::VectorXd, kFitPoints> shape_fit_;
  mutable Eigen::VectorXd fit_shape_;  // scratch
  mutable double fit_time_s_ = 0.0;
  mutable double fit_interval_s_ = 0.0;
  mutable int fits_ = 0;
  mutable long fit_version_ = 0;  // bumped whenever fit_ changes
  // root_resistance_ is the fit at root_fit_tau_s_ (FrameResistanceCubic),
  // made only when root_stale_ is cleared (RootResistance).
  mutable bool root_is_fit_ = false;
  mutable bool root_stale_ = false;
  mutable double root_fit_tau_s_ = 0.0;
  // The local part at the fitted state's shape (LocalPart; at an exact
  // evaluation's, scratch).
  mutable std::vector<Matrix6> local_part_;
  mutable double last_fit_error_ = 0.0;
  mutable Eigen::MatrixXd root_resistance_;  // in use: exact, extrapolated or fitted
  mutable bool extrapolated_ = false;
  mutable std::vector<double> shape_;  // scratch
  // The shape root_resistance_ was made for, and the exact evaluations then.
  mutable std::vector<double> used_shape_;
  mutable int used_of_recomputation_ = -1;
  mutable Eigen::MatrixXd world_resistance_;
  mutable int recomputations_ = 0;
  mutable int extrapolations_ = 0;
  // root_resistance_'s version: bumped whenever it changes.
  mutable long root_version_ = 0;
  // What world_resistance_ was made from: the root's rotation and offset
  // from the subtree centre of mass, and root_resistance_'s version. A
  // further evaluation of the same state (within a step, or by a meter
  // after it) reuses it.
  mutable Eigen::Matrix3d world_rotation_;
  mutable Eigen::Vector3d world_offset_;
  mutable long world_of_version_ = -1;
};

}  // namespace ipmc
