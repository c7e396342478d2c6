#include "plugin/fluid/geom_resistance.h"

#include <boost/math/special_functions/ellint_rd.hpp>
#include <boost/math/special_functions/ellint_rf.hpp>

#include "sim/base/numbers.h"

namespace ipmc {

PrincipalResistance EllipsoidResistance(const Eigen::Vector3d& semi_axes_m,
                                        double viscosity_Pa_s) {
  const Eigen::Vector3d c2 = semi_axes_m.cwiseProduct(semi_axes_m);
  const double chi = 2.0 * boost::math::ellint_rf(c2[0], c2[1], c2[2]);
  Eigen::Vector3d alpha;
  for (int i = 0; i < 3; ++i) {
    alpha[i] = 2.0 / 3.0 * boost::math::ellint_rd(c2[(i + 1) % 3], c2[(i + 2) % 3], c2[i]);
  }
  PrincipalResistance resistance;
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3, k = (i + 2) % 3;
    resistance.translation_N_s_m[i] = 16.0 * kPi * viscosity_Pa_s / (chi + c2[i] * alpha[i]);
    resistance.rotation_N_m_s[i] = 16.0 * kPi * viscosity_Pa_s * (c2[j] + c2[k]) /
                                   (3.0 * (c2[j] * alpha[j] + c2[k] * alpha[k]));
  }
  return resistance;
}

Matrix6 PrincipalResistanceAbout(const PrincipalResistance& principal,
                                 const Eigen::Vector3d& center_W, const Eigen::Matrix3d& axes_W,
                                 const Eigen::Vector3d& c_W) {
  const Eigen::Matrix3d k_t =
      axes_W * principal.translation_N_s_m.asDiagonal() * axes_W.transpose();
  const Eigen::Matrix3d k_r = axes_W * principal.rotation_N_m_s.asDiagonal() * axes_W.transpose();
  const Eigen::Matrix3d rx = CrossMatrix(center_W - c_W);
  const Eigen::Matrix3d rx_kt = rx * k_t;
  Matrix6 s;
  s.topLeftCorner<3, 3>() = k_r - rx_kt * rx;
  s.topRightCorner<3, 3>() = rx_kt;
  s.bottomLeftCorner<3, 3>() = rx_kt.transpose();
  s.bottomRightCorner<3, 3>() = k_t;
  return s;
}

}  // namespace ipmc
