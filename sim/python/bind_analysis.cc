// Analyses from Python: Bode data and margins, closed-loop steps,
// identification of a record, the controller design of one link and the
// export of a scenario's controllers as code, each
// as its ipmc-swim command computes it (sim/identify/loop_analysis.h,
// sim/identify/identify_run.h): the keywords are the names of the
// command's option table, which the command line reads too, and the
// checks and the files are the library's, so both front ends write the
// same bytes.
#include <algorithm>
#include <complex>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "sim/identify/controller_export.h"
#include "sim/identify/identify_run.h"
#include "sim/identify/loop_analysis.h"
#include "sim/io/columns.h"
#include "sim/python/convert.h"

namespace ipmc::python {
namespace {

py::object Optional(const std::optional<double>& value) {
  return value ? py::object(py::float_(*value)) : py::object(py::none());
}

py::dict MarginsDict(const StabilityMargins& m) {
  py::dict dict;
  dict["gain_crossover_rad_s"] = Optional(m.gain_crossover_rad_s);
  dict["phase_margin_deg"] = Optional(m.phase_margin_deg);
  dict["gain_margin_dB"] = Optional(m.gain_margin_dB);
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

// ------------------------------------------------------------------ bode ---

py::dict BodeLinkDict(const BodeLink& link) {
  const BodeAnalysis& analysis = link.analysis;
  const BodeColumns& curves = link.columns;
  py::dict response;
  response[columns::kFrequency] = Array(curves.plant.w_rad_s);
  const std::pair<const char*, const BodeData*> parts[] = {
      {columns::kPlantCurve, &curves.plant},
      {columns::kControllerCurve, &curves.controller},
      {columns::kOpenLoopCurve, &curves.open_loop},
      {columns::kReferenceOpenLoopCurve, &curves.reference_open_loop}};
  for (const auto& [name, data] : parts) {
    response[py::str(columns::MagnitudeDb(name))] = Array(data->magnitude_dB);
    response[py::str(columns::PhaseDeg(name))] = Array(data->phase_deg);
  }
  py::dict at_design;
  at_design["w_rad_s"] = analysis.design_frequency_rad_s;
  at_design["controller"] = analysis.controller_at_design;
  at_design["plant"] = analysis.plant_at_design;
  at_design["open_loop"] = analysis.controller_at_design * analysis.plant_at_design;

  py::dict result;
  result["link"] = link.spec.link;
  result["controller"] = analysis.controller_description;
  result["plant"] = analysis.plant_description;
  result["margins"] = MarginsDict(analysis.margins);
  result["at_design"] = at_design;
  result["response"] = response;
  return result;
}

py::list Bode(const py::dict& kwargs) {
  const std::vector<BodeLink> links =
      RunCommandWithoutGil("bode", kwargs, BodeOptions(), RunBodeCommand);
  py::list result;
  for (const BodeLink& link : links) result.append(BodeLinkDict(link));
  return result;
}

// ------------------------------------------------------------------ step ---

py::dict Step(const py::dict& kwargs) {
  const StepAnalysis analysis = RunCommandWithoutGil("step", kwargs, StepOptions(), RunStepCommand);

  const auto link_dicts = [](const std::vector<LinkStep>& steps) {
    py::list links;
    for (const LinkStep& step : steps) {
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
      link["iae_mm_s"] = step.indices.iae_mm_s;
      link["itae_mm_s2"] = step.indices.itae_mm_s2;
      links.append(link);
    }
    return links;
  };
  py::dict reference;
  reference["time_s"] = Array(analysis.time_s);
  reference["output_mm"] = Array(analysis.reference);
  reference["metrics"] = StepMetricsDict(analysis.reference_metrics);

  py::dict result;
  result["controller"] = analysis.controller_description;
  result["links"] = link_dicts(analysis.links);
  result["bench"] = link_dicts(analysis.bench);
  result["reference"] = reference;
  result["metrics_horizon_s"] = analysis.metrics_horizon_s;
  result["settling_band"] = analysis.settling_band;
  return result;
}

// -------------------------------------------------------------- identify ---

// Column `name` of the record (a dict, a numpy record array, a pandas
// DataFrame), or nullopt if it has none.
std::optional<std::vector<double>> OptionalColumn(const py::object& data, const std::string& name,
                                                  const std::string& what) {
  py::object column;
  try {
    column = data[py::str(name)];  // the item is looked up here, on assignment
  } catch (const py::error_already_set& error) {
    if (!error.matches(PyExc_KeyError) && !error.matches(PyExc_ValueError) &&
        !error.matches(PyExc_IndexError)) {
      throw;
    }
    return std::nullopt;
  }
  const py::array_t<double, py::array::c_style | py::array::forcecast> values =
      py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(column);
  if (!values || values.ndim() != 1) {
    throw py::type_error(what + ": column '" + name + "' must be one-dimensional numbers");
  }
  return std::vector<double>(values.data(), values.data() + values.size());
}

std::vector<double> Column(const py::object& data, const std::string& name,
                           const std::string& what) {
  std::optional<std::vector<double>> column = OptionalColumn(data, name, what);
  if (!column) throw std::invalid_argument(what + ": no column '" + name + "'");
  return std::move(*column);
}

// A fit's P = s^-0.5 G at the frequencies.
py::array_t<std::complex<double>> FittedArray(const LinkModelFit& fit,
                                              const std::vector<double>& w_rad_s) {
  std::vector<std::complex<double>> response;
  for (double w : w_rad_s) response.push_back(FittedResponse(fit.params, w));
  return Array(response);
}

// data: the record, by column names; `name` (the record's name in
// messages and identification.json) is a keyword of its own: the command
// line's is the file's path.
py::dict Identify(const py::object& data, const py::dict& kwargs) {
  Options options("identify", kwargs);
  IdentifyCommand named;
  named.data_path = "data";
  options.ReadPath("name", &named.data_path);
  IdentifyCommand command = ReadCommandKeywords(options, IdentifyOptions(), std::move(named));
  command.Validate();
  const IdentifySpec& spec = command;
  const std::vector<double> u = Column(data, spec.input_column, spec.data_path);
  const std::vector<double> y = Column(data, spec.output_column, spec.data_path);
  // time_s is optional: without it the samples are sample_rate_Hz apart.
  const std::optional<std::vector<double>> t =
      OptionalColumn(data, columns::kTime, spec.data_path);
  const RecordIdentification result =
      WithoutGil([&] { return RunIdentifyCommand(command, u, y, t ? &*t : nullptr); });
  const nlohmann::json json = IdentificationJson(spec, result);
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

py::dict DesignDict(int link, const LinkDesign& design) {
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
  pid["sample_rate_Hz"] = 1.0 / design.tuning.sample_period_s;
  pid["derivative_filter_s"] = design.tuning.derivative_filter_s;
  pid["derivative_noise_V"] = design.derivative_noise_V;

  py::dict result;
  result["link"] = link;
  result["fractional"] = fractional;
  result["pid"] = pid;
  result["tuning_s"] = design.tuning_s;
  return result;
}

py::list Design(const py::dict& kwargs) {
  Options options("design", kwargs);
  const DesignCommand command = ReadCommandKeywords(options, DesignOptions());
  const OptionGiven given = GivenKeywords(options, DesignOptions());
  // Ctrl-C stops the tuning at its next evaluation of J (milliseconds
  // apart), as it stops the command line at once; nothing is written.
  const std::vector<LinkDesign> designs = Interruptible([&](const std::atomic<bool>& stop) {
    return RunDesignCommand(command, given, [&stop] { ThrowIfStopRequested(stop); });
  });
  py::list result;
  for (const LinkDesign& design : designs) result.append(DesignDict(design.link, design));
  return result;
}

// ---------------------------------------------------------------- export ---

py::object Export(const py::object& scenario_arg, const py::dict& overrides,
                  const py::dict& kwargs) {
  Options options("export", kwargs);
  const ExportCommand command = ReadCommandKeywords(options, ExportOptions());
  const ScenarioConfig scenario = ReadScenarioArgument(scenario_arg, overrides, "export").scenario;
  const ExportedController exported =
      WithoutGil([&] { return RunExportCommand(command.out, scenario); });
  return ToPython(exported.coefficients);
}

}  // namespace

void BindAnalysis(py::module_& m) {
  m.def("bode", &Bode, py::arg("options"));
  m.def("step", &Step, py::arg("options"));
  m.def("identify", &Identify, py::arg("data"), py::arg("options"));
  m.def("design", &Design, py::arg("options"));
  m.def("export", &Export, py::arg("scenario"), py::arg("overrides"), py::arg("options"));
}

}  // namespace ipmc::python
