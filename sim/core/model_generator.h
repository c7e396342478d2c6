// Writes MJCF for a planar N-link IPMC flagellum swimming in Stokes flow.
//
// Geometry (Table 1 of the paper for the default): links of length L_q
// [mm], width w [mm] (normal to the bending plane) and thickness h [um]
// (in the bending plane), separated by gaps g [mm]; hinges about z sit at
// the middle of each gap of rigid links. An optional rigid head (the
// electrode clamp that link 1 bends against) precedes link 1. The root is
// free in the x-y plane (slide x, slide y, hinge z) or welded ("clamped",
// as on the test bench).
//
// Each link is n rigid sub-segments joined by hinges at their ends, with
// no gap. n = 1: one rigid link. n >= 2: n - 1 sub-segments of
// l = L_q / (n - 1/2) and a last one of l / 2 ending at the link's tip;
// the link's root hinge sits at the strip's root (the gap before it is
// rigid, part of the previous link's last sub-segment).
//
// Mechanics (assumptions, overridable): mass from density rho; each hinge
// carries the strip's bending stiffness for its share s of the length,
// k = E I / s with I = w h^3 / 12 (discrete elastic rods weight each hinge
// by its Voronoi length): s = l / 2 for a link's root hinge, whose other
// side is the stiff junction, s = l for the others, the last one's share
// reaching the tip, so the shares add up to L_q and each interior hinge
// sits at the middle of its share (second order in l, docs/DYNAMICS.md);
// for n = 1, k = 2 E I / L, the stiffness of a cantilever under an end
// moment: M L^2 / (2 E I) = L M / k. Damping c = 2 zeta_h sqrt(k J)
// (J = m_s l^2 / 3, the sub-segment's inertia about its hinge) damps the
// rigid sub-segment's hinge mode with ratio zeta_h.
//
// Fluid: the <custom> fields read by the ipmc_swim plugin (rft_drag.h).
#pragma once

#include <string>
#include <vector>

namespace ipmc {

// Most links a generated flagellum may have: each link nests a body in the
// one before, and MuJoCo 2.2's XML reader refuses the nesting of 100 links
// ("XML parse error 18"); 90 still load.
constexpr std::size_t kMaxGeneratedLinks = 64;

// Most bodies the generator nests: every link and sub-segment is a body in
// the one before (a kinematic chain is a nesting of bodies in MJCF), and
// MuJoCo 2.2's XML reader (tinyxml2) refuses elements nested deeper than
// 99 (XML_ELEMENT_DEPTH_EXCEEDED): <mujoco>, <worldbody>, the bodies and
// the innermost body's <joint>/<geom>. So head + links x segments_per_link
// <= 96: 31 sub-segments per link on the paper's three links and head, 32
// on three links without a head, 48 on two. tests/nesting_limit_test.cc
// checks that the limit loads and one body more does not.
constexpr int kMaxNestedBodies = 96;
// The largest segments_per_link for `links` links with or without a head.
int MaxSegmentsPerLink(int links, bool head);

struct FlagellumSpec {
  std::vector<double> link_lengths_mm = {10.0, 10.0, 10.0};
  int segments_per_link = 1;            // [1, MaxSegmentsPerLink(links, head)]
  double gap_mm = 0.5;
  double width_mm = 3.0;
  double thickness_um = 250.0;
  double head_length_mm = 1.0;          // 0: no head, link 1 is the root
  double density_kg_m3 = 2000.0;
  double bending_modulus_Pa = 0.25e9;
  double hinge_damping_ratio = 1.0;     // zeta_h
  bool clamped = false;
  double timestep_s = 1e-4;
  std::string integrator = "implicit";  // Euler | implicit | RK4
  // Resistive-force theory (see plugin/fluid/rft_drag.h).
  double viscosity_Pa_s = 1.0e-3;
  std::string coefficients = "gray_hancock";  // gray_hancock | lighthill | direct
  double wavelength_mm = 32.0;
  double equivalent_radius_mm = 0.0;    // 0: (w + h) / 4, Batchelor's flat strip
  double xi_normal_N_s_m2 = 0.0;        // only with coefficients = direct
  double xi_tangential_N_s_m2 = 0.0;
  double fluid_density_kg_m3 = 1000.0;
  // IPMC actuators on every link (plugin/actuators/ipmc_actuators.h), Table 2
  // parameters; needs a hinge per link (a head, or a clamped root), which
  // Validate() requires.
  bool ipmc_actuators = true;
  std::string plants = "uniform";           // uniform | table2
  std::string ipmc_model = "g1";            // g1 | g2
  // The links' own plants of eq. 5 (G1) or eq. 6 (G2) over the assigned,
  // length-scaled ones: each empty (the assigned plant) or one value per
  // link, written as ipmc_a0_mm_per_V [mm/V], ipmc_b1 [s or s^alpha],
  // ipmc_b2_s2 [s^2] and ipmc_alpha.
  std::vector<double> a0_mm_per_V, b1, b2_s2, alpha;
  std::string actuation = "distributed";    // distributed | single
  std::string name = "flagellum";

  // Throws FieldError naming the field (link_lengths_mm, ...) and its allowed range.
  void Validate() const;
  int Links() const { return static_cast<int>(link_lengths_mm.size()); }
};

// Derived mechanics of one sub-segment of link `link_index` and of the
// hinge at its root, in SI, as written into the MJCF; `segment_index` 0 is
// the link's first sub-segment (its hinge is the link's root hinge).
struct SegmentMechanics {
  double length_m;
  double mass_kg;
  double inertia_about_hinge_kg_m2;
  double hinge_share_m;  // s
  double stiffness_N_m_rad;
  double damping_N_m_s_rad;
};
SegmentMechanics ComputeSegmentMechanics(const FlagellumSpec& spec, int link_index,
                                         int segment_index);

std::string GenerateFlagellumMjcf(const FlagellumSpec& spec);

}  // namespace ipmc
