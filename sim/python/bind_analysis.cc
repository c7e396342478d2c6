// Analyses from Python: Bode data and margins, closed-loop steps,
// identification of a record and the controller design of one link, each
// as its ipmc-swim command computes it (sim/identify/loop_analysis.h,
// sim/identify/identify_run.h). The options are the command's, with
// underscores for dashes (--band-rad-s is band_rad_s), and so are the
// error messages.
#include <algorithm>
#include <complex>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "sim/identify/identify_run.h"
#include "sim/identify/loop_analysis.h"
#include "sim/io/files.h"
#include "sim/python/convert.h"

namespace ipmc::python {
namespace {

// Whether the keyword of a command-line option ("--band-rad-s": band_rad_s)
// was given.
OptionGiven GivenIn(const Options& options) {
  return [&options](const std::string& option) {
    std::string key = option.substr(2);
    std::replace(key.begin(), key.end(), '-', '_');
    return options.Given(key);
  };
}

py::object Optional(const std::optional<double>& value) {
  return value ? py::object(py::float_(*value)) : py::object(py::none());
}

py::dict MarginsDict(const StabilityMargins& m) {
  py::dict dict;
  dict["gain_crossover_rad_s"] = Optional(m.gain_crossover_rad_s);
  dict["phase_margin_deg"] = Optional(m.phase_margin_deg);
  dict["gain_margin_db"] = Optional(m.gain_margin_db);
  dict["phase_crossover_rad_s"] = Optional(m.phase_crossover_rad_s);
  dict["gain_crossovers_rad_s"] = Array(m.gain_crossovers_rad_s);
  return dict;
}

py::dict StepMetricsDict(const StepMetrics& m) {
  py::dict dict;
  dict["final_value"] = m.final_value;
  dict["overshoot_percent"] = m.overshoot_percent;
  dict["rise_time_s"] = Optional(m.rise_time_s);
  dict["peak_value"] = m.peak_value;
  dict["peak_time_s"] = m.peak_time_s;
  dict["settling_time_s"] = Optional(m.settling_time_s);
  return dict;
}

void ReadGains(Options& options, ControllerGains* gains) {
  options.Read("kp", &gains->kp);
  options.Read("ki", &gains->ki);
  options.Read("kd", &gains->kd);
  options.Read("gain", &gains->gain);
  options.Read("order", &gains->order);
}

void WriteInto(const py::object& out, const std::string& file, const std::string& content) {
  const std::string dir = PathText(out, "out");
  EnsureDirectory(dir);
  WriteFileAtomically((std::filesystem::path(dir) / file).string(), content);
}

// ------------------------------------------------------------------ bode ---

py::dict Bode(const std::string& controller, const py::dict& kwargs, const py::object& out) {
  Options options("bode", kwargs);
  BodeSpec spec;
  spec.controller = controller;
  options.Read("link", &spec.link);
  options.Read("plant", &spec.plant);
  ReadGains(options, &spec.gains);
  options.Read("oustaloup_pairs", &spec.oustaloup_n);
  options.Read("band_rad_s", &spec.band_rad_s);
  options.Read("w_min", &spec.w_min_rad_s);
  options.Read("w_max", &spec.w_max_rad_s);
  options.Read("points_per_decade", &spec.points_per_decade);
  options.RejectUnknown();
  ValidateBodeSpec("bode", spec, GivenIn(options));
  const BodeAnalysis analysis = AnalyseBode(spec);
  const BodeColumns columns = ComputeBodeColumns(analysis, spec);
  if (!out.is_none()) WriteInto(out, "bode.csv", BodeCsv(columns));

  py::dict response;
  response["w_rad_s"] = Array(columns.plant.w_rad_s);
  const std::pair<const char*, const BodeData*> parts[] = {
      {"plant", &columns.plant},
      {"controller", &columns.controller},
      {"open_loop", &columns.open_loop},
      {"reference_open_loop", &columns.reference_open_loop}};
  for (const auto& [name, data] : parts) {
    response[py::str(std::string(name) + "_db")] = Array(data->magnitude_db);
    response[py::str(std::string(name) + "_deg")] = Array(data->phase_deg);
  }
  py::dict at_design;
  at_design["w_rad_s"] = analysis.design_frequency_rad_s;
  at_design["controller"] = analysis.controller_at_design;
  at_design["plant"] = analysis.plant_at_design;
  at_design["open_loop"] = analysis.controller_at_design * analysis.plant_at_design;

  py::dict result;
  result["controller"] = analysis.controller_description;
  result["plant"] = analysis.plant_description;
  result["margins"] = MarginsDict(analysis.margins);
  result["at_design"] = at_design;
  result["response"] = response;
  return result;
}

// ------------------------------------------------------------------ step ---

py::dict Step(const std::string& controller, const py::dict& kwargs, const py::object& out) {
  Options options("step", kwargs);
  StepSpec spec;
  spec.controller = controller;
  options.Read("plant", &spec.plant);
  options.Read("links", &spec.links);
  ReadGains(options, &spec.gains);
  options.Read("horizon_s", &spec.horizon_s);
  options.Read("max_horizon_s", &spec.max_horizon_s);
  options.Read("sample_rate_hz", &spec.sample_rate_hz);
  options.Read("no_clamp", &spec.no_clamp);
  options.Read("v_max", &spec.v_max);
  options.RejectUnknown();
  ValidateStepSpec("step", spec, GivenIn(options));
  const StepAnalysis analysis = WithoutGil([&] { return AnalyseStep(spec); });
  if (!out.is_none()) WriteInto(out, "step.csv", StepCsv(analysis));

  py::list links;
  for (const LinkStep& step : analysis.links) {
    py::dict link;
    link["link"] = step.link;
    link["time_s"] = Array(step.response.time_s);
    link["output_mm"] = Array(step.response.output);
    link["control_V"] = Array(step.response.control);
    link["metrics"] = StepMetricsDict(step.metrics);
    link["record_status"] = std::string(StepRecordStatusText(step.status));
    link["determined"] = step.status == StepRecordStatus::kDetermined;
    link["max_abs_control_V"] = step.max_abs_control_V;
    link["cost"] = step.cost;
    links.append(link);
  }
  py::dict reference;
  reference["time_s"] = Array(analysis.time_s);
  reference["output_mm"] = Array(analysis.reference);
  reference["metrics"] = StepMetricsDict(analysis.reference_metrics);

  py::dict result;
  result["controller"] = analysis.controller_description;
  result["links"] = links;
  result["reference"] = reference;
  result["metrics_horizon_s"] = analysis.metrics_horizon_s;
  result["settling_band"] = analysis.settling_band;
  return result;
}

// -------------------------------------------------------------- identify ---

std::vector<double> Column(const py::object& data, const std::string& name,
                           const std::string& what) {
  py::object column;
  try {
    column = data[py::str(name)];
  } catch (const py::error_already_set& error) {
    if (!error.matches(PyExc_KeyError) && !error.matches(PyExc_ValueError) &&
        !error.matches(PyExc_IndexError)) {
      throw;
    }
    throw std::invalid_argument(what + ": no column '" + name + "'");
  }
  const py::array_t<double, py::array::c_style | py::array::forcecast> values =
      py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(column);
  if (!values || values.ndim() != 1) {
    throw py::type_error(what + ": column '" + name + "' must be one-dimensional numbers");
  }
  return std::vector<double>(values.data(), values.data() + values.size());
}

bool HasColumn(const py::object& data, const std::string& name) {
  try {
    data[py::str(name)];
    return true;
  } catch (const py::error_already_set&) {
    return false;
  }
}

// A fit's P = s^-0.5 G at the frequencies.
py::array_t<std::complex<double>> FittedArray(const LinkModelFit& fit,
                                              const std::vector<double>& w_rad_s) {
  std::vector<std::complex<double>> response;
  for (double w : w_rad_s) response.push_back(FittedResponse(fit.params, w));
  return Array(response);
}

py::dict Identify(const py::object& data, const std::string& input, const std::string& output,
                  const py::dict& kwargs, const py::object& out) {
  Options options("identify", kwargs);
  IdentifySpec spec;
  spec.data_path = "data";
  options.Read("name", &spec.data_path);
  spec.input_column = input;
  spec.output_column = output;
  options.Read("sample_rate_hz", &spec.sample_rate_hz);
  options.Read("band_rad_s", &spec.band_rad_s);
  options.RejectUnknown();
  spec.Validate();
  const std::vector<double> u = Column(data, input, spec.data_path);
  const std::vector<double> y = Column(data, output, spec.data_path);
  std::optional<std::vector<double>> t;
  if (HasColumn(data, "time_s")) t = Column(data, "time_s", spec.data_path);
  const RecordIdentification result =
      WithoutGil([&] { return IdentifyRecord(spec, u, y, t ? &*t : nullptr); });
  const nlohmann::json json = IdentificationJson(spec, result);
  if (!out.is_none()) {
    WriteInto(out, "response.csv", ResponseCsv(result.estimate, result.id));
    WriteInto(out, "identification.json", json.dump(2) + "\n");
  }
  const FrequencyResponseEstimate& e = result.estimate;
  py::dict response;
  response["w_rad_s"] = Array(e.w_rad_s);
  response["frequency_Hz"] = Array(e.frequency_Hz);
  response["measured"] = Array(e.response);
  response["coherence"] = Array(e.coherence);
  response["input_psd"] = Array(e.input_psd);
  response["output_psd"] = Array(e.output_psd);
  response["p1"] = FittedArray(result.id.g1, e.w_rad_s);
  response["p2"] = FittedArray(result.id.g2, e.w_rad_s);
  py::dict dict = ToPython(json);
  dict["response"] = response;
  dict["g2_orders_tried"] = result.id.g2_orders_tried;
  dict["g2_orders_stable"] = result.id.g2_orders_stable;
  return dict;
}

// ---------------------------------------------------------------- design ---

py::dict Design(const py::dict& kwargs) {
  Options options("design", kwargs);
  DesignSpec spec;
  options.Read("link", &spec.link);
  options.Read("plant", &spec.plant);
  options.Read("crossover_rad_s", &spec.crossover_rad_s);
  options.Read("phase_margin_deg", &spec.phase_margin_deg);
  options.Read("reference_order", &spec.reference_order);
  options.Read("horizon_s", &spec.horizon_s);
  options.Read("sample_rate_hz", &spec.sample_rate_hz);
  options.RejectUnknown();
  const LinkDesign design = WithoutGil([&] { return DesignLink(spec); });

  py::dict fractional;
  fractional["gain"] = design.fractional.design.gain;
  fractional["order"] = design.fractional.design.order;
  fractional["plant_magnitude"] = design.fractional.design.plant_magnitude;
  fractional["plant_phase_deg"] = design.fractional.design.plant_phase_deg;
  fractional["margins"] = MarginsDict(design.fractional.margins);

  auto gains = [](const PidGains& g) {
    py::dict dict;
    dict["kp"] = g.kp;
    dict["ki"] = g.ki;
    dict["kd"] = g.kd;
    return dict;
  };
  py::list runs;
  for (const PidTuningRun& run : design.tuned.runs) {
    py::dict entry;
    entry["start"] = gains(run.start);
    entry["gains"] = gains(run.gains);
    entry["start_cost"] = run.start_cost;
    entry["cost"] = run.cost;
    entry["evaluations"] = run.evaluations;
    entry["converged"] = run.converged;
    runs.append(entry);
  }
  py::dict pid = gains(design.tuned.gains);
  pid["cost"] = design.tuned.cost;
  pid["paper_cost"] = design.paper_cost;
  pid["margins"] = MarginsDict(design.pid_margins);
  pid["runs"] = runs;

  py::dict result;
  result["fractional"] = fractional;
  result["pid"] = pid;
  result["tuning_s"] = design.tuning_s;
  return result;
}

}  // namespace

void BindAnalysis(py::module_& m) {
  m.def("bode", &Bode, py::arg("controller"), py::arg("options"), py::arg("out"));
  m.def("step", &Step, py::arg("controller"), py::arg("options"), py::arg("out"));
  m.def("identify", &Identify, py::arg("data"), py::arg("input"), py::arg("output"),
        py::arg("options"), py::arg("out"));
  m.def("design", &Design, py::arg("options"));
}

}  // namespace ipmc::python
