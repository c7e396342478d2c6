// Flat plates as a fluid model: each segment of the strip is a rigid
// rectangle of zero thickness, its length along the segment and the strip's
// width along z (normal to the plane the generated models beat in), and
// the plates' surface force densities follow from a boundary integral
// equation of the first kind with regularized Stokeslets, every plate's
// force felt on every other plate (the links interact through the fluid).
//
// Equation (Cortez, Fauci & Medovikov, Phys. Fluids 17, 031504, 2005,
// eq. 10a; the kernel of plugin/fluid/regularized_stokeslets.h): the
// velocity of the surface point x is
//   8 pi mu u(x) = int_S S_eps(x - y) f(y) dS(y),
// with f the force per area the surface exerts on the fluid.
//
// Discretisation: the nearest-neighbour method (Smith, J. Comput. Phys.
// 358, 88-102, 2018). f is constant on the cells of a coarse grid of force
// points (`points_across` across the width, square cells along the
// length); the integral is a midpoint rule on a grid `quadrature_refinement`
// times finer, each quadrature point's kernel added to the column of its
// nearest force point (the cell it lies in, on its own plate). So the
// quadrature error (h_q^2 / eps) and the regularization error (O(eps)) are
// controlled separately while the matrix stays (3 N_force)^2. The blob is
// eps = `blob_over_spacing` h_f (h_f the force spacing across the width).
//
// Richardson extrapolation in eps (Gallagher & Smith, R. Soc. Open Sci. 8,
// 210108, 2021): the regularization error is linear in eps, so with
// `richardson` the resistance is 2 R(eps / 2) - R(eps), the same force
// and quadrature grids solved twice.
//
// Near a no-slip plane wall z = -h (`wall_distance_m` h, the plates'
// centreline height; the wall is parallel to the beat plane z = 0) every
// block adds the wall's image system at the quadrature points' mirror
// points (Ainley, Durkin, Embid, Boindala & Cortez, J. Comput. Phys. 227,
// 4600-4616, 2008; RegularizedWallImage, regularized_stokeslets.h), which
// makes u = 0 on the wall. The image is regular on the plates (its
// singularities lie below the wall, at least twice the gap away), so its
// dependence on eps is O(eps^2), and the Richardson extrapolation, which
// removes the free-space kernel's O(eps) error, holds unchanged
// (plate_wall_test measures it).
//
// Rigid links: a plate's free-space block of the matrix (its force points
// against its own quadrature points) is the same in the plate's frame for
// every shape, so it is computed once per plate and rotated; the blocks
// between plates and, near a wall, every block's image part (a plate's own
// image depends on its height and tilt) are recomputed with the shape.
// Mirror symmetry: without a wall, with every plate's width along +-z and
// every plate centred on one plane z = z0 (links bending in their plane),
// the reflection z -> 2 z0 - z maps the force points onto force points
// and the velocity matrix onto itself (A(pi i, pi j) = P A(i, j) P,
// P = diag(1, 1, -1); the kernel is isotropic). The solve then splits into
// its z-even and z-odd halves of about n / 2 unknowns, the in-plane rigid
// motions driving the even half and the out-of-plane ones the odd half: a
// quarter of the factorisation and solves and half the kernel sums, the
// same R to round-off (SurfaceResistance). Otherwise the full matrix is
// solved.
//
// The solve: R = W A^-1 M, M the rigid motions' velocities at the force
// points and W the forces' wrenches, is Z X with X = L^-1 P M and
// Z^T = U^-T W^T from A's partial-pivoting LU (P A = L U). A body's
// columns of M and rows of W are zero outside its own force points, so
// each triangular solve starts at the body's first unknown. With
// Richardson the kernel sums at eps and eps / 2 share one pass over the
// point pairs. docs/FLUIDS.md, "Cost on flexible links", times it.
//
// The resistance is kept while the shape moves less than
// `shape_tolerance_rad`, and extrapolated along the secant of the last two
// within `secant_reach_rad` or fitted in time within `fit_tolerance`
// (dense_resistance_fluid.h).
// docs/FLUIDS.md has the validation (disk, straight strip) and the
// convergence of the paper's swimmer.
#pragma once

#include <mujoco/mujoco.h>

#include <Eigen/Core>
#include <Eigen/StdVector>
#include <memory>
#include <optional>
#include <vector>

#include "plugin/fluid/dense_resistance_fluid.h"

namespace ipmc {

constexpr int kMaxPlatePointsAcross = 16;
constexpr int kMaxPlateQuadratureRefinement = 8;

// The plate model's settings; a 0 width takes the model's strip width.
struct PlateSettings {
  int points_across = 4;           // force points across each plate's width
  int quadrature_refinement = 4;   // quadrature points per force point, along each side
  double blob_over_spacing = 0.5;  // eps over the force spacing h_f
  bool richardson = true;          // 2 R(eps / 2) - R(eps)
  double width_m = 0.0;            // the plates' width; default the strip's
  double shape_tolerance_rad = 1e-3;  // recompute beyond this joint motion
  double secant_reach_rad = kDefaultSecantReachRad;  // extrapolate within this
  double fit_tolerance = kDefaultFitTolerance;  // the fit in time's (0: none)
  // The centreline's height h over a no-slip wall z = -h; none: free space.
  std::optional<double> wall_distance_m;
  // Checked: throws std::invalid_argument naming the setting and its range.
  void Validate() const;
};

// A rigid surface in its own frame: force points, and quadrature points
// (with their areas) each owned by its nearest force point.
struct SurfaceMesh {
  std::vector<Eigen::Vector3d> force_points;
  std::vector<Eigen::Vector3d> quadrature_points;
  std::vector<double> quadrature_area_m2;
  std::vector<int> owner;  // the nearest force point of each quadrature point
};

// The force cells along a rectangle with `across` of them across its width:
// the whole number nearest length / (width / across), at least 1.
int CellsAlong(double length_m, double width_m, int across);
// A rectangle `length_m` along x and `width_m` along z, centred on the
// origin: `across` force cells across the width, square-ish cells along
// (the whole number of cells nearest w / across long), each cut into
// refinement^2 quadrature cells.
SurfaceMesh RectangleMesh(double length_m, double width_m, int across, int refinement);
// A disk of radius `radius_m` in the x-y plane, centred on the origin:
// `rings` rings of force cells, near-square (polar cells, the rim exact),
// each cut into refinement^2 quadrature cells, which its force point (the
// cell's centroid) owns.
SurfaceMesh DiskMesh(double radius_m, int rings, int refinement);

// A mesh placed in the world: x_W = position + rotation x, part of rigid
// body `body`.
struct PlacedSurface {
  const SurfaceMesh* mesh = nullptr;
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  int body = 0;
};
struct Segment;  // rft_drag.h

// The plate of `segment`, as the plate model places it: x along the
// segment, z across the width (the generated models' width, normal to the
// beat plane), centred on the segment's centre.
PlacedSurface PlateOnSegment(const Segment& segment, const SurfaceMesh* mesh, int body);

// The velocity matrix of the nearest-neighbour method, (1 / 8 pi mu) times
// sum over the quadrature points y owned by force point j of
// S_eps(x_i - y) dA(y), for force points i of `target` and j of `source`.
Eigen::MatrixXd NearestNeighbourBlock(const PlacedSurface& target, const PlacedSurface& source,
                                      double blob_m, double viscosity_Pa_s);
// The same with the wall z = wall_z_m's image system in place of the
// free-space kernel (RegularizedWallImage): the part a wall adds.
Eigen::MatrixXd NearestNeighbourImageBlock(const PlacedSurface& target,
                                           const PlacedSurface& source, double wall_z_m,
                                           double blob_m, double viscosity_Pa_s);

// Whether the surfaces are mirror-symmetric about a plane z = z0, as
// SurfaceResistance's split solve needs: no wall, every rotation's third
// column exactly +-z, every surface centred on the same z exactly, and
// every mesh mirror-symmetric about its own z = 0 (force points onto force
// points, quadrature points onto quadrature points of the same area owned
// by their owner's image, to 1e-12 of the mesh's size).
bool MirrorSymmetric(const std::vector<PlacedSurface>& surfaces,
                     std::optional<double> wall_z_m = std::nullopt);

// How SurfaceResistance solves: by the z-even and z-odd halves when the
// surfaces are MirrorSymmetric (the full matrix otherwise); by the z-even
// half alone when they are, leaving the rows and columns of the
// out-of-plane motions (w_x, w_y, v_z) zero (for bodies that cannot make
// them: they cannot feel them either, R being block diagonal in the
// halves); or always by the full matrix (the reference the halves are
// tested against).
enum class SurfaceSolve { kMirrorHalvesWhenSymmetric, kInPlaneHalfWhenSymmetric, kFullMatrix };

// The resistance of rigid bodies made of surfaces: R (6 bodies x 6 bodies)
// maps the bodies' spatial velocities [w; v] (v that of the body point at
// c) to minus their drag wrenches [torque about c; force]. `self_blocks`,
// if not empty, holds each surface's own block in its frame
// (NearestNeighbourBlock of the unrotated surface with itself). With
// `wall_z_m`, a no-slip wall z = wall_z_m below every surface: every
// block adds its NearestNeighbourImageBlock.
Eigen::MatrixXd SurfaceResistance(const std::vector<PlacedSurface>& surfaces, int bodies,
                                  const Eigen::Vector3d& c, double blob_m, double viscosity_Pa_s,
                                  const std::vector<Eigen::MatrixXd>& self_blocks = {},
                                  std::optional<double> wall_z_m = std::nullopt,
                                  SurfaceSolve solve = SurfaceSolve::kMirrorHalvesWhenSymmetric);
// The same, Richardson-extrapolated in eps when asked: 2 R(eps/2) - R(eps),
// both blobs' kernels summed in one pass; `half_blob_self_blocks` the own
// blocks at eps / 2 (given whenever `self_blocks` is);
// *out_of_plane_left_out (if given): whether `solve` left the out-of-plane
// rows and columns zero.
Eigen::MatrixXd ExtrapolatedResistance(
    const std::vector<PlacedSurface>& surfaces, int bodies, const Eigen::Vector3d& c,
    double blob_m, bool richardson, double viscosity_Pa_s,
    std::optional<double> wall_z_m = std::nullopt,
    const std::vector<Eigen::MatrixXd>& self_blocks = {},
    const std::vector<Eigen::MatrixXd>& half_blob_self_blocks = {},
    SurfaceSolve solve = SurfaceSolve::kMirrorHalvesWhenSymmetric,
    bool* out_of_plane_left_out = nullptr);

// The straight strip's drag per length [N s/m^2], broadside (normal to
// its face) and axial: the plates' resistance of one rectangle, Richardson
// in eps at 4 and 6 force points across, then extrapolated in the spacing
// (the remaining error is first order in it): F = (6 F_6 - 4 F_4) / 2.
// RFT's coefficients calibrated on the strip ("ribbon", rft_drag.h).
struct StripDragPerLength {
  double broadside_N_s_m2 = 0.0;
  double axial_N_s_m2 = 0.0;
};
StripDragPerLength ConvergedStripDrag(double viscosity_Pa_s, double length_m, double width_m);

class PlateFluid : public DenseResistanceFluid {
 public:
  // The segments' geoms and viscosity are `segments`' (the model's RFT
  // fields); a 0 width takes the model's strip width. Throws
  // std::invalid_argument on bad settings.
  PlateFluid(const mjModel* m, const RftDrag& segments, const PlateSettings& plates);
  // The registry's entry (fluid_model.h): the settings' parameters
  // (ipmc_fluid_plate_* fields, fluid.plate_* keys), the model they set,
  // with the wall of the segments' near-wall coefficients, and its force
  // points.
  static constexpr char kSummary[] =
      "flat plates, each link a rectangle of regularized Stokeslets by the nearest-neighbour "
      "method, with a wall's image system";
  static std::vector<FluidParameter> Parameters();
  static std::unique_ptr<Fluid> Make(const mjModel* m, const RftDrag& segments,
                                     const RftDragOverrides& overrides);
  static double ForcePoints(const mjModel* m, const RftDrag& segments,
                            const RftDragOverrides& overrides);

  double TowingDrag_N(double speed_m_s) const override;
  const PlateSettings& settings() const { return settings_; }
  double blob_m() const { return blob_m_; }
  // The wall's plane z = wall_z, if any.
  std::optional<double> wall_z_m() const;
  int force_points() const;

 private:
  Eigen::MatrixXd ComputeResistance(const mjModel* m, const mjData* d,
                                    const Eigen::Vector3d& origin_W) const override;
  // The plates' even half alone when they are mirror-symmetric.
  Eigen::MatrixXd ComputeInPlaneResistance(const mjModel* m, const mjData* d,
                                           const Eigen::Vector3d& origin_W,
                                           bool* out_of_plane_left_out) const override;
  // The plates on d's segments.
  std::vector<PlacedSurface> Plates(const mjModel* m, const mjData* d) const;
  double shape_tolerance_rad() const override { return settings_.shape_tolerance_rad; }
  double secant_reach_rad() const override { return settings_.secant_reach_rad; }
  double fit_tolerance() const override { return settings_.fit_tolerance; }
  // R for the plates placed as given, with the cached self blocks (and
  // the wall's images).
  Eigen::MatrixXd Resistance(
      const std::vector<PlacedSurface>& plates, const Eigen::Vector3d& c,
      SurfaceSolve solve = SurfaceSolve::kMirrorHalvesWhenSymmetric,
      bool* out_of_plane_left_out = nullptr) const;

  PlateSettings settings_;
  double blob_m_ = 0.0;
  std::vector<SurfaceMesh> meshes_;  // one per segment, in geom_ids() order
  // Each plate's own block in its frame, at eps and (Richardson) eps / 2.
  std::vector<Eigen::MatrixXd> self_blocks_, half_blob_self_blocks_;
};

}  // namespace ipmc
