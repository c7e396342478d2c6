// Reference model of the controller design (paper section 5.2, after the
// reference-model strategy it cites as [57]): Bode's ideal loop
//
//   L_ol(s) = (w_c / s)^gamma                    (eq. 8)
//   L_cl(s) = 1 / ((s / w_c)^gamma + 1)          (eq. 9)
//
// with w_c = 5 rad/s and gamma = 1.16 (phase margin 180 - 90 gamma = 75.6
// deg). Its unit-step response is
//
//   y(t) = 1 - E_gamma(-(w_c t)^gamma),
//
// E_alpha the Mittag-Leffler function E_alpha(z) = sum_k z^k / Gamma(alpha k
// + 1). For real z <= 0 and 0 < alpha <= 2 it is evaluated here by one of
// two algorithms, switching at tau = |z|^(1/alpha) = kMittagLefflerSwitchTau:
//  - tau <= switch: the power series, summed in long double with Kahan
//    compensation (the terms reach about e^tau / alpha in size, so the
//    cancellation costs at most a factor e^tau of the long double epsilon);
//  - tau > switch: the Laplace-inversion (Hankel contour) representation
//    of E_alpha(-tau^alpha) = L^-1[s^(alpha-1) / (s^alpha + 1)](tau):
//      E_alpha(-tau^alpha) = sin(alpha pi) / (pi alpha) * I(tau)
//        + [alpha > 1] (2 / alpha) exp(tau cos(pi / alpha))
//            cos(tau sin(pi / alpha)),
//    I(tau) = int_0^inf exp(-tau w^(1/alpha)) dw
//                       / (w^2 + 2 w cos(alpha pi) + 1),
//    the [alpha > 1] term being the residues at the two poles
//    s = exp(+-i pi / alpha) of the principal sheet. The integral is taken
//    in v = ln w (integrand exp(-tau e^(v/alpha)) / (2 cosh v + 2 cos(alpha
//    pi)), exponentially decaying both ways) by Boost.Math's adaptive
//    Gauss-Kronrod (7/15 points). It holds for every tau >= 0.
// alpha = 1 gives exp(z) and alpha = 2 gives cos(sqrt(-z)) exactly.
#ifndef IPMC_SWIM_CONTROLLERS_REFERENCE_MODEL_H_
#define IPMC_SWIM_CONTROLLERS_REFERENCE_MODEL_H_

#include <complex>
#include <optional>

namespace ipmc {

// Switch between the series and the integral representation, in
// tau = |z|^(1/alpha).
constexpr double kMittagLefflerSwitchTau = 5.0;

// E_alpha(z) for 0 < alpha <= 2 and real z <= 0 (both finite), by the
// series or the integral representation as described above. Throws
// std::domain_error naming the argument otherwise.
double MittagLeffler(double alpha, double z);

// The two algorithms on their own (same domain, alpha != 1 for the
// integral, alpha < 2 too), for cross-checks. The series loses accuracy as
// e^tau / 1e19 and gives up (std::domain_error) beyond tau = 40.
double MittagLefflerSeries(double alpha, double z);
double MittagLefflerIntegral(double alpha, double z);

class ReferenceModel {
 public:
  struct Config {
    double crossover_rad_s = 5.0;  // w_c, finite and > 0
    double order = 1.16;           // gamma, in (0, 2]

    // Throws std::invalid_argument naming the field and its allowed range.
    void Validate() const;
  };

  // The paper's model: w_c = 5 rad/s, gamma = 1.16.
  ReferenceModel();
  // Throws std::invalid_argument for a bad configuration.
  explicit ReferenceModel(const Config& config);

  // Eq. 8 and eq. 9 on the principal branch; e.g. OpenLoop({0, w}).
  std::complex<double> OpenLoop(std::complex<double> s) const;
  std::complex<double> ClosedLoop(std::complex<double> s) const;

  // Unit-step response y(t) = 1 - E_gamma(-(w_c t)^gamma); 0 for t <= 0.
  // Throws std::domain_error if t is not finite.
  double StepResponse(double t_s) const;

  struct Peak {
    double time_s = 0;
    double value = 0;
  };
  // The first local maximum of the step response: a scan in steps of
  // w_c t = 0.05 up to w_c t = 200, then golden-section search (the
  // flatness of the peak limits the time to about 1e-7 s, the value to
  // about 1e-15). Empty if there is none in that range (always for
  // gamma <= 1: the response is then monotone).
  std::optional<Peak> StepPeak() const;

  const Config& config() const { return config_; }

 private:
  Config config_;
};

}  // namespace ipmc

#endif  // IPMC_SWIM_CONTROLLERS_REFERENCE_MODEL_H_
