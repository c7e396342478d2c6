// Travelling-wave references (eq. 2, eq. 3) and their projection onto the
// three links (section 5.1).
//
// Expected values are analytic and derived next to each test: the Table 4
// tip amplitude c1 * 31 mm, straight and parabolic waves whose joint points
// follow from plane geometry, and the first-order (small-amplitude) form of
// the projection. Tolerances are about ten times the residual measured here
// (quoted beside each), except where the tolerance is itself the contract:
// chords to 1e-9 mm and periodicity to 1e-12 mm.
#include "sim/core/waveform.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "tests/test_util.h"
#include "sim/base/numbers.h"

namespace ipmc {
namespace {

using ::ipmc::testing::ExpectInvalidArgument;

constexpr double kMmPerUm = 1e-3;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// Hinge positions of the paper's links, x = 0 at the root of link 1, and
// the tip of link 3: partial sums of the pitches 10.25, 10.5, 10.25 mm.
const std::vector<double> kPaperHinges_mm = {0.0, 10.25, 20.75, 31.0};

double Chord_mm(const DiscreteWave& wave, int q) {
  return std::hypot(wave.joint_x_mm[q] - wave.joint_x_mm[q - 1],
                    wave.joint_y_mm[q] - wave.joint_y_mm[q - 1]);
}

// The fundamental of r_q(t) over one period, as r ~ A sin(w t + phase).
std::vector<double> FundamentalPhases_rad(const WaveformConfig& wave,
                                          const LinkGeometry& geometry) {
  constexpr int kSamples = 1000;
  const double period_s = 1.0 / std::abs(wave.frequency_Hz);
  const std::size_t links = geometry.pitch_mm.size();
  std::vector<double> sine(links, 0.0), cosine(links, 0.0);
  for (int i = 0; i < kSamples; ++i) {
    const double t_s = period_s * i / kSamples;
    const double omega_t = 2.0 * kPi * i / kSamples;
    const DiscreteWave discrete = DiscretiseWave(wave, geometry, t_s);
    for (std::size_t q = 0; q < links; ++q) {
      sine[q] += discrete.relative_deflection_mm[q] * std::sin(omega_t);
      cosine[q] += discrete.relative_deflection_mm[q] * std::cos(omega_t);
    }
  }
  std::vector<double> phase_rad(links);
  for (std::size_t q = 0; q < links; ++q) phase_rad[q] = std::atan2(cosine[q], sine[q]);
  return phase_rad;
}

// a - b wrapped into (-pi, pi].
double WrappedDifference_rad(double a, double b) {
  double d = std::remainder(a - b, 2.0 * kPi);
  if (d <= -kPi) d += 2.0 * kPi;
  return d;
}

// max |r_q - r_q^linear| / max |r_q^linear| over one period of a Table 4
// wave with amplitude coefficient c1 [um/mm], where the linearised
// projection puts the joints at the hinges X_q:
//   theta_q = (y(X_q) - y(X_(q-1))) / s_q,  r_q^linear = L_q (theta_q - theta_(q-1)).
double LinearisationError(double c1_um_per_mm) {
  WaveformConfig wave;
  wave.c1_um_per_mm = c1_um_per_mm;
  const LinkGeometry geometry = PaperLinkGeometry();
  double worst_error_mm = 0.0, largest_r_mm = 0.0;
  for (int i = 0; i < 200; ++i) {
    const double t_s = 0.5 * i;
    const DiscreteWave discrete = DiscretiseWave(wave, geometry, t_s);
    double previous_theta = 0.0;
    for (int q = 1; q <= 3; ++q) {
      const double theta =
          (WaveY_um(wave, kPaperHinges_mm[q], t_s) - WaveY_um(wave, kPaperHinges_mm[q - 1], t_s)) *
          kMmPerUm / geometry.pitch_mm[q - 1];
      const double linear_mm = geometry.length_mm[q - 1] * (theta - previous_theta);
      previous_theta = theta;
      worst_error_mm =
          std::max(worst_error_mm, std::abs(discrete.relative_deflection_mm[q - 1] - linear_mm));
      largest_r_mm = std::max(largest_r_mm, std::abs(linear_mm));
    }
  }
  return worst_error_mm / largest_r_mm;
}

TEST(WaveformTest, PaperGeometryHasTenMillimetreLinksOnThirtyOneMillimetres) {
  const LinkGeometry geometry = PaperLinkGeometry();
  ASSERT_EQ(geometry.pitch_mm.size(), 3u);
  ASSERT_EQ(geometry.length_mm.size(), 3u);
  double x_mm = 0.0;
  for (int q = 0; q < 3; ++q) {
    EXPECT_EQ(geometry.length_mm[q], 10.0);
    x_mm += geometry.pitch_mm[q];
    EXPECT_EQ(x_mm, kPaperHinges_mm[q + 1]);  // exact in binary
  }
}

TEST(WaveformTest, TableFourTipAmplitudeIsSixPointTwoMillimetres) {
  // Table 4 read as y [um], x [mm]: amplitude c1 x = 200 um/mm * 31 mm.
  const WaveformConfig wave;
  EXPECT_EQ(wave.kind, WaveformKind::kPolynomial);
  EXPECT_EQ(wave.c0_um, 0.0);
  EXPECT_EQ(wave.c1_um_per_mm, 200.0);
  EXPECT_EQ(wave.c2_um_per_mm2, 0.0);
  EXPECT_EQ(wave.frequency_Hz, 0.01);
  EXPECT_EQ(wave.wavelength_mm, 32.0);

  // The crest reaches the tip when 2 pi (31/32 - f t) = pi/2, at
  // t = (31/32 - 1/4) / f = 71.875 s, and a trough half a period later.
  // Measured residual 0 both times; tolerance ten ulp of 6200 um.
  EXPECT_NEAR(WaveY_um(wave, 31.0, 71.875), 6200.0, 1e-11);
  EXPECT_NEAR(WaveY_um(wave, 31.0, 71.875 + 50.0), -6200.0, 1e-11);

  // Sampled over one period, |y(31, t)| never exceeds 6.2 mm and the head
  // stays at rest (c0 = 0).
  double peak_um = 0.0;
  for (int i = 0; i < 4000; ++i) {
    const double t_s = 100.0 * i / 4000;
    peak_um = std::max(peak_um, std::abs(WaveY_um(wave, 31.0, t_s)));
    EXPECT_EQ(WaveY_um(wave, 0.0, t_s), 0.0) << "t = " << t_s;
  }
  EXPECT_LE(peak_um, 6200.0 + 1e-11);
  EXPECT_GT(peak_um, 6199.0);  // the sampling step is 0.09 deg of phase
}

TEST(WaveformTest, JointPointsLieOnTheWaveAtPitchDistance) {
  // Measured: max ||P_q - P_(q-1)| - s_q| = 5.3e-15 mm over 1000 instants
  // of the Table 4 wave; the tolerance, 1e-9 mm, is the solver's contract.
  const WaveformConfig wave;
  const LinkGeometry geometry = PaperLinkGeometry();
  for (int i = 0; i < 1000; ++i) {
    const double t_s = 0.1 * i;
    const DiscreteWave discrete = DiscretiseWave(wave, geometry, t_s);
    ASSERT_EQ(discrete.joint_x_mm.size(), 4u);
    ASSERT_EQ(discrete.joint_y_mm.size(), 4u);
    ASSERT_EQ(discrete.relative_deflection_mm.size(), 3u);
    EXPECT_EQ(discrete.joint_x_mm[0], 0.0);
    for (int q = 0; q <= 3; ++q) {
      // The joints are evaluated through the same y(x, t), bit for bit.
      EXPECT_EQ(discrete.joint_y_mm[q], WaveY_um(wave, discrete.joint_x_mm[q], t_s) * kMmPerUm);
    }
    for (int q = 1; q <= 3; ++q) {
      EXPECT_GT(discrete.joint_x_mm[q], discrete.joint_x_mm[q - 1]);
      const double error_mm = std::abs(Chord_mm(discrete, q) - geometry.pitch_mm[q - 1]);
      EXPECT_LT(error_mm, 1e-9) << "t = " << t_s << ", q = " << q;
    }
  }
}

TEST(WaveformTest, JointIsTheFirstCrossingOfAWigglyWave) {
  // A steep harmonic wave (5 mm amplitude, 4 mm wavelength) leaves and
  // re-enters the circle of radius s around P_(q-1); the joint is where
  // it first leaves.
  WaveformConfig wave;
  wave.c0_um = 5000.0;
  wave.c1_um_per_mm = 0.0;
  wave.wavelength_mm = 4.0;
  LinkGeometry geometry;
  geometry.pitch_mm = {10.0, 10.0};
  geometry.length_mm = {10.0, 10.0};
  bool re_enters = false;
  for (const double t_s : {0.0, 13.0, 37.0, 61.0, 89.0}) {
    const DiscreteWave discrete = DiscretiseWave(wave, geometry, t_s);
    for (int q = 1; q <= 2; ++q) {
      const double x0 = discrete.joint_x_mm[q - 1], y0 = discrete.joint_y_mm[q - 1];
      const double s = geometry.pitch_mm[q - 1];
      EXPECT_NEAR(Chord_mm(discrete, q), s, 1e-9);
      const auto chord = [&](double x_mm) {
        return std::hypot(x_mm - x0, WaveY_um(wave, x_mm, t_s) * kMmPerUm - y0);
      };
      // No sample between the joints is as far as s from P_(q-1).
      for (double x = x0; x < discrete.joint_x_mm[q] - 1e-6; x += 1e-3) {
        ASSERT_LT(chord(x), s) << "t = " << t_s << ", q = " << q << ", x = " << x;
      }
      for (double x = discrete.joint_x_mm[q] + 1e-3; x < x0 + s; x += 1e-3) {
        re_enters = re_enters || chord(x) < s;
      }
    }
  }
  EXPECT_TRUE(re_enters) << "the case no longer tests the first crossing";
}

TEST(WaveformTest, StraightWaveBendsOnlyTheFirstLink) {
  // lambda = 1e12 mm and f t = -1/4: y = c1 x cos(2 pi x / lambda), a
  // straight line of slope k = c1 / 1000 = 0.5 (the cosine differs from 1
  // by 2e-20 at 31 mm). Then P_q = X_q (1, k) / sqrt(1 + k^2) with X_q the
  // hinge positions, phi_q = atan(k), r_1 = L_1 k / sqrt(1 + k^2)
  // = 2 sqrt(5) mm and r_2 = r_3 = 0. Measured residuals <= 3.6e-15 mm;
  // tolerance 4e-14 mm.
  WaveformConfig wave;
  wave.c1_um_per_mm = 500.0;
  wave.wavelength_mm = 1e12;
  const double slope = 0.5;
  const double t_s = -0.25 / wave.frequency_Hz;
  const DiscreteWave discrete = DiscretiseWave(wave, PaperLinkGeometry(), t_s);
  for (int q = 0; q <= 3; ++q) {
    const double x_mm = kPaperHinges_mm[q] / std::sqrt(1.0 + slope * slope);
    EXPECT_NEAR(discrete.joint_x_mm[q], x_mm, 4e-14) << q;
    EXPECT_NEAR(discrete.joint_y_mm[q], slope * x_mm, 4e-14) << q;
  }
  EXPECT_NEAR(discrete.relative_deflection_mm[0], 2.0 * std::sqrt(5.0), 4e-14);
  EXPECT_NEAR(discrete.relative_deflection_mm[1], 0.0, 4e-14);
  EXPECT_NEAR(discrete.relative_deflection_mm[2], 0.0, 4e-14);
}

TEST(WaveformTest, ParabolicWaveMatchesPlaneGeometry) {
  // Same quasi-static trick on y = k x^2 (c2 = 20 um/mm^2, k = 0.02 /mm).
  // P_1 solves x^2 + k^2 x^4 = s_1^2:
  //   x_1^2 = 2 s_1^2 / (1 + sqrt(1 + 4 k^2 s_1^2)),
  // and every chord of a parabola has slope k (x_(q-1) + x_q), so
  // r_q = L_q sin(atan(k (x_(q-1) + x_q)) - atan(k (x_(q-2) + x_(q-1)))).
  // Measured residuals <= 3.1e-15 mm; tolerance 4e-14 mm.
  WaveformConfig wave;
  wave.c1_um_per_mm = 0.0;
  wave.c2_um_per_mm2 = 20.0;
  wave.wavelength_mm = 1e12;
  const double k = 0.02;
  const LinkGeometry geometry = PaperLinkGeometry();
  const DiscreteWave discrete = DiscretiseWave(wave, geometry, -0.25 / wave.frequency_Hz);

  const double s1 = geometry.pitch_mm[0];
  const double x1 = std::sqrt(2.0 * s1 * s1 / (1.0 + std::sqrt(1.0 + 4.0 * k * k * s1 * s1)));
  EXPECT_NEAR(discrete.joint_x_mm[1], x1, 4e-14);  // 10.0496...
  EXPECT_NEAR(discrete.joint_y_mm[1], k * x1 * x1, 4e-14);

  double previous_angle_rad = 0.0;
  for (int q = 1; q <= 3; ++q) {
    const double angle_rad = std::atan(k * (discrete.joint_x_mm[q - 1] + discrete.joint_x_mm[q]));
    EXPECT_NEAR(discrete.relative_deflection_mm[q - 1],
                geometry.length_mm[q - 1] * std::sin(angle_rad - previous_angle_rad), 4e-14)
        << q;
    previous_angle_rad = angle_rad;
  }
}

TEST(WaveformTest, SmallAmplitudeLimitIsTheLinearisedProjection) {
  // For |dy/dx| << 1 the joints sit at the hinges X_q, phi_q = theta_q =
  // (y(X_q) - y(X_(q-1))) / s_q and r_q = L_q (theta_q - theta_(q-1)), with
  // relative error O(slope^2). c1 = 0.01 um/mm keeps |dy/dx| < 1e-4.
  // Measured max error / max |r| over one period: 1.34e-9 at c1 = 0.01,
  // 1.34e-7 at c1 = 0.1 (quadratic in the amplitude); tolerance 1.5e-8 at
  // c1 = 0.01 and a ratio between the two within [50, 200].
  const double small = LinearisationError(0.01);
  const double larger = LinearisationError(0.1);
  EXPECT_LT(small, 1.5e-8);
  EXPECT_GT(larger / small, 50.0);
  EXPECT_LT(larger / small, 200.0);
}

TEST(WaveformTest, ReferencesArePeriodic) {
  // Measured max difference between t and t + 1/f: 3.6e-15 mm; tolerance
  // 1e-12 mm.
  const WaveformConfig wave;
  const LinkGeometry geometry = PaperLinkGeometry();
  const double period_s = 1.0 / wave.frequency_Hz;
  for (const double t_s : {0.0, 3.7, 25.0, 48.2, 71.875, 99.9}) {
    const DiscreteWave a = DiscretiseWave(wave, geometry, t_s);
    const DiscreteWave b = DiscretiseWave(wave, geometry, t_s + period_s);
    for (int q = 0; q < 3; ++q) {
      EXPECT_NEAR(a.relative_deflection_mm[q], b.relative_deflection_mm[q], 1e-12)
          << "t = " << t_s << ", q = " << q + 1;
    }
    for (int q = 0; q <= 3; ++q) {
      EXPECT_NEAR(a.joint_x_mm[q], b.joint_x_mm[q], 1e-12);
      EXPECT_NEAR(a.joint_y_mm[q], b.joint_y_mm[q], 1e-12);
    }
  }
}

TEST(WaveformTest, WaveTravelsHeadToTailForPositiveFrequency) {
  // y = A(x) sin(k x - w t): along the body the time signal lags by about
  // k dx, so link q+1 lags link q. Measured fundamentals of the Table 4
  // references: link 1 -> 2 lags 2.574 rad, link 2 -> 3 lags 2.155 rad
  // (k * 10.5 mm = 2.062 rad between hinges 2 and 3; the projection is
  // nonlinear at this amplitude).
  WaveformConfig wave;
  const LinkGeometry geometry = PaperLinkGeometry();
  const std::vector<double> forward = FundamentalPhases_rad(wave, geometry);
  for (int q = 0; q < 2; ++q) {
    const double lag_rad = WrappedDifference_rad(forward[q], forward[q + 1]);
    EXPECT_GT(lag_rad, 0.0) << "link " << q + 1 << " -> " << q + 2;
    EXPECT_LT(lag_rad, kPi) << "link " << q + 1 << " -> " << q + 2;
  }

  // f -> -f is t -> -t: the same references played backwards, bit for bit.
  wave.frequency_Hz = -0.01;
  for (const double t_s : {0.0, 12.5, 60.0}) {
    WaveformConfig positive = wave;
    positive.frequency_Hz = 0.01;
    EXPECT_EQ(DiscretiseWave(wave, geometry, t_s).relative_deflection_mm,
              DiscretiseWave(positive, geometry, -t_s).relative_deflection_mm);
  }
  const std::vector<double> backward = FundamentalPhases_rad(wave, geometry);
  for (int q = 0; q < 2; ++q) {
    const double lead_rad = WrappedDifference_rad(backward[q + 1], backward[q]);
    EXPECT_GT(lead_rad, 0.0) << "link " << q + 2 << " leads " << q + 1;
    // Mirror image of the forward lag; measured difference 4.4e-16 rad.
    EXPECT_NEAR(lead_rad, WrappedDifference_rad(forward[q], forward[q + 1]), 1e-14);
  }
}

TEST(WaveformTest, FractionalWaveWithUnitAlphaIsTheLinearWave) {
  // eq. 3 with alpha = 1 is eq. 2 with c1 = c, c0 = c2 = 0 (pow(x, 1) = x).
  // Measured differences: 0 in y and in r.
  WaveformConfig linear;
  linear.c1_um_per_mm = 150.0;
  WaveformConfig fractional;
  fractional.kind = WaveformKind::kFractional;
  fractional.c0_um = 7.0;  // ignored by eq. 3
  fractional.c_um = 150.0;
  fractional.alpha = 1.0;
  for (const double t_s : {0.0, 17.0, 55.5}) {
    for (const double x_mm : {0.0, 1.0, 10.25, 31.0}) {
      EXPECT_DOUBLE_EQ(WaveY_um(fractional, x_mm, t_s), WaveY_um(linear, x_mm, t_s));
    }
    const DiscreteWave a = DiscretiseWave(fractional, PaperLinkGeometry(), t_s);
    const DiscreteWave b = DiscretiseWave(linear, PaperLinkGeometry(), t_s);
    for (int q = 0; q < 3; ++q) {
      EXPECT_NEAR(a.relative_deflection_mm[q], b.relative_deflection_mm[q], 1e-13);
    }
  }
}

TEST(WaveformTest, FractionalWaveGrowsAsAPowerOfX) {
  // c x^alpha at the crest: with alpha = 1/2, c = 1000 um/mm^0.5, the
  // amplitude at x = 16 mm is 4000 um. The crest is at x = 16 mm when
  // 2 pi (16/32 - f t) = pi/2, t = 25 s. Measured residuals: 0 in y,
  // 1.8e-15 mm in the chords.
  WaveformConfig wave;
  wave.kind = WaveformKind::kFractional;
  wave.c_um = 1000.0;
  wave.alpha = 0.5;
  EXPECT_NEAR(WaveY_um(wave, 16.0, 25.0), 4000.0, 1e-11);
  EXPECT_EQ(WaveY_um(wave, 0.0, 25.0), 0.0);
  const DiscreteWave discrete = DiscretiseWave(wave, PaperLinkGeometry(), 25.0);
  for (int q = 1; q <= 3; ++q) {
    EXPECT_NEAR(Chord_mm(discrete, q), PaperLinkGeometry().pitch_mm[q - 1], 1e-9);
  }
}

TEST(WaveformTest, RejectsBadConfiguration) {
  const LinkGeometry geometry = PaperLinkGeometry();
  const auto expect_rejected = [&](const WaveformConfig& wave, const std::string& field) {
    ExpectInvalidArgument([&] { wave.Validate(); }, field);
    ExpectInvalidArgument([&] { WaveY_um(wave, 1.0, 0.0); }, field);
    ExpectInvalidArgument([&] { DiscretiseWave(wave, geometry, 0.0); }, field);
  };
  for (const double wavelength : {0.0, -1.0, kNaN, kInf}) {
    WaveformConfig wave;
    wave.wavelength_mm = wavelength;
    expect_rejected(wave, "wavelength_mm");
  }
  for (const double frequency : {0.0, kNaN, -kInf}) {
    WaveformConfig wave;
    wave.frequency_Hz = frequency;
    expect_rejected(wave, "frequency_Hz");
  }
  for (const double alpha : {0.0, -0.5, 1.5, kNaN}) {
    WaveformConfig wave;
    wave.kind = WaveformKind::kFractional;
    wave.c_um = 100.0;
    wave.alpha = alpha;
    expect_rejected(wave, "alpha");
  }
  {
    WaveformConfig wave;
    wave.c0_um = kNaN;
    expect_rejected(wave, "c0_um");
    wave = WaveformConfig();
    wave.c1_um_per_mm = kInf;
    expect_rejected(wave, "c1_um_per_mm");
    wave = WaveformConfig();
    wave.c2_um_per_mm2 = kNaN;
    expect_rejected(wave, "c2_um_per_mm2");
    wave = WaveformConfig();
    wave.kind = WaveformKind::kFractional;
    wave.c_um = kNaN;
    expect_rejected(wave, "c_um");
  }
  // The message carries the offending value.
  WaveformConfig negative;
  negative.wavelength_mm = -1.0;
  ExpectInvalidArgument([&] { negative.Validate(); },
                        "waveform: wavelength_mm must be finite and > 0 (got -1)");

  // alpha is only checked for eq. 3; a negative frequency is allowed.
  WaveformConfig polynomial;
  polynomial.alpha = 2.0;
  polynomial.frequency_Hz = -0.01;
  EXPECT_NO_THROW(polynomial.Validate());
  WaveformConfig unit_alpha;
  unit_alpha.kind = WaveformKind::kFractional;
  unit_alpha.alpha = 1.0;
  EXPECT_NO_THROW(unit_alpha.Validate());
}

TEST(WaveformTest, RejectsBadArguments) {
  const WaveformConfig wave;
  ExpectInvalidArgument([&] { WaveY_um(wave, kNaN, 0.0); }, "x_mm");
  ExpectInvalidArgument([&] { WaveY_um(wave, 1.0, kInf); }, "t_s");
  ExpectInvalidArgument([&] { DiscretiseWave(wave, PaperLinkGeometry(), kNaN); }, "t_s");
  WaveformConfig fractional;
  fractional.kind = WaveformKind::kFractional;
  ExpectInvalidArgument([&] { WaveY_um(fractional, -1.0, 0.0); }, "x_mm");

  LinkGeometry geometry = PaperLinkGeometry();
  geometry.length_mm.pop_back();
  ExpectInvalidArgument([&] { DiscretiseWave(wave, geometry, 0.0); }, "length_mm");
  geometry = PaperLinkGeometry();
  geometry.pitch_mm[1] = 0.0;
  ExpectInvalidArgument([&] { DiscretiseWave(wave, geometry, 0.0); }, "pitch_mm[1]");
  geometry = PaperLinkGeometry();
  geometry.length_mm[2] = kNaN;
  ExpectInvalidArgument([&] { DiscretiseWave(wave, geometry, 0.0); }, "length_mm[2]");
  ExpectInvalidArgument([&] { DiscretiseWave(wave, LinkGeometry(), 0.0); }, "pitch_mm");
}

}  // namespace
}  // namespace ipmc
