#include "sim/identify/controller_export.h"

#include <cmath>
#include <filesystem>
#include <functional>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "controllers/controller_names.h"
#include "controllers/first_order_sections.h"
#include "controllers/fractional_integrator.h"
#include "controllers/pid.h"
#include "sim/base/error.h"
#include "sim/base/numbers.h"
#include "sim/core/scenario_overrides.h"
#include "sim/core/scenario_simulation.h"
#include "sim/io/csv.h"
#include "sim/io/files.h"
#include "sim/runs/closed_loop_run.h"

namespace ipmc {
namespace {

constexpr char kCommand[] = "export";
// A literal that reads back as the same double.
constexpr int kLiteralDigits = 17;

OptionTable<ExportCommand> MakeExportOptions() {
  OptionTable<ExportCommand> table(
      kCommand, "Write a scenario's controllers as C, JSON and CSV for a processor's loop");
  OptionInfo scenario{"scenario", "", "a TOML file", "Scenario file (TOML)"};
  scenario.positional = true;
  scenario.required = true;
  table.AddPath(scenario, [](ExportCommand& c) -> std::string& { return c.scenario; });
  OptionInfo set{"set", "", "KEY=VALUE, repeatable",
                 "Set a scenario key (dotted, as in sweep files; VALUE is TOML: strings in "
                 "quotes); see `ipmc-swim keys`. Python: keyword overrides"};
  set.command_line_only = true;
  table.Add<std::vector<std::string>>(
      set, [](ExportCommand& c) -> std::vector<std::string>& { return c.set; });
  OptionInfo out{"out", "", "a folder",
                 "Folder for ipmc_controller.h, ipmc_controller.c, coefficients.json and "
                 "coefficients.csv"};
  out.aliases = {"o"};
  out.required = true;
  table.AddPath(out, [](ExportCommand& c) -> std::string& { return c.out; });
  return table;
}

// A C floating literal that reads back as the same double ("1000.0", not
// the integer 1000).
std::string Literal(double value) {
  std::string text = FormatDouble(value, kLiteralDigits);
  if (text.find_first_of(".eEn") == std::string::npos) text += ".0";
  return text;
}

// One link's controller in the form exported.
struct LinkExport {
  PidController::Config pid;
  FractionalIntegrator::Config fractional;
  ParallelSections sections;  // fractional only
};

// ----------------------------------------------------------------- C ---

const char kRealTypes[] = R"(#ifdef IPMC_CONTROLLER_FLOAT
typedef float ipmc_real;
#else
typedef double ipmc_real;
#endif
)";

// A table of one coefficient per link, each commented.
std::string LinkTable(const char* name, const std::vector<LinkExport>& links,
                      const std::function<double(const LinkExport&)>& value,
                      const std::string& meaning) {
  std::string text = "static const ipmc_real " + std::string(name) + "[IPMC_CONTROLLER_LINKS] = {\n";
  for (size_t q = 0; q < links.size(); ++q) {
    text += "    R(" + Literal(value(links[q])) + "), /* link " + std::to_string(q + 1) + ": " +
            meaning + " */\n";
  }
  return text + "};\n";
}

// A table of one coefficient per link and section, each commented.
std::string SectionTable(const char* name, const std::vector<LinkExport>& links,
                         const std::function<double(const FirstOrderSection&)>& value,
                         const std::string& meaning, double period_s, bool with_pole) {
  std::string text = "static const ipmc_real " + std::string(name) +
                     "[IPMC_CONTROLLER_LINKS][IPMC_CONTROLLER_SECTIONS] = {\n";
  for (size_t q = 0; q < links.size(); ++q) {
    text += "    {\n";
    const std::vector<FirstOrderSection>& sections = links[q].sections.sections;
    for (size_t i = 0; i < sections.size(); ++i) {
      const FirstOrderSection& s = sections[i];
      text += "        R(" + Literal(value(s)) + "), /* link " + std::to_string(q + 1) +
              ", section " + std::to_string(i + 1) + ": " + meaning +
              (with_pole ? " (pole " + FormatDouble(s.pole(), 10) + ", corner " +
                               FormatDouble(s.CornerRadS(period_s), 6) + " rad/s)"
                         : std::string()) +
              " */\n";
    }
    text += "    },\n";
  }
  return text + "};\n";
}

std::string HeaderText(const ScenarioConfig& scenario, const std::vector<LinkExport>& links,
                       bool pid, bool clamp, double v_max_V) {
  const double rate = scenario.controller.sample_rate_Hz;
  std::ostringstream h;
  h << "/* ipmc_controller.h: the "
    << (pid ? "PID (eq. 10)" : "fractional integrator K / s^lambda (eq. 13)")
    << " controllers of\n * " << scenario.source << " as ipmc-swim runs them: " << links.size()
    << " link(s) at " << FormatShortest(rate) << " Hz,\n"
    << " * error e = reference - measured [mm] in, voltage [V] out"
    << (clamp ? ", clamped to +-" + FormatShortest(v_max_V) + " V\n * with anti-windup" : "")
    << ".\n"
    << " * Written by `ipmc-swim export`; docs/PROTOTYPE.md gives the difference equations.\n"
    << " *\n"
    << " * Use: ipmc_controller_reset(&s) once with the strip at rest; then every\n"
    << " * 1 / IPMC_CONTROLLER_SAMPLE_RATE_HZ s, for each link (0-based),\n"
    << " *   u = ipmc_controller_update(&s, link, reference_mm, measured_mm);\n"
    << " * and hold u [V] on that link until the next sample. A link outside\n"
    << " * [0, IPMC_CONTROLLER_LINKS) gets 0 V. double by default; compile with\n"
    << " * -DIPMC_CONTROLLER_FLOAT for float. No allocation, no library calls. */\n"
    << "#ifndef IPMC_CONTROLLER_H_\n#define IPMC_CONTROLLER_H_\n\n"
    << "#ifdef __cplusplus\nextern \"C\" {\n#endif\n\n"
    << kRealTypes << "\n"
    << "#define IPMC_CONTROLLER_LINKS " << links.size() << "\n"
    << "#define IPMC_CONTROLLER_SAMPLE_RATE_HZ " << Literal(rate) << "\n"
    << "#define IPMC_CONTROLLER_CLAMP " << (clamp ? 1 : 0) << " /* clamp and anti-windup */\n";
  if (!pid) {
    h << "#define IPMC_CONTROLLER_SECTIONS " << links.front().sections.sections.size()
      << " /* first-order sections per link */\n";
  }
  h << "\ntypedef struct {\n";
  if (pid) {
    h << "    ipmc_real integral[IPMC_CONTROLLER_LINKS];       /* I_k [V] */\n"
      << "    ipmc_real derivative[IPMC_CONTROLLER_LINKS];     /* D_k [V] */\n"
      << "    ipmc_real previous_error[IPMC_CONTROLLER_LINKS]; /* e_(k-1) [mm] */\n";
  } else {
    h << "    /* x_i,k: the sections' states (the error low-passed, [mm]) */\n"
      << "    ipmc_real x[IPMC_CONTROLLER_LINKS][IPMC_CONTROLLER_SECTIONS];\n";
  }
  h << "} ipmc_controller_state;\n\n"
    << "void ipmc_controller_reset(ipmc_controller_state* s);\n"
    << "ipmc_real ipmc_controller_update(ipmc_controller_state* s, int link, ipmc_real reference_mm,\n"
    << "                                 ipmc_real measured_mm);\n\n"
    << "#ifdef __cplusplus\n}\n#endif\n\n#endif /* IPMC_CONTROLLER_H_ */\n";
  return h.str();
}

// The helpers in std::max, std::min and std::clamp's own comparisons, so
// that the doubles are the simulator's (signed zeros included).
const char kClampHelper[] = R"(#if IPMC_CONTROLLER_CLAMP
static ipmc_real clamp_of(ipmc_real v, ipmc_real limit) {
    return v < -limit ? -limit : (limit < v ? limit : v);
}
#endif
)";
const char kMinMaxHelpers[] = R"(#if IPMC_CONTROLLER_CLAMP
static ipmc_real max_of(ipmc_real a, ipmc_real b) { return a < b ? b : a; }
static ipmc_real min_of(ipmc_real a, ipmc_real b) { return b < a ? b : a; }
#endif
)";

std::string PidSource(const std::vector<LinkExport>& links, double period_s, double v_max_V) {
  std::ostringstream c;
  c << "/* PID, parallel form (controllers/pid.h), per link, at T = 1 / rate:\n"
    << " *   e_k = r_k - y_k                                      [mm]\n"
    << " *   D_k = (Tf D_(k-1) + Kd (e_k - e_(k-1))) / (Tf + T)   filtered derivative [V]\n"
    << " *   I_k = I_(k-1) + Ki T e_k                             backward-Euler integral [V]\n"
    << " *   u_k = Kp e_k + I_k + D_k, clamped to +-V_max; while the clamp holds, the\n"
    << " *   integral advances only until the output reaches the limit (conditional\n"
    << " *   integration) and moves freely back out. */\n\n"
    << LinkTable("kKp", links, [](const LinkExport& l) { return l.pid.kp; },
                 "Kp [V/mm], proportional gain")
    << LinkTable("kKi", links, [](const LinkExport& l) { return l.pid.ki; },
                 "Ki [V/(mm s)], integral gain")
    << LinkTable("kKd", links, [](const LinkExport& l) { return l.pid.kd; },
                 "Kd [V s/mm], derivative gain")
    << LinkTable("kTf", links, [](const LinkExport& l) { return l.pid.derivative_filter_time_s; },
                 "Tf [s], derivative filter time constant (0: ideal derivative)")
    << "static const ipmc_real kSamplePeriod = R(" << Literal(period_s) << "); /* T [s] */\n"
    << "#if IPMC_CONTROLLER_CLAMP\nstatic const ipmc_real kVMax = R(" << Literal(v_max_V)
    << "); /* V_max [V], the clamp */\n#endif\n\n"
    << R"(void ipmc_controller_reset(ipmc_controller_state* s) {
    int q;
    for (q = 0; q < IPMC_CONTROLLER_LINKS; ++q) {
        s->integral[q] = R(0);
        s->derivative[q] = R(0);
        s->previous_error[q] = R(0);
    }
}

ipmc_real ipmc_controller_update(ipmc_controller_state* s, int link, ipmc_real reference_mm,
                                 ipmc_real measured_mm) {
    ipmc_real error, proportional, increment, integral, output;
    if (link < 0 || link >= IPMC_CONTROLLER_LINKS) return R(0);
    error = reference_mm - measured_mm;
    s->derivative[link] =
        (kTf[link] * s->derivative[link] + kKd[link] * (error - s->previous_error[link])) /
        (kTf[link] + kSamplePeriod);
    s->previous_error[link] = error;
    proportional = kKp[link] * error;
    increment = kKi[link] * kSamplePeriod * error;
    integral = s->integral[link] + increment;
    output = proportional + integral + s->derivative[link];
#if IPMC_CONTROLLER_CLAMP
    {
        const ipmc_real headroom = (increment < 0 ? -kVMax : kVMax) - proportional -
                                   s->derivative[link];
        if (increment > 0 && output > kVMax) {
            integral = max_of(s->integral[link], min_of(integral, headroom));
        } else if (increment < 0 && output < -kVMax) {
            integral = min_of(s->integral[link], max_of(integral, headroom));
        }
        output = clamp_of(proportional + integral + s->derivative[link], kVMax);
    }
#endif
    s->integral[link] = integral;
    return output;
}
)";
  return c.str();
}

std::string FractionalSource(const std::vector<LinkExport>& links, double period_s,
                             double v_max_V) {
  std::ostringstream c;
  c << "/* Fractional integrator K / s^lambda (controllers/fractional_integrator.h):\n"
    << " * its realisation's exact zero-order-hold discretisation at T as parallel\n"
    << " * first-order sections (controllers/first_order_sections.h), per link:\n"
    << " *   e_k = r_k - y_k                                  [mm]\n"
    << " *   u_k = d e_k + sum_i c_i x_i,k                    [V], clamped to +-V_max\n"
    << " *   x_i,(k+1) = x_i,k - alpha_i x_i,k + b_i e_k      alpha_i = 1 - pole_i\n"
    << " * While the unclamped |u_k| > V_max and e_k has the sign of u_k the states\n"
    << " * hold (conditional integration). alpha_i, not the pole, is stored: a pole\n"
    << " * near z = 1 keeps its corner in float. */\n\n"
    << LinkTable("kD", links, [](const LinkExport& l) { return l.sections.d; },
                 "d [V/mm], direct term")
    << SectionTable("kAlpha", links, [](const FirstOrderSection& s) { return s.alpha; },
                    "alpha = 1 - pole", period_s, true)
    << SectionTable("kB", links, [](const FirstOrderSection& s) { return s.b; },
                    "b, input coefficient", period_s, false)
    << SectionTable("kC", links, [](const FirstOrderSection& s) { return s.c; },
                    "c [V/mm], output coefficient (the section's DC gain)", period_s, false)
    << "#if IPMC_CONTROLLER_CLAMP\nstatic const ipmc_real kVMax = R(" << Literal(v_max_V)
    << "); /* V_max [V], the clamp */\n#endif\n\n"
    << R"(void ipmc_controller_reset(ipmc_controller_state* s) {
    int q, i;
    for (q = 0; q < IPMC_CONTROLLER_LINKS; ++q) {
        for (i = 0; i < IPMC_CONTROLLER_SECTIONS; ++i) s->x[q][i] = R(0);
    }
}

ipmc_real ipmc_controller_update(ipmc_controller_state* s, int link, ipmc_real reference_mm,
                                 ipmc_real measured_mm) {
    ipmc_real error, output;
    ipmc_real* x;
    int i, hold = 0;
    if (link < 0 || link >= IPMC_CONTROLLER_LINKS) return R(0);
    error = reference_mm - measured_mm;
    x = s->x[link];
    output = kD[link] * error;
    for (i = 0; i < IPMC_CONTROLLER_SECTIONS; ++i) output += kC[link][i] * x[i];
#if IPMC_CONTROLLER_CLAMP
    hold = (output > kVMax || output < -kVMax) && error * output > 0;
    output = clamp_of(output, kVMax);
#endif
    if (!hold) {
        for (i = 0; i < IPMC_CONTROLLER_SECTIONS; ++i) {
            x[i] += kB[link][i] * error - kAlpha[link][i] * x[i];
        }
    }
    return output;
}
)";
  return c.str();
}

// ------------------------------------------------------- JSON and CSV ---

constexpr char kSignConvention[] =
    "Each section as an IIR filter H_i(z) = (b0 + b1 z^-1) / (1 + a1 z^-1) with b0 = 0, "
    "b1 = c_i b_i and a1 = -pole_i (MATLAB filter() and SciPy lfilter(): "
    "y_n = b0 x_n + b1 x_(n-1) - a1 y_(n-1)); CMSIS-DSP's biquads (arm_biquad_cascade_df1) "
    "add a1 y_(n-1) instead, so they take a1_cmsis = pole_i = -a1. The sections' outputs add "
    "to d e_k. alpha_i = 1 - pole_i is the coefficient to keep in float.";

constexpr char kPidConvention[] =
    "Parallel form, e = reference - measured, every gain >= 0. CMSIS-DSP's arm_pid "
    "(y_n = y_(n-1) + A0 x_n + A1 x_(n-1) + A2 x_(n-2)) takes Ki T and Kd / T as its Ki and Kd, "
    "has no derivative filter, clamp or anti-windup: run the equations above instead.";

struct CsvRow {
  int link;
  std::string name;
  double value;
  std::string unit, meaning;
};

std::string CoefficientsCsv(const std::vector<CsvRow>& rows) {
  std::string text = "link,name,value,unit,meaning\n";
  for (const CsvRow& row : rows) {
    text += std::to_string(row.link) + "," + CsvField(row.name) + "," +
            FormatDouble(row.value, kLiteralDigits) + "," + CsvField(row.unit) + "," +
            CsvField(row.meaning) + "\n";
  }
  return text;
}

}  // namespace

const OptionTable<ExportCommand>& ExportOptions() {
  static const OptionTable<ExportCommand> table = MakeExportOptions();
  return table;
}

ExportedController ExportControllers(const ScenarioConfig& scenario) {
  const int model_links = ScenarioLinkCount(scenario);
  CheckLinkGains(scenario, model_links);
  const int driven = scenario.actuation == Actuation::kSingle ? 1 : model_links;
  const ControllerScenario& controller = scenario.controller;
  const bool pid = controller.kind == ControllerKind::kPid;
  const bool clamp = pid ? controller.pid.clamp_enabled : controller.fractional.clamp_enabled;
  const double v_max_V = pid ? controller.pid.v_max : controller.fractional.v_max;
  const double period_s = pid ? controller.pid.sample_period_s : controller.fractional.sample_period_s;

  std::vector<LinkExport> links(driven);
  for (int q = 0; q < driven; ++q) {
    if (pid) {
      links[q].pid = controller.LinkPid(q);
      links[q].pid.Validate();
    } else {
      links[q].fractional = controller.LinkFractional(q);
      const FractionalIntegrator integrator(links[q].fractional);
      try {
        links[q].sections = ParallelFirstOrderSections(integrator.discrete());
      } catch (const std::invalid_argument& error) {
        throw std::invalid_argument(scenario.source + ": link " + std::to_string(q + 1) + ": " +
                                    error.what());
      }
      if (links[q].sections.sections.size() != links.front().sections.sections.size()) {
        throw std::invalid_argument(scenario.source +
                                    ": the links' fractional integrators differ in order");
      }
    }
  }

  ExportedController exported;
  nlohmann::ordered_json& json = exported.coefficients;
  json["scenario"] = scenario.source;
  json["controller"] = pid ? controller_names::kPid : controller_names::kFractional;
  if (!pid) json["realisation"] = FractionalRealisationName(controller.fractional.realisation);
  json["links"] = driven;
  json["sample_rate_Hz"] = controller.sample_rate_Hz;
  json["sample_period_s"] = period_s;
  json["clamp"] = clamp;
  json["v_max_V"] = v_max_V;
  json["error"] = "e_k = reference_k - measured_k [mm] at t_k = k T; u_k [V] held over [t_k, t_(k+1))";
  // Link 0: what every link shares.
  std::vector<CsvRow> rows = {
      {0, "sample_period_s", period_s, "s", "T: every link, every sample; u_k held over it"},
      {0, "v_max_V", clamp ? v_max_V : 0.0, "V",
       clamp ? "the clamp: u_k in [-V_max, V_max]" : "no clamp (0)"}};
  nlohmann::ordered_json per_link = nlohmann::ordered_json::array();
  if (pid) {
    json["difference_equations"] = {
        "D_k = (Tf D_(k-1) + Kd (e_k - e_(k-1))) / (Tf + T)",
        "I_k = I_(k-1) + Ki T e_k",
        "u_k = Kp e_k + I_k + D_k",
        "clamp: if Ki T e_k > 0 and u_k > V_max, I_k = max(I_(k-1), min(I_k, V_max - Kp e_k - "
        "D_k)); if Ki T e_k < 0 and u_k < -V_max, I_k = min(I_(k-1), max(I_k, -V_max - Kp e_k - "
        "D_k)); u_k = min(max(Kp e_k + I_k + D_k, -V_max), V_max)",
        "at rest: I = D = e_(k-1) = 0"};
    json["sign_convention"] = kPidConvention;
    for (int q = 0; q < driven; ++q) {
      const PidController::Config& p = links[q].pid;
      per_link.push_back({{"link", q + 1},
                          {"kp", p.kp},
                          {"ki", p.ki},
                          {"kd", p.kd},
                          {"derivative_filter_s", p.derivative_filter_time_s}});
      rows.push_back({q + 1, "kp", p.kp, "V/mm", "u_k = Kp e_k + I_k + D_k"});
      rows.push_back({q + 1, "ki", p.ki, "V/(mm s)", "I_k = I_(k-1) + Ki T e_k"});
      rows.push_back({q + 1, "kd", p.kd, "V s/mm",
                      "D_k = (Tf D_(k-1) + Kd (e_k - e_(k-1))) / (Tf + T)"});
      rows.push_back({q + 1, "derivative_filter_s", p.derivative_filter_time_s, "s",
                      "Tf of D_k (0: the ideal derivative Kd (e_k - e_(k-1)) / T)"});
    }
  } else {
    json["difference_equations"] = {
        "u_k = d e_k + sum_i c_i x_i,k",
        "x_i,(k+1) = x_i,k - alpha_i x_i,k + b_i e_k  (pole_i = 1 - alpha_i)",
        "clamp: if |u_k| > V_max and e_k u_k > 0 the states hold (x_(k+1) = x_k); "
        "u_k = min(max(u_k, -V_max), V_max)",
        "at rest: x = 0"};
    json["sign_convention"] = kSignConvention;
    for (int q = 0; q < driven; ++q) {
      const LinkExport& l = links[q];
      nlohmann::ordered_json sections = nlohmann::ordered_json::array();
      rows.push_back({q + 1, "d", l.sections.d, "V/mm", "u_k = d e_k + sum_i c_i x_i,k"});
      for (size_t i = 0; i < l.sections.sections.size(); ++i) {
        const FirstOrderSection& s = l.sections.sections[i];
        const std::string n = std::to_string(i + 1);
        sections.push_back({{"alpha", s.alpha},
                            {"b", s.b},
                            {"c_V_per_mm", s.c},
                            {"pole", s.pole()},
                            {"corner_rad_s", s.CornerRadS(period_s)},
                            {"b1", s.c * s.b},
                            {"a1", -s.pole()},
                            {"a1_cmsis", s.pole()}});
        const std::string x = "x" + n;
        rows.push_back({q + 1, "section" + n + "_alpha", s.alpha, "",
                        x + "_(k+1) = " + x + "_k - alpha " + x + "_k + b e_k"});
        rows.push_back({q + 1, "section" + n + "_b", s.b, "", "input coefficient of " + x});
        rows.push_back({q + 1, "section" + n + "_c", s.c, "V/mm",
                        "output coefficient: u_k gets c " + x + "_k"});
        rows.push_back({q + 1, "section" + n + "_b1", s.c * s.b, "V/mm",
                        "IIR numerator (b0 = 0): (b1 z^-1) / (1 + a1 z^-1)"});
        rows.push_back({q + 1, "section" + n + "_a1", -s.pole(), "",
                        "IIR denominator, MATLAB/SciPy sign: y_n = b1 x_(n-1) - a1 y_(n-1)"});
        rows.push_back({q + 1, "section" + n + "_a1_cmsis", s.pole(), "",
                        "the same for CMSIS-DSP, which adds a1 y_(n-1): -a1"});
      }
      per_link.push_back({{"link", q + 1},
                          {"gain", l.fractional.gain},
                          {"order", l.fractional.order},
                          {"d_V_per_mm", l.sections.d},
                          {"sections", sections}});
    }
  }
  json["per_link"] = per_link;

  std::string source = std::string("/* ipmc_controller.c: see ipmc_controller.h. Numbers with ") +
                       std::to_string(kLiteralDigits) +
                       " digits: as doubles they are the simulator's. */\n"
                       "#include \"ipmc_controller.h\"\n\n#define R(x) ((ipmc_real)(x))\n\n" +
                       "/* std::min, std::max and std::clamp's own comparisons. */\n" +
                       (pid ? kMinMaxHelpers : "") + kClampHelper + "\n";
  source += pid ? PidSource(links, period_s, v_max_V) : FractionalSource(links, period_s, v_max_V);
  exported.texts = {HeaderText(scenario, links, pid, clamp, v_max_V), source,
                    json.dump(2) + "\n", CoefficientsCsv(rows)};
  return exported;
}

ExportedController RunExportCommand(const std::string& out, const ScenarioConfig& scenario) {
  if (out.empty()) throw FieldError("export: out must be a folder", "out", "a folder");
  RequireWritableDirectory(out);
  ExportedController exported = ExportControllers(scenario);
  EnsureDirectory(out);
  std::vector<std::pair<std::string, std::string>> files;
  for (size_t i = 0; i < exported.texts.size(); ++i) {
    files.emplace_back((std::filesystem::path(out) / kExportFiles[i]).string(), exported.texts[i]);
  }
  WriteFilesTogether(files);
  return exported;
}

ExportedController RunExportCommand(const ExportCommand& command) {
  ScenarioConfig scenario;
  if (command.set.empty()) {
    scenario = LoadScenario(command.scenario);
  } else {
    std::vector<ScenarioSetting> settings;
    for (const std::string& set : command.set) settings.push_back(SetOption(kCommand, set));
    scenario = ScenarioWithSettings(kCommand, command.scenario, settings);
  }
  return RunExportCommand(command.out, scenario);
}

}  // namespace ipmc
