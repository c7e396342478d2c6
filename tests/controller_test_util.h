// What the controllers' tests share: gain and phase of a response, and
// eq. 12's PID and eq. 14's fractional integrator in the paper's linear
// loop (no clamp).
#pragma once

#include <cmath>
#include <complex>

#include "controllers/fractional_integrator.h"
#include "controllers/pid.h"
#include "sim/base/numbers.h"

namespace ipmc::testing {

inline double Db(std::complex<double> h) { return 20 * std::log10(std::abs(h)); }
inline double Deg(std::complex<double> h) { return std::arg(h) * 180 / kPi; }

// Eq. 12's gains (the PidController::Config defaults), unclamped.
inline PidController::Config LinearPid(double sample_period_s = 1e-3) {
  PidController::Config config;  // eq. 12 gains
  config.clamp_enabled = false;
  config.sample_period_s = sample_period_s;
  return config;
}

inline FractionalIntegrator::Config WideBandIntegrator(double sample_period_s) {
  // "Exact-ish" realisation: 20 pairs on [1e-5, 1e5] rad/s (two per decade).
  FractionalIntegrator::Config config;  // eq. 14 gain and order
  config.oustaloup_n = 20;
  config.w_low_rad_s = 1e-5;
  config.w_high_rad_s = 1e5;
  config.clamp_enabled = false;
  config.sample_period_s = sample_period_s;
  return config;
}

}  // namespace ipmc::testing
