// Linear algebra of the CVODE integrator's exact Newton solve
// (plugin/actuators/cvode_integrator.h, kBlockSchur): each link block's A
// in real Schur form, solved shifted, (I - gamma T) w = z, by back
// substitution.
#pragma once

#include <Eigen/Core>

namespace ipmc {

// True if every nonzero of a above the diagonal is the upper corner of a
// 2x2 diagonal block, with no two such blocks overlapping.
bool IsQuasiLowerTriangular(const Eigen::MatrixXd& a);

// Solves (I - gamma T) w = z in place for the n x n quasi-upper-triangular
// T (1x1 and 2x2 diagonal blocks), stored by rows, by back substitution.
// Returns false if a pivot vanishes (an unstable block with
// 1 - gamma lambda = 0).
bool SolveShiftedQuasiTriangular(const double* t_rows, int n, double gamma, double* z);

// x = (I - gamma A)^-1 r for one n x n block A = Q T Q^T:
// x = Q (I - gamma T)^-1 Q^T r, with q the column-major Q, or null for
// Q = P, the reversal of the states (a quasi-lower-triangular A, for which
// T = P A P), and t_rows T by rows. work holds n values; x may alias r.
// Returns false as SolveShiftedQuasiTriangular does.
bool SolveShiftedSchur(const double* q, const double* t_rows, int n, double gamma, const double* r,
                       double* x, double* work);

}  // namespace ipmc
