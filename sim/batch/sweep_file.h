// Sweep files: one scenario file (the base) run at many points, each point
// the base with some of its keys replaced (the table of results:
// sim/batch/sweep_table.h; running the points: sim/batch/sweep_scheduler.h).
//
// Sweep file (TOML); paths are relative to the sweep file:
//
//   base = "paper.toml"                 # a scenario file (sim/core/scenario.h); required
//   [set]                               # optional: overrides applied to every point
//   cycles = 2
//   [grid]                              # the Cartesian product of these arrays
//   "waveform.frequency_Hz" = [0.005, 0.01, 0.02]
//   actuation = ["single", "distributed"]
//   keep_runs = true                    # optional: keep each point's run directory
//
// or, with a [gait] table instead of base, prescribed gaits:
// sim/batch/sweep_gait.h;
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
// frequency_Hz = [...]` are the same key. Overrides apply to the base as
// sim/core/scenario_overrides.h describes (an override that changes a
// table's kind drops the base's keys of the other kind: paper.toml's kp,
// ki, kd when the controller becomes "fractional").
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
//    (sim/base/error.h, a std::runtime_error) with one line "FILE:LINE: key
//    ..." naming the sweep file (or the base); the scenario reader's errors
//    are classified and relocated by their problem and key, not by their
//    text;
//  - any other bad scenario (a value out of range, a combination the
//    scenario reader refuses) and any failure of the run (e.g. divergence)
//    is recorded in that point's row, and the other points still run.
//
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "sim/core/scenario.h"
#include "sim/runs/gait_command.h"

namespace ipmc {

// Sweep file keys (the key table's, sim/core/scenario_keys.cc).
namespace sweep_keys {
constexpr char kBase[] = "base";
constexpr char kSet[] = "set";
constexpr char kGrid[] = "grid";
constexpr char kPoint[] = "point";
constexpr char kKeepRuns[] = "keep_runs";
// A grid this large is a mistake in the sweep file, not a plan.
constexpr double kMaxPoints = 1e6;
}  // namespace sweep_keys

struct SweepPoint {
  int index = 0;
  std::vector<std::string> values;         // one per SweepPlan::keys, as printed
  std::optional<ScenarioConfig> scenario;  // absent if the overrides make a bad scenario,
  std::string error;                       // ... and then the reason (one line)
  std::string scenario_toml;               // the base with the overrides, as read
                                           // (a gait's: GaitCommandText)
  std::optional<GaitCommand> gait;         // a gait sweep's point (sim/batch/sweep_gait.h)
};

struct SweepPlan {
  std::string source;              // the sweep file
  std::string base_path;           // the base scenario, resolved against the sweep file
  std::vector<std::string> keys;   // swept keys: the table's columns
  std::vector<SweepPoint> points;  // by index
  int links = 0;                   // per-link column groups
  bool keep_runs = false;          // the sweep file's keep_runs
  bool gait = false;               // a [gait] sweep: points run gaits (sim/batch/sweep_gait.h)
};

// Reads a sweep and builds every point's scenario (no run yet). Loads each
// point's model once to count its links. Throws InputError (one line) as
// described above.
SweepPlan ParseSweep(const std::string& toml_text, const std::string& source);
SweepPlan LoadSweep(const std::string& path);

}  // namespace ipmc
