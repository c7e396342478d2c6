#include "sim/core/electrical.h"

#include <cmath>
#include <string>

#include "sim/base/error.h"

namespace ipmc {
namespace {

constexpr char kWho[] = "electrical";

}  // namespace

void ElectricalConfig::Validate() const {
  RequireFinitePositive(kWho, "series_resistance_ohm_m2", series_resistance_ohm_m2);
  RequireFinitePositive(kWho, "parallel_resistance_ohm_m2", parallel_resistance_ohm_m2);
  RequireFinitePositive(kWho, "capacitance_F_m2", capacitance_F_m2);
  RequireFinitePositive(kWho, "electrode_width_mm", electrode_width_mm);
}

IpmcImpedance::IpmcImpedance(double series_ohm, double parallel_ohm, double capacitance_F)
    : r_s_(series_ohm), r_p_(parallel_ohm), c_(capacitance_F) {
  RequireFinitePositive(kWho, "series_ohm", series_ohm);
  RequireFinitePositive(kWho, "parallel_ohm", parallel_ohm);
  RequireFinitePositive(kWho, "capacitance_F", capacitance_F);
}

IpmcImpedance IpmcImpedance::ForArea(const ElectricalConfig& config, double area_m2) {
  config.Validate();
  RequireFinitePositive(kWho, "area_m2", area_m2);
  return IpmcImpedance(config.series_resistance_ohm_m2 / area_m2,
                       config.parallel_resistance_ohm_m2 / area_m2,
                       config.capacitance_F_m2 * area_m2);
}

HoldEnergies IpmcImpedance::Hold(double voltage_V, double hold_s) {
  const double tau = time_constant_s();
  const double v_inf = voltage_V * r_p_ / (r_s_ + r_p_);
  const double a = v_c_ - v_inf;
  const double x = hold_s / tau;
  // E1 = tau (1 - e^-x), E2 = tau / 2 (1 - e^-2x), accurate for small x.
  const double e1 = -tau * std::expm1(-x);
  const double e2 = -0.5 * tau * std::expm1(-2.0 * x);
  const double drop = voltage_V - v_inf;  // across R_s at the end of a long hold
  HoldEnergies w;
  w.input_J = voltage_V / r_s_ * (drop * hold_s - a * e1);
  w.series_J = (drop * drop * hold_s - 2.0 * drop * a * e1 + a * a * e2) / r_s_;
  w.parallel_J = (v_inf * v_inf * hold_s + 2.0 * v_inf * a * e1 + a * a * e2) / r_p_;
  const double v_end = v_inf + a * std::exp(-x);
  w.stored_change_J = 0.5 * c_ * (v_end * v_end - v_c_ * v_c_);
  v_c_ = v_end;
  return w;
}

std::complex<double> IpmcImpedance::Impedance_ohm(double omega_rad_s) const {
  return r_s_ + r_p_ / std::complex<double>(1.0, omega_rad_s * r_p_ * c_);
}

}  // namespace ipmc
