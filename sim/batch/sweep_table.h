// A sweep's table of results, one row per point.
//
// The table (SweepTable) has one row per point, ordered by point index:
//   point, <swept keys>, status (ok | error), error,
//   link<q>_iae_mm_s, link<q>_itae_mm_s2, link<q>_rms_voltage_V,
//   link<q>_clamped_fraction, link<q>_actuator_power_W  (q = 1..links, the most
//   links of any point's model),
//   last_cycle_com_along_mm, mean_speed_along_mm_s, reynolds_tip, reynolds_swim,
//   actuator_power_W, fluid_power_W, hinge_damping_power_W, stepping_power_W,
//   lighthill_efficiency, cost_of_transport_J_m, electrical_power_W,
//   electromechanical_efficiency (0 without the electrical model),
//   warnings (the count), warn_reynolds, warn_clamp, warn_tracking,
//   warn_reach, warn_stepping, warn_timestep (1 where the run failed the check:
//   sim/runs/run_warnings.h)
// (sim/runs/closed_loop_run.h, sim/core/swim_meter.h, sim/core/energy.h). Swept values are printed as
// the shortest text that reads back exactly ("" where a list's point keeps
// the base's value); results with 17 significant digits (max_digits10), so
// tables compare exactly. Error rows leave the results empty.
#pragma once

#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "sim/batch/sweep_file.h"
#include "sim/runs/output.h"

namespace ipmc {

// Where a row's result comes from: the point's scenario as run (every key,
// defaults filled in: ResolvedScenarioToml, sim/core/scenario.h) and the
// SHA-256 of its model's bytes (ScenarioModelSha256, sim/core/scenario_simulation.h).
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
  // The sweep's fingerprint (SweepFingerprint, sim/batch/journal.h) when
  // known: the JSON then carries it and each row's SweepRowCheck, which
  // reading the table back verifies and merge compares across shards.
  std::string fingerprint;
};

// The table's columns for a plan.
std::vector<std::string> SweepColumns(const SweepPlan& plan);

// CSV (sim/io/csv.h: RFC 4180, "\n" line ends).
std::string SweepTableCsv(const SweepTable& table);
// {"columns": [...], "points": [{column: value, ...}, ...],
//  "program_version": "...", "provenance": [{"point": i,
//  "resolved_scenario": "...", "model_sha256": "..."}, ...]}: point is an
// integer, status and error strings, results numbers (null when empty),
// swept values numbers, booleans, arrays or strings as their text reads;
// program_version and provenance only when known; with a fingerprint,
// "fingerprint" and "row_checks" ([{"point": i, "check": "..."}, ...]).
// The same table gives
// the same JSON, whether it was run or merged.
nlohmann::ordered_json SweepTableJson(const SweepTable& table);

// Reads a table written by SweepTableCsv; throws InputError
// (sim/base/error.h) "SOURCE:LINE: ..." if it is not one.
SweepTable ParseSweepTableCsv(const std::string& csv_text, const std::string& source);
// The same from PREFIX.csv, with program_version, provenance and
// fingerprint from PREFIX.json beside it if there is one (InputError if it
// is not a table's JSON, or if a row of the CSV fails its check there:
// edited by hand, or from another table).
SweepTable LoadSweepTableCsv(const std::string& path);

// Joins the tables of a sweep's shards into one, ordered by point index,
// with their provenance. Throws InputError (one line, naming the file) if
// the headers, the program versions or the sweeps' fingerprints differ
// (shards of two sweeps) or a point appears twice, and std::runtime_error if
// (unless allow_missing) points are missing below the highest index (a missing tail of the sweep
// cannot be told from a shorter sweep).
SweepTable MergeSweepTables(const std::vector<SweepTable>& tables,
                            const std::vector<std::string>& sources, bool allow_missing = false);

// The table as one tree for sim/io/result_files.h:
//   table        a column per table column (swept lists as matrices, a
//                row per point; empty results NaN)
//   points       a group per point, "point_<index>": its row's values and
//                its provenance (resolved_scenario, model_sha256)
//   program_version
nlohmann::ordered_json SweepResultTree(const SweepTable& table);

// Before the work: throws FieldError naming `option` (--out) if PREFIX
// cannot name a table's files: empty, ending in '/', or a directory
// (PREFIX.csv would be a hidden file ".csv" in it); and throws as
// RequireWritableParent (sim/io/files.h) if its folder cannot take
// PREFIX.journal (not writable, a name too long).
void CheckTablePrefix(const std::string& who, const std::string& option, const std::string& prefix);

// Writes PREFIX.csv and PREFIX.json, and PREFIX.mat / PREFIX.h5 as
// `formats` asks, together or none (creating PREFIX's directory if
// needed); PREFIX.mat or .h5 of an earlier table that this one does not
// write goes.
void WriteSweepTable(const std::string& prefix, const SweepTable& table,
                     const RunFileFormats& formats = {});

}  // namespace ipmc
