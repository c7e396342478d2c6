// Drawing a figure with gnuplot (from PATH; Debian package gnuplot-nox)
// into PDF, SVG or PNG, chosen by the output file's extension:
//   .pdf  pdfcairo, vector, the figure's size in inches, fonts in points;
//   .svg  gnuplot's own svg terminal, vector, text kept as <text>
//         elements (searchable, editable);
//   .png  pngcairo at 150 pixels per inch, fonts and lines scaled to
//         match the PDF.
// Any other extension is an error. A figure is a gnuplot script body (the
// commands after the terminal is set) plus the data files it reads, which
// live in a scratch directory removed afterwards. The output is written to
// a temporary file beside it and renamed into place only if gnuplot exited
// with 0 and the file starts with the format's signature; otherwise
// nothing is left behind and the error carries gnuplot's last message.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace ipmc {

enum class FigureFormat { kPdf, kSvg, kPng };

// The format of `path` by its extension (case-insensitive). Throws
// FieldError (sim/base/error.h, field --out) "PATH: unknown figure format 'EXT' (allowed: .pdf,
// .svg, .png)".
FigureFormat FigureFormatOf(const std::string& path);

// A fresh directory under the system's temporary directory for a figure's
// data, removed with everything in it when the object goes.
class FigureScratch {
 public:
  FigureScratch();
  ~FigureScratch();
  FigureScratch(const FigureScratch&) = delete;
  FigureScratch& operator=(const FigureScratch&) = delete;

  std::filesystem::path File(const std::string& name) const { return path_ / name; }
  // Writes a data file and returns its path quoted for a script.
  std::string Data(const std::string& name, const std::string& content) const;

 private:
  std::filesystem::path path_;
};

struct Figure {
  std::string commands;   // gnuplot commands after the terminal and output
  double width_in = 7.0;  // size of the drawing [in]
  double height_in = 4.5;
};

// Pixel size for PNG (and, at 150 px/in, the size of PDF and SVG), if the
// caller sets one.
struct FigureSize {
  int width_px = 0, height_px = 0;  // 0: the figure's own
};

// Draws `figure` into out_path (its parent directory is created).
// `input` names the data in error messages. Throws std::runtime_error if
// gnuplot cannot be run, fails (with its message) or writes no file of
// the format.
void DrawFigure(const Figure& figure, const FigureScratch& scratch, const std::string& out_path,
                const std::string& input, FigureSize size = {});

// Gnuplot text helpers: a string literal (single quotes; line breaks become
// spaces), a number at 10 significant digits, a data value (non-finite
// values become the missing-value marker NaN), and columns as a
// whitespace-separated table.
std::string GnuplotQuote(const std::string& text);
// Lines as one gnuplot string (double quotes, "\n" between them), for
// titles on two lines.
std::string GnuplotLines(const std::vector<std::string>& lines);
std::string GnuplotNumber(double value);
std::string GnuplotValue(double value);
std::string GnuplotTable(const std::vector<std::vector<double>>& columns);

}  // namespace ipmc
