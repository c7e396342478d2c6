#include "sim/core/step_count.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace ipmc {

long CheckedStepCount(double interval_s, double timestep_s, long min_steps, const std::string& what) {
  std::ostringstream msg;
  msg.precision(6);
  if (!std::isfinite(timestep_s) || timestep_s <= 0.0) {
    msg << what << ": the model's time step must be finite and > 0 s (got " << timestep_s << ")";
    throw std::invalid_argument(msg.str());
  }
  if (!std::isfinite(interval_s) || interval_s <= 0.0) {
    msg << what << ": must last a finite time > 0 s (got " << interval_s << " s)";
    throw std::invalid_argument(msg.str());
  }
  const double steps = std::round(interval_s / timestep_s);
  if (steps < static_cast<double>(min_steps) || steps > kMaxStepsPerInterval) {
    msg << what << " of " << interval_s << " s takes " << steps << " steps of " << timestep_s
        << " s; allowed [" << min_steps << ", " << kMaxStepsPerInterval << "]";
    throw std::invalid_argument(msg.str());
  }
  return static_cast<long>(steps);
}

namespace {

constexpr double kBeyondAnyMachine = 1e15;

std::string Duration(double seconds) {
  std::ostringstream text;
  text.precision(3);
  if (seconds < 120) {
    text << seconds << " s";
  } else if (seconds < 7200) {
    text << seconds / 60 << " min";
  } else if (seconds < 2 * 86400) {
    text << seconds / 3600 << " h";
  } else {
    text << seconds / 86400 << " days";
  }
  return text.str();
}

std::string Bytes(double bytes) {
  std::ostringstream text;
  text.precision(3);
  if (bytes < 1e6) {
    text << bytes / 1e3 << " kB";
  } else if (bytes < 1e9) {
    text << bytes / 1e6 << " MB";
  } else {
    text << bytes / 1e9 << " GB";
  }
  return text.str();
}

}  // namespace

void CheckStokesletSize(double points, bool allowed, const std::string& what) {
  const double rows = 3.0 * points;
  const double bytes = 16.0 * rows * rows;
  const double factor_s = rows * rows * rows / 3.0 / kStokesletFlops;
  const bool too_big = !(bytes <= kMaxRunRecordBytes);
  if (!too_big && (factor_s <= kMaxStokesletRecompute_s || allowed)) return;
  std::ostringstream msg;
  msg.precision(3);
  if (!(bytes <= kBeyondAnyMachine)) {
    msg << what << ": " << points << " Stokeslet points, a mobility matrix no machine holds ("
        << "the limit is " << Bytes(kMaxRunRecordBytes) << "; fewer points)";
    throw std::invalid_argument(msg.str());
  }
  msg << what << ": " << points << " Stokeslet points make a " << rows << " x " << rows
      << " mobility matrix of " << Bytes(bytes) << " (with its factor) that takes about "
      << Duration(factor_s) << " to factor, each time the resistance is recomputed; ";
  if (too_big) {
    msg << "the limit is " << Bytes(kMaxRunRecordBytes) << " (fewer points)";
  } else {
    msg << "the limit is " << kMaxStokesletRecompute_s
        << " s a recomputation (fewer points, or --allow-long to run it anyway)";
  }
  throw std::invalid_argument(msg.str());
}

void CheckRunSize(double steps, double recorded_bytes, bool allowed, const std::string& what) {
  const bool too_long = steps > kMaxRunSteps || recorded_bytes > kMaxRunRecordBytes;
  const bool impossible = !(steps <= kBeyondAnyMachine) || !(recorded_bytes <= kBeyondAnyMachine);
  if (!impossible && (!too_long || allowed)) return;
  std::ostringstream msg;
  msg.precision(3);
  msg << what << " needs " << steps << " steps (about " << Duration(steps * kMeasuredStepCost_s)
      << " at " << kMeasuredStepCost_s * 1e6 << " us a step) and " << Bytes(recorded_bytes)
      << " of recorded samples; ";
  if (impossible) {
    msg << "no machine runs that (shorten the run or lengthen the time step)";
  } else {
    msg << "the limit is " << kMaxRunSteps << " steps and " << Bytes(kMaxRunRecordBytes)
        << " (pass --allow-long to run it anyway)";
  }
  throw std::invalid_argument(msg.str());
}

}  // namespace ipmc
