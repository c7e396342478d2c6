// `gait` as the command line runs it (sim/runs/gait_run.h): the option
// table, the gait built from its options for the model's servos, the
// output folder checked before the run, the run and its files.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <mujoco/mujoco.h>

#include "sim/core/gait.h"
#include "sim/io/option_table.h"
#include "sim/runs/gait_run.h"

namespace ipmc {

struct GaitCommand {
  std::string model;  // default: models/flagellum3.xml
  std::string gait = "sine";  // sine | square | csv
  double frequency_Hz = 0.01;
  double amplitude_rad = 0.3;
  double phase_lag_rad = 2.0;
  std::vector<double> amplitudes_rad;  // sine: per joint (empty: amplitude_rad)
  std::vector<double> phases_rad;      // sine: per joint (empty: the phase lag's)
  std::string csv;  // csv gait: time_s, q_1..q_n [rad]
  GaitRunOptions run;
  std::string out;  // "": no files
  GaitCommand();
};

const OptionTable<GaitCommand>& GaitOptions();

// The actuators named servo_*: the joints a gait drives.
int CountServos(const mjModel* m);

// The gait the options describe, for `joints` servos; throws FieldError
// naming the field (csv without a file, amplitudes_rad of the wrong size).
std::unique_ptr<Gait> MakeGait(const GaitCommand& command, int joints);

// Checks `out` (CheckRunOutputDirectory, never over the model or the csv),
// runs the gait with `on_sample` (progress) and writes OUT's files; the
// period is passed to `on_start` before the run.
GaitRunResult RunGaitCommand(const GaitCommand& command,
                             const std::function<void(double period_s)>& on_start = {},
                             const std::function<void(double t_s)>& on_sample = {});

}  // namespace ipmc
