// Optimisation files (OPT.toml): a scenario's design optimised over some
// of its number keys (docs/OPTIMIZE.md). Read and checked here, once,
// before any run; every error is a FieldError (sim/base/error.h) whose
// one-line message names the file (and line), the field and its allowed
// range; errors of the base scenario and of [set] are the scenario
// reader's InputErrors.
//
//   base = "paper.toml"                   # a scenario file, relative to this file; required
//   [set]                                 # optional: overrides of the base, as a sweep's
//   cycles = 2
//   metrics.from_cycle = 2
//   [[variable]]                          # one or more: a number key or a number-array
//   key = "link_lengths_mm[0]"            # key's element, with its unit in the name
//   lower = 6.0                           # lower < upper, inside the key's own range
//   upper = 18.0
//   initial = 10.0                        # in [lower, upper]
//   [sum]                                 # optional: a linear equality, eliminated
//   key = "link_lengths_mm[2]"            # = total - the variables (all, or those in `of`)
//   total = 30.0
//   lower = 6.0                           # its bounds: two inequality constraints
//   upper = 18.0
//   of = ["link_lengths_mm[0]", "link_lengths_mm[1]"]   # optional
//   [objective]
//   metric = "last_cycle_com_along_mm"    # a column of the sweep table (summary metrics)
//   sense = "maximize"                    # maximize | minimize
//   [[constraint]]                        # optional, any number
//   metric = "link3_clamped_fraction"
//   at_most = 0.0                         # or at_least = ...
//   [algorithm]
//   name = "cobyla"                       # cobyla | bobyqa | subplex
//   max_evaluations = 150                 # per start; [1, 100000]
//   xtol_rel = 1e-4                       # >= 0 (0: not used)
//   ftol_rel = 0.0                        # >= 0 (0: not used)
//   multistart = 0                        # starts besides the initial point; [0, 64]
//   penalty = 10.0                        # bobyqa, subplex: the constraints' penalty weight; > 0
//   failed_objective = 0.0                # the objective a failed run counts as
//   [controllers]
//   retune = false                        # true: each design's controllers designed for its
//                                         # plants (sim/optimize/retune.h)
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "sim/core/scenario.h"
#include "sim/optimize/nlopt_driver.h"

namespace ipmc {

// A scenario number key, or one element of a number-array key.
struct DesignKey {
  std::string name;     // as written: "link_lengths_mm[0]"
  std::string key;      // the scenario key: "link_lengths_mm"
  int element = -1;     // the array element, -1 for a number key
};

struct DesignVariable {
  DesignKey key;
  double lower = 0.0, upper = 0.0, initial = 0.0;
};

struct DesignSum {
  DesignKey key;
  double total = 0.0, lower = 0.0, upper = 0.0;
  std::vector<int> of;  // indices into the variables
};

struct DesignConstraint {
  std::string metric;
  ValueBound bound;
};

// The file's sense ([objective] sense) and [algorithm] are the driver's
// settings (DriverSettings), held once.
struct OptimizeConfig : DriverSettings {
  std::string source;     // the OPT file
  std::string base_path;  // the base scenario, resolved against it
  ScenarioConfig base;    // the base with [set], parsed once
  int links = 0;          // of the base's model (the per-link metrics)
  std::vector<DesignVariable> variables;
  std::optional<DesignSum> sum;
  std::string objective;  // a metric name
  std::vector<DesignConstraint> constraints;
  // Each design's controllers retuned for its plants (sim/optimize/retune.h).
  bool retune_controllers = false;

  // The driver's problem (bounds, constraints, algorithm).
  DriverProblem Problem() const;
  // The design keys in the order of an evaluation's x: the variables, then the sum.
  std::vector<DesignKey> Keys() const;
};

// The metric names an objective or constraint may use: the sweep table's
// result columns for `links` links (sim/io/columns.h).
std::vector<std::string> MetricNames(int links);

OptimizeConfig ParseOptimizeFile(const std::string& toml_text, const std::string& source);
OptimizeConfig LoadOptimizeFile(const std::string& path);

// `base` with the design keys set to x (one value per key). Throws
// InputError / FieldError (a value the scenario refuses).
ScenarioConfig DesignScenario(const ScenarioConfig& base, const std::vector<DesignKey>& keys,
                              const std::vector<double>& x);

}  // namespace ipmc
