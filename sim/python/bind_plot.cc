// Figures from Python: plot(kind, inputs, out, options) draws what
// `ipmc-swim plot KIND INPUT... --out FILE` draws (renders/figures.h), the
// same bytes, and returns what the command prints: the title and the
// notes.
#include <string>
#include <vector>

#include "renders/figures.h"
#include "sim/python/convert.h"

namespace ipmc::python {
namespace {

py::dict Plot(const std::string& kind_name, const py::list& input_list, const py::object& out,
              const py::dict& keywords) {
  const FigureKind kind = FigureKindOf(kind_name);
  std::vector<std::string> inputs;
  for (const py::handle& input : input_list) inputs.push_back(PathText(input, "plot(): input"));
  const std::string out_path = PathText(out, "plot(): out");
  Options options("plot", keywords);
  FigureOptions figure;
  options.Read("title", &figure.title);
  options.Read("width_px", &figure.size.width_px);
  options.Read("height_px", &figure.size.height_px);
  // The kind's own options, by the command line's names with _ for -.
  std::vector<std::string> given;
  for (const std::string& option : FigureKindOptionNames()) {
    std::string key = option;
    for (char& c : key) c = c == '-' ? '_' : c;
    if (options.Given(key)) given.push_back(option);
  }
  options.Read("curves", &figure.curves);
  options.Read("instants", &figure.instants);
  options.Read("times_s", &figure.times_s);
  options.Read("period_s", &figure.period_s);
  options.Read("max_lines", &figure.max_lines);
  options.Read("x", &figure.x_column);
  options.Read("y", &figure.y_column);
  options.Read("group", &figure.group_column);
  options.Read("log_x", &figure.log_x);
  options.Read("log_y", &figure.log_y);
  options.Read("labels", &figure.labels);
  options.RejectUnknown();
  CheckFigureOptionsApply(kind, given);
  const FigureReport report =
      WithoutGil([&] { return DrawFigureOf(kind, inputs, figure, out_path); });
  py::dict result;
  result["title"] = report.title;
  result["title_lines"] = report.title_lines;
  result["notes"] = report.notes;
  return result;
}

}  // namespace

void BindPlot(py::module_& m) {
  m.def("plot", &Plot, py::arg("kind"), py::arg("inputs"), py::arg("out"), py::arg("options"));
}

}  // namespace ipmc::python
