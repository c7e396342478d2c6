// Measures how a free swimmer moves: its pose, the net displacement per
// cycle, the mean speed and the Reynolds numbers. Shared by the gait and
// the closed-loop runs.
//
// Frames: the swimming axis is -x (the head points to -x at rest); "along"
// is displacement along -x (positive = head first), "across" along +y.
// The head is the root body's origin (where link 1 starts); the centre of
// mass is that of the root body's subtree.
#pragma once

#include <mujoco/mujoco.h>

#include <string>
#include <vector>

#include "sim/core/link_sensors.h"
#include "sim/core/step_resolution.h"

namespace ipmc {

struct BodyPose {
  double t_s = 0.0;
  double com_x_mm = 0.0, com_y_mm = 0.0, head_x_mm = 0.0, head_y_mm = 0.0, yaw_rad = 0.0;
  std::vector<double> tip_x_mm, tip_y_mm;  // sites tip1..tipN, or the links' tips (LinkTips)
};

struct Displacement_mm {
  double com_along = 0.0, com_across = 0.0, head_along = 0.0, head_across = 0.0;
};

struct SwimMetrics {
  std::vector<Displacement_mm> per_cycle;
  int from_cycle = 1;                        // the mean speed's first cycle
  double mean_speed_along_mm_s = 0.0;       // centre of mass, over cycles from from_cycle
  double peak_lateral_tip_speed_mm_s = 0.0;  // last tip, across the axis
  double reynolds_tip = 0.0;                 // rho v_tip w / mu
  double reynolds_swim = 0.0;                // rho |U| L_body / mu
  // The oscillating strip's, rho omega w^2 / (4 mu) (Sader, J. Appl.
  // Phys. 84, 64 (1998): a beam of width w oscillating at omega); 0 when
  // the run has no frequency.
  double reynolds_oscillatory = 0.0;
  double frequency_Hz = 0.0;                 // the wave's or gait's
  double viscosity_Pa_s = 0.0;               // the fluid's
  double body_length_mm = 0.0;               // sum of the drag segments
  double longest_segment_mm = 0.0;           // the longest drag segment
  // Whether the time step resolves the swim: the drag relaxation measured
  // at the start (Start(m, d, ...)), the swim's error at the end (Finish).
  StepResolution step;
  double controller_rate_Hz = 0.0;  // rounds the step the warning names
  double LargestReynolds() const;
  // What the run's numbers should be read with (FluidWarnings).
  std::vector<std::string> warnings;
};

// A Reynolds number above this warns that the run is outside the drag
// models' validity (all of them Stokes flow, Re < 1): Oseen's first
// inertial correction to the Stokes drag of a sphere is a factor
// 1 + 3/16 Re (Re on the diameter), 15 % at the paper run's 0.79 and 19 %
// at 1 (docs/MODEL.md); past 1 the correction itself fails.
constexpr double kReynoldsWarning = 1.0;
// The Reynolds number the warning's advice aims at (Stokes flow to about
// 2 % on a sphere, by Oseen's factor).
constexpr double kReynoldsStokes = 0.1;
// Fewer drag segments than this per wavelength cannot represent the wave
// (three straight chords of a sine are the fewest that bend both ways).
constexpr double kMinSegmentsPerWavelength = 3.0;

// The warnings for a swim: a time step that does not resolve the swim
// (StepResolutionWarnings), a Reynolds number above
// kReynoldsWarning (with the viscosity or frequency that makes it
// kReynoldsStokes) and, for a wave of `wavelength_mm` (0: none), fewer
// than kMinSegmentsPerWavelength drag segments per wavelength.
std::vector<std::string> FluidWarnings(const SwimMetrics& swim, double wavelength_mm);

// Throws std::runtime_error "WHAT: METRIC is not finite" for the first
// metric (per-cycle displacement, speed, Reynolds number) that is not: a
// run must not report a number it did not compute.
void RequireFiniteMetrics(const SwimMetrics& swim, const std::string& what);

class SwimMeter {
 public:
  // The tips are the sites tip1..tipN; a model without them, given an
  // attached d, has its IPMC links' tips (LinkTips, sim/core/link_sensors.h).
  explicit SwimMeter(const mjModel* m, const mjData* d = nullptr);

  BodyPose Pose(const mjData* d) const;
  // Marks the start of the run and of its first cycle.
  void Start(const mjData* d);
  // The same, and measures m's drag relaxation at d's state for the step
  // check of a wave of `frequency_Hz` (MeasureStepResolution); the warning rounds the step it names to
  // `controller_rate_Hz` (0: none).
  void Start(const mjModel* m, const mjData* d, double frequency_Hz,
             double controller_rate_Hz = 0.0);
  // After every step: tracks the peak lateral tip speed (of the state at
  // the start of the step, like sensordata).
  void Observe(const mjModel* m, const mjData* d);
  // At the end of each cycle: records its net displacement.
  void EndCycle(const mjData* d);
  // Mean speed since the start of cycle `from_cycle` (1: since Start) and
  // the Reynolds numbers (needs the model's RFT fields through the
  // coupling of d; without them all are 0), with FluidWarnings for the
  // wave's wavelength (0: no wave); the oscillatory Reynolds number at
  // `frequency_Hz` (0: none).
  SwimMetrics Finish(const mjData* d, int from_cycle = 1,
                     double wavelength_mm = 0.0, double frequency_Hz = 0.0) const;

 private:
  std::vector<LinkTip> tips_;
  BodyPose run_start_, cycle_start_;
  std::vector<BodyPose> cycle_starts_;  // of every cycle ended, the first first
  SwimMetrics metrics_;
};

}  // namespace ipmc
