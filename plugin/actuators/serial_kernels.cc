// Serial vector kernels compiled with the project.
//
// Why: Debian 12's SUNDIALS 6.4 libraries are built without optimisation
// (N_VScale_Serial stores every argument to the stack and reloads it), and
// for the actuator bank's short vectors (tens of states) the vector
// kernels are most of CVODE's cost. CPU time per call on the bank's 30
// states, both called through the vector's operation table as CVODE calls
// them (bench/serial_kernels_bench.cc, median of 5): N_VLinearSum 74-113 ns
// stock against 13-14 ns here, N_VWrmsNorm 269 ns against 26-31 ns,
// N_VScale 76 ns against 12-20 ns.
//
// Each kernel computes what the corresponding N_V*_Serial operation
// defines (tests/serial_kernels_test.cc compares them on random vectors).
// Element-wise loops read x[i] before writing z[i], so aliased arguments
// behave as in SUNDIALS.
#include "plugin/actuators/serial_kernels.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace ipmc::serial_kernels {
namespace {

inline double* Data(N_Vector v) { return NV_DATA_S(v); }
inline sunindextype Length(N_Vector v) { return NV_LENGTH_S(v); }

// z = a x + b y
void LinearSum(realtype a, N_Vector x, realtype b, N_Vector y, N_Vector z) {
  const double* xd = Data(x);
  const double* yd = Data(y);
  double* zd = Data(z);
  for (sunindextype i = 0, n = Length(z); i < n; ++i) {
    zd[i] = a * xd[i] + b * yd[i];
  }
}

void Const(realtype c, N_Vector z) {
  double* zd = Data(z);
  for (sunindextype i = 0, n = Length(z); i < n; ++i) zd[i] = c;
}

void Prod(N_Vector x, N_Vector y, N_Vector z) {
  const double* xd = Data(x);
  const double* yd = Data(y);
  double* zd = Data(z);
  for (sunindextype i = 0, n = Length(z); i < n; ++i) zd[i] = xd[i] * yd[i];
}

void Div(N_Vector x, N_Vector y, N_Vector z) {
  const double* xd = Data(x);
  const double* yd = Data(y);
  double* zd = Data(z);
  for (sunindextype i = 0, n = Length(z); i < n; ++i) zd[i] = xd[i] / yd[i];
}

void Scale(realtype c, N_Vector x, N_Vector z) {
  const double* xd = Data(x);
  double* zd = Data(z);
  for (sunindextype i = 0, n = Length(z); i < n; ++i) zd[i] = c * xd[i];
}

void Abs(N_Vector x, N_Vector z) {
  const double* xd = Data(x);
  double* zd = Data(z);
  for (sunindextype i = 0, n = Length(z); i < n; ++i) zd[i] = std::abs(xd[i]);
}

void Inv(N_Vector x, N_Vector z) {
  const double* xd = Data(x);
  double* zd = Data(z);
  for (sunindextype i = 0, n = Length(z); i < n; ++i) zd[i] = 1.0 / xd[i];
}

void AddConst(N_Vector x, realtype b, N_Vector z) {
  const double* xd = Data(x);
  double* zd = Data(z);
  for (sunindextype i = 0, n = Length(z); i < n; ++i) zd[i] = xd[i] + b;
}

realtype DotProd(N_Vector x, N_Vector y) {
  const double* xd = Data(x);
  const double* yd = Data(y);
  double sum = 0;
  for (sunindextype i = 0, n = Length(x); i < n; ++i) sum += xd[i] * yd[i];
  return sum;
}

realtype MaxNorm(N_Vector x) {
  const double* xd = Data(x);
  double max = 0;
  for (sunindextype i = 0, n = Length(x); i < n; ++i) {
    max = std::max(max, std::abs(xd[i]));
  }
  return max;
}

// sum_i (x_i w_i)^2
realtype WSqrSum(N_Vector x, N_Vector w) {
  const double* xd = Data(x);
  const double* wd = Data(w);
  double sum = 0;
  for (sunindextype i = 0, n = Length(x); i < n; ++i) {
    const double p = xd[i] * wd[i];
    sum += p * p;
  }
  return sum;
}

// The same over the i with id_i > 0.
realtype WSqrSumMask(N_Vector x, N_Vector w, N_Vector id) {
  const double* xd = Data(x);
  const double* wd = Data(w);
  const double* idd = Data(id);
  double sum = 0;
  for (sunindextype i = 0, n = Length(x); i < n; ++i) {
    if (!(idd[i] > 0)) continue;
    const double p = xd[i] * wd[i];
    sum += p * p;
  }
  return sum;
}

// sqrt(WSqrSum / n): the mean is over all n entries, masked or not.
realtype WrmsNorm(N_Vector x, N_Vector w) {
  return std::sqrt(WSqrSum(x, w) / static_cast<double>(Length(x)));
}

realtype WrmsNormMask(N_Vector x, N_Vector w, N_Vector id) {
  return std::sqrt(WSqrSumMask(x, w, id) / static_cast<double>(Length(x)));
}

realtype Min(N_Vector x) {
  const double* xd = Data(x);
  double min = xd[0];
  for (sunindextype i = 1, n = Length(x); i < n; ++i) min = std::min(min, xd[i]);
  return min;
}

realtype Wl2Norm(N_Vector x, N_Vector w) { return std::sqrt(WSqrSum(x, w)); }

realtype L1Norm(N_Vector x) {
  const double* xd = Data(x);
  double sum = 0;
  for (sunindextype i = 0, n = Length(x); i < n; ++i) sum += std::abs(xd[i]);
  return sum;
}

// z_i = 1 if |x_i| >= c, else 0
void Compare(realtype c, N_Vector x, N_Vector z) {
  const double* xd = Data(x);
  double* zd = Data(z);
  for (sunindextype i = 0, n = Length(z); i < n; ++i) {
    zd[i] = std::abs(xd[i]) >= c ? 1.0 : 0.0;
  }
}

// z_i = 1 / x_i where x_i != 0 (z_i untouched elsewhere); false if any
// x_i = 0.
booleantype InvTest(N_Vector x, N_Vector z) {
  const double* xd = Data(x);
  double* zd = Data(z);
  booleantype ok = SUNTRUE;
  for (sunindextype i = 0, n = Length(z); i < n; ++i) {
    if (xd[i] == 0.0) {
      ok = SUNFALSE;
    } else {
      zd[i] = 1.0 / xd[i];
    }
  }
  return ok;
}

// The data of `count` vectors, gathered once so that the element loops do
// not chase each vector's content pointer per element.
class DataPointers {
 public:
  DataPointers(int count, N_Vector* v) : heap_(count > kInline ? count : 0) {
    data_ = count > kInline ? heap_.data() : inline_;
    for (int k = 0; k < count; ++k) data_[k] = Data(v[k]);
  }
  double* operator[](int k) const { return data_[k]; }

 private:
  static constexpr int kInline = 16;
  double* inline_[kInline];
  std::vector<double*> heap_;
  double** data_;
};

// z = sum_k c[k] X[k], summed in k order; -1 for count < 1.
int LinearCombination(int count, realtype* c, N_Vector* x, N_Vector z) {
  if (count < 1) return -1;
  double* zd = Data(z);
  const sunindextype n = Length(z);
  const DataPointers xd(count, x);
  for (sunindextype i = 0; i < n; ++i) {
    double sum = c[0] * xd[0][i];
    for (int k = 1; k < count; ++k) sum += c[k] * xd[k][i];
    zd[i] = sum;
  }
  return 0;
}

// Z[k] = a[k] x + Y[k]; -1 for count < 1. Vector by vector unless x is one
// of the Z[k] (then element by element, reading x_i before any write).
int ScaleAddMulti(int count, realtype* a, N_Vector x, N_Vector* y, N_Vector* z) {
  if (count < 1) return -1;
  const double* xd = Data(x);
  const sunindextype n = Length(x);
  const DataPointers yd(count, y), zd(count, z);
  bool x_is_written = false;
  for (int k = 0; k < count; ++k) x_is_written |= zd[k] == xd;
  if (!x_is_written) {
    for (int k = 0; k < count; ++k) {
      const double ak = a[k];
      const double* yk = yd[k];
      double* zk = zd[k];
      for (sunindextype i = 0; i < n; ++i) zk[i] = ak * xd[i] + yk[i];
    }
    return 0;
  }
  for (sunindextype i = 0; i < n; ++i) {
    const double xi = xd[i];
    for (int k = 0; k < count; ++k) zd[k][i] = a[k] * xi + yd[k][i];
  }
  return 0;
}

// Z[k] = c[k] X[k]; -1 for count < 1.
int ScaleVectorArray(int count, realtype* c, N_Vector* x, N_Vector* z) {
  if (count < 1) return -1;
  for (int k = 0; k < count; ++k) Scale(c[k], x[k], z[k]);
  return 0;
}

}  // namespace

void Install(N_Vector v) {
  N_Vector_Ops ops = v->ops;
  ops->nvlinearsum = LinearSum;
  ops->nvconst = Const;
  ops->nvprod = Prod;
  ops->nvdiv = Div;
  ops->nvscale = Scale;
  ops->nvabs = Abs;
  ops->nvinv = Inv;
  ops->nvaddconst = AddConst;
  ops->nvdotprod = DotProd;
  ops->nvmaxnorm = MaxNorm;
  ops->nvwrmsnorm = WrmsNorm;
  ops->nvwrmsnormmask = WrmsNormMask;
  ops->nvmin = Min;
  ops->nvwl2norm = Wl2Norm;
  ops->nvl1norm = L1Norm;
  ops->nvcompare = Compare;
  ops->nvinvtest = InvTest;
  ops->nvlinearcombination = LinearCombination;
  ops->nvscaleaddmulti = ScaleAddMulti;
  ops->nvscalevectorarray = ScaleVectorArray;
  // Serial: the local reductions are the global ones.
  ops->nvdotprodlocal = DotProd;
  ops->nvmaxnormlocal = MaxNorm;
  ops->nvminlocal = Min;
  ops->nvl1normlocal = L1Norm;
  ops->nvinvtestlocal = InvTest;
  ops->nvwsqrsumlocal = WSqrSum;
  ops->nvwsqrsummasklocal = WSqrSumMask;
}

}  // namespace ipmc::serial_kernels
