// Identification (paper sections 4.1, 4.2): Welch's frequency response
// against a known linear system, Levy's fits of G1 and G2, the
// identification of the simulated clamped flagellum against the parameters
// the simulator was given, and the identify / design / pipeline
// subcommands. The controller design itself (5.2) is
// tests/controller_design_test.cc.
#include <gtest/gtest.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iterator>
#include <limits>
#include <memory>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "sim/linear/ipmc_link_model.h"
#include "sim/base/numbers.h"
#include "sim/cli/design_command.h"
#include "sim/cli/identify_command.h"
#include "sim/cli/pipeline_command.h"
#include "sim/core/scenario_simulation.h"
#include "sim/core/simulation.h"
#include "sim/identify/controller_design.h"
#include "sim/identify/levy.h"
#include "sim/identify/welch.h"
#include "sim/linear/frequency_response.h"
#include "sim/runs/bench_run.h"
#include "tests/cli_util.h"
#include "tests/test_util.h"

namespace ipmc::testing {
namespace {

namespace fs = std::filesystem;
using Complex = std::complex<double>;

constexpr double kSamplePeriod_s = 1e-3;  // the bench's 1 kHz

// The test chirp: 3 V, 0.1 to 20 Hz over 60 s (the paper's runs 200 s to
// 200 Hz; this one keeps the tests short and still covers [0.5, 50] rad/s
// with a 0.47 rad/s resolution).
BenchSignal TestChirp(double duration_s = 60.0) {
  BenchSignal chirp;
  chirp.kind = BenchSignal::Kind::kChirp;
  chirp.amplitude_V = 3.0;
  chirp.start_Hz = 0.1;
  chirp.end_Hz = 20.0;
  chirp.duration_s = duration_s;
  chirp.sample_rate_Hz = 1000.0;
  return chirp;
}

// A sampled experiment on a linear plant, recorded like the bench: the
// voltage x_k is held over [t_k, t_k+1) and y_k = c x(t_k) + d x_k
// (exact zero-order-hold integration).
struct LinearRecord {
  std::vector<double> input;
  std::vector<double> output;
  DiscreteStateSpace plant;
};

LinearRecord SimulateLinear(const StateSpace& plant, const BenchSignal& chirp,
                            double noise_mm = 0.0, unsigned seed = 1) {
  LinearRecord record;
  record.plant = DiscretizeZeroOrderHold(plant, kSamplePeriod_s);
  const long samples = std::lround(chirp.duration_s / kSamplePeriod_s);
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, noise_mm > 0 ? noise_mm : 1.0);
  Eigen::VectorXd x = Eigen::VectorXd::Zero(plant.States());
  Eigen::VectorXd next(plant.States());
  for (long k = 0; k < samples; ++k) {
    const double u = chirp.VoltageAt(k * kSamplePeriod_s);
    record.input.push_back(u);
    record.output.push_back(record.plant.c.row(0).dot(x) + record.plant.d(0, 0) * u +
                            (noise_mm > 0 ? noise(rng) : 0.0));
    next.noalias() = record.plant.a * x;
    next += record.plant.b.col(0) * u;
    x.swap(next);
  }
  return record;
}

// The sampled system's exact response from x_k to y_k at e^(j w T).
Complex DiscreteResponse(const DiscreteStateSpace& plant, double w_rad_s) {
  const int n = static_cast<int>(plant.a.rows());
  const Complex z = std::exp(Complex(0.0, w_rad_s * kSamplePeriod_s));
  const Eigen::MatrixXcd resolvent =
      z * Eigen::MatrixXcd::Identity(n, n) - plant.a.cast<Complex>();
  const Eigen::VectorXcd solved = resolvent.partialPivLu().solve(plant.b.cast<Complex>());
  return (plant.c.cast<Complex>() * solved)(0) + plant.d(0, 0);
}

double RelativeDeviation(double identified, double given) { return identified / given - 1.0; }

// -------------------------------------------------------------- Welch ---

TEST(WelchTest, RecoversAKnownLinearSystemWhereCoherenceIsHigh) {
  // Link 3's P = s^-0.5 G1 (eq. 7; s^-0.5 by the simulator's 8 Oustaloup
  // pairs), integrated exactly at 1 kHz, 1 um measurement noise.
  const StateSpace plant = LinkStateSpace(PaperLinkParams(3, IpmcModelKind::kG1));
  const BenchSignal chirp = TestChirp();
  const LinearRecord record = SimulateLinear(plant, chirp, 1e-3);
  const FrequencyResponseEstimate estimate =
      EstimateFrequencyResponse(record.input, record.output);
  // 60000 samples: L = floor(60000 / 4.5) = 13333 would put the last
  // section one sample past the end, so L = 13332, step 6666.
  EXPECT_EQ(estimate.section_samples, 13332);
  EXPECT_EQ(estimate.section_step, 6666);
  EXPECT_EQ(estimate.sections_per_record, 8);
  EXPECT_NEAR(estimate.w_rad_s.front(), 2 * kPi * 1000.0 / 13332, 1e-12);

  // Where the chirp has swept (w from 8 rad/s to just below its 126 rad/s
  // end) and the coherence is high, H1 matches the sampled system's exact
  // response. Measured: 2.5 % and 1.4 deg at most, over 189 of the 218
  // bins (the largest magnitude error sits at the resonance, 21.7 rad/s,
  // where |H| changes across the Hamming window's main lobe).
  double worst_magnitude = 0, worst_phase_deg = 0;
  int checked = 0;
  for (std::size_t i = 0; i < estimate.w_rad_s.size(); ++i) {
    const double w = estimate.w_rad_s[i];
    if (w < 8.0 || w > 110.0 || estimate.coherence[i] < 0.99) continue;
    const Complex ratio = estimate.response[i] / DiscreteResponse(record.plant, w);
    worst_magnitude = std::max(worst_magnitude, std::abs(std::abs(ratio) - 1.0));
    worst_phase_deg = std::max(worst_phase_deg, std::abs(std::arg(ratio)) * 180 / kPi);
    ++checked;
  }
  std::printf("known system: %d bins in [8, 110] rad/s with coherence > 0.99; worst %.4f "
              "relative, %.3f deg\n",
              checked, worst_magnitude, worst_phase_deg);
  EXPECT_GT(checked, 170);
  EXPECT_LT(worst_magnitude, 0.035);
  EXPECT_LT(worst_phase_deg, 2.0);

  // Below 8 rad/s the chirp passes while the first section's window is
  // still rising, and s^-0.5's long memory puts into that section output
  // whose input the window suppressed: H1 is biased there (measured 2.3
  // deg at 5.2 rad/s, 35 % and 27 deg at 0.94 rad/s) although the
  // coherence stays above 0.96. This is the method's own limit on a chirp
  // (the simulator is not involved).
  // Above the chirp's end (20 Hz) only the noise remains: the coherence
  // falls to that of unrelated signals averaged over 8 sections.
  double coherence_in_band = 0, coherence_above = 0;
  int in_band = 0, above = 0;
  for (std::size_t i = 0; i < estimate.w_rad_s.size(); ++i) {
    const double w = estimate.w_rad_s[i];
    if (w > 8.0 && w < 110.0) {
      coherence_in_band += estimate.coherence[i];
      ++in_band;
    }
    if (w > 2 * kPi * 22.0 && w < 300.0) {
      coherence_above += estimate.coherence[i];
      ++above;
    }
  }
  coherence_in_band /= in_band;
  coherence_above /= above;
  std::printf("mean coherence: %.5f in [8, 110] rad/s, %.3f in [138, 300] rad/s\n",
              coherence_in_band, coherence_above);
  EXPECT_GT(coherence_in_band, 0.99);
  EXPECT_LT(coherence_above, 0.3);
}

TEST(WelchTest, PoolsRepeatedRecords) {
  const StateSpace plant = SecondOrderLag(0.37609, 23.31e-3, 2.13e-3);
  const BenchSignal chirp = TestChirp(20.0);
  const LinearRecord a = SimulateLinear(plant, chirp, 2e-3, 1);
  const LinearRecord b = SimulateLinear(plant, chirp, 2e-3, 2);
  // Two identical records pool to the single record's response, with no
  // spread between them.
  const FrequencyResponseEstimate one = EstimateFrequencyResponse(a.input, a.output);
  const FrequencyResponseEstimate same =
      EstimateFrequencyResponse({a.input, a.input}, {a.output, a.output});
  ASSERT_EQ(one.response.size(), same.response.size());
  EXPECT_EQ(same.records, 2);
  ASSERT_EQ(same.magnitude_std.size(), same.response.size());
  for (std::size_t i = 0; i < one.response.size(); ++i) {
    EXPECT_NEAR(std::abs(same.response[i] - one.response[i]), 0.0,
                1e-12 * std::abs(one.response[i]));
    EXPECT_NEAR(same.magnitude_std[i], 0.0, 1e-12 * std::abs(one.response[i]));
    EXPECT_NEAR(same.input_psd[i], one.input_psd[i], 1e-12 * one.input_psd[i]);
  }
  EXPECT_TRUE(one.magnitude_std.empty());
  // Different noise: a spread, largest where the chirp gives no input.
  const FrequencyResponseEstimate pooled =
      EstimateFrequencyResponse({a.input, b.input}, {a.output, b.output});
  double in_band = 0, above = 0;
  for (std::size_t i = 0; i < pooled.w_rad_s.size(); ++i) {
    const double w = pooled.w_rad_s[i];
    if (w > 5 && w < 50) in_band = std::max(in_band, pooled.magnitude_std[i]);
    if (w > 200 && w < 300) above = std::max(above, pooled.magnitude_std[i]);
  }
  EXPECT_GT(in_band, 0.0);
  EXPECT_GT(above, 10 * in_band);
}

TEST(WelchTest, OneSidedSpectralDensityOfASine) {
  // A 1 V sine on a bin: its power 1/2 V^2, summed over the window's main
  // lobe of the one-sided density times the bin width.
  const int samples = 9000;  // L = 2000, bins of 0.5 Hz at 1 kHz
  std::vector<double> x(samples), y(samples);
  for (int k = 0; k < samples; ++k) {
    x[k] = std::sin(2 * kPi * 50.0 * k * 1e-3);
    y[k] = 2.0 * x[k];
  }
  const FrequencyResponseEstimate e = EstimateFrequencyResponse(x, y);
  ASSERT_EQ(e.section_samples, 2000);
  double power = 0;
  for (std::size_t i = 0; i < e.frequency_Hz.size(); ++i) {
    if (std::abs(e.frequency_Hz[i] - 50.0) < 5.0) power += e.input_psd[i] * 0.5;
  }
  EXPECT_NEAR(power, 0.5, 1e-3);
  EXPECT_NEAR(std::abs(e.response[99] - 2.0), 0.0, 1e-9);  // 50 Hz is bin 100
  EXPECT_NEAR(e.coherence[99], 1.0, 1e-9);
}

TEST(WelchTest, RejectsBadInput) {
  const std::vector<double> ok(100, 1.0);
  std::vector<double> nan = ok;
  nan[17] = std::nan("");
  ExpectInvalidArgument([&] { EstimateFrequencyResponse(ok, nan); },
                        "output is not finite at sample 17");
  std::vector<double> inf = ok;
  inf[3] = std::numeric_limits<double>::infinity();
  ExpectInvalidArgument([&] { EstimateFrequencyResponse(inf, ok); }, "input is not finite");
  ExpectInvalidArgument([&] { EstimateFrequencyResponse(ok, std::vector<double>(99, 1.0)); },
                        "output has 99 samples, input 100");
  ExpectInvalidArgument(
      [&] {
        EstimateFrequencyResponse(std::vector<double>(71, 1.0), std::vector<double>(71, 1.0));
      },
      "minimum 72");
  EXPECT_NO_THROW(
      EstimateFrequencyResponse(std::vector<double>(72, 1.0), std::vector<double>(72, 1.0)));
  WelchOptions options;
  options.sample_rate_Hz = 0;
  ExpectInvalidArgument([&] { EstimateFrequencyResponse(ok, ok, options); }, "sample_rate_Hz");
  options.sample_rate_Hz = -1000;
  ExpectInvalidArgument([&] { EstimateFrequencyResponse(ok, ok, options); }, "sample_rate_Hz");
  ExpectInvalidArgument(
      [&] { EstimateFrequencyResponse({ok, std::vector<double>(90, 1.0)}, {ok, ok}); },
      "input[1] has 90 samples");
  ExpectInvalidArgument([&] { EstimateFrequencyResponse({ok}, {ok, ok}); }, "records");
}

// --------------------------------------------------------------- Levy ---

// P(j w) of given parameters on a Welch-like grid (0.1414 rad/s, the paper's
// 200 s records).
void ExactResponse(const IpmcLinkParams& params, std::vector<double>& w,
                   std::vector<Complex>& response) {
  for (int m = 1; m <= 500; ++m) {
    w.push_back(m * 0.14137);
    response.push_back(FittedResponse(params, w.back()));
  }
}

TEST(LevyTest, RecoversG1OfLink3FromNoiseFreeData) {
  const IpmcLinkParams given = PaperLinkParams(3, IpmcModelKind::kG1);  // eq. 7
  std::vector<double> w;
  std::vector<Complex> response;
  ExactResponse(given, w, response);
  const LinkModelFit fit = FitG1Levy(w, response);
  EXPECT_TRUE(fit.stable);
  EXPECT_EQ(fit.params.kind, IpmcModelKind::kG1);
  EXPECT_EQ(fit.params.integrator.order, -0.5);
  // Measured: exact to 1e-13 relative; required: 1 %.
  EXPECT_NEAR(fit.params.a0_mm_per_V, 376.09e-3, 0.01 * 376.09e-3);
  EXPECT_NEAR(fit.params.b1, 23.31e-3, 0.01 * 23.31e-3);
  EXPECT_NEAR(fit.params.b2_s2, 2.13e-3, 0.01 * 2.13e-3);
  EXPECT_NEAR(fit.params.a0_mm_per_V, 376.09e-3, 1e-9);
  EXPECT_NEAR(fit.indices.r_squared, 1.0, 1e-12);
  EXPECT_LT(fit.indices.levy_cost, 1e-20);
  // The band [0.2, 50] rad/s: points 2..353 of the grid.
  EXPECT_EQ(fit.indices.points, 352);
  EXPECT_NEAR(fit.indices.w_first_rad_s, 2 * 0.14137, 1e-12);
}

TEST(LevyTest, SweepFindsTheOrderOfG2) {
  // Link 3's G2 (Table 2's alpha = 1.71 and a0, the fitted b1).
  const IpmcLinkParams given = PaperLinkParams(3, IpmcModelKind::kG2);
  std::vector<double> w;
  std::vector<Complex> response;
  ExactResponse(given, w, response);
  const LinkIdentification id = IdentifyLinkModels(w, response);
  EXPECT_EQ(id.g2_orders_tried, 99);  // 1.01 .. 1.99
  EXPECT_EQ(id.g2_orders_stable, 99);
  EXPECT_TRUE(id.g2.stable);
  EXPECT_NEAR(id.g2.params.alpha, 1.71, 1e-12);
  EXPECT_NEAR(id.g2.params.a0_mm_per_V, given.a0_mm_per_V, 1e-9 * given.a0_mm_per_V);
  EXPECT_NEAR(id.g2.params.b1, given.b1, 1e-9 * given.b1);
  // G1 cannot represent it exactly.
  EXPECT_GT(id.g1.indices.levy_cost, 1e6 * id.g2.indices.levy_cost);
}

TEST(LevyTest, StabilityOfTheFits) {
  // Data from an unstable second-order lag (b1 < 0): Levy recovers it and
  // says so. G2 with b1 < 0 has its pole lambda = -1/b1 > 0 on the
  // positive real axis of lambda = s^alpha: unstable for every alpha.
  IpmcLinkParams unstable = PaperLinkParams(3, IpmcModelKind::kG1);
  unstable.b1 = -0.01;
  std::vector<double> w;
  std::vector<Complex> response;
  ExactResponse(unstable, w, response);
  const LinkModelFit g1 = FitG1Levy(w, response);
  EXPECT_NEAR(g1.params.b1, -0.01, 1e-9);
  EXPECT_FALSE(g1.stable);

  IpmcLinkParams negative_g2 = PaperLinkParams(3, IpmcModelKind::kG2);
  negative_g2.b1 = -negative_g2.b1;
  w.clear();
  response.clear();
  ExactResponse(negative_g2, w, response);
  const LinkModelFit g2 = FitG2LevyAtOrder(w, response, negative_g2.alpha);
  EXPECT_NEAR(g2.params.b1, negative_g2.b1, 1e-9);
  EXPECT_FALSE(g2.stable);
  const LinkIdentification id = IdentifyLinkModels(w, response);
  // No order gives a stable fit: the sweep keeps the least J, flagged.
  EXPECT_EQ(id.g2_orders_stable, 0);
  EXPECT_FALSE(id.g2.stable);
  EXPECT_NEAR(id.g2.params.alpha, negative_g2.alpha, 1e-12);
}

TEST(LevyTest, FitIndicesFollowTheirDefinitions) {
  // Data = model + a constant complex error c: MSE = |c|^2, MAD = MD = |c|,
  // R^2 = 1 - K |c|^2 / sum |P - mean P|^2; J from the data's G.
  const IpmcLinkParams model = PaperLinkParams(2, IpmcModelKind::kG1);
  std::vector<double> w;
  std::vector<Complex> response;
  ExactResponse(model, w, response);
  const Complex c(3e-4, -4e-4);  // |c| = 5e-4 mm/V
  for (Complex& p : response) p += c;
  LevyOptions options;
  options.w_low_rad_s = 1.0;
  options.w_high_rad_s = 40.0;
  const FitIndices i = ComputeFitIndices(w, response, model, options);
  Complex mean = 0.0;
  double total = 0.0, levy = 0.0;
  int points = 0;
  for (std::size_t k = 0; k < w.size(); ++k) {
    if (w[k] < 1.0 || w[k] > 40.0) continue;
    mean += response[k];
    ++points;
  }
  mean /= static_cast<double>(points);
  for (std::size_t k = 0; k < w.size(); ++k) {
    if (w[k] < 1.0 || w[k] > 40.0) continue;
    total += std::norm(response[k] - mean);
    const Complex s(0.0, w[k]);
    const Complex g = response[k] * std::sqrt(s);
    levy += std::norm(g * (model.b2_s2 * s * s + model.b1 * s + 1.0) - model.a0_mm_per_V);
  }
  EXPECT_EQ(i.points, points);
  EXPECT_NEAR(i.mse, 25e-8, 1e-15);
  EXPECT_NEAR(i.mad, 5e-4, 1e-12);
  EXPECT_NEAR(i.max_deviation, 5e-4, 1e-12);
  EXPECT_NEAR(i.r_squared, 1.0 - points * 25e-8 / total, 1e-12);
  EXPECT_NEAR(i.levy_cost, levy, 1e-9 * levy);
}

TEST(LevyTest, RejectsBadInput) {
  const IpmcLinkParams model = PaperLinkParams(3, IpmcModelKind::kG1);
  std::vector<double> w;
  std::vector<Complex> response;
  ExactResponse(model, w, response);  // 0.14 .. 70.7 rad/s
  LevyOptions options;
  options.w_high_rad_s = 100.0;
  ExpectInvalidArgument([&] { FitG1Levy(w, response, options); },
                        "reaches outside the data");
  options = LevyOptions{};
  options.w_low_rad_s = 0.1;
  ExpectInvalidArgument([&] { IdentifyLinkModels(w, response, options); },
                        "reaches outside the data");
  options = LevyOptions{};
  options.w_low_rad_s = 10.0;
  options.w_high_rad_s = 10.2;
  ExpectInvalidArgument([&] { FitG1Levy(w, response, options); },
                        "holds 2 points, fewer than 3");
  options.w_high_rad_s = 5.0;
  ExpectInvalidArgument([&] { FitG1Levy(w, response, options); }, "0 < w_low_rad_s < w_high_rad_s");
  std::vector<Complex> short_response(response.begin(), response.end() - 1);
  ExpectInvalidArgument([&] { FitG1Levy(w, short_response); }, "response has 499 points");
  std::vector<Complex> bad = response;
  bad[10] = Complex(std::nan(""), 0.0);
  ExpectInvalidArgument([&] { FitG1Levy(w, bad); }, "response is not finite at point 10");
  std::vector<double> unsorted = w;
  std::swap(unsorted[3], unsorted[4]);
  ExpectInvalidArgument([&] { FitG1Levy(unsorted, response); }, "strictly increasing");
  ExpectInvalidArgument([&] { FitG2LevyAtOrder(w, response, 2.0); }, "alpha");
}

// ------------------------------------------- the simulated clamped robot ---

TEST(IdentificationTest, SimulatedClampedFlagellumGivesItsOwnLinkModels) {
  // Each link driven in turn with the test chirp (60 s, 0.1-20 Hz, 3 V),
  // its relative tip deflection L_q sin(theta_q) identified over
  // [0.47, 50] rad/s (the first Welch bin up).
  const std::string path = std::string(IPMC_SWIM_SOURCE_DIR) + "/models/flagellum3_clamped.xml";
  std::vector<std::unique_ptr<Simulation>> sims;
  for (int q = 0; q < 3; ++q) {
    sims.push_back(std::make_unique<Simulation>(LoadModelFile(path), path));
  }
  const std::vector<IpmcLinkParams> given_plants = AttachedLinkPlants(sims[0]->data());
  std::vector<BenchRecord> records(3);
  std::vector<std::exception_ptr> errors(3);
  std::vector<std::thread> threads;
  for (int q = 0; q < 3; ++q) {
    threads.emplace_back([&, q] {
      try {
        BenchSignal chirp = TestChirp();
        chirp.driven_links = {q + 1};
        records[q] = RunBench(*sims[q], chirp);
      } catch (...) {
        errors[q] = std::current_exception();
      }
    });
  }
  for (std::thread& thread : threads) thread.join();
  for (const std::exception_ptr& error : errors) {
    if (error) std::rethrow_exception(error);
  }

  // The simulator's response is P_q times the rigid hinge's first-order
  // lag 1/(tau s + 1), tau = c/k = 3.2 ms (docs/MODEL.md, "IPMC actuators"), and
  // 0.5 ms of sampling delay (half the 1 ms hold; the bench records the
  // state at the sample time): about 10.5 deg of extra lag at 50 rad/s.
  // Levy's |D|-weighted error counts
  // most above the resonance, where that extra phase lag reads as a
  // sharper resonance (b1 low). Links 1 and 2 also carry the links beyond
  // them through the fluid (drag and their inertia). Measured deviations
  // (a0, b1, b2) with the hinge stiffness 2 E I / L and the model's 0.5 ms
  // step, which damps the hinges with c_eff and holds the moment over the
  // step (plugin/dynamics/step_model.h: a delay of h / 2, 0.6 points of b1
  // against the hinges' own c):
  //   link 1: +2.0 %, -11.4 %, +0.5 %
  //   link 2: -0.6 %, -8.1 %, +2.6 %
  //   link 3: -1.7 %, -7.7 %, +2.8 %
  // Tolerances: a0 5 %, b2 6 %, b1 below the given value by at most 30 %.
  const double measured[3][3] = {{0.020, -0.114, 0.005}, {-0.006, -0.081, 0.026},
                                 {-0.017, -0.077, 0.028}};
  for (int q = 0; q < 3; ++q) {
    const FrequencyResponseEstimate estimate =
        EstimateFrequencyResponse(records[q].voltage_V[q], records[q].relative_mm[q]);
    LevyOptions options;
    options.w_low_rad_s = estimate.w_rad_s.front();
    const LinkIdentification id = IdentifyLinkModels(estimate, options);
    const IpmcLinkParams& given = given_plants[q];
    const IpmcLinkParams& g1 = id.g1.params;
    const double a0 = RelativeDeviation(g1.a0_mm_per_V, given.a0_mm_per_V);
    const double b1 = RelativeDeviation(g1.b1, given.b1);
    const double b2 = RelativeDeviation(g1.b2_s2, given.b2_s2);
    std::printf("link %d: G1 a0 %.5g (%+.1f %%), b1 %.5g (%+.1f %%), b2 %.5g (%+.1f %%), R^2 "
                "%.4f; G2 alpha %.2f, a0 %.5g, b1 %.5g, R^2 %.4f\n",
                q + 1, g1.a0_mm_per_V, 100 * a0, g1.b1, 100 * b1, g1.b2_s2, 100 * b2,
                id.g1.indices.r_squared, id.g2.params.alpha, id.g2.params.a0_mm_per_V,
                id.g2.params.b1, id.g2.indices.r_squared);
    EXPECT_TRUE(id.g1.stable) << "link " << q + 1;
    EXPECT_TRUE(id.g2.stable) << "link " << q + 1;
    EXPECT_LT(std::abs(a0), 0.05) << "link " << q + 1;
    EXPECT_LT(std::abs(b2), 0.06) << "link " << q + 1;
    EXPECT_LT(b1, 0.0) << "link " << q + 1;
    EXPECT_GT(b1, -0.30) << "link " << q + 1;
    // Regression on the measured deviations (the simulation is
    // deterministic): within 0.5 points.
    EXPECT_NEAR(a0, measured[q][0], 0.005) << "link " << q + 1;
    EXPECT_NEAR(b1, measured[q][1], 0.005) << "link " << q + 1;
    EXPECT_NEAR(b2, measured[q][2], 0.005) << "link " << q + 1;
    // G2 describes the simulator's G1 response with alpha near 1.8 and
    // fits it worse than G1 does.
    EXPECT_GT(id.g2.params.alpha, 1.7);
    EXPECT_LT(id.g2.params.alpha, 1.9);
    EXPECT_GT(id.g2.indices.levy_cost, id.g1.indices.levy_cost);
    EXPECT_GT(id.g1.indices.r_squared, 0.9);
  }
}

// ------------------------------------------------------------ commands ---

struct CommandRun {
  int status = 0;
  std::string error;  // what() of an exception, if any
};

CommandRun RunCommand(const std::vector<std::string>& argv) {
  CLI::App app{"test"};
  app.require_subcommand(1);
  IdentifyArgs identify;
  DesignArgs design;
  PipelineArgs pipeline;
  AddIdentifyCommand(app, identify);
  AddDesignCommand(app, design);
  AddPipelineCommand(app, pipeline);
  std::vector<std::string> reversed(argv.rbegin(), argv.rend());
  app.parse(reversed);
  CommandRun run;
  try {
    run.status = std::max({RunIdentifyCommandLine(identify), RunDesignCommandLine(design),
                           RunPipelineCommandLine(pipeline)});
  } catch (const std::exception& error) {
    run.status = 1;
    run.error = error.what();
  }
  return run;
}

fs::path WriteLinearBenchCsv(const fs::path& dir) {
  // Columns as the bench writes them; the output is link 3's exact linear
  // P plus a column with a bad value further down.
  const LinearRecord record =
      SimulateLinear(LinkStateSpace(PaperLinkParams(3, IpmcModelKind::kG1)), TestChirp());
  const fs::path path = dir / "bench.csv";
  std::ofstream csv(path);
  csv << std::setprecision(12) << "time_s,voltage1_V,relative1_mm\n";
  for (std::size_t k = 0; k < record.input.size(); ++k) {
    csv << k * kSamplePeriod_s << "," << record.input[k] << "," << record.output[k] << "\n";
  }
  return path;
}

TEST(IdentifyCommandTest, IdentifiesACsvRecordAndWritesTheResponses) {
  const fs::path dir = FreshDir("identify_command");
  const fs::path csv = WriteLinearBenchCsv(dir);
  const fs::path out = dir / "out";
  const CommandRun run =
      RunCommand({"identify", csv.string(), "--input", "voltage1_V", "--output", "relative1_mm",
                  "--band-rad-s", "0.5,50", "--out", out.string()});
  ASSERT_EQ(run.status, 0) << run.error;
  std::ifstream json_file(out / "identification.json");
  const nlohmann::json json = nlohmann::json::parse(json_file);
  // Measured on the exact linear P: a0 -0.75 %, b1 +0.2 %, b2 -0.4 %.
  EXPECT_NEAR(json["g1"]["a0_mm_per_V"].get<double>(), 376.09e-3, 0.02 * 376.09e-3);
  EXPECT_NEAR(json["g1"]["b1"].get<double>(), 23.31e-3, 0.02 * 23.31e-3);
  EXPECT_NEAR(json["g1"]["b2_s2"].get<double>(), 2.13e-3, 0.02 * 2.13e-3);
  EXPECT_TRUE(json["g2"]["stable"].get<bool>());
  std::ifstream response(out / "response.csv");
  std::string header;
  std::getline(response, header);
  EXPECT_EQ(header.rfind("w_rad_s,frequency_Hz,coherence,", 0), 0u) << header;
  EXPECT_EQ(CountLines(std::string(std::istreambuf_iterator<char>(response), {})), 13332 / 2);
}

TEST(IdentifyCommandTest, BadDataAndOptionsGiveOneLineAndNoFiles) {
  const fs::path dir = FreshDir("identify_command_errors");
  const fs::path csv = WriteLinearBenchCsv(dir);
  const fs::path out = dir / "out";
  const auto expect_error = [&](const std::vector<std::string>& argv, const std::string& needle) {
    const CommandRun run = RunCommand(argv);
    EXPECT_EQ(run.status, 1);
    EXPECT_NE(run.error.find(needle), std::string::npos) << run.error;
    EXPECT_EQ(run.error.find('\n'), std::string::npos) << run.error;
    EXPECT_FALSE(fs::exists(out));
  };
  const std::string path = csv.string();
  expect_error({"identify", path, "--input", "voltage1_V", "--output", "relative3_mm", "--out",
                out.string()},
               "no column 'relative3_mm' (columns: time_s, voltage1_V, relative1_mm)");
  expect_error({"identify", path, "--input", "voltage1_V", "--output", "relative1_mm",
                "--sample-rate-hz", "500", "--out", out.string()},
               "--sample-rate-hz 500 disagrees with the time_s column");
  // The default band starts at 0.2 rad/s, below this 60 s record's first
  // bin.
  expect_error({"identify", path, "--input", "voltage1_V", "--output", "relative1_mm", "--out",
                out.string()},
               "below the first Welch bin 0.4713 rad/s");
  expect_error({"identify", path, "--input", "voltage1_V", "--output", "relative1_mm",
                "--band-rad-s", "50,5", "--out", out.string()},
               "--band-rad-s must be 0 < LOW < HIGH");
  {
    std::ofstream bad(dir / "bad.csv");
    bad << "time_s,voltage1_V,relative1_mm\n0,1,2\n0.001,1,abc\n";
  }
  expect_error({"identify", (dir / "bad.csv").string(), "--input", "voltage1_V", "--output",
                "relative1_mm", "--out", out.string()},
               "bad.csv:3: column relative1_mm: 'abc' is not a number");
  {
    std::ofstream short_file(dir / "short.csv");
    short_file << "voltage1_V,relative1_mm\n";
    for (int k = 0; k < 50; ++k) short_file << k << "," << k << "\n";
  }
  expect_error({"identify", (dir / "short.csv").string(), "--input", "voltage1_V", "--output",
                "relative1_mm", "--out", out.string()},
               "fewer than the minimum 72");
  expect_error({"design", "--links", "4"}, "design: --links must be 1, 2 or 3, got 4");
  expect_error({"design", "--horizon-s", "0.00015"}, "whole number of samples");
  expect_error({"pipeline", "--repeats", "0"}, "pipeline: --repeats must be in [1, 100], got 0");
  expect_error({"pipeline", "--noise-mm", "-1"}, "--noise-mm must be finite and >= 0");
  expect_error({"pipeline", "--f1-hz", "600"}, "pipeline: --end-hz must be in (0.1, 500)");
}

TEST(IdentifyCommandTest, PipelineWritesTheReport) {
  // The paper's experiment (link 1 driven, every tip measured), shortened
  // to 30 s up to 20 Hz, two noisy repeats.
  const fs::path dir = FreshDir("identify_pipeline");
  const CommandRun run =
      RunCommand({"pipeline", "--drive", "first", "--duration-s", "30", "--f1-hz", "20",
                  "--repeats", "2", "--noise-mm", "0.001", "--band-rad-s", "1,50", "--out",
                  dir.string()});
  ASSERT_EQ(run.status, 0) << run.error;
  std::ifstream file(dir / "report.md");
  const std::string report(std::istreambuf_iterator<char>(file), {});
  for (const char* needle :
       {"# Identification of the simulated flagellum", "## Identified models (as Table 2)",
        "## Fit indices (as Table 3)", "## Controllers for link 3", "fractional integrator",
        "Gains of each tip against the one before", "Repeats: 2", "2 records x 8 sections"}) {
    EXPECT_NE(report.find(needle), std::string::npos) << needle;
  }
  for (int q = 1; q <= 3; ++q) {
    EXPECT_TRUE(fs::exists(dir / ("response_link" + std::to_string(q) + ".csv"))) << q;
  }
}

}  // namespace
}  // namespace ipmc::testing
