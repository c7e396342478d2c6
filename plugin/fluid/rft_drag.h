// Resistive-force theory (RFT) drag on slender rigid segments in Stokes flow.
//
// Force per unit length on an element with unit tangent t moving with
// velocity u relative to still fluid (Gray & Hancock 1955):
//   f = -xi_t (u.t) t - xi_n (u - (u.t) t)            [N/m]
// For a rigid segment of length L, centre c, velocity v_c and angular
// velocity w, u(s) = v_c + s (w x t), s in [-L/2, L/2]. Integrated exactly:
//   F   = -L R v_c,                  R = xi_t t t^T + xi_n (I - t t^T)
//   T_c = -xi_n L^3 / 12 (w - (w.t) t)      (torque about the centre)
// The wrenches are added to qfrc_passive from mjcb_passive as J^T [F; T],
// what mj_applyFT gives, for all segments in one pass over the tree.
// Both are linear in the segment's spatial velocity V = [w; v] at any point
// c (v the velocity of the body point at c): with r = p_center - c and
// [r x] its cross-product matrix, [T_c; F] = -S V with the symmetric,
// positive semi-definite 6 x 6 spatial resistance
//   S = [ K_w - L [r x] R [r x]    L [r x] R ]
//       [ -L R [r x]               L R       ],  K_w = xi_n L^3/12 (I - t t^T),
// T_c = T + r x F the torque about c. The drag callback applies -S V and
// the Stokes stepper (plugin/dynamics/stokes_step.h) assembles J^T S J from
// the same S, so the two share one formula.
//
// Coefficients [N s/m^2] from the viscosity mu, the equivalent radius a and
// the wavelength lambda:
//   Gray & Hancock (1955): xi_n = 4 pi mu / (ln(2 lambda / a) + 1/2),
//                          xi_t = 2 pi mu / (ln(2 lambda / a) - 1/2)
//   Lighthill (1976):      xi_n = 4 pi mu / (ln(2 q / a) + 1/2),
//                          xi_t = 2 pi mu /  ln(2 q / a),  q = 0.09 lambda
//   near a no-slip plane wall (Katz, Blake & Paveri-Fontana 1975), the
//   centreline parallel to it a distance h away: near_wall_rft.h
// or set directly. For the flat 3 mm x 250 um strip a = (w + h) / 4
// (Batchelor 1970, elliptical section of semi-axes w/2, h/2).
//
// MJCF fields (all optional but the viscosity, which marks the model as
// using RFT; a model without it gets no drag):
//   numeric ipmc_rft_viscosity_Pa_s        mu > 0
//   text    ipmc_rft_coefficients          gray_hancock | lighthill | near_wall
//                                          | direct | ribbon | ribbon_fitted
//   numeric ipmc_rft_wall_distance_m       h > a (near_wall): the centreline's
//                                          distance to the wall, in the plane
//                                          z = const below the body
//   numeric ipmc_rft_equivalent_radius_m   a > 0
//   numeric ipmc_rft_wavelength_m          lambda > 2a (> 0.5 a / 0.09 for Lighthill)
//   numeric ipmc_rft_xi_normal_N_s_m2, ipmc_rft_xi_tangential_N_s_m2 (direct)
//   numeric ipmc_rft_fluid_density_kg_m3   rho_f >= 0 (Reynolds number only)
//   text    ipmc_rft_geoms                 geom names; default every geom
//                                          not on the world body
// Every geom the drag acts on is one of:
//   box, capsule, cylinder   a slender segment (SlenderAxis, plugin/mjcf/
//                            geom_axes.h: a capsule's or cylinder's local z,
//                            length 2 size[1]; a box's axis along its chain,
//                            length its side there), with the coefficients
//                            above from its own radius (SlenderRadius_m: a
//                            capsule's or cylinder's, a box's (w + h) / 4 from
//                            its width and thickness), or from
//                            ipmc_rft_equivalent_radius_m for every segment
//                            where the model sets it (the paper's strip);
//   sphere, ellipsoid        a whole body with its exact Stokes resistance
//                            (geom_resistance.h: Stokes, Oberbeck, Edwardes),
//                            in free space only (not with near_wall).
// Any other geom (plane, mesh, height field) is refused by name, as is a
// box with no axis (centred on its body, two longest sides equal).
#pragma once

#include <mujoco/mujoco.h>

#include <Eigen/Core>
#include <Eigen/StdVector>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "ipmc_swim/fields.h"
#include "plugin/fluid/fluid_model.h"
#include "plugin/fluid/geom_resistance.h"

namespace ipmc {

struct DragCoefficients {
  double normal_N_s_m2 = 0.0;
  double tangential_N_s_m2 = 0.0;
  // The torque about a segment's centre per angular velocity normal to its
  // axis [N m s]; 0 takes RFT's xi_n L^3 / 12.
  double rotation_N_m_s = 0.0;
};
// xi.rotation_N_m_s, or xi_n L^3 / 12 when it is 0.
double RotationalDrag_N_m_s(const DragCoefficients& xi, double length_m);

DragCoefficients GrayHancockCoefficients(double viscosity_Pa_s, double radius_m,
                                         double wavelength_m);
DragCoefficients LighthillCoefficients(double viscosity_Pa_s, double radius_m,
                                       double wavelength_m);

// Settings that a program may impose over the model's fields (a scenario:
// the coefficient set, and the wavelength of the wave it drives, so that the
// coefficients follow the wave). With model set to gray_hancock or lighthill
// a model's direct coefficients are ignored; wavelength_m is used by those
// two sets only.
struct RftDragOverrides {
  std::optional<CoefficientModel> model;
  std::optional<double> wavelength_m;
  std::optional<double> wall_distance_m;
  // The fluid model (FluidModels(), fluid_model.h) over the model's
  // ipmc_fluid_model.
  std::optional<std::string> fluid_model;
  // Fluid models' parameters over their <custom> fields (FluidParameter):
  // the field's name to its value in SI units.
  std::map<std::string, double> fluid_parameters;
};

struct RftDragConfig {
  double viscosity_Pa_s = 1.0e-3;
  CoefficientModel model = CoefficientModel::kGrayHancock;
  double equivalent_radius_m = 0.8125e-3;
  double wavelength_m = 32e-3;
  DragCoefficients direct;  // used with CoefficientModel::kDirect
  double wall_distance_m = 0.0;  // used with CoefficientModel::kNearWall
  double fluid_density_kg_m3 = 1000.0;
  std::vector<std::string> geom_names;  // empty: every geom not on the world body
  // Each segment's coefficients from its geom's own radius (FromModel: the
  // model sets no ipmc_rft_equivalent_radius_m); equivalent_radius_m is
  // then the segments' length-weighted mean radius (RftDrag sets it), the
  // radius of the dense models' centrelines.
  bool radius_from_geoms = false;

  // nullopt if the model has no ipmc_rft_viscosity_Pa_s field. Throws
  // std::invalid_argument naming the field if a field is malformed.
  static std::optional<RftDragConfig> FromModel(const mjModel* m,
                                                const RftDragOverrides& overrides = {});
  void Validate() const;  // throws std::invalid_argument naming the field
  // Throws std::invalid_argument naming `what` (the field, or a geom) if the
  // coefficient set cannot take a segment of this radius.
  void ValidateRadius(double radius_m, const std::string& what) const;
  DragCoefficients Coefficients() const;
  // The coefficients of a segment of radius radius_m (Coefficients() for
  // the radius-free sets: direct, ribbon, ribbon_fitted).
  DragCoefficients CoefficientsForRadius(double radius_m) const;
};


// A rigid slender segment in the world frame.
struct Segment {
  Eigen::Vector3d center_W;
  Eigen::Vector3d tangent_W;  // unit
  double length_m = 0.0;
  Eigen::Vector3d velocity_center_W;
  Eigen::Vector3d angular_velocity_W;
};

// Force and torque about the segment centre, world frame.
struct Wrench {
  Eigen::Vector3d force_W = Eigen::Vector3d::Zero();
  Eigen::Vector3d torque_center_W = Eigen::Vector3d::Zero();
};

Wrench SegmentDragExact(const Segment& segment, const DragCoefficients& xi);

using SpatialResistance = Eigen::Matrix<double, 6, 6>;
// S of a segment (centre, unit tangent, length) about the point c_W
// (see above): the drag wrench [torque about c; force] is -S [w; v_c].
SpatialResistance SegmentResistance(const Eigen::Vector3d& center_W,
                                    const Eigen::Vector3d& tangent_W, double length_m,
                                    const Eigen::Vector3d& c_W, const DragCoefficients& xi);
// The block of SegmentResistance in the components [w_z; v_x; v_y] (its
// rows and columns 2 to 4): all of S that a body moving in the x-y plane
// feels, without the rest (the same formula, term by term; any tangent and
// centre).
Eigen::Matrix3d SegmentPlanarResistance(const Eigen::Vector3d& center_W,
                                        const Eigen::Vector3d& tangent_W, double length_m,
                                        const Eigen::Vector3d& c_W, const DragCoefficients& xi);
// Gauss-Legendre quadrature of the same integral with `points` nodes per
// sub-interval over `intervals` equal sub-intervals (cross-check only).
Wrench SegmentDragQuadrature(const Segment& segment, const DragCoefficients& xi, int intervals);
// Mechanical power of the drag wrench on the segment [W]; never positive.
double SegmentDragPower(const Segment& segment, const Wrench& wrench);

// The RFT fluid model (fluid_model.h), and the segments every fluid model
// acts on.
class RftDrag : public Fluid {
 public:
  // Resolves geoms and coefficients; throws std::invalid_argument on a bad
  // configuration (unknown geom name, a geom it cannot represent, named
  // with the reason).
  RftDrag(const mjModel* m, const RftDragConfig& config);
  // The registry's entry (fluid_model.h): a copy of `segments`.
  static std::unique_ptr<Fluid> Make(const mjModel* m, const RftDrag& segments,
                                     const RftDragOverrides& overrides);

  // Adds the drag of every segment into d->qfrc_passive.
  void Apply(const mjModel* m, mjData* d) const override;
  // The current segments (positions and velocities from d).
  std::vector<Segment> Segments(const mjModel* m, const mjData* d) const;
  // The power the body loses to the fluid [W], minus the sum over the
  // segments of the drag wrench's power (F . v_c + T_c . w, the integral
  // of -f . u along each segment), from d's positions and velocities
  // (xpos, cvel); never negative.
  double DissipatedPower_W(const mjModel* m, const mjData* d) const override;
  // The drag [N] on the segments laid straight along one axis and towed
  // along it at `speed_m_s` (the resistance of the straightened body:
  // the sum of xi_t L, by SegmentDragExact), and on the spheres and
  // ellipsoids towed along world x as the model's reference pose (qpos0)
  // holds them.
  double TowingDrag_N(double speed_m_s) const override;
  // The segments' lengths, in geom_ids() order.
  std::vector<double> SegmentLengths_m() const override;
  double Viscosity_Pa_s() const override { return config_.viscosity_Pa_s; }
  double FluidDensity_kg_m3() const override { return config_.fluid_density_kg_m3; }
  // The straight body's drag torque about one end per angular velocity,
  // xi_n L^3 / 3 (L the segments' total length).
  double RotationalDragScale_N_m_s() const override;

  // Each segment's block (see Fluid): its resistance S about the subtree
  // centre of mass of its body's root, from d's positions (valid after
  // mj_comPos): all of S (Dim = 6, SegmentResistance), or its
  // [w_z; v_x; v_y] block (Dim = 3, SegmentPlanarResistance).
  template <int Dim>  // 6 or 3
  void Resistances(const mjModel* m, const mjData* d, BodyResistanceBlocks<Dim>* out) const;
  void LocalResistances(const mjModel* m, const mjData* d,
                        BodyResistanceBlocks<6>* out) const override {
    Resistances(m, d, out);
  }
  void LocalResistances(const mjModel* m, const mjData* d,
                        BodyResistanceBlocks<3>* out) const override {
    Resistances(m, d, out);
  }

  const RftDragConfig& config() const { return config_; }
  const DragCoefficients& coefficients() const { return coefficients_; }
  // Each segment's coefficients, in geom_ids() order: coefficients() for
  // every segment, but with kRibbon and kRibbonFitted (whose coefficients()
  // is the body's mean drag per length).
  const std::vector<DragCoefficients>& segment_coefficients() const {
    return segment_coefficients_;
  }
  // The segments' geoms (boxes, capsules, cylinders): the geoms every
  // fluid model acts on.
  const std::vector<int>& geom_ids() const { return geom_ids_; }
  // The spheres' and ellipsoids' geoms, which only RFT represents (the
  // dense models refuse them, fluid_model.cc).
  std::vector<int> head_geom_ids() const;

 private:
  struct SlenderGeom {
    int geom_id;
    int axis;          // segment axis in the geom frame (SlenderAxis)
    double length_m;
    double radius_m;   // SlenderRadius_m
  };
  struct HeadGeom {
    int geom_id;
    PrincipalResistance principal;  // along the geom's local axes
  };
  void AddGeom(const mjModel* m, int g);
  DragCoefficients SegmentCoefficients(const SlenderGeom& geom) const;
  // A head's 6 x 6 resistance about the subtree centre of mass of its
  // body's root.
  static BodyResistanceBlock<6> HeadResistanceOf(const mjModel* m, const mjData* d,
                                                 const HeadGeom& head);
  static Segment SegmentOf(const mjModel* m, const mjData* d, const SlenderGeom& geom);
  template <int Dim>
  BodyResistanceBlock<Dim> ResistanceOf(const mjModel* m, const mjData* d,
                                        const SlenderGeom& geom,
                                        const DragCoefficients& xi) const;
  RftDragConfig config_;
  DragCoefficients coefficients_;
  std::vector<DragCoefficients> segment_coefficients_;
  std::vector<int> geom_ids_;
  std::vector<SlenderGeom> slender_;
  std::vector<HeadGeom> heads_;
  double heads_tow_N_s_m_ = 0.0;  // the heads' drag along x per speed, at qpos0
};

}  // namespace ipmc
