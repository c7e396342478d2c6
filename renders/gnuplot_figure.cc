#include "renders/gnuplot_figure.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <stdexcept>

#include "sim/base/error.h"
#include "sim/io/files.h"
#include "sim/io/process.h"
#include "sim/base/numbers.h"

namespace ipmc {
namespace {

namespace fs = std::filesystem;

constexpr char kGnuplot[] = "gnuplot";
// PNG resolution, and the SVG terminal's user units (CSS pixels), per inch.
constexpr double kPngPxPerInch = 150.0;
constexpr double kSvgUnitsPerInch = 96.0;
// Body text size [pt]; PNG and SVG scale it from the 72 points per inch.
constexpr double kFontPt = 9.0;

std::string Lower(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return text;
}

// The last non-empty line of gnuplot's output, its error message, with the
// temporary script's path (gone by the time anyone reads it) shortened.
std::string GnuplotSaid(const fs::path& log, const fs::path& script) {
  std::string last = LastLineOfFile(log.string());
  if (last.empty()) return "no message";
  const std::string quoted_script = "\"" + script.string() + "\"";
  if (const size_t at = last.find(quoted_script); at != std::string::npos) {
    last.replace(at, quoted_script.size(), "script");
  }
  return last;
}

// Runs "gnuplot SCRIPT" with its output in LOG; throws unless it exits 0.
void RunGnuplot(const fs::path& script, const fs::path& log, const std::string& input) {
  ProgramExit exit;
  try {
    exit = RunProgram({kGnuplot, script.string()}, log.string());
  } catch (const std::runtime_error& error) {
    throw std::runtime_error(std::string("plot: ") + error.what() +
                             " (Debian package gnuplot-nox)");
  }
  if (!exit.ok()) {
    throw std::runtime_error("plot: gnuplot failed drawing " + input + " (" + exit.How() +
                             "): " + GnuplotSaid(log, script));
  }
}

// Whether the file starts as the format's files do.
bool HasSignature(const std::string& path, FigureFormat format) {
  std::ifstream in(path, std::ios::binary);
  char head[256] = {};
  in.read(head, sizeof(head));
  const std::string start(head, static_cast<size_t>(in.gcount()));
  switch (format) {
    case FigureFormat::kPdf:
      return start.rfind("%PDF-", 0) == 0;
    case FigureFormat::kPng:
      return start.rfind("\x89PNG\r\n\x1a\n", 0) == 0;
    case FigureFormat::kSvg:
      return start.find("<svg") != std::string::npos;
  }
  return false;
}

const char* FormatName(FigureFormat format) {
  switch (format) {
    case FigureFormat::kPdf:
      return "PDF";
    case FigureFormat::kSvg:
      return "SVG";
    case FigureFormat::kPng:
      return "PNG";
  }
  return "";
}

// The terminal line for the format at width x height inches.
std::string Terminal(FigureFormat format, double width_in, double height_in) {
  char line[256];
  switch (format) {
    case FigureFormat::kPdf:
      std::snprintf(line, sizeof(line),
                    "set terminal pdfcairo size %.3fin,%.3fin noenhanced font 'sans,%g' "
                    "linewidth 1\n",
                    width_in, height_in, kFontPt);
      break;
    case FigureFormat::kSvg:
      std::snprintf(line, sizeof(line),
                    "set terminal svg size %d,%d noenhanced font 'sans,%g' linewidth 1 "
                    "background '#ffffff'\n",
                    static_cast<int>(std::lround(width_in * kSvgUnitsPerInch)),
                    static_cast<int>(std::lround(height_in * kSvgUnitsPerInch)),
                    kFontPt * kSvgUnitsPerInch / 72.0);
      break;
    case FigureFormat::kPng:
      std::snprintf(line, sizeof(line),
                    "set terminal pngcairo size %d,%d noenhanced font 'sans,%g' "
                    "linewidth %g\n",
                    static_cast<int>(std::lround(width_in * kPngPxPerInch)),
                    static_cast<int>(std::lround(height_in * kPngPxPerInch)),
                    kFontPt * kPngPxPerInch / 72.0, kPngPxPerInch / 72.0);
      break;
  }
  return line;
}

}  // namespace

FigureFormat FigureFormatOf(const std::string& path) {
  const std::string extension = Lower(fs::path(path).extension().string());
  if (extension == ".pdf") return FigureFormat::kPdf;
  if (extension == ".svg") return FigureFormat::kSvg;
  if (extension == ".png") return FigureFormat::kPng;
  throw FieldError(path + ": unknown figure format '" + extension + "' (allowed: .pdf, .svg, .png)",
                   "--out", ".pdf, .svg, .png");
}

FigureScratch::FigureScratch() {
  std::string name = (fs::temp_directory_path() / "ipmc-swim-plot.XXXXXX").string();
  if (mkdtemp(name.data()) == nullptr) {
    throw std::runtime_error("plot: cannot create a temporary directory (" +
                             std::string(std::strerror(errno)) + ")");
  }
  path_ = name;
}

FigureScratch::~FigureScratch() {
  std::error_code ignored;
  fs::remove_all(path_, ignored);
}

std::string FigureScratch::Data(const std::string& name, const std::string& content) const {
  const fs::path path = File(name);
  WriteFileAtomically(path.string(), content);
  return GnuplotQuote(path.string());
}

void DrawFigure(const Figure& figure, const FigureScratch& scratch, const std::string& out_path,
                const std::string& input, FigureSize size) {
  const FigureFormat format = FigureFormatOf(out_path);
  const double width_in = size.width_px > 0 ? size.width_px / kPngPxPerInch : figure.width_in;
  const double height_in = size.height_px > 0 ? size.height_px / kPngPxPerInch : figure.height_in;

  EnsureParentDirectory(out_path);
  PendingFile output(out_path);
  const std::string script = "set encoding utf8\n" + Terminal(format, width_in, height_in) +
                             "set output " + GnuplotQuote(output.temp_path()) +
                             "\n"
                             "set datafile missing 'NaN'\n"
                             "set grid back lt 1 lc rgb 'gray88' lw 1\n"
                             "set border lw 1\n" +
                             figure.commands + "unset output\n";
  const fs::path script_path = scratch.File("plot.gp");
  WriteFileAtomically(script_path.string(), script);
  const fs::path log = scratch.File("gnuplot.log");
  RunGnuplot(script_path, log, input);
  if (!HasSignature(output.temp_path(), format)) {
    throw std::runtime_error(std::string("plot: gnuplot wrote no ") + FormatName(format) +
                             " drawing " + input + ": " + GnuplotSaid(log, script_path));
  }
  output.Commit();
}

std::string GnuplotQuote(const std::string& text) {
  std::string quoted = "'";
  for (char c : text) {
    if (c == '\n' || c == '\r') {
      quoted += ' ';
    } else {
      quoted += c;
      if (c == '\'') quoted += '\'';
    }
  }
  return quoted + "'";
}

std::string GnuplotLines(const std::vector<std::string>& lines) {
  std::string quoted = "\"";
  for (size_t k = 0; k < lines.size(); ++k) {
    if (k > 0) quoted += "\\n";
    for (char c : lines[k]) {
      if (c == '\n' || c == '\r') {
        quoted += ' ';
      } else {
        if (c == '"' || c == '\\') quoted += '\\';
        quoted += c;
      }
    }
  }
  return quoted + "\"";
}

std::string GnuplotNumber(double value) { return FormatDouble(value, 10); }

std::string GnuplotValue(double value) {
  return std::isfinite(value) ? GnuplotNumber(value) : "NaN";
}

std::string GnuplotTable(const std::vector<std::vector<double>>& columns) {
  std::string text;
  const size_t rows = columns.empty() ? 0 : columns.front().size();
  for (size_t r = 0; r < rows; ++r) {
    for (size_t c = 0; c < columns.size(); ++c) {
      text += (c ? " " : "") + GnuplotValue(columns[c][r]);
    }
    text += "\n";
  }
  return text;
}

}  // namespace ipmc
