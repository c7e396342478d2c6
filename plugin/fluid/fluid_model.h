// The fluid the body's segments feel, as one interface: the drag callback
// (mjcb_passive, inertial dynamics), the Stokes stepper
// (plugin/dynamics/stokes_step.h) and the energy meter (sim/core/energy.h)
// call `Fluid` and nothing else, and the registry below builds the model a
// run asks for. The models, one header/source pair each:
//
//   rft            resistive-force theory (plugin/fluid/rft_drag.h): each
//                  segment's resistance is its own (local), a 6 x 6 block
//                  per segment (also near a wall, with Katz, Blake &
//                  Paveri-Fontana's coefficients).
//   stokeslets     regularized Stokeslets (plugin/fluid/stokeslet_fluid.h):
//                  every segment's velocity moves every other segment
//                  (hydrodynamic interaction), one dense resistance over
//                  the segments' bodies.
//   ribbon         slender-ribbon theory (plugin/fluid/ribbon_fluid.h): the
//                  strip as one flat ribbon with a kinked centreline, the
//                  same dense resistance over the segments' bodies.
//   plates         flat plates (plugin/fluid/plate_fluid.h): each segment a
//                  rectangle of the strip's width, regularized Stokeslets
//                  on its surface by the nearest-neighbour method, the
//                  same dense resistance (dense_resistance_fluid.h).
//
// Every model acts on the same segments, the slender geoms RftDrag finds
// (RftDragConfig::FromModel reads them and the viscosity from the model's
// ipmc_rft_* <custom> fields), and reads its own settings, declared as
// FluidParameter entries below, from its own fields and the program's
// overrides (RftDragOverrides). The model's <custom> text ipmc_fluid_model
// chooses the model; a program's override (the scenario's fluid.model)
// wins over it.
//
// The meters (sim/core/swim_meter.h, sim/core/energy.h) and the gait run
// ask the model, not the segments: Fluid's methods below are all they see.
//
// Adding a model: a header/source pair with a class derived from Fluid
// (or from DenseResistanceFluid, which answers the meters' questions from
// the segments), its settings read by FluidParameterValue from its
// parameter table, and one line in FluidModels() (fluid_model.cc). The
// scenario keys (fluid.model's choices, one key per parameter) come from
// the registry.
#pragma once

#include <mujoco/mujoco.h>

#include <Eigen/Core>
#include <Eigen/StdVector>
#include <array>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "ipmc_swim/fields.h"

namespace ipmc {

class RftDrag;
struct RftDragOverrides;

// One segment's body and its spatial resistance S about the subtree centre
// of mass of the body's root (where MuJoCo gives cdof and cvel): all of S
// (Dim = 6, [w; v]) or its [w_z; v_x; v_y] block (Dim = 3, a body moving
// in the x-y plane). The drag wrench [torque; force] is -S cvel.
template <int Dim>
struct BodyResistanceBlock {
  int body;
  Eigen::Matrix<double, Dim, Dim> resistance;
};
template <int Dim>
using BodyResistanceBlocks =
    std::vector<BodyResistanceBlock<Dim>, Eigen::aligned_allocator<BodyResistanceBlock<Dim>>>;

// A resistance R_F(t) = sum_k tau^k coefficients[k], tau = t - t_0 [s]
// (Fluid::FrameResistanceCubic); `version` changes whenever the
// coefficients do.
struct ResistanceCubic {
  const std::array<Eigen::MatrixXd, 4>* coefficients = nullptr;
  double tau_s = 0.0;
  long version = -1;
  // Plus a part on the diagonal, one 6 x 6 block per interacting body
  // (the fit follows R less it), at d's shape; null: none.
  const std::vector<Eigen::Matrix<double, 6, 6>>* local = nullptr;
};

class Fluid {
 public:
  virtual ~Fluid() = default;

  // Adds the drag into d->qfrc_passive (positions and velocities from d).
  virtual void Apply(const mjModel* m, mjData* d) const = 0;
  // The power the body loses to the fluid [W], never negative, from d's
  // positions and velocities; measuring it does not change the run.
  virtual double DissipatedPower_W(const mjModel* m, const mjData* d) const = 0;
  // The drag [N] on the body laid straight along x and towed along it.
  virtual double TowingDrag_N(double speed_m_s) const = 0;

  // What the meters read of the fluid, each model answering for itself:
  // the lengths [m] of the segments it acts on (in the order of
  // RftDrag::geom_ids()), the fluid's viscosity [Pa s] and density
  // [kg/m^3] (the density only for the Reynolds number), and a scale of
  // the body's rotational drag about one end [N m s] (the servo gains of
  // a prescribed gait, sim/runs/gait_run.h).
  virtual std::vector<double> SegmentLengths_m() const = 0;
  virtual double Viscosity_Pa_s() const = 0;
  virtual double FluidDensity_kg_m3() const = 0;
  virtual double RotationalDragScale_N_m_s() const = 0;

  // The resistance the Stokes step solves with, from d's positions (after
  // mj_comPos), in one of two forms. A model whose segments do not
  // interact gives one block per segment (LocalResistances: all of S, or
  // the planar block); one whose segments interact gives the dense
  // resistance R over InteractingBodies() (InteractionResistance: 6 per
  // body, [w; v] about the subtree centre of mass of the root, world
  // frame; the bodies' drag wrenches are -R V of their velocities V). The
  // form a model does not use is empty: no blocks, a null matrix.
  virtual void LocalResistances(const mjModel* m, const mjData* d,
                                BodyResistanceBlocks<6>* out) const;
  virtual void LocalResistances(const mjModel* m, const mjData* d,
                                BodyResistanceBlocks<3>* out) const;
  virtual const Eigen::MatrixXd* InteractionResistance(const mjModel* m, const mjData* d) const;
  virtual const std::vector<int>& InteractingBodies() const;
  // The same R as R = F^T R_F F, F = diag(G, G, ...) with one 6 x 6 G for
  // every body: R_F in a frame the model keeps it in, G the map from
  // [w; v] about the root's subtree centre of mass in the world to that
  // frame, and `version`, which changes whenever R_F does (so a caller
  // may reuse what it made of R_F; -1: none, nothing to reuse). By
  // default R_F = R, G = I and version -1; null as InteractionResistance.
  virtual const Eigen::MatrixXd* FrameResistance(const mjModel* m, const mjData* d,
                                                 Eigen::Matrix<double, 6, 6>* frame,
                                                 long* version) const;
  // When R_F at d's positions is a cubic in time between exact evaluations
  // (a dense model's fit, dense_resistance_fluid.h), that cubic:
  // R_F = sum_k tau^k coefficients[k], so that a caller making something
  // linear of R_F may make it of each coefficient once per fit and sum
  // the four at every step. False (nothing set) when R_F is not a fit's:
  // FrameResistance then has it. The frame G is FrameResistance's.
  virtual bool FrameResistanceCubic(const mjModel* m, const mjData* d,
                                    Eigen::Matrix<double, 6, 6>* frame,
                                    ResistanceCubic* cubic) const;

  // Whether a model may leave out what only out-of-plane motions (w_x,
  // w_y, v_z) feel when every joint of d moves its bodies in the x-y plane
  // (hinges about z, slides in the plane): the fluid of a stepped model,
  // whose drag acts on d's joints only, not one asked for a rigid body's
  // six motions. Off unless set.
  void set_in_plane_when_planar(bool on) { in_plane_when_planar_ = on; }
  bool in_plane_when_planar() const { return in_plane_when_planar_; }

 private:
  bool in_plane_when_planar_ = false;
};

// An integer in [minimum, maximum].
FluidParameter IntegerParameter(const char* key, const char* field, int default_value,
                                int minimum, int maximum, int example, const char* meaning);
// A number above `minimum` (at least it when `minimum_included`).
FluidParameter NumberParameter(const char* key, const char* field, const char* unit,
                               double field_per_key, double default_value,
                               const char* default_text, double minimum, bool minimum_included,
                               double example, const char* meaning);
FluidParameter BooleanParameter(const char* key, const char* field, bool default_value,
                                const char* meaning);
// `parameter` marked as one that sets how many force points the model has.
FluidParameter SetsResolution(FluidParameter parameter);
// The parameter's value in its field's SI unit: the program's override,
// else the model's <custom> field, else the default (nullopt: the model
// derives it). Throws std::invalid_argument naming the model, the field
// and its range when the value is out of range.
std::optional<double> FluidParameterValue(const mjModel* m, const RftDragOverrides& overrides,
                                          const char* model, const FluidParameter& parameter);

// The registry of fluid models: a name (the value of the <custom> text
// ipmc_fluid_model and of the scenario key fluid.model), a phrase for the
// key's reference, the model's parameters, whether it takes a no-slip
// wall (RftDragOverrides::wall_distance_m, ipmc_rft_wall_distance_m with
// the near-wall coefficients), how it is built over the segments, and for
// a model with one dense mobility over force points their number, from
// the settings alone (before it is built, so that a program can refuse a
// resolution no machine factors; nullptr: none).
struct FluidModelEntry : FluidModelDescription {
  std::unique_ptr<Fluid> (*make)(const mjModel* m, const RftDrag& segments,
                                 const RftDragOverrides& overrides);
  double (*force_points)(const mjModel* m, const RftDrag& segments,
                         const RftDragOverrides& overrides);
};
const std::vector<FluidModelEntry>& FluidModels();
// The entry called `name`, or nullptr.
const FluidModelEntry* FindFluidModel(const std::string& name);

// It and every model's parameter fields (the coupling's known fields).
std::vector<std::string> FluidModelFields();
// The model the settings choose: the program's RftDragOverrides::
// fluid_model, else the model's ipmc_fluid_model, else "rft". Throws
// std::invalid_argument naming the field and the models when unknown.
const FluidModelEntry& ChosenFluidModel(const mjModel* m, const RftDragOverrides& overrides);
// Throws std::invalid_argument, naming the options, if the model turns on
// MuJoCo's own fluid forces (<option viscosity> or <option density> not
// 0, with or without a geom's fluidshape), which would add to this
// library's drag.
void RequireNoMujocoFluid(const mjModel* m);
// That model, built over `segments` (the model's RFT segments and
// coefficients). Throws std::invalid_argument on bad settings, naming the
// model, on MuJoCo's own fluid (RequireNoMujocoFluid), and for a dense
// model given a sphere or ellipsoid (only rft represents them).
std::unique_ptr<Fluid> MakeFluid(const mjModel* m, const RftDrag& segments,
                                 const RftDragOverrides& overrides);
// The wall's distance from the centreline that the segments' coefficients
// were made for [m] (near-wall RFT), or nullopt in free space.
std::optional<double> WallDistance_m(const RftDrag& segments);

}  // namespace ipmc
