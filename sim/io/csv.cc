#include "sim/io/csv.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <utility>

#include "sim/base/error.h"
#include "sim/io/files.h"

namespace ipmc {
namespace {

bool IsBlank(char c) { return c == ' ' || c == '\t'; }

// Reads records character by character; see the header for the rules.
class CsvReader {
 public:
  CsvReader(const std::string& text, const std::string& source) : text_(text), source_(source) {}

  std::vector<CsvRecord> Read() {
    for (std::size_t i = 0; i < text_.size(); ++i) {
      const char c = text_[i];
      if (quoted_) {
        ReadQuoted(c, &i);
      } else if (c == ',') {
        EndField();
      } else if (c == '\n') {
        EndRecord();
        record_line_ = ++line_;
      } else if (c == '"' && !was_quoted_ && field_.empty()) {
        quoted_ = was_quoted_ = true;
      } else if (c != '\r' && !(IsBlank(c) && field_.empty() && !was_quoted_)) {
        field_ += c;
      }
    }
    if (quoted_) {
      throw InputError(InputProblem::kSyntax, {source_, static_cast<std::uint32_t>(record_line_)},
                       "", "unterminated quoted cell");
    }
    EndRecord();
    return std::move(records_);
  }

 private:
  void ReadQuoted(char c, std::size_t* i) {
    if (c != '"') {
      if (c == '\n') ++line_;
      field_ += c;
    } else if (*i + 1 < text_.size() && text_[*i + 1] == '"') {
      field_ += '"';
      ++*i;
    } else {
      quoted_ = false;
      protected_size_ = field_.size();
    }
  }

  void EndField() {
    std::size_t end = field_.size();
    while (end > protected_size_ && IsBlank(field_[end - 1])) --end;
    field_.resize(end);
    record_.fields.push_back(std::move(field_));
    blank_ = blank_ && !was_quoted_ && record_.fields.back().empty();
    field_.clear();
    was_quoted_ = false;
    protected_size_ = 0;
  }

  void EndRecord() {
    EndField();
    if (!(blank_ && record_.fields.size() == 1)) {
      record_.line = record_line_;
      records_.push_back(std::move(record_));
    }
    record_ = CsvRecord();
    blank_ = true;
  }

  const std::string& text_;
  const std::string& source_;
  std::vector<CsvRecord> records_;
  CsvRecord record_;
  std::string field_;
  bool quoted_ = false;      // inside quotes
  bool was_quoted_ = false;  // this field started with a quote
  std::size_t protected_size_ = 0;  // the quoted part, kept as it is
  bool blank_ = true;        // the record so far is one empty unquoted field
  int line_ = 1;
  int record_line_ = 1;
};

}  // namespace

std::vector<CsvRecord> ParseCsvRecords(const std::string& text, const std::string& source) {
  // A spreadsheet's UTF-8 byte order mark is no part of the first column's name.
  constexpr char kUtf8Bom[] = "\xEF\xBB\xBF";
  if (text.rfind(kUtf8Bom, 0) == 0) return CsvReader(text.substr(3), source).Read();
  return CsvReader(text, source).Read();
}

CsvTable CsvTable::Parse(const std::string& text, const std::string& source) {
  std::vector<CsvRecord> records = ParseCsvRecords(text, source);
  if (records.empty()) {
    throw InputError(InputProblem::kSyntax, {source}, "", "empty file (no header row)");
  }
  CsvTable table;
  table.source_ = source;
  table.columns_ = std::move(records.front().fields);
  for (std::size_t r = 1; r < records.size(); ++r) {
    if (records[r].fields.size() != table.columns_.size()) {
      throw InputError(InputProblem::kSyntax,
                       {source, static_cast<std::uint32_t>(records[r].line)}, "",
                       "expected " + std::to_string(table.columns_.size()) + " cells, got " +
                           std::to_string(records[r].fields.size()));
    }
    table.rows_.push_back(std::move(records[r].fields));
    table.lines_.push_back(records[r].line);
  }
  return table;
}

CsvTable CsvTable::Read(const std::string& path) {
  return Parse(ReadTextFile(path, "CSV file"), path);
}

bool CsvTable::Has(const std::string& column) const {
  return std::find(columns_.begin(), columns_.end(), column) != columns_.end();
}

std::size_t CsvTable::Column(const std::string& column) const {
  const auto it = std::find(columns_.begin(), columns_.end(), column);
  if (it == columns_.end()) {
    std::string names;
    for (const std::string& name : columns_) names += (names.empty() ? "" : ", ") + name;
    throw InputError(InputProblem::kMissing, {source_}, column,
                     "no column '" + column + "' (columns: " + names + ")");
  }
  return static_cast<std::size_t>(it - columns_.begin());
}

double CsvTable::Number(std::size_t row, std::size_t column) const {
  const std::string& text = rows_[row][column];
  const std::optional<double> value = ParseDouble(text);
  if (!value) {
    throw InputError(InputProblem::kBadValue, {source_, static_cast<std::uint32_t>(lines_[row])},
                     columns_[column],
                     "column " + columns_[column] + ": '" + text + "' is not a number", "a number");
  }
  return *value;
}

std::vector<double> CsvTable::Numbers(const std::string& column) const {
  const std::size_t index = Column(column);
  std::vector<double> values(rows_.size());
  for (std::size_t r = 0; r < rows_.size(); ++r) values[r] = Number(r, index);
  return values;
}

std::vector<double> CsvTable::FiniteNumbers(const std::string& column) const {
  const std::size_t index = Column(column);
  std::vector<double> values(rows_.size());
  for (std::size_t r = 0; r < rows_.size(); ++r) {
    values[r] = Number(r, index);
    if (!std::isfinite(values[r])) {
      throw InputError(InputProblem::kBadValue,
                       {source_, static_cast<std::uint32_t>(lines_[r])}, column,
                       "column " + column + ": value is not finite (" + rows_[r][index] + ")",
                       "a finite number");
    }
  }
  return values;
}

std::string NamedColumnsCsv(const NamedColumns& columns, int significant_digits) {
  CsvWriter csv(significant_digits);
  for (const auto& column : columns) csv.Add(column.first);
  csv.EndRow();
  const size_t rows = columns.empty() ? 0 : columns.front().second.size();
  for (size_t i = 0; i < rows; ++i) {
    for (const auto& column : columns) csv.Add(column.second[i]);
    csv.EndRow();
  }
  return csv.Text();
}

std::string CsvField(const std::string& text) {
  const bool blank_end = !text.empty() && (IsBlank(text.front()) || IsBlank(text.back()));
  if (!blank_end && text.find_first_of(",\"\n\r") == std::string::npos) return text;
  std::string quoted = "\"";
  for (char c : text) {
    if (c == '"') quoted += '"';
    quoted += c;
  }
  return quoted + "\"";
}

CsvWriter& CsvWriter::Add(const std::string& field) {
  if (row_started_) text_ += ',';
  text_ += CsvField(field);
  row_started_ = true;
  return *this;
}

CsvWriter& CsvWriter::Add(double value) {
  return Add(digits_ >= kRoundTripDigits ? FormatShortest(value) : FormatDouble(value, digits_));
}

CsvWriter& CsvWriter::AddInteger(long long value) { return Add(std::to_string(value)); }

void CsvWriter::EndRow() {
  text_ += '\n';
  row_started_ = false;
}

void CsvWriter::Row(const std::vector<std::string>& fields) {
  for (const std::string& field : fields) Add(field);
  EndRow();
}

}  // namespace ipmc
