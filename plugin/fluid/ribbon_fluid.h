// Slender-ribbon theory (SRT) as a fluid model: the strip is one thin,
// flat ribbon along the segments' centreline, its width along z (normal to
// the plane the generated models beat in), and the force density along it
// follows from the velocity of every point of the body (nonlocal, like the
// regularized Stokeslets: the links interact through the fluid).
//
// Equation (Koens & Lauga, "Slender-ribbon theory", Phys. Fluids 28,
// 013101, 2016, for a ribbon of vanishing thickness; the analytic
// solutions of Koens & Lauga, Phys. Rev. Fluids 2, 084101, 2017):
// with the arclength scaled by the half-length L to s in [-1, 1], the
// half-width scaled to b rho(s) (b = half-width / L, rho <= 1 the width
// profile), t the tangent and w the unit vector across the width, the force
// per unit length f(s) on the fluid moves the ribbon at
//   8 pi mu U(s) = [Lg(s) (I + t t) - 2 t t + 2 w w] f(s)
//                + int_{-1}^{1} [(I + R R / |R|^2) / |R| f(s')
//                                - (I + t t) / |s - s'| f(s)] ds',
//   Lg(s) = ln(16 (1 - s^2) / (b^2 rho(s)^2)),  R = r(s) - r(s') (scaled).
// For a flat ellipse (rho = sqrt(1 - s^2), Lambda = ln(4 L_full / w_full))
// it gives the drags 4 pi mu L U / (2 Lambda - 1) along the axis,
// 4 pi mu L U / Lambda broadside and 4 pi mu L U / (Lambda + 1) edgewise.
//
// Discretisation: each Cartesian component of f is a sum of the first
// `modes` Legendre polynomials P_n(s) on the whole body; the equation is
// projected onto the same polynomials (Galerkin). On a straight piece
// int (P_n(s') - P_n(s)) / |s - s'| ds' = -2 H_n P_n(s) (H_n the harmonic
// numbers; Tornberg & Shelley, J. Comput. Phys. 196, 8, 2004), so the
// remaining integrand, [(I + R R / |R|^2) / |R| - (I + t t) / |s - s'|]
// f(s'), vanishes on s's own segment and is a regular integral over the
// others, done by Gauss-Legendre quadrature on panels graded towards the
// segments' ends (the kinks).
//
// Ends: a rectangular ribbon (rho = 1) makes Lg diverge at its ends and
// the operator indefinite once the modes resolve wavelengths below about
// two widths. The ribbon here is a rectangle whose last `end_cap_m` at each
// end narrows as a quarter ellipse to the tip (rho = sqrt(1 - s^2) /
// sqrt(1 - s_c^2) beyond s_c), which keeps Lg finite: constant,
// ln(16 (1 - s_c^2) / b^2), over the caps. A cap of half the strip's length
// is the flat ellipse.
//
// Kinks: the segments are laid end to end along their own tangents from
// the first segment's start (the hinges' gaps closed), so the whole body is
// one ribbon with a kinked centreline in the nonlocal integral and one
// smooth force density across the kinks; the velocities and wrenches use
// the segments' own points. The resistance is symmetrised (reciprocal
// theorem) and, as the Stokeslets', kept in the root body's frame until a
// joint has moved more than `shape_tolerance_rad`, and extrapolated along
// the secant of the last two within `secant_reach_rad` or fitted in time
// within `fit_tolerance` (dense_resistance_fluid.h). docs/FLUIDS.md has the
// validation and the error on the paper's strip.
#pragma once

#include <mujoco/mujoco.h>

#include <Eigen/Core>
#include <memory>
#include <optional>
#include <vector>

#include "plugin/fluid/dense_resistance_fluid.h"

namespace ipmc {

// Legendre modes per force component: [1, kMaxRibbonModes].
constexpr int kMaxRibbonModes = 9;
constexpr int kDefaultRibbonModes = 8;

// The ribbon model's settings; a 0 length takes its default from the model.
struct RibbonSettings {
  int modes = kDefaultRibbonModes;   // Legendre modes of each force component
  double width_m = 0.0;              // the ribbon's full width; default the strip's
  double end_cap_m = 0.0;            // length of each elliptic end; default half the width
  double shape_tolerance_rad = 1e-3; // recompute beyond this joint motion
  double secant_reach_rad = kDefaultSecantReachRad;  // extrapolate within this
  double fit_tolerance = kDefaultFitTolerance;  // the fit in time's (0: none)
  // Checked: throws std::invalid_argument naming the setting and its range.
  void Validate() const;
};

// A straight piece of the ribbon: `length_m` from `start_W` along the unit
// `tangent_W`, its width across `width_axis_W` (made normal to the
// tangent), part of rigid body `body`. `hydro_start_W` is where the piece
// starts on the ribbon the fluid sees (the pieces laid end to end).
struct RibbonPiece {
  Eigen::Vector3d start_W;
  Eigen::Vector3d hydro_start_W;
  Eigen::Vector3d tangent_W;
  Eigen::Vector3d width_axis_W;
  double length_m = 0.0;
  int body = 0;
};

// The part of the Galerkin operator between two pieces that depends on
// their arclengths alone (the -1 / |s - s'| of the regular remainder,
// projected on the modes, for every pair in both quadratures): the same
// for every shape of a ribbon with these piece lengths and modes, so a
// fluid computes it once.
class RibbonArclengthPart {
 public:
  RibbonArclengthPart(const std::vector<double>& lengths_m, int modes);
  // W_P^T [1 / |s - s'|] W_Q for pieces p < q, `whole` the one-panel
  // quadrature's (FarApart), the graded one's otherwise.
  const Eigen::MatrixXd& Projection(int p, int q, bool whole) const;
  int pieces() const { return pieces_; }
  int modes() const { return modes_; }

 private:
  int pieces_ = 0;
  int modes_ = 0;
  std::vector<Eigen::MatrixXd> graded_, whole_;  // at p * pieces + q
};

// The resistance of rigid bodies made of ribbon pieces (in order along the
// ribbon): R (6 bodies x 6 bodies) maps the bodies' spatial velocities
// [w; v] (v that of the body point at c) to minus their drag wrenches
// [torque about c; force]: wrench = -R V. `settings` with its lengths set.
// `arclength`, if given, is that of the pieces' lengths and the modes.
Eigen::MatrixXd RibbonBodyResistance(const std::vector<RibbonPiece>& pieces, int bodies,
                                     const Eigen::Vector3d& c, const RibbonSettings& settings,
                                     double viscosity_Pa_s,
                                     const RibbonArclengthPart* arclength = nullptr);

// Straight pieces of the given lengths end to end along x from the origin,
// width along z, all of body 0.
std::vector<RibbonPiece> StraightRibbon(const std::vector<double>& lengths_m);

class RibbonFluid : public DenseResistanceFluid {
 public:
  // The segments' geoms and viscosity are `segments`' (the model's RFT
  // fields); the 0 lengths of `ribbon` take the model's strip width.
  // Throws std::invalid_argument on bad settings.
  RibbonFluid(const mjModel* m, const RftDrag& segments, const RibbonSettings& ribbon);
  // The registry's entry (fluid_model.h): the settings' parameter (the
  // modes: ipmc_fluid_ribbon_modes, fluid.ribbon_modes) and the model it
  // sets. Free space only.
  static constexpr char kSummary[] =
      "slender-ribbon theory, the strip as one flat ribbon with kinks (free space only)";
  static std::vector<FluidParameter> Parameters();
  static std::unique_ptr<Fluid> Make(const mjModel* m, const RftDrag& segments,
                                     const RftDragOverrides& overrides);

  double TowingDrag_N(double speed_m_s) const override;
  const RibbonSettings& settings() const { return settings_; }

 private:
  std::vector<RibbonPiece> Pieces(const mjModel* m, const mjData* d) const;
  Eigen::MatrixXd ComputeResistance(const mjModel* m, const mjData* d,
                                    const Eigen::Vector3d& origin_W) const override;
  double shape_tolerance_rad() const override { return settings_.shape_tolerance_rad; }
  double secant_reach_rad() const override { return settings_.secant_reach_rad; }
  double fit_tolerance() const override { return settings_.fit_tolerance; }

  RibbonSettings settings_;
  std::optional<RibbonArclengthPart> arclength_;  // of the segments' lengths
};

}  // namespace ipmc
