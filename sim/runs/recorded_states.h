// The model's generalised positions (mjData.qpos) at the recorded samples
// of a run, so that the run can be filmed after it ends, or later from its
// output directory, without simulating it again (renders/swim_film.h).
//
// DIR/states.csv: a header `time_s,<coordinate>,...` and one row per
// sample. Coordinates are named after the model's joints, with units:
//   slide `<joint>_m`, hinge `<joint>_rad`,
//   ball  `<joint>_qw,_qx,_qy,_qz`,
//   free  `<joint>_x_m,_y_m,_z_m,_qw,_qx,_qy,_qz`
// (an unnamed joint is `joint<id>`). Reading maps the columns back to the
// qpos addresses of a model by these names, so a model with the same
// joints (not necessarily in the same order) replays the run.
//
// Between two samples, StateAt interpolates linearly; quaternions are
// normalised afterwards (exact at the samples, and a close approximation
// between samples of a smooth run).
#pragma once

#include <mujoco/mujoco.h>

#include <string>
#include <vector>

namespace ipmc {

struct RecordedStates {
  std::vector<std::string> columns;  // one per qpos coordinate, in qpos order
  std::vector<double> t_s;           // strictly increasing
  std::vector<std::vector<double>> qpos;

  // Starts an empty record for model m (names its columns).
  static RecordedStates For(const mjModel* m);
  // Appends d->time and d->qpos.
  void Record(const mjData* d);
  bool empty() const { return t_s.empty(); }

  // The state at time t_s (clamped to the recorded span), linearly
  // interpolated between the neighbouring samples. Needs a non-empty record.
  std::vector<double> StateAt(const mjModel* m, double t_s) const;
};

// The column names of model m's qpos coordinates, in qpos order.
std::vector<std::string> QposColumns(const mjModel* m);

// CSV text of the record (full precision).
std::string RecordedStatesCsv(const RecordedStates& states);

// Reads DIR/states.csv for model m: columns are matched by name and put in
// m's qpos order. Throws std::runtime_error "PATH: reason" naming a
// missing column, a malformed number (with its line) or times that do not
// increase.
RecordedStates ReadRecordedStates(const std::string& path, const mjModel* m);

}  // namespace ipmc
