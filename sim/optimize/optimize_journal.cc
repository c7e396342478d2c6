#include "sim/optimize/optimize_journal.h"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>

#include "sim/io/files.h"

namespace ipmc {
namespace {

constexpr char kFormat[] = "ipmc_swim_optimize_journal";

std::string Hex(double value) {
  char text[64];
  std::snprintf(text, sizeof(text), "%a", value);
  return text;
}

[[noreturn]] void Fail(const std::string& path, const std::string& message) {
  throw std::runtime_error(path + ": " + message);
}

nlohmann::json JournalHeader(const std::string& fingerprint,
                             const std::vector<std::string>& columns) {
  return {{kFormat, 1}, {"fingerprint", fingerprint}, {"columns", columns}};
}

// The records of a journal's text (the header checked; a torn last line
// dropped).
JournalRecords ParseJournal(const std::string& path, const std::string& text,
                            const std::string& fingerprint,
                            const std::vector<std::string>& columns) {
  const nlohmann::json header = JournalHeader(fingerprint, columns);
  JournalRecords records;
  std::istringstream lines(text);
  std::string line;
  int number = 0;
  size_t consumed = 0;
  while (std::getline(lines, line)) {
    ++number;
    consumed += line.size() + 1;
    if (consumed > text.size()) break;  // a torn last line
    const nlohmann::json record = nlohmann::json::parse(line, nullptr, false);
    if (number == 1) {
      if (!record.is_object() || !record.contains(kFormat)) Fail(path, "not an optimisation journal");
      if (record.value("fingerprint", "") != fingerprint ||
          record.value("columns", nlohmann::json()) != header["columns"]) {
        Fail(path, "records another optimisation (its base scenario, [set] or design keys "
                   "differ); use another --out");
      }
      continue;
    }
    if (!record.is_object() || !record.contains("x") || !record.contains("cells")) {
      Fail(path + ":" + std::to_string(number), "not a journal record");
    }
    std::string key;
    for (const auto& value : record["x"]) key += (key.empty() ? "" : ",") + value.get<std::string>();
    records[key] = record["cells"].get<std::vector<std::string>>();
  }
  return records;
}

}  // namespace

std::string HexKey(const std::vector<double>& x) {
  std::string key;
  for (double value : x) key += (key.empty() ? "" : ",") + Hex(value);
  return key;
}

OptimizeJournal::OptimizeJournal(const std::string& path, const std::string& fingerprint,
                                 const std::vector<std::string>& columns)
    : file_(path, "in use by another optimisation") {
  const std::string text = file_.Read();
  if (text.find('\n') == std::string::npos) {
    // New, or created by a run killed before its header was whole.
    file_.Reset(JournalHeader(fingerprint, columns).dump() + "\n");
    return;
  }
  records_ = ParseJournal(path, text, fingerprint, columns);
  // A torn last record (a kill in the middle of a write) is dropped, so
  // that the next record starts a line of its own.
  const size_t complete_size = text.rfind('\n') + 1;
  if (complete_size < text.size()) file_.Truncate(complete_size);
}

std::optional<std::vector<std::string>> OptimizeJournal::Find(const std::vector<double>& x) const {
  std::lock_guard<std::mutex> lock(mutex_);
  const auto it = records_.find(HexKey(x));
  if (it == records_.end()) return std::nullopt;
  return it->second;
}

void OptimizeJournal::Record(const std::vector<double>& x, const std::vector<std::string>& cells) {
  nlohmann::json hex = nlohmann::json::array();
  for (double value : x) hex.push_back(Hex(value));
  const std::string line = nlohmann::json({{"x", hex}, {"cells", cells}}).dump() + "\n";
  std::lock_guard<std::mutex> lock(mutex_);
  file_.Append(line);
  records_[HexKey(x)] = cells;
}

JournalRecords ReadOptimizeJournal(const std::string& path, const std::string& fingerprint,
                                   const std::vector<std::string>& columns) {
  std::error_code error;
  if (!std::filesystem::exists(path, error)) return {};
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  if (!in.good() && !in.eof()) Fail(path, "cannot read the journal");
  return ParseJournal(path, text.str(), fingerprint, columns);
}

size_t OptimizeJournal::size() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return records_.size();
}

}  // namespace ipmc
