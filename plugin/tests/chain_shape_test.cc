// The shape of an IPMC link as a chain of rigid sub-segments
// (plugin/actuators/ipmc_actuators.h, ChainShape): the curvature that gives
// a free tip deflection, the chain's reach, and the closed form for equal
// sub-segments against the sum over them, on the layout the model
// generator writes (sim/core/model_generator.h).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "plugin/actuators/ipmc_actuators.h"

namespace ipmc::testing {
namespace {

// ---------------------------------------------------- the chain's shape ---

TEST(ChainShapeTest, OneSegmentIsTheRigidLink) {
  const ChainShape shape({0.01});
  EXPECT_DOUBLE_EQ(shape.Reach_m(), 0.01);
  bool clamped = true;
  // theta0 = kappa L / 2 = asin(delta / L).
  const double kappa = shape.Curvature_1_m(0.004, 0.0, &clamped);
  EXPECT_FALSE(clamped);
  EXPECT_DOUBLE_EQ(kappa * shape.Share_m(0), std::asin(0.4));
  shape.Curvature_1_m(-0.0101, 0.0, &clamped);
  EXPECT_TRUE(clamped);
}

// The generator's layout of a link of length L in n >= 2 sub-segments:
// n - 1 of l = L / (n - 1/2) and a last one of l / 2 (model_generator.h).
std::vector<double> GeneratorLayout(int n, double length_m) {
  std::vector<double> lengths(n, length_m / (n - 0.5));
  lengths.back() *= 0.5;
  return lengths;
}

TEST(ChainShapeTest, CurvatureInvertsTheTipDeflection) {
  for (int n : {2, 3, 8, 64}) {
    const ChainShape shape(GeneratorLayout(n, 0.01));
    // Shares: l/2 at the root, l inside and at the last hinge, whose share
    // reaches the tip (Voronoi lengths adding up to L).
    const double l = 0.01 / (n - 0.5);
    EXPECT_DOUBLE_EQ(shape.Share_m(0), 0.5 * l);
    EXPECT_DOUBLE_EQ(shape.Share_m(1), l);
    EXPECT_DOUBLE_EQ(shape.Share_m(n - 1), l);
    for (double deflection_m : {1e-6, -3e-3, 5e-3, 0.99 * shape.Reach_m()}) {
      bool clamped = true;
      const double kappa = shape.Curvature_1_m(deflection_m, 0.0, &clamped);
      EXPECT_FALSE(clamped);
      EXPECT_NEAR(shape.TipDeflection_m(kappa), deflection_m, 1e-15) << "n = " << n;
    }
    // The chain reaches about as far as the arc's first maximum:
    // (1 - cos(x)) / x L peaks where tan(x / 2) = x, at x = 2.3311,
    // 0.72461 L. Measured -1.02 / -0.65 / -0.088 % for n = 2 / 3 / 8
    // (at most 0.059 / n^2).
    EXPECT_NEAR(shape.Reach_m() / (0.72461 * 0.01), 1.0, 0.1 / (n * n)) << "n = " << n;
  }
}

TEST(ChainShapeTest, EqualSegmentsClosedFormMatchesTheSum) {
  // All sub-segments but the last equal take
  // f = l sin^2(kappa S / 2) / sin(kappa l / 2) + e sin(kappa L) and its
  // derivative; lengths 1e-6 apart take the sum over the sub-segments.
  // The two agree to the perturbation (measured CLOSED_MEASURED relative).
  double worst = 0;
  for (int n : {2, 16, 32}) {
    std::vector<double> uneven = GeneratorLayout(n, 0.01);
    uneven[0] *= 1 + 1e-6;
    uneven[n - 2] *= 1 - 1e-6;
    const ChainShape equal(GeneratorLayout(n, 0.01)), summed(uneven);
    EXPECT_NEAR(equal.Reach_m() / summed.Reach_m(), 1.0, 2e-6) << "n = " << n;
    for (double deflection_m : {1e-6, -3e-3, 5e-3, 0.99 * equal.Reach_m()}) {
      bool clamped = true;
      const double kappa = equal.Curvature_1_m(deflection_m, 0.0, &clamped);
      const double kappa_summed = summed.Curvature_1_m(deflection_m, 0.0, &clamped);
      EXPECT_NEAR(kappa / kappa_summed, 1.0, 2e-6) << "n = " << n;
      EXPECT_NEAR(equal.TipDeflection_m(kappa) / summed.TipDeflection_m(kappa), 1.0, 2e-6);
      worst = std::max({worst, std::abs(kappa / kappa_summed - 1),
                        std::abs(equal.TipDeflection_m(kappa) / summed.TipDeflection_m(kappa) - 1)});
    }
  }
  std::printf("closed form against the sum: %.3g relative\n", worst);
}

}  // namespace
}  // namespace ipmc::testing
