// Local derivative-free optimisation by NLopt (LN_COBYLA, LN_BOBYQA,
// LN_SBPLX) from one or several starting points, each start its own
// NLopt instance, the starts in parallel on the thread fan-out
// (sim/core/fan_out.h). NLopt is deterministic given the same values,
// so the records do not depend on the number of threads.
//
// The problem is to maximise or minimise f(x) over the box
// lower <= x <= upper subject to inequality constraints on values the
// evaluation reports (value <= bound or value >= bound), and optionally
// one linear equality eliminated: a dependent quantity
//   d = total - sum of x[i] over `of`
// with its own bounds lower_d <= d <= upper_d (two inequality
// constraints the driver computes without an evaluation). The evaluation
// receives x with d appended.
//
// COBYLA takes the inequality constraints as constraints. BOBYQA and
// SBPLX take none: they minimise the exact (L1) penalty
//   s f(x) + penalty * sum_i max(0, g_i(x))
// (s = -1 to maximise, +1 to minimise; g_i <= 0 is constraint i, in the
// units of its value), which for a penalty weight above the constraints'
// Lagrange multipliers has the constrained optimum as its minimum.
// A failed evaluation counts as f = failed_objective with every
// constraint violated by 1 (g_i = 1): worse than any design, never a
// crash.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace ipmc {

enum class OptimizeAlgorithm { kCobyla, kBobyqa, kSubplex };
// "cobyla", "bobyqa", "subplex".
const char* AlgorithmName(OptimizeAlgorithm algorithm);
const std::vector<std::string>& AlgorithmNames();

// value <= bound (at_most) or value >= bound.
struct ValueBound {
  double bound = 0.0;
  bool at_most = true;
  // g <= 0 when the bound holds.
  double Violation(double value) const { return at_most ? value - bound : bound - value; }
};

struct EliminatedSum {
  double total = 0.0;
  std::vector<int> of;  // indices of the free variables it subtracts
  double lower = 0.0, upper = 0.0;
  double Value(const std::vector<double>& x) const;
};

// How the driver searches: the sense, the algorithm and its stopping
// rules, the starts; an optimisation file's [objective] sense and
// [algorithm] (OptimizeConfig) hold them as they are.
struct DriverSettings {
  bool maximize = true;
  OptimizeAlgorithm algorithm = OptimizeAlgorithm::kCobyla;
  int max_evaluations = 100;  // per start
  double xtol_rel = 1e-4;
  double ftol_rel = 0.0;      // 0: not used
  int multistart = 0;         // starts besides the initial point
  double penalty = 10.0;      // BOBYQA, SBPLX: the penalty weight
  double failed_objective = 0.0;
};

struct DriverProblem : DriverSettings {
  std::vector<double> lower, upper, initial;
  std::optional<EliminatedSum> sum;
  std::vector<ValueBound> constraints;  // one per constraint value
  int only_start = -1;        // >= 0: run this start alone, the others left empty
};

// What one evaluation reports.
struct DriverEvaluation {
  bool ok = true;
  std::string error;        // !ok: why (one line)
  double objective = 0.0;   // as reported (not negated)
  std::vector<double> constraint_values;  // one per DriverProblem::constraints
  std::string warnings;     // the run's failed checks, "; "-separated (sim/runs/run_warnings.h)
};

struct DriverRecord {
  int start = 0;
  int evaluation = 0;           // 0-based, within the start
  std::vector<double> x;        // the free variables, then the sum's value
  DriverEvaluation result;
  bool feasible = false;        // ok and every constraint (and the sum's bounds) holds
};

struct DriverStart {
  std::vector<double> initial;  // the free variables
  std::vector<DriverRecord> records;
  std::string stop_reason;      // "xtol_rel", "ftol_rel", "max_evaluations", ...
  bool converged = false;       // stopped by a tolerance
  bool stopped = false;         // by stop_requested (the start is incomplete)
};

struct DriverResult {
  std::vector<DriverStart> starts;
  bool stopped = false;  // some start was stopped
  // The best feasible record (largest objective when maximising, the
  // earliest start and evaluation on a tie), if any.
  std::optional<DriverRecord> best;
};

// The initial point, then `multistart` points of a Halton sequence
// (bases 2, 3, 5, ...; its first point, the centre, skipped) scaled to the
// box, skipping those that put the eliminated sum outside its bounds.
std::vector<std::vector<double>> StartPoints(const DriverProblem& problem);

// Called from the worker threads (one start per thread at a time) with
// the start and x (free variables, then the sum's value). Returning
// nullopt stops the start (stop requested): it ends incomplete. What it
// throws ends the start and RunDriver rethrows it (FanOut: the lowest
// start's) when the running starts are done.
using DriverEvaluate =
    std::function<std::optional<DriverEvaluation>(int start, const std::vector<double>& x)>;

// Runs every start on `jobs` threads. Throws std::invalid_argument for a
// problem that is not one (sizes, bounds) or jobs < 1.
DriverResult RunDriver(const DriverProblem& problem, const DriverEvaluate& evaluate, int jobs);

}  // namespace ipmc
