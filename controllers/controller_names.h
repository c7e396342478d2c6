// The names of the controllers, as scenario files (controller.kind), the
// bode and step commands (controller), summaries and tables spell them;
// every reader and writer of a name uses these.
#pragma once

namespace ipmc::controller_names {

inline constexpr char kPid[] = "pid";                // eq. 10 (gains of eq. 12)
inline constexpr char kFractional[] = "fractional";  // eq. 13 (K, lambda of eq. 14)
// The fractional integrator as the paper's printed eq. 15, a ratio of quartics.
inline constexpr char kFractionalEq15[] = "fractional-eq15";
// The fractional integrator through its Oustaloup realisation.
inline constexpr char kFractionalOustaloup[] = "fractional-oustaloup";
inline constexpr char kNone[] = "none";              // C = 1: the plant alone

}  // namespace ipmc::controller_names
