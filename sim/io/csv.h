// CSV, read and written by one set of rules (RFC 4180 with "\n" line
// ends). Column names: sim/io/columns.h.
//
// Writing: a field is quoted when it holds a comma, a quote, a line break
// or blanks (spaces, tabs) at either end; a quote inside quotes is
// doubled. Numbers are written by FormatDouble (sim/base/numbers.h) at the
// writer's significant digits.
//
// Reading: unquoted fields lose their leading and trailing blanks (and
// any carriage return, so CRLF files read alike); a field that starts
// with a quote is quoted, may hold commas and line breaks, and ends at the
// next lone quote; blank lines are skipped. A number field must be a
// number as a whole (ParseDouble). A UTF-8 byte order mark at the start
// of the text is dropped. Every error is an InputError
// (sim/base/error.h) naming the source and line, and the column where there
// is one:
//   SOURCE:LINE: unterminated quoted cell
//   SOURCE:LINE: expected N cells, got M            (rows against the header)
//   SOURCE: no column 'NAME' (columns: a, b, ...)
//   SOURCE:LINE: column NAME: 'TEXT' is not a number
//   SOURCE:LINE: column NAME: value is not finite (TEXT)
#pragma once

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include "sim/base/numbers.h"

namespace ipmc {

// One record and the line it starts on (1-based).
struct CsvRecord {
  std::vector<std::string> fields;
  int line = 0;
};

// The records of CSV text, blank lines left out.
std::vector<CsvRecord> ParseCsvRecords(const std::string& text, const std::string& source);

// A CSV document with a header row; columns are found by name.
class CsvTable {
 public:
  // Throws InputError if the text has no header or a row has a different
  // number of cells than the header.
  static CsvTable Parse(const std::string& text, const std::string& source);
  // The same for a file; throws InputError if it cannot be read.
  static CsvTable Read(const std::string& path);

  const std::string& source() const { return source_; }
  const std::vector<std::string>& columns() const { return columns_; }
  std::size_t Rows() const { return rows_.size(); }
  const std::vector<std::string>& Row(std::size_t row) const { return rows_[row]; }
  int Line(std::size_t row) const { return lines_[row]; }
  bool Has(const std::string& column) const;

  // The index of `column`; throws InputError naming the columns there are.
  std::size_t Column(const std::string& column) const;
  const std::string& Text(std::size_t row, std::size_t column) const {
    return rows_[row][column];
  }
  // The field as a number (inf and nan included).
  double Number(std::size_t row, std::size_t column) const;
  std::vector<double> Numbers(const std::string& column) const;
  // Every value of the column, each required finite.
  std::vector<double> FiniteNumbers(const std::string& column) const;

 private:
  std::string source_;
  std::vector<std::string> columns_;
  std::vector<std::vector<std::string>> rows_;
  std::vector<int> lines_;
};

// `text` as one CSV field, quoted if it must be.
std::string CsvField(const std::string& text);

// A table held by columns: each column's name and its numbers, in the
// order of the file. The one description of a time series that its CSV
// (NamedColumnsCsv) and the Python module's arrays are both made from.
using NamedColumns = std::vector<std::pair<std::string, std::vector<double>>>;

// `columns` as CSV text: their names, then one row per sample (every
// column holds as many numbers as the first), numbers at
// `significant_digits`.
std::string NamedColumnsCsv(const NamedColumns& columns, int significant_digits);

// Builds CSV text a row at a time:
//   CsvWriter csv(10);
//   csv.Row({"time_s", "x_mm"});
//   csv.Add(t).Add(x).EndRow();
class CsvWriter {
 public:
  // Numbers are written with `significant_digits`; by default (or with
  // kRoundTripDigits) in the shortest text that reads back exactly.
  explicit CsvWriter(int significant_digits = kRoundTripDigits) : digits_(significant_digits) {}

  CsvWriter& Add(const std::string& field);
  CsvWriter& Add(const char* field) { return Add(std::string(field)); }
  CsvWriter& Add(double value);
  CsvWriter& AddInteger(long long value);
  void EndRow();
  // A whole row of text fields.
  void Row(const std::vector<std::string>& fields);

  const std::string& Text() const { return text_; }

 private:
  int digits_;
  std::string text_;
  bool row_started_ = false;
};

}  // namespace ipmc
