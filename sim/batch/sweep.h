// Parameter sweeps: one scenario file (the base) run at many points, each
// point the base with some of its keys replaced, and one table of results.
//
// Sweep file (TOML); paths are relative to the sweep file:
//
//   base = "paper.toml"                 # a scenario file (sim/core/scenario.h); required
//   [set]                               # optional: overrides applied to every point
//   cycles = 2
//   [grid]                              # the Cartesian product of these arrays
//   "waveform.frequency_Hz" = [0.005, 0.01, 0.02]
//   actuation = ["single", "distributed"]
//
// or, instead of [grid], a list of points, each a table of overrides:
//
//   [[point]]
//   "waveform.frequency_Hz" = 0.005
//   [[point]]
//   actuation = "single"
//   controller = { kind = "fractional", gain = 15.62 }   # = controller.kind, controller.gain
//
// Keys are the scenario's dotted keys ("controller.kp", "waveform.alpha",
// "fluid.viscosity_Pa_s", ...); a nested table stands for the dotted keys
// under it, so `waveform.frequency_Hz = [...]` and `[grid.waveform]
// frequency_Hz = [...]` are the same key. An override replaces the value in
// the base's TOML (adding the key, and its table, if the base lacks it); the
// result is serialised and read by ParseScenario with the base's path as
// source, so every key and check of scenario files applies and relative
// paths resolve as in the base. An override that changes a table's kind
// (controller.kind, waveform.kind) drops the base's keys that belong only
// to the other kind (paper.toml's kp, ki, kd when the controller becomes
// "fractional"); keys of the other kind given by the sweep stay errors.
// A key is given once per point: in [set] (not a column) or swept.
//
// Order: the swept keys are the table's columns in the order they first
// appear in the sweep file. A grid's points run through the product like
// nested loops, the first key outermost: with keys k_1..k_m of n_1..n_m
// values, point index = sum_j i_j prod_{l>j} n_l (0-based). A list's
// points are numbered in file order.
//
// Errors:
//  - a malformed sweep file, an unknown key or a value of the wrong type
//    (as the scenario reader judges it), or a base that is not a valid
//    scenario by itself stops the sweep before any run: InputError
//    (plugin/base/error.h, a std::runtime_error) with one line "FILE:LINE: key
//    ..." naming the sweep file (or the base); the scenario reader's errors
//    are classified and relocated by their problem and key, not by their
//    text;
//  - any other bad scenario (a value out of range, a combination the
//    scenario reader refuses) and any failure of the run (e.g. divergence)
//    is recorded in that point's row, and the other points still run.
//
// The table (SweepTable) has one row per point, ordered by point index:
//   point, <swept keys>, status (ok | error), error,
//   link<q>_iae_mm_s, link<q>_itae_mm_s2, link<q>_rms_voltage_V,
//   link<q>_clamped_fraction  (q = 1..links, the most links of any point's model),
//   last_cycle_com_along_mm, mean_speed_along_mm_s, reynolds_tip, reynolds_swim
// (sim/runs/closed_loop_run.h, sim/core/swim_meter.h). Swept values are printed as
// the shortest text that reads back exactly ("" where a list's point keeps
// the base's value); results with 17 significant digits (max_digits10), so
// tables compare exactly. Error rows leave the results empty.
#pragma once

#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <toml++/toml.h>

#include "sim/core/scenario.h"

namespace ipmc {

struct SweepPoint {
  int index = 0;
  std::vector<std::string> values;         // one per SweepPlan::keys, as printed
  std::optional<ScenarioConfig> scenario;  // absent if the overrides make a bad scenario,
  std::string error;                       // ... and then the reason (one line)
  std::string scenario_toml;               // the base with the overrides, as read
};

struct SweepPlan {
  std::string source;              // the sweep file
  std::string base_path;           // the base scenario, resolved against the sweep file
  std::vector<std::string> keys;   // swept keys: the table's columns
  std::vector<SweepPoint> points;  // by index
  int links = 0;                   // per-link column groups
};

// Reads a sweep and builds every point's scenario (no run yet). Loads each
// point's model once to count its links. Throws InputError (one line) as
// described above.
SweepPlan ParseSweep(const std::string& toml_text, const std::string& source);
SweepPlan LoadSweep(const std::string& path);

// One scenario: the scenario file `base_path` with `overrides` applied as
// a sweep's [set] applies them (dotted keys, nested tables standing for
// the dotted keys under them, a changed kind dropping the base's keys of
// the other kind). With an empty base_path the overrides are the whole
// scenario and relative paths resolve from the working directory. Throws
// InputError (plugin/base/error.h) with one line: errors in the base name the
// base file and line, errors in an override `source`, the override's line
// and the key.
ScenarioConfig ScenarioWithOverrides(const std::string& base_path, const toml::table& overrides,
                                     const std::string& source);

// Part i of n (1 <= i <= n) of a sweep: the points with index % n == i - 1.
struct SweepShard {
  int index = 1;
  int count = 1;
};
// Reads "i/n"; throws std::invalid_argument naming --shard.
SweepShard ParseSweepShard(const std::string& text);

struct SweepProgress {
  int done = 0;   // points finished, this one included
  int total = 0;  // points to run (in this shard)
  int point = 0;  // the index of the point just finished
  bool ok = true;
  std::string error;
  double elapsed_s = 0.0;
  const std::vector<std::string>* row = nullptr;  // the point's row, as in the table
};

struct SweepOptions {
  int jobs = 1;  // threads; >= 1
  SweepShard shard;
  // Called after each point, one call at a time, from the worker threads.
  std::function<void(const SweepProgress&)> on_point_done;
  // Rows of points that finished before (by point index): not run again,
  // copied into the table as they are.
  const std::map<int, std::vector<std::string>>* finished = nullptr;
  // Asked, from the worker threads, before each point starts; once it
  // returns true no further point starts.
  std::function<bool()> stop_requested;
};

// Where a row's result comes from: the point's scenario as run (every key,
// defaults filled in: ResolvedScenarioToml, sim/core/scenario.h) and the
// SHA-256 of its model's bytes (ScenarioModelSha256, sim/runs/closed_loop_run.h).
struct PointProvenance {
  std::string resolved_scenario;
  std::string model_sha256;
};

struct SweepTable {
  std::vector<std::string> columns;
  std::vector<std::vector<std::string>> rows;  // cells as printed, by point index
  // The program that made the rows ("" if unknown: a table read from a CSV
  // without its JSON) and, by point index, each row's provenance (none
  // for a point whose scenario was refused).
  std::string program_version;
  std::map<int, PointProvenance> provenance;
};

// The table's columns for a plan.
std::vector<std::string> SweepColumns(const SweepPlan& plan);

// Runs the shard's points on options.jobs threads (RunScenario per point),
// the longest runs (cycles / frequency / time step) first. The rows, in
// index order, do not depend on the number of jobs. Points in
// options.finished are not run; progress counts only the points run. If
// stop_requested stopped the sweep, the table holds the points finished
// by then (fewer rows than the shard has points). Throws
// std::invalid_argument for bad options only.
SweepTable RunSweep(const SweepPlan& plan, const SweepOptions& options);

// CSV (sim/io/csv.h: RFC 4180, "\n" line ends).
std::string SweepTableCsv(const SweepTable& table);
// {"columns": [...], "points": [{column: value, ...}, ...],
//  "program_version": "...", "provenance": [{"point": i,
//  "resolved_scenario": "...", "model_sha256": "..."}, ...]}: point is an
// integer, status and error strings, results numbers (null when empty),
// swept values numbers, booleans, arrays or strings as their text reads;
// program_version and provenance only when known. The same table gives
// the same JSON, whether it was run or merged.
nlohmann::ordered_json SweepTableJson(const SweepTable& table);

// Reads a table written by SweepTableCsv; throws InputError
// (plugin/base/error.h) "SOURCE:LINE: ..." if it is not one.
SweepTable ParseSweepTableCsv(const std::string& csv_text, const std::string& source);
// The same from PREFIX.csv, with program_version and provenance from
// PREFIX.json beside it if there is one (InputError if it is not a
// table's JSON).
SweepTable LoadSweepTableCsv(const std::string& path);

// Joins the tables of a sweep's shards into one, ordered by point index,
// with their provenance. Throws InputError (one line, naming the file) if
// the headers or the program versions differ or a point appears twice, and std::runtime_error if (unless allow_missing)
// points are missing below the highest index (a missing tail of the sweep
// cannot be told from a shorter sweep).
SweepTable MergeSweepTables(const std::vector<SweepTable>& tables,
                            const std::vector<std::string>& sources,
                            bool allow_missing = false);

// Writes PREFIX.csv and PREFIX.json, each atomically (creating PREFIX's
// directory if needed).
void WriteSweepTable(const std::string& prefix, const SweepTable& table);

}  // namespace ipmc
