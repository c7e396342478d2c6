// Electrical power of the IPMC links (docs/ENERGY.md): each link's strip as
// the lumped impedance of an IPMC between its electrodes,
//
//   V --- R_s ---+--- R_p ---+
//                |           |
//                +---- C ----+--- 0
//
// a series resistance R_s (electrodes and contacts) before a parallel
// branch of the double-layer capacitance C and the leakage resistance R_p:
// the lumped circuit of Bonomo, Fortuna, Giannone, Graziani & Strazzeri
// (2007, Smart Mater. Struct. 16, 1-12) and of Cha, Aureli & Porfiri
// (2012, J. Appl. Phys. 111, 124901) with their nonlinear and Warburg
// elements left out. The values are per unit electrode area and scale with
// each link's electrode area A = L_q x width: R_s = r_s / A, R_p = r_p / A,
// C = c A (the time constants do not depend on A).
//
// The applied voltage V is the controller's clamped output, held over each
// controller sample (zero-order hold). With v the capacitor's voltage,
//   I = (V - v) / R_s,   C dv/dt = I - v / R_p
// so   dv/dt = (v_inf - v) / tau,  v_inf = V R_p / (R_s + R_p),
//      tau = C R_s R_p / (R_s + R_p),
// and over a hold of length h from v_0, exactly,
//   v(t) = v_inf + a e^(-t/tau),  a = v_0 - v_inf.
// With E1 = tau (1 - e^(-h/tau)) and E2 = tau / 2 (1 - e^(-2h/tau)):
//   electrical energy in  W_in = V / R_s ((V - v_inf) h - a E1)
//   dissipated in R_s     W_s  = ((V - v_inf)^2 h - 2 (V - v_inf) a E1 + a^2 E2) / R_s
//   dissipated in R_p     W_p  = (v_inf^2 h + 2 v_inf a E1 + a^2 E2) / R_p
//   stored in C           dW_C = C (v(h)^2 - v_0^2) / 2
// and W_in = W_s + W_p + dW_C (tests/electrical_test.cc, to rounding).
#pragma once

#include <complex>

namespace ipmc {

struct ElectricalConfig {
  bool enabled = false;                         // off: no electrical power is reported
  double series_resistance_ohm_m2 = 1.0e-4;     // r_s, > 0 (1 ohm cm^2)
  double parallel_resistance_ohm_m2 = 1.0e-2;   // r_p, > 0 (100 ohm cm^2)
  double capacitance_F_m2 = 10.0;               // c, > 0 (1 mF/cm^2)
  double electrode_width_mm = 3.0;              // > 0, the strip's width
  // Throws FieldError "electrical: FIELD must be finite and > 0, got V".
  void Validate() const;
};

// The energies of one hold interval [J].
struct HoldEnergies {
  double input_J = 0.0;           // the integral of V I
  double series_J = 0.0;          // dissipated in R_s
  double parallel_J = 0.0;        // dissipated in R_p
  double stored_change_J = 0.0;   // C (v_end^2 - v_start^2) / 2
};

// One link's network, starting uncharged.
class IpmcImpedance {
 public:
  // Throws FieldError unless every value is finite and > 0.
  IpmcImpedance(double series_ohm, double parallel_ohm, double capacitance_F);
  // The link of electrode area `area_m2` with `config`'s values per area.
  static IpmcImpedance ForArea(const ElectricalConfig& config, double area_m2);

  // Holds `voltage_V` for `hold_s` (>= 0) and advances the capacitor
  // exactly; returns the interval's energies.
  HoldEnergies Hold(double voltage_V, double hold_s);
  // Z(omega) = R_s + R_p / (1 + j omega R_p C).
  std::complex<double> Impedance_ohm(double omega_rad_s) const;

  double capacitor_voltage_V() const { return v_c_; }
  double series_ohm() const { return r_s_; }
  double parallel_ohm() const { return r_p_; }
  double capacitance_F() const { return c_; }
  double time_constant_s() const { return c_ * r_s_ * r_p_ / (r_s_ + r_p_); }

 private:
  double r_s_, r_p_, c_;
  double v_c_ = 0.0;
};

}  // namespace ipmc
