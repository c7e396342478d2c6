// Shared helpers for the test suites.
#pragma once

#include <gtest/gtest.h>

#include <functional>
#include <memory>
#include <stdexcept>
#include <string>

#include "sim/core/gait.h"
#include "sim/runs/gait_run.h"
#include "sim/core/model_generator.h"
#include "sim/core/simulation.h"

namespace ipmc::testing {

// A slender chain for Stokes-limit tests: density 100 kg/m^3, so the
// viscous relaxation time rho A / xi_n is 29 ms, against gait periods of
// 50 s (kStokesFrequency_Hz: omega tau = 3.6e-3); free hinges (no bending
// stiffness) and no head.
constexpr double kStokesFrequency_Hz = 0.02;
inline FlagellumSpec StokesChain(int links, double total_length_mm) {
  FlagellumSpec spec;
  spec.link_lengths_mm.assign(links, total_length_mm / links);
  spec.gap_mm = 0.0;
  spec.head_length_mm = 0.0;
  spec.density_kg_m3 = 100.0;
  spec.bending_modulus_Pa = 0.0;
  spec.hinge_damping_ratio = 0.0;
  spec.timestep_s = 1e-3;
  spec.ipmc_actuators = false;
  spec.name = "stokes_chain";
  return spec;
}

// Fails unless `statement` throws `Exception` whose message contains
// `needle`.
template <typename Exception, typename Function>
void ExpectThrowMentioning(Function statement, const std::string& needle) {
  try {
    statement();
    ADD_FAILURE() << "expected an exception mentioning '" << needle << "'";
  } catch (const Exception& error) {
    EXPECT_NE(std::string(error.what()).find(needle), std::string::npos) << error.what();
  }
}

// Fails unless `statement` throws std::invalid_argument naming `field`.
inline void ExpectInvalidArgument(const std::function<void()>& statement,
                                  const std::string& field) {
  ExpectThrowMentioning<std::invalid_argument>(statement, field);
}

inline std::unique_ptr<Simulation> MakeSimulation(const FlagellumSpec& spec) {
  return std::make_unique<Simulation>(LoadModelString(GenerateFlagellumMjcf(spec)), spec.name);
}

inline GaitRunResult RunGaitOn(const FlagellumSpec& spec, const Gait& gait, int cycles) {
  auto sim = MakeSimulation(spec);
  GaitRunOptions options;
  options.cycles = cycles;
  return RunGait(*sim, gait, options);
}

}  // namespace ipmc::testing
