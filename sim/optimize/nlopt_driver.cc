// The NLopt driver: one NLopt instance per start, each evaluation
// recorded as NLopt asks for it.
#include "sim/optimize/nlopt_driver.h"

#include <nlopt.hpp>

#include <algorithm>
#include <cmath>
#include <exception>
#include <stdexcept>
#include <utility>

#include "sim/core/fan_out.h"

namespace ipmc {
namespace {

constexpr int kPrimes[] = {2,  3,  5,  7,  11, 13, 17, 19, 23, 29, 31, 37, 41,
                           43, 47, 53, 59, 61, 67, 71, 73, 79, 83, 89, 97};

// The radical inverse of `index` in `base`: Halton's coordinate.
double RadicalInverse(long index, int base) {
  double inverse = 0.0, scale = 1.0 / base;
  for (; index > 0; index /= base, scale /= base) inverse += scale * static_cast<double>(index % base);
  return inverse;
}

nlopt::algorithm NloptAlgorithm(OptimizeAlgorithm algorithm) {
  switch (algorithm) {
    case OptimizeAlgorithm::kCobyla: return nlopt::LN_COBYLA;
    case OptimizeAlgorithm::kBobyqa: return nlopt::LN_BOBYQA;
    case OptimizeAlgorithm::kSubplex: return nlopt::LN_SBPLX;
  }
  return nlopt::LN_COBYLA;
}

std::string StopReason(nlopt::result result) {
  switch (result) {
    case nlopt::SUCCESS: return "success";
    case nlopt::STOPVAL_REACHED: return "stopval";
    case nlopt::FTOL_REACHED: return "ftol_rel";
    case nlopt::XTOL_REACHED: return "xtol_rel";
    case nlopt::MAXEVAL_REACHED: return "max_evaluations";
    case nlopt::MAXTIME_REACHED: return "max_time";
    default: return "failure";
  }
}

// One start: evaluates each point NLopt asks for once (COBYLA asks for
// the objective, then the constraints, of the same point).
class StartRun {
 public:
  StartRun(const DriverProblem& problem, const DriverEvaluate& evaluate, int start,
           DriverStart* out)
      : problem_(problem), evaluate_(evaluate), start_(start), out_(out) {}

  // The merit NLopt minimises (the penalised objective without COBYLA).
  double Merit(const double* x) {
    Evaluate(x);
    if (stopped_) throw nlopt::forced_stop();
    double merit = sign() * objective_;
    if (problem_.algorithm != OptimizeAlgorithm::kCobyla) {
      for (double g : violations_) merit += problem_.penalty * std::max(0.0, g);
    }
    return merit;
  }

  void Constraints(unsigned m, double* result, const double* x) {
    if (!SameAsLast(x)) Evaluate(x);
    for (unsigned i = 0; i < m; ++i) result[i] = stopped_ ? 0.0 : violations_[i];
  }

  bool stopped() const { return stopped_ && !failure_; }
  // What the evaluation threw, if it threw.
  std::exception_ptr failure() const { return failure_; }
  size_t ConstraintCount() const {
    return problem_.constraints.size() + (problem_.sum ? 2 : 0);
  }

 private:
  double sign() const { return problem_.maximize ? -1.0 : 1.0; }

  bool SameAsLast(const double* x) const {
    if (last_x_.empty()) return false;
    for (size_t i = 0; i < last_x_.size(); ++i) {
      if (x[i] != last_x_[i]) return false;
    }
    return true;
  }

  void Evaluate(const double* x) {
    if (stopped_) return;
    const size_t n = problem_.lower.size();
    last_x_.assign(x, x + n);
    DriverRecord record;
    record.start = start_;
    record.evaluation = static_cast<int>(out_->records.size());
    record.x = last_x_;
    if (problem_.sum) record.x.push_back(problem_.sum->Value(last_x_));
    std::optional<DriverEvaluation> result;
    try {
      result = evaluate_(start_, record.x);
    } catch (...) {  // not the design's failure (a journal that cannot be written): rethrown
      failure_ = std::current_exception();
    }
    if (!result) {
      stopped_ = true;
      return;
    }
    record.result = std::move(*result);
    violations_.clear();
    bool feasible = record.result.ok;
    for (size_t i = 0; i < problem_.constraints.size(); ++i) {
      const double g = record.result.ok && i < record.result.constraint_values.size()
                           ? problem_.constraints[i].Violation(record.result.constraint_values[i])
                           : 1.0;
      violations_.push_back(g);
      feasible = feasible && g <= 0.0;
    }
    if (problem_.sum) {
      const double d = record.x.back();
      violations_.push_back(d - problem_.sum->upper);
      violations_.push_back(problem_.sum->lower - d);
      feasible = feasible && d <= problem_.sum->upper && d >= problem_.sum->lower;
    }
    objective_ = record.result.ok ? record.result.objective : problem_.failed_objective;
    record.feasible = feasible;
    out_->records.push_back(std::move(record));
  }

  const DriverProblem& problem_;
  const DriverEvaluate& evaluate_;
  int start_;
  DriverStart* out_;
  std::vector<double> last_x_;
  std::vector<double> violations_;
  double objective_ = 0.0;
  bool stopped_ = false;
  std::exception_ptr failure_;
};

double MeritThunk(unsigned, const double* x, double*, void* data) {
  return static_cast<StartRun*>(data)->Merit(x);
}

void ConstraintsThunk(unsigned m, double* result, unsigned, const double* x, double*, void* data) {
  static_cast<StartRun*>(data)->Constraints(m, result, x);
}

void CheckProblem(const DriverProblem& problem) {
  const size_t n = problem.lower.size();
  if (n == 0 || problem.upper.size() != n || problem.initial.size() != n) {
    throw std::invalid_argument("optimize: needs one lower, upper and initial value per variable");
  }
  for (size_t i = 0; i < n; ++i) {
    if (!(problem.lower[i] < problem.upper[i]) || !(problem.initial[i] >= problem.lower[i]) ||
        !(problem.initial[i] <= problem.upper[i])) {
      throw std::invalid_argument("optimize: variable " + std::to_string(i + 1) +
                                  " needs lower < upper and the initial value between them");
    }
  }
  if (problem.sum) {
    for (int i : problem.sum->of) {
      if (i < 0 || i >= static_cast<int>(n)) {
        throw std::invalid_argument("optimize: the sum names a variable that is not one");
      }
    }
  }
  if (problem.max_evaluations < 1 || problem.multistart < 0) {
    throw std::invalid_argument("optimize: max_evaluations must be >= 1, multistart >= 0");
  }
}

}  // namespace

const char* AlgorithmName(OptimizeAlgorithm algorithm) {
  switch (algorithm) {
    case OptimizeAlgorithm::kCobyla: return "cobyla";
    case OptimizeAlgorithm::kBobyqa: return "bobyqa";
    case OptimizeAlgorithm::kSubplex: return "subplex";
  }
  return "";
}

const std::vector<std::string>& AlgorithmNames() {
  static const std::vector<std::string> names = {"cobyla", "bobyqa", "subplex"};
  return names;
}

double EliminatedSum::Value(const std::vector<double>& x) const {
  double value = total;
  for (int i : of) value -= x[i];
  return value;
}

std::vector<std::vector<double>> StartPoints(const DriverProblem& problem) {
  CheckProblem(problem);
  const size_t n = problem.lower.size();
  if (n > std::size(kPrimes)) {
    throw std::invalid_argument("optimize: multistart takes at most " +
                                std::to_string(std::size(kPrimes)) + " variables");
  }
  std::vector<std::vector<double>> points = {problem.initial};
  const long tries = 1000L * (problem.multistart + 1);
  for (long index = 1; index <= tries && static_cast<int>(points.size()) <= problem.multistart;
       ++index) {
    std::vector<double> x(n);
    for (size_t i = 0; i < n; ++i) {
      x[i] = problem.lower[i] + RadicalInverse(index, kPrimes[i]) * (problem.upper[i] - problem.lower[i]);
    }
    if (problem.sum) {
      const double d = problem.sum->Value(x);
      if (d < problem.sum->lower || d > problem.sum->upper) continue;
    }
    points.push_back(std::move(x));
  }
  if (static_cast<int>(points.size()) <= problem.multistart) {
    throw std::invalid_argument(
        "optimize: the eliminated sum's bounds leave too little of the box for the starts");
  }
  return points;
}

DriverResult RunDriver(const DriverProblem& problem, const DriverEvaluate& evaluate, int jobs) {
  if (jobs < 1) throw std::invalid_argument("optimize: jobs must be >= 1");
  const std::vector<std::vector<double>> points = StartPoints(problem);
  DriverResult result;
  result.starts.resize(points.size());
  FanOut(points.size(), jobs, [&](size_t s) {
    DriverStart& out = result.starts[s];
    out.initial = points[s];
    if (problem.only_start >= 0 && static_cast<int>(s) != problem.only_start) {
      out.stop_reason = "not run";
      return;
    }
    StartRun run(problem, evaluate, static_cast<int>(s), &out);
    const unsigned n = static_cast<unsigned>(problem.lower.size());
    nlopt::opt opt(NloptAlgorithm(problem.algorithm), n);
    opt.set_lower_bounds(problem.lower);
    opt.set_upper_bounds(problem.upper);
    opt.set_maxeval(problem.max_evaluations);
    if (problem.xtol_rel > 0.0) opt.set_xtol_rel(problem.xtol_rel);
    if (problem.ftol_rel > 0.0) opt.set_ftol_rel(problem.ftol_rel);
    opt.set_min_objective(MeritThunk, &run);
    if (problem.algorithm == OptimizeAlgorithm::kCobyla && run.ConstraintCount() > 0) {
      opt.add_inequality_mconstraint(ConstraintsThunk, &run,
                                     std::vector<double>(run.ConstraintCount(), 0.0));
    }
    std::vector<double> x = points[s];
    double merit = 0.0;
    try {
      const nlopt::result status = opt.optimize(x, merit);
      out.stop_reason = StopReason(status);
      out.converged = status == nlopt::SUCCESS || status == nlopt::FTOL_REACHED ||
                      status == nlopt::XTOL_REACHED;
    } catch (const nlopt::forced_stop&) {
      out.stop_reason = "stopped";
    } catch (const nlopt::roundoff_limited&) {
      out.stop_reason = "roundoff_limited";
    } catch (const std::exception& failure) {
      out.stop_reason = std::string("failure: ") + failure.what();
    }
    if (run.failure()) std::rethrow_exception(run.failure());
    out.stopped = run.stopped();
  });
  for (const DriverStart& start : result.starts) {
    result.stopped = result.stopped || start.stopped;
    for (const DriverRecord& record : start.records) {
      if (!record.feasible) continue;
      const bool better = !result.best || (problem.maximize
                                               ? record.result.objective > result.best->result.objective
                                               : record.result.objective < result.best->result.objective);
      if (better) result.best = record;
    }
  }
  return result;
}

}  // namespace ipmc
