#include "sim/runs/recorded_states.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "sim/io/columns.h"
#include "sim/io/csv.h"
#include "sim/base/numbers.h"

namespace ipmc {
namespace {

std::string JointName(const mjModel* m, int joint) {
  const char* name = mj_id2name(m, mjOBJ_JOINT, joint);
  return name && *name ? name : "joint" + std::to_string(joint);
}

// Rescales the quaternions of ball and free joints to unit length.
void NormaliseQuaternions(const mjModel* m, std::vector<double>& qpos) {
  for (int j = 0; j < m->njnt; ++j) {
    const int adr = m->jnt_qposadr[j];
    if (m->jnt_type[j] == mjJNT_BALL) mju_normalize4(qpos.data() + adr);
    if (m->jnt_type[j] == mjJNT_FREE) mju_normalize4(qpos.data() + adr + 3);
  }
}

}  // namespace

std::vector<std::string> QposColumns(const mjModel* m) {
  std::vector<std::string> columns(m->nq);
  for (int j = 0; j < m->njnt; ++j) {
    const std::string name = JointName(m, j);
    const int adr = m->jnt_qposadr[j];
    switch (m->jnt_type[j]) {
      case mjJNT_SLIDE:
        columns[adr] = name + "_m";
        break;
      case mjJNT_HINGE:
        columns[adr] = name + "_rad";
        break;
      case mjJNT_BALL:
        for (int k = 0; k < 4; ++k) columns[adr + k] = name + "_q" + "wxyz"[k];
        break;
      case mjJNT_FREE:
        for (int k = 0; k < 3; ++k) columns[adr + k] = name + "_" + "xyz"[k] + "_m";
        for (int k = 0; k < 4; ++k) columns[adr + 3 + k] = name + "_q" + "wxyz"[k];
        break;
    }
  }
  return columns;
}

RecordedStates RecordedStates::For(const mjModel* m) {
  RecordedStates states;
  states.columns = QposColumns(m);
  return states;
}

void RecordedStates::Record(const mjData* d) {
  t_s.push_back(d->time);
  qpos.emplace_back(d->qpos, d->qpos + columns.size());
}

std::vector<double> RecordedStates::StateAt(const mjModel* m, double t) const {
  if (t_s.empty()) throw std::logic_error("recorded states: no sample");
  if (t <= t_s.front()) return qpos.front();
  if (t >= t_s.back()) return qpos.back();
  const size_t next = std::upper_bound(t_s.begin(), t_s.end(), t) - t_s.begin();
  const size_t prev = next - 1;
  const double span = t_s[next] - t_s[prev];
  const double w = (t - t_s[prev]) / span;
  // Within rounding of a sample: that sample, exactly.
  constexpr double kSnap = 1e-9;
  if (w < kSnap) return qpos[prev];
  if (w > 1.0 - kSnap) return qpos[next];
  std::vector<double> state(qpos[prev].size());
  for (size_t i = 0; i < state.size(); ++i) state[i] = (1.0 - w) * qpos[prev][i] + w * qpos[next][i];
  NormaliseQuaternions(m, state);
  return state;
}

std::string RecordedStatesCsv(const RecordedStates& states) {
  CsvWriter csv;
  std::vector<std::string> header = {columns::kTime};
  header.insert(header.end(), states.columns.begin(), states.columns.end());
  csv.Row(header);
  for (size_t k = 0; k < states.t_s.size(); ++k) {
    csv.Add(states.t_s[k]);
    for (double value : states.qpos[k]) csv.Add(value);
    csv.EndRow();
  }
  return csv.Text();
}

RecordedStates ReadRecordedStates(const std::string& path, const mjModel* m) {
  const CsvTable table = CsvTable::Read(path);
  RecordedStates states = RecordedStates::For(m);
  if (!table.Has(columns::kTime)) table.Column(columns::kTime);  // throws naming the columns
  for (const std::string& column : states.columns) {
    if (!table.Has(column)) {
      throw std::runtime_error(path + ": no column " + column +
                               " (the model's joints: is it the run's model?)");
    }
  }
  states.t_s = table.FiniteNumbers(columns::kTime);
  for (size_t k = 1; k < states.t_s.size(); ++k) {
    if (!(states.t_s[k] > states.t_s[k - 1])) {
      throw std::runtime_error(path + ":" + std::to_string(table.Line(k)) + ": " +
                               columns::kTime + " must increase (" +
                               FormatDouble(states.t_s[k]) + " after " +
                               FormatDouble(states.t_s[k - 1]) + ")");
    }
  }
  states.qpos.assign(states.t_s.size(), std::vector<double>(states.columns.size()));
  for (size_t i = 0; i < states.columns.size(); ++i) {
    const std::vector<double> values = table.FiniteNumbers(states.columns[i]);
    for (size_t k = 0; k < values.size(); ++k) states.qpos[k][i] = values[k];
  }
  if (states.empty()) throw std::runtime_error(path + ": no recorded state (header only)");
  return states;
}

}  // namespace ipmc
