// The project's serial N_Vector kernels (plugin/actuators/serial_kernels.h) against
// the stock N_V*_Serial kernels of SUNDIALS on random vectors: the same
// numbers, bit for bit, except where SUNDIALS factors a (x +- y) in
// N_VLinearSum (a = +-b, |a| != 1), which rounds differently.
#include "plugin/actuators/serial_kernels.h"

#include <gtest/gtest.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace ipmc {
namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon();

// Lengths: 1, odd and even, shorter and longer than a SIMD register's
// multiple, and the bank's 30 states.
const std::vector<sunindextype> kLengths = {1, 2, 3, 7, 30, 31, 101};

// For a = +-b, fl(fl(a x) + fl(b y)) and fl(a fl(x +- y)) each lie within
// 2 u (|a x| + |b y|) of the exact a x + b y (u = eps / 2, two roundings
// each, to first order in u), so they differ by at most
// 2 eps (|a x| + |b y|). Measured largest difference over the lengths
// below, 20 trials each: 1.3 eps (|a x| + |b y|) (printed by the test).
constexpr double kFactoredSumBound = 2.0;

class SerialKernelsTest : public ::testing::Test {
 protected:
  void SetUp() override { ASSERT_EQ(SUNContext_Create(nullptr, &context_), 0); }
  void TearDown() override {
    for (N_Vector v : vectors_) N_VDestroy(v);
    SUNContext_Free(&context_);
    if (largest_factored_difference_ > 0) {
      std::printf("largest factored-sum difference: %.3g eps (|a x| + |b y|)\n",
                  largest_factored_difference_);
    }
  }

  // A pair of vectors holding the same values: `ours` with the project's
  // kernels (cloned from a vector they were installed on, as CVODE's work
  // vectors are), `stock` with SUNDIALS's.
  struct Pair {
    N_Vector ours;
    N_Vector stock;
  };

  Pair Make(sunindextype n) {
    N_Vector ours_template = Keep(N_VNew_Serial(n, context_));
    serial_kernels::Install(ours_template);
    Pair pair{Keep(N_VClone(ours_template)), Keep(N_VNew_Serial(n, context_))};
    Fill(pair, [&](sunindextype) { return RandomValue(); });
    return pair;
  }

  template <typename Generator>
  void Fill(const Pair& pair, Generator value) {
    for (sunindextype i = 0; i < NV_LENGTH_S(pair.ours); ++i) {
      NV_Ith_S(pair.ours, i) = NV_Ith_S(pair.stock, i) = value(i);
    }
  }

  // Signed values over twelve decades, so products and sums round.
  double RandomValue() {
    const double magnitude = std::pow(10.0, std::uniform_real_distribution<double>(-6, 6)(rng_));
    return std::bernoulli_distribution(0.5)(rng_) ? -magnitude : magnitude;
  }
  double RandomScalar() { return std::uniform_real_distribution<double>(-3, 3)(rng_); }

  static void ExpectSame(const Pair& pair, const std::string& what) {
    for (sunindextype i = 0; i < NV_LENGTH_S(pair.ours); ++i) {
      EXPECT_EQ(NV_Ith_S(pair.ours, i), NV_Ith_S(pair.stock, i))
          << what << ", n = " << NV_LENGTH_S(pair.ours) << ", element " << i;
    }
  }

  // z = a x + b y against SUNDIALS's a (x +- y) for a = +-b.
  void ExpectFactoredSum(const Pair& z, double a, const Pair& x, double b, const Pair& y,
                         const std::string& what) {
    for (sunindextype i = 0; i < NV_LENGTH_S(z.ours); ++i) {
      const double scale = std::abs(a * NV_Ith_S(x.stock, i)) + std::abs(b * NV_Ith_S(y.stock, i));
      const double difference = std::abs(NV_Ith_S(z.ours, i) - NV_Ith_S(z.stock, i));
      largest_factored_difference_ =
          std::max(largest_factored_difference_, difference / (kEps * scale));
      EXPECT_LE(difference, kFactoredSumBound * kEps * scale)
          << what << ", a = " << a << ", b = " << b << ", element " << i;
    }
  }

  std::mt19937_64 rng_{20240611};

 private:
  N_Vector Keep(N_Vector v) {
    vectors_.push_back(v);
    return v;
  }

  SUNContext context_ = nullptr;
  std::vector<N_Vector> vectors_;
  double largest_factored_difference_ = 0;
};

TEST_F(SerialKernelsTest, InstallReplacesEveryListedOperationOfTheVectorAndItsClones) {
  Pair pair = Make(4);
  const N_Vector_Ops ours = pair.ours->ops;
  const N_Vector_Ops stock = pair.stock->ops;
  // The stock vector's own table is SUNDIALS's; the fused operations are
  // off (null) in it by default.
  EXPECT_EQ(stock->nvlinearsum, &N_VLinearSum_Serial);
  EXPECT_EQ(stock->nvlinearcombination, nullptr);
  const std::vector<std::pair<const char*, std::pair<void*, void*>>> operations = {
      {"linearsum", {(void*)ours->nvlinearsum, (void*)stock->nvlinearsum}},
      {"const", {(void*)ours->nvconst, (void*)stock->nvconst}},
      {"prod", {(void*)ours->nvprod, (void*)stock->nvprod}},
      {"div", {(void*)ours->nvdiv, (void*)stock->nvdiv}},
      {"scale", {(void*)ours->nvscale, (void*)stock->nvscale}},
      {"abs", {(void*)ours->nvabs, (void*)stock->nvabs}},
      {"inv", {(void*)ours->nvinv, (void*)stock->nvinv}},
      {"addconst", {(void*)ours->nvaddconst, (void*)stock->nvaddconst}},
      {"dotprod", {(void*)ours->nvdotprod, (void*)stock->nvdotprod}},
      {"maxnorm", {(void*)ours->nvmaxnorm, (void*)stock->nvmaxnorm}},
      {"wrmsnorm", {(void*)ours->nvwrmsnorm, (void*)stock->nvwrmsnorm}},
      {"wrmsnormmask", {(void*)ours->nvwrmsnormmask, (void*)stock->nvwrmsnormmask}},
      {"min", {(void*)ours->nvmin, (void*)stock->nvmin}},
      {"wl2norm", {(void*)ours->nvwl2norm, (void*)stock->nvwl2norm}},
      {"l1norm", {(void*)ours->nvl1norm, (void*)stock->nvl1norm}},
      {"compare", {(void*)ours->nvcompare, (void*)stock->nvcompare}},
      {"invtest", {(void*)ours->nvinvtest, (void*)stock->nvinvtest}},
      {"linearcombination", {(void*)ours->nvlinearcombination, (void*)&N_VLinearCombination_Serial}},
      {"scaleaddmulti", {(void*)ours->nvscaleaddmulti, (void*)&N_VScaleAddMulti_Serial}},
      {"scalevectorarray", {(void*)ours->nvscalevectorarray, (void*)&N_VScaleVectorArray_Serial}},
      {"dotprodlocal", {(void*)ours->nvdotprodlocal, (void*)stock->nvdotprodlocal}},
      {"maxnormlocal", {(void*)ours->nvmaxnormlocal, (void*)stock->nvmaxnormlocal}},
      {"minlocal", {(void*)ours->nvminlocal, (void*)stock->nvminlocal}},
      {"l1normlocal", {(void*)ours->nvl1normlocal, (void*)stock->nvl1normlocal}},
      {"invtestlocal", {(void*)ours->nvinvtestlocal, (void*)stock->nvinvtestlocal}},
      {"wsqrsumlocal", {(void*)ours->nvwsqrsumlocal, (void*)stock->nvwsqrsumlocal}},
      {"wsqrsummasklocal", {(void*)ours->nvwsqrsummasklocal, (void*)stock->nvwsqrsummasklocal}},
  };
  for (const auto& [name, pointers] : operations) {
    EXPECT_NE(pointers.first, nullptr) << name;
    EXPECT_NE(pointers.second, nullptr) << name << " (stock)";
    EXPECT_NE(pointers.first, pointers.second) << name << " is still the stock kernel";
  }
}

TEST_F(SerialKernelsTest, LinearSumEqualsStockInEveryCaseOfItsCoefficients) {
  for (sunindextype n : kLengths) {
    const Pair x = Make(n), y = Make(n), z = Make(n);
    const double a = RandomScalar(), b = RandomScalar();
    // N_VLinearSum_Serial's special cases: a or b = +-1, and the general
    // a x + b y; all round alike.
    const std::vector<std::pair<double, double>> coefficients = {
        {a, b}, {1, 1}, {1, -1}, {-1, 1}, {-1, -1}, {1, b}, {a, 1}, {-1, b}, {a, -1}, {0, b}, {a, 0}};
    for (const auto& [ca, cb] : coefficients) {
      N_VLinearSum(ca, x.ours, cb, y.ours, z.ours);
      N_VLinearSum_Serial(ca, x.stock, cb, y.stock, z.stock);
      ExpectSame(z, "z = a x + b y, a = " + std::to_string(ca) + ", b = " + std::to_string(cb));
    }
    // Aliased: y <- a x + y (b = 1) and x <- x + b y (a = 1) are its axpy
    // cases.
    N_VLinearSum(a, x.ours, 1.0, y.ours, y.ours);
    N_VLinearSum_Serial(a, x.stock, 1.0, y.stock, y.stock);
    ExpectSame(y, "y <- a x + y");
    N_VLinearSum(1.0, x.ours, b, y.ours, x.ours);
    N_VLinearSum_Serial(1.0, x.stock, b, y.stock, x.stock);
    ExpectSame(x, "x <- x + b y");
    N_VLinearSum(a, x.ours, b, y.ours, x.ours);
    N_VLinearSum_Serial(a, x.stock, b, y.stock, x.stock);
    ExpectSame(x, "x <- a x + b y");
  }
}

TEST_F(SerialKernelsTest, LinearSumWithEqualOrOppositeCoefficientsIsWithinRounding) {
  for (sunindextype n : kLengths) {
    for (int trial = 0; trial < 20; ++trial) {
      const Pair x = Make(n), y = Make(n), z = Make(n);
      const double a = RandomScalar();
      for (const double b : {a, -a}) {
        N_VLinearSum(a, x.ours, b, y.ours, z.ours);
        N_VLinearSum_Serial(a, x.stock, b, y.stock, z.stock);  // a (x +- y)
        ExpectFactoredSum(z, a, x, b, y, "z = a x + b y");
      }
    }
  }
}

TEST_F(SerialKernelsTest, ElementwiseKernelsEqualStock) {
  for (sunindextype n : kLengths) {
    const Pair x = Make(n), y = Make(n), z = Make(n);
    const double c = RandomScalar();
    N_VConst(c, z.ours);
    N_VConst_Serial(c, z.stock);
    ExpectSame(z, "const");
    N_VProd(x.ours, y.ours, z.ours);
    N_VProd_Serial(x.stock, y.stock, z.stock);
    ExpectSame(z, "prod");
    N_VDiv(x.ours, y.ours, z.ours);
    N_VDiv_Serial(x.stock, y.stock, z.stock);
    ExpectSame(z, "div");
    for (const double scale : {c, 1.0, -1.0, 0.0}) {  // stock: general, copy, negation
      N_VScale(scale, x.ours, z.ours);
      N_VScale_Serial(scale, x.stock, z.stock);
      ExpectSame(z, "scale by " + std::to_string(scale));
    }
    N_VAbs(x.ours, z.ours);
    N_VAbs_Serial(x.stock, z.stock);
    ExpectSame(z, "abs");
    N_VInv(x.ours, z.ours);
    N_VInv_Serial(x.stock, z.stock);
    ExpectSame(z, "inv");
    N_VAddConst(x.ours, c, z.ours);
    N_VAddConst_Serial(x.stock, c, z.stock);
    ExpectSame(z, "addconst");
    // In place, as CVODE calls them.
    N_VScale(c, z.ours, z.ours);
    N_VScale_Serial(c, z.stock, z.stock);
    ExpectSame(z, "z <- c z");
    N_VProd(z.ours, y.ours, z.ours);
    N_VProd_Serial(z.stock, y.stock, z.stock);
    ExpectSame(z, "z <- z y");
    N_VAbs(z.ours, z.ours);
    N_VAbs_Serial(z.stock, z.stock);
    ExpectSame(z, "z <- |z|");
    N_VInv(z.ours, z.ours);
    N_VInv_Serial(z.stock, z.stock);
    ExpectSame(z, "z <- 1 / z");
  }
}

TEST_F(SerialKernelsTest, CompareAndInvTestEqualStockIncludingTiesAndZeros) {
  for (sunindextype n : kLengths) {
    const Pair x = Make(n), z = Make(n), z_tested = Make(n);
    const double c = std::abs(RandomValue());
    // Every third entry exactly +-c (the >= tie), every fourth zero.
    Fill(x, [&](sunindextype i) {
      if (i % 4 == 3) return 0.0;
      if (i % 3 == 1) return i % 2 ? -c : c;
      return RandomValue();
    });
    N_VCompare(c, x.ours, z.ours);
    N_VCompare_Serial(c, x.stock, z.stock);
    ExpectSame(z, "compare");
    // InvTest leaves z_i alone where x_i = 0: z starts equal on both sides.
    EXPECT_EQ(N_VInvTest(x.ours, z_tested.ours), N_VInvTest_Serial(x.stock, z_tested.stock));
    ExpectSame(z_tested, "invtest with zeros");
    EXPECT_EQ(N_VInvTestLocal(x.ours, z_tested.ours),
              x.stock->ops->nvinvtestlocal(x.stock, z_tested.stock));
    ExpectSame(z_tested, "invtestlocal with zeros");
    Fill(x, [&](sunindextype) { return RandomValue(); });
    EXPECT_EQ(N_VInvTest(x.ours, z_tested.ours), N_VInvTest_Serial(x.stock, z_tested.stock));
    EXPECT_EQ(N_VInvTest(x.ours, z_tested.ours), SUNTRUE);
    ExpectSame(z_tested, "invtest without zeros");
  }
}

TEST_F(SerialKernelsTest, ReductionsEqualStockWithMasksAndWeights) {
  for (sunindextype n : kLengths) {
    const Pair x = Make(n), y = Make(n), w = Make(n), id = Make(n);
    // CVODE's weights are positive; SUNDIALS defines the norms for any.
    const Pair w_positive = Make(n);
    Fill(w_positive, [&](sunindextype) { return std::abs(RandomValue()); });
    // Mask entries of both signs, zeros of both signs, and fractions: only
    // id_i > 0 counts.
    const std::vector<double> mask_values = {1.0, 0.0, -1.0, 0.5, -0.0, 2.0, -0.25};
    Fill(id, [&](sunindextype i) { return mask_values[(i * 5 + 2) % mask_values.size()]; });
    EXPECT_EQ(N_VDotProd(x.ours, y.ours), N_VDotProd_Serial(x.stock, y.stock)) << n;
    EXPECT_EQ(N_VMaxNorm(x.ours), N_VMaxNorm_Serial(x.stock)) << n;
    EXPECT_EQ(N_VMin(x.ours), N_VMin_Serial(x.stock)) << n;
    EXPECT_EQ(N_VL1Norm(x.ours), N_VL1Norm_Serial(x.stock)) << n;
    for (const Pair* weights : {&w, &w_positive}) {
      EXPECT_EQ(N_VWrmsNorm(x.ours, weights->ours), N_VWrmsNorm_Serial(x.stock, weights->stock)) << n;
      EXPECT_EQ(N_VWrmsNormMask(x.ours, weights->ours, id.ours),
                N_VWrmsNormMask_Serial(x.stock, weights->stock, id.stock)) << n;
      EXPECT_EQ(N_VWL2Norm(x.ours, weights->ours), N_VWL2Norm_Serial(x.stock, weights->stock)) << n;
      EXPECT_EQ(N_VWSqrSumLocal(x.ours, weights->ours),
                N_VWSqrSumLocal_Serial(x.stock, weights->stock)) << n;
      EXPECT_EQ(N_VWSqrSumMaskLocal(x.ours, weights->ours, id.ours),
                N_VWSqrSumMaskLocal_Serial(x.stock, weights->stock, id.stock)) << n;
    }
    // The local reductions are the stock vector's own table entries.
    EXPECT_EQ(N_VDotProdLocal(x.ours, y.ours), x.stock->ops->nvdotprodlocal(x.stock, y.stock)) << n;
    EXPECT_EQ(N_VMaxNormLocal(x.ours), x.stock->ops->nvmaxnormlocal(x.stock)) << n;
    EXPECT_EQ(N_VMinLocal(x.ours), x.stock->ops->nvminlocal(x.stock)) << n;
    EXPECT_EQ(N_VL1NormLocal(x.ours), x.stock->ops->nvl1normlocal(x.stock)) << n;
    // A mask that drops every entry: the norm is 0, not undefined.
    Fill(id, [](sunindextype) { return 0.0; });
    EXPECT_EQ(N_VWrmsNormMask(x.ours, w.ours, id.ours), 0.0);
    EXPECT_EQ(N_VWrmsNormMask_Serial(x.stock, w.stock, id.stock), 0.0);
  }
}

TEST_F(SerialKernelsTest, FusedOperationsEqualStock) {
  for (sunindextype n : kLengths) {
    for (int count : {1, 2, 3, 5}) {
      std::vector<Pair> xs;
      std::vector<N_Vector> xs_ours, xs_stock;
      std::vector<double> c;
      for (int k = 0; k < count; ++k) {
        xs.push_back(Make(n));
        xs_ours.push_back(xs.back().ours);
        xs_stock.push_back(xs.back().stock);
        // Distinct magnitudes: for two vectors c[0] = +-c[1] would take
        // the stock's factored a (x +- y) (tested above).
        c.push_back(RandomScalar() * (k + 1) + (k % 2 ? 0.125 : -0.0625));
      }
      const std::string what = "count " + std::to_string(count) + ", n = " + std::to_string(n);
      // z = sum c_k X_k into a separate z.
      Pair z = Make(n);
      EXPECT_EQ(N_VLinearCombination(count, c.data(), xs_ours.data(), z.ours), 0);
      EXPECT_EQ(N_VLinearCombination_Serial(count, c.data(), xs_stock.data(), z.stock), 0);
      ExpectSame(z, "linearcombination, " + what);
      // Into X[0] itself, with c[0] = 1 (stock: X[0] += ...) and c[0] != 1.
      for (const double c0 : {1.0, c[0]}) {
        std::vector<double> c_in_place = c;
        c_in_place[0] = c0;
        if (count == 2 && std::abs(c0) == std::abs(c[1])) continue;
        EXPECT_EQ(N_VLinearCombination(count, c_in_place.data(), xs_ours.data(), xs_ours[0]), 0);
        EXPECT_EQ(N_VLinearCombination_Serial(count, c_in_place.data(), xs_stock.data(),
                                              xs_stock[0]), 0);
        ExpectSame(xs[0], "linearcombination into X[0], c[0] = " + std::to_string(c0) + ", " + what);
      }
      // Z[k] = a_k x + Y[k], separate and in place (Z == Y).
      const Pair x = Make(n);
      std::vector<Pair> zs;
      std::vector<N_Vector> zs_ours, zs_stock;
      for (int k = 0; k < count; ++k) {
        zs.push_back(Make(n));
        zs_ours.push_back(zs.back().ours);
        zs_stock.push_back(zs.back().stock);
      }
      EXPECT_EQ(N_VScaleAddMulti(count, c.data(), x.ours, xs_ours.data(), zs_ours.data()), 0);
      EXPECT_EQ(N_VScaleAddMulti_Serial(count, c.data(), x.stock, xs_stock.data(), zs_stock.data()), 0);
      for (const Pair& zk : zs) ExpectSame(zk, "scaleaddmulti, " + what);
      EXPECT_EQ(N_VScaleAddMulti(count, c.data(), x.ours, xs_ours.data(), xs_ours.data()), 0);
      EXPECT_EQ(N_VScaleAddMulti_Serial(count, c.data(), x.stock, xs_stock.data(), xs_stock.data()), 0);
      for (const Pair& xk : xs) ExpectSame(xk, "scaleaddmulti in place, " + what);
      // Z[k] = c_k X[k], separate and in place.
      EXPECT_EQ(N_VScaleVectorArray(count, c.data(), xs_ours.data(), zs_ours.data()), 0);
      EXPECT_EQ(N_VScaleVectorArray_Serial(count, c.data(), xs_stock.data(), zs_stock.data()), 0);
      for (const Pair& zk : zs) ExpectSame(zk, "scalevectorarray, " + what);
      EXPECT_EQ(N_VScaleVectorArray(count, c.data(), xs_ours.data(), xs_ours.data()), 0);
      EXPECT_EQ(N_VScaleVectorArray_Serial(count, c.data(), xs_stock.data(), xs_stock.data()), 0);
      for (const Pair& xk : xs) ExpectSame(xk, "scalevectorarray in place, " + what);
    }
  }
}

TEST_F(SerialKernelsTest, FusedOperationsRejectAnEmptyListAsStockDoes) {
  const Pair x = Make(3), z = Make(3);
  N_Vector ours[] = {x.ours}, stock[] = {x.stock}, zs_ours[] = {z.ours}, zs_stock[] = {z.stock};
  double c[] = {2.0};
  EXPECT_EQ(x.ours->ops->nvlinearcombination(0, c, ours, z.ours),
            N_VLinearCombination_Serial(0, c, stock, z.stock));
  EXPECT_EQ(x.ours->ops->nvscaleaddmulti(0, c, x.ours, ours, zs_ours),
            N_VScaleAddMulti_Serial(0, c, x.stock, stock, zs_stock));
  EXPECT_EQ(x.ours->ops->nvscalevectorarray(0, c, ours, zs_ours),
            N_VScaleVectorArray_Serial(0, c, stock, zs_stock));
  EXPECT_EQ(N_VLinearCombination_Serial(0, c, stock, z.stock), -1);
}

}  // namespace
}  // namespace ipmc
