// Exact Stokes drag of an ellipsoid, for the fluid models' tests.
#pragma once

#include <boost/math/quadrature/exp_sinh.hpp>
#include <cmath>

#include <Eigen/Core>

#include "sim/base/numbers.h"

namespace ipmc::testing {

// Oberbeck's (1876) ellipsoid of semi-axes c [m] in a fluid of viscosity
// mu [Pa s] (Kim & Karrila, Microhydrodynamics, 1991, sec. 3.3), with
//   chi = int_0^inf dl / D,  alpha_i = int_0^inf dl / ((c_i^2 + l) D),
//   D = sqrt(prod_k (c_k^2 + l)):
// translation along axis i, F_i = 16 pi mu U / (chi + c_i^2 alpha_i);
// rotation about axis i, T_i = 16 pi mu (c_j^2 + c_k^2) Omega /
// (3 (c_j^2 alpha_j + c_k^2 alpha_k)).
class OberbeckEllipsoid {
 public:
  OberbeckEllipsoid(const Eigen::Vector3d& semi_axes_m, double mu_Pa_s)
      : c_(semi_axes_m), mu_Pa_s_(mu_Pa_s) {
    const auto d = [&](double l) {
      return std::sqrt((c_[0] * c_[0] + l) * (c_[1] * c_[1] + l) * (c_[2] * c_[2] + l));
    };
    boost::math::quadrature::exp_sinh<double> integrator;
    chi_ = integrator.integrate([&](double l) { return 1.0 / d(l); });
    for (int i = 0; i < 3; ++i) {
      alpha_[i] =
          integrator.integrate([&](double l) { return 1.0 / ((c_[i] * c_[i] + l) * d(l)); });
    }
  }
  // F_i / U [N s/m].
  double Drag_N_s_m(int i) const {
    return 16.0 * kPi * mu_Pa_s_ / (chi_ + c_[i] * c_[i] * alpha_[i]);
  }
  // T_i / Omega [N m s].
  double RotationalDrag_N_m_s(int i) const {
    const int j = (i + 1) % 3, k = (i + 2) % 3;
    return 16.0 * kPi * mu_Pa_s_ * (c_[j] * c_[j] + c_[k] * c_[k]) /
           (3.0 * (c_[j] * c_[j] * alpha_[j] + c_[k] * c_[k] * alpha_[k]));
  }

 private:
  Eigen::Vector3d c_, alpha_;
  double mu_Pa_s_;
  double chi_ = 0.0;
};

}  // namespace ipmc::testing
