#include "plugin/actuators/shifted_schur.h"

#include <cmath>

namespace ipmc {

bool IsQuasiLowerTriangular(const Eigen::MatrixXd& a) {
  const Eigen::Index n = a.rows();
  for (Eigen::Index i = 0; i < n; ++i) {
    for (Eigen::Index j = i + 1; j < n; ++j) {
      if (a(i, j) == 0.0) continue;
      if (j != i + 1) return false;
      if (i > 0 && a(i - 1, i) != 0.0) return false;  // overlaps the pair above
    }
  }
  return true;
}

bool SolveShiftedQuasiTriangular(const double* t_rows, int n, double gamma, double* z) {
  constexpr double kTiny = 1e-300;
  const auto t = [t_rows, n](int row, int col) { return t_rows[row * n + col]; };
  // z_k += gamma sum_{j > last} T(k, j) z_j, the already solved part.
  const auto eliminate = [&](int k, int last) {
    const double* row = t_rows + k * n;
    double sum = 0.0;
    for (int j = last + 1; j < n; ++j) sum += row[j] * z[j];
    z[k] += gamma * sum;
  };
  int i = n - 1;
  while (i >= 0) {
    const bool pair = i > 0 && t(i, i - 1) != 0.0;
    const int top = pair ? i - 1 : i;
    for (int k = top; k <= i; ++k) eliminate(k, i);
    if (!pair) {
      const double pivot = 1.0 - gamma * t(i, i);
      if (std::abs(pivot) < kTiny) return false;
      z[i] /= pivot;
    } else {
      // [1 - g t00, -g t01; -g t10, 1 - g t11] [w0; w1] = [z0; z1]
      const double m00 = 1.0 - gamma * t(top, top);
      const double m01 = -gamma * t(top, i);
      const double m10 = -gamma * t(i, top);
      const double m11 = 1.0 - gamma * t(i, i);
      const double det = m00 * m11 - m01 * m10;
      if (std::abs(det) < kTiny) return false;
      const double z0 = z[top];
      const double z1 = z[i];
      z[top] = (m11 * z0 - m01 * z1) / det;
      z[i] = (m00 * z1 - m10 * z0) / det;
    }
    i = top - 1;
  }
  return true;
}

bool SolveShiftedSchur(const double* q, const double* t_rows, int n, double gamma, const double* r,
                       double* x, double* work) {
  // work = Q^T r (column i of Q dotted with r, or r reversed when Q = P).
  if (q == nullptr) {
    for (int i = 0; i < n; ++i) work[i] = r[n - 1 - i];
  } else {
    for (int i = 0; i < n; ++i) {
      const double* column = q + i * n;
      double sum = 0.0;
      for (int k = 0; k < n; ++k) sum += column[k] * r[k];
      work[i] = sum;
    }
  }
  if (!SolveShiftedQuasiTriangular(t_rows, n, gamma, work)) return false;
  // x = Q work, column by column.
  if (q == nullptr) {
    for (int i = 0; i < n; ++i) x[n - 1 - i] = work[i];
    return true;
  }
  for (int k = 0; k < n; ++k) x[k] = 0.0;
  for (int i = 0; i < n; ++i) {
    const double* column = q + i * n;
    const double w = work[i];
    for (int k = 0; k < n; ++k) x[k] += column[k] * w;
  }
  return true;
}

}  // namespace ipmc
