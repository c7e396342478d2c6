#include "sim/runs/recorded_states.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <stdexcept>

namespace ipmc {
namespace {

constexpr char kTimeColumn[] = "time_s";

std::string JointName(const mjModel* m, int joint) {
  const char* name = mj_id2name(m, mjOBJ_JOINT, joint);
  return name && *name ? name : "joint" + std::to_string(joint);
}

// The cells of one CSV line (no quoting: the file holds names and numbers).
std::vector<std::string> Cells(const std::string& line) {
  std::vector<std::string> cells;
  std::string cell;
  std::istringstream in(line);
  while (std::getline(in, cell, ',')) {
    while (!cell.empty() && (cell.back() == '\r' || cell.back() == ' ')) cell.pop_back();
    cells.push_back(cell);
  }
  return cells;
}

double ParseNumber(const std::string& cell, const std::string& path, int line, const std::string& column) {
  char* end = nullptr;
  const double value = std::strtod(cell.c_str(), &end);
  if (cell.empty() || end != cell.c_str() + cell.size() || !std::isfinite(value)) {
    throw std::runtime_error(path + ":" + std::to_string(line) + ": column " + column +
                             ": not a finite number ('" + cell + "')");
  }
  return value;
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
  std::ostringstream csv;
  csv << std::setprecision(17) << kTimeColumn;
  for (const std::string& column : states.columns) csv << "," << column;
  csv << "\n";
  for (size_t k = 0; k < states.t_s.size(); ++k) {
    csv << states.t_s[k];
    for (double value : states.qpos[k]) csv << "," << value;
    csv << "\n";
  }
  return csv.str();
}

RecordedStates ReadRecordedStates(const std::string& path, const mjModel* m) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path + ": cannot open the recorded states");
  std::string line;
  if (!std::getline(in, line)) throw std::runtime_error(path + ": empty file (no header row)");
  const std::vector<std::string> header = Cells(line);
  RecordedStates states = RecordedStates::For(m);
  // File column of time and of each qpos coordinate.
  const auto find = [&](const std::string& name) {
    const auto it = std::find(header.begin(), header.end(), name);
    if (it == header.end()) {
      throw std::runtime_error(path + ": no column " + name + " (the model's joints: is it the run's model?)");
    }
    return static_cast<size_t>(it - header.begin());
  };
  const size_t time_column = find(kTimeColumn);
  std::vector<size_t> source;
  for (const std::string& column : states.columns) source.push_back(find(column));

  for (int number = 2; std::getline(in, line); ++number) {
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    const std::vector<std::string> cells = Cells(line);
    if (cells.size() != header.size()) {
      throw std::runtime_error(path + ":" + std::to_string(number) + ": " +
                               std::to_string(cells.size()) + " cells, the header has " +
                               std::to_string(header.size()));
    }
    const double t = ParseNumber(cells[time_column], path, number, kTimeColumn);
    if (!states.t_s.empty() && !(t > states.t_s.back())) {
      throw std::runtime_error(path + ":" + std::to_string(number) + ": time_s must increase (" +
                               cells[time_column] + " after " + std::to_string(states.t_s.back()) + ")");
    }
    std::vector<double> q(source.size());
    for (size_t i = 0; i < source.size(); ++i) {
      q[i] = ParseNumber(cells[source[i]], path, number, states.columns[i]);
    }
    states.t_s.push_back(t);
    states.qpos.push_back(std::move(q));
  }
  if (states.empty()) throw std::runtime_error(path + ": no recorded state (header only)");
  return states;
}

}  // namespace ipmc
