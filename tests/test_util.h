// Shared helpers for the test suites.
#pragma once

#include <gtest/gtest.h>
#include <mujoco/mujoco.h>

#include <functional>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

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

// The one-line message of the std::runtime_error that `statement` throws,
// or "" (with a failure) if it throws none; `given` is what it was given.
inline std::string OneLineErrorOf(const std::function<void()>& statement,
                                  const std::string& given) {
  try {
    statement();
  } catch (const std::runtime_error& error) {
    const std::string message = error.what();
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    return message;
  }
  ADD_FAILURE() << "no error for:\n" << given;
  return "";
}

// Fails a test on any MuJoCo warning (mju_warning: the engine's and the
// coupling's) that the test did not declare with ExpectWarning. The
// collector is mju_user_warning while the test runs (the previous handler
// is put back after); it may be called from any thread that steps.
// Derive a suite's fixture from it: class MySuite : public MujocoWarnings {}.
class MujocoWarnings : public ::testing::Test {
 public:
  // Warnings containing `needle` are expected; at least `min_count` of
  // them must arrive.
  void ExpectWarning(const std::string& needle, int min_count = 1) {
    expected_.emplace_back(needle, min_count);
  }
  // The warnings received so far, in order.
  std::vector<std::string> Received() const {
    std::lock_guard<std::mutex> lock(Mutex());
    return received_;
  }
  // How many received warnings contain `needle`.
  int Count(const std::string& needle) const {
    int count = 0;
    for (const std::string& warning : Received()) count += warning.find(needle) != std::string::npos;
    return count;
  }

 protected:
  void SetUp() override {
    std::lock_guard<std::mutex> lock(Mutex());
    previous_ = mju_user_warning;
    Active() = this;
    mju_user_warning = &Collect;
  }
  void TearDown() override {
    {
      std::lock_guard<std::mutex> lock(Mutex());
      mju_user_warning = previous_;
      Active() = nullptr;
    }
    for (const std::string& warning : Received()) {
      bool expected = false;
      for (const auto& [needle, min_count] : expected_) {
        expected = expected || warning.find(needle) != std::string::npos;
      }
      if (!expected) ADD_FAILURE() << "unexpected MuJoCo warning: " << warning;
    }
    for (const auto& [needle, min_count] : expected_) {
      const int count = Count(needle);
      if (count < min_count) {
        ADD_FAILURE() << "expected at least " << min_count << " MuJoCo warning(s) containing '"
                      << needle << "', got " << count;
      }
    }
  }

 private:
  static void Collect(const char* message) {
    std::lock_guard<std::mutex> lock(Mutex());
    if (Active()) Active()->received_.emplace_back(message);
  }
  static std::mutex& Mutex() {
    static std::mutex mutex;
    return mutex;
  }
  static MujocoWarnings*& Active() {
    static MujocoWarnings* active = nullptr;
    return active;
  }

  void (*previous_)(const char*) = nullptr;
  std::vector<std::string> received_;
  std::vector<std::pair<std::string, int>> expected_;
};

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
