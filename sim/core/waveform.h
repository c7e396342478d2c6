// Travelling-wave references (paper section 2.2 and 5.1) and their
// discretisation into per-link relative tip-deflection references.
//
//   eq. 2:  y(x, t) = (c0 + c1 x + c2 x^2) sin(2 pi / lambda (x - Vp t))
//   eq. 3:  y(x, t) = c x^alpha sin(2 pi / lambda (x - Vp t)),  Vp = lambda f
//
// Units at this interface are the paper's: x in mm along the body from the
// head (x = 0 at the root of link 1), y in um. Coefficients:
// c0 [um], c1 [um/mm], c2 [um/mm^2], c [um/mm^alpha]. With Table 4
// (c1 = 200 um/mm, lambda = 32 mm, f = 0.01 Hz) the tip at 31 mm has a
// 6.2 mm amplitude. A negative frequency sends the wave tail-to-head.
//
// Discretisation ("projection"): P_0 = (0, y(0, t)); P_q is the point of
// the wave, beyond P_(q-1), at straight-line distance s_q (the segment
// pitch) from P_(q-1); phi_q is the angle of P_(q-1) P_q to the x axis,
// phi_0 = 0; link q's reference is its relative tip deflection
// r_q = L_q sin(phi_q - phi_(q-1)) [mm].
#pragma once

#include <string>
#include <vector>

namespace ipmc {

enum class WaveformKind { kPolynomial, kFractional };

struct WaveformConfig {
  WaveformKind kind = WaveformKind::kPolynomial;
  double c0_um = 0.0;
  double c1_um_per_mm = 200.0;
  double c2_um_per_mm2 = 0.0;
  double c_um = 0.0;            // eq. 3, [um/mm^alpha]
  double alpha = 0.5;           // eq. 3, in (0, 1]
  double frequency_Hz = 0.01;   // != 0
  double wavelength_mm = 32.0;  // > 0
  void Validate() const;        // FieldError (std::invalid_argument) naming the field
};

// [waveform]: the wave, and the fade-in of the references: they are
// multiplied by (1 - cos(pi t / T_r)) / 2 for t < T_r = start_ramp_cycles
// / f, so the run starts without a jump. The wave is checked by its
// Validate(); start_ramp_cycles against the run's cycles by its key.
struct WaveformScenario : WaveformConfig {
  double start_ramp_cycles = 0.25;
};

// The start ramp's fade-in: (1 - cos(pi t / T_r)) / 2 for t < T_r =
// ramp_s, then 1.
double StartRamp(double t_s, double ramp_s);

// y(x, t) [um].
double WaveY_um(const WaveformConfig& wave, double x_mm, double t_s);

struct LinkGeometry {
  std::vector<double> pitch_mm;   // s_q: hinge q to hinge q+1 (last: to the tip)
  std::vector<double> length_mm;  // L_q: the link's own length
};

// The paper's three links: L = 10 mm, pitch 10.25 / 10.5 / 10.25 mm
// (hinges at the middle of the 0.5 mm gaps).
LinkGeometry PaperLinkGeometry();

struct DiscreteWave {
  std::vector<double> joint_x_mm, joint_y_mm;  // P_0..P_n
  std::vector<double> relative_deflection_mm;  // r_1..r_n
};

DiscreteWave DiscretiseWave(const WaveformConfig& wave, const LinkGeometry& geometry, double t_s);

}  // namespace ipmc
