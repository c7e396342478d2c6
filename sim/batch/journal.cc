#include "sim/batch/journal.h"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "sim/core/data_paths.h"
#include "sim/core/sha256.h"
#include "sim/io/files.h"

namespace ipmc {
namespace {

namespace fs = std::filesystem;

constexpr char kFormatKey[] = "ipmc_swim_sweep_journal";
// Format 2 added the program version to the header and a checksum to
// every record.
constexpr int kFormatVersion = 2;
constexpr char kProgramVersionKey[] = "program_version";
constexpr char kSweepKey[] = "sweep";
constexpr char kFingerprintKey[] = "fingerprint";
constexpr char kPointsKey[] = "points";
constexpr char kColumnsKey[] = "columns";
constexpr char kPointKey[] = "point";
constexpr char kRowKey[] = "row";
constexpr char kCheckKey[] = "check";

// FNV-1a, 64 bit (offset basis and prime from Fowler, Noll and Vo).
class Fnv1a {
 public:
  // Each field with its length first, so that fields cannot run together.
  void Add(const std::string& field) {
    const std::uint64_t size = field.size();
    for (int shift = 0; shift < 64; shift += 8) Byte(static_cast<unsigned char>(size >> shift));
    for (char c : field) Byte(static_cast<unsigned char>(c));
  }
  std::string Hex() const {
    char text[17];
    std::snprintf(text, sizeof(text), "%016llx", static_cast<unsigned long long>(hash_));
    return text;
  }

 private:
  void Byte(unsigned char byte) {
    hash_ ^= byte;
    hash_ *= 0x100000001b3ULL;
  }
  std::uint64_t hash_ = 0xcbf29ce484222325ULL;
};

// The bytes of an input file, "" if there is none (a FIFO or a device is
// refused: it could block or never end).
std::string FileText(const std::string& path) {
  RequireRegularInput(path, "model file");
  std::ifstream file(path, std::ios::binary);
  std::ostringstream text;
  text << file.rdbuf();
  return text.str();
}

std::string HeaderLine(const SweepJournalHeader& header) {
  nlohmann::ordered_json json = {{kFormatKey, kFormatVersion},
                                 {kProgramVersionKey, header.program_version},
                                 {kSweepKey, header.sweep},
                                 {kFingerprintKey, header.fingerprint},
                                 {kPointsKey, header.points},
                                 {kColumnsKey, header.columns}};
  return json.dump() + "\n";
}

SweepJournalHeader HeaderOf(const SweepPlan& plan) {
  SweepJournalHeader header;
  header.program_version = ProgramVersion();
  header.sweep = plan.source;
  header.fingerprint = SweepFingerprint(plan);
  header.points = static_cast<int>(plan.points.size());
  header.columns = SweepColumns(plan);
  return header;
}

template <typename T>
bool ReadField(const nlohmann::json& json, const char* key, T* value) {
  const auto it = json.find(key);
  if (it == json.end()) return false;
  try {
    *value = it->get<T>();
    return true;
  } catch (const nlohmann::json::exception&) {
    return false;
  }
}

// Parses a journal's text; `complete_size` receives the length of its
// whole lines (a torn last line is left out).
SweepJournalContents ParseJournal(const std::string& text, const std::string& path,
                                  size_t* complete_size) {
  const size_t end = text.rfind('\n');
  *complete_size = end == std::string::npos ? 0 : end + 1;
  SweepJournalContents contents;
  std::istringstream lines(text.substr(0, *complete_size));
  std::string line;
  int number = 0;
  while (std::getline(lines, line)) {
    ++number;
    const std::string where = path + ":" + std::to_string(number);
    const nlohmann::json json = nlohmann::json::parse(line, nullptr, false);
    if (number == 1) {
      SweepJournalHeader& header = contents.header;
      int version = 0;
      if (!json.is_discarded() && ReadField(json, kFormatKey, &version) &&
          version != kFormatVersion) {
        throw std::runtime_error(where + ": a sweep journal of format " + std::to_string(version) +
                                 ", this program reads format " + std::to_string(kFormatVersion) +
                                 "; remove it to start over, or choose another output");
      }
      if (json.is_discarded() || !ReadField(json, kFormatKey, &version) ||
          !ReadField(json, kProgramVersionKey, &header.program_version) ||
          !ReadField(json, kSweepKey, &header.sweep) ||
          !ReadField(json, kFingerprintKey, &header.fingerprint) ||
          !ReadField(json, kPointsKey, &header.points) ||
          !ReadField(json, kColumnsKey, &header.columns) || header.points < 0) {
        throw std::runtime_error(where + ": not a sweep journal (no header)");
      }
      continue;
    }
    int point = -1;
    std::vector<std::string> row;
    std::string check;
    if (json.is_discarded() || !ReadField(json, kPointKey, &point) ||
        !ReadField(json, kRowKey, &row) || !ReadField(json, kCheckKey, &check) || point < 0 ||
        point >= contents.header.points ||
        row.size() != contents.header.columns.size() || row[0] != std::to_string(point)) {
      throw std::runtime_error(where + ": not a record of this journal's sweep (" +
                               std::to_string(contents.header.points) + " points, " +
                               std::to_string(contents.header.columns.size()) + " columns)");
    }
    if (check != SweepRowCheck(contents.header.fingerprint, point, row)) {
      throw std::runtime_error(where + ": the record of point " + std::to_string(point) +
                               " fails its checksum (edited, or not written by this sweep); "
                               "delete that line to run the point again, or remove the journal");
    }
    const auto [recorded, inserted] = contents.rows.emplace(point, row);
    if (!inserted && recorded->second != row) {
      throw std::runtime_error(where + ": a second, different record of point " +
                               std::to_string(point) +
                               "; delete the wrong line to go on, or remove the journal");
    }
  }
  if (number == 0) throw std::runtime_error(path + ": empty journal (no header)");
  return contents;
}

}  // namespace

std::string SweepRowCheck(const std::string& fingerprint, int point,
                          const std::vector<std::string>& row) {
  std::vector<std::string> fields = {fingerprint, std::to_string(point)};
  fields.insert(fields.end(), row.begin(), row.end());
  return Sha256OfFields(fields);
}

std::string SweepFingerprint(const SweepPlan& plan) {
  Fnv1a hash;
  for (const std::string& column : SweepColumns(plan)) hash.Add(column);
  std::map<std::string, std::string> models;  // path -> contents
  for (const SweepPoint& point : plan.points) {
    hash.Add(std::to_string(point.index));
    for (const std::string& value : point.values) hash.Add(value);
    hash.Add(point.scenario_toml);
    hash.Add(point.error);
    if (point.gait) {  // a gait's model and trajectory ("" for a file that is not there)
      for (const std::string* file : {&point.gait->model, &point.gait->csv}) {
        if (file->empty()) continue;
        if (models.count(*file) == 0) models.emplace(*file, FileText(*file));
        hash.Add(models.at(*file));
      }
    }
    if (point.scenario && !point.scenario->model.Generated()) {
      const std::string& model = point.scenario->model.path;
      if (models.count(model) == 0) models.emplace(model, FileText(model));
      hash.Add(models.at(model));
    }
  }
  return hash.Hex();
}

SweepJournalContents ReadSweepJournal(const std::string& path) {
  const std::optional<std::string> text = ReadJournalText(path, "journal");
  if (!text) throw std::runtime_error(path + ": cannot open the journal (no such file)");
  size_t complete_size = 0;
  return ParseJournal(*text, path, &complete_size);
}

std::string JournalPathOf(const std::string& table_csv_path) {
  fs::path path(table_csv_path);
  if (path.extension() == ".csv") path.replace_extension();
  return path.string() + ".journal";
}

SweepJournal::SweepJournal(const std::string& path, const SweepPlan& plan,
                           bool accept_other_version)
    : file_(path, "in use by another running sweep (one sweep per output prefix at a time)") {
  const SweepJournalHeader expected = HeaderOf(plan);
  fingerprint_ = expected.fingerprint;
  const std::string text = file_.Read();
  if (text.find('\n') == std::string::npos) {
    // New, or created by a sweep killed before its header was whole:
    // no record can follow a torn header.
    file_.Reset(HeaderLine(expected));
    return;
  }
  size_t complete_size = 0;
  SweepJournalContents contents = ParseJournal(text, path, &complete_size);
  const SweepJournalHeader& found = contents.header;
  if (found.fingerprint != expected.fingerprint) {
    throw std::runtime_error(
        path + ": records another sweep (" + found.sweep + ", " + std::to_string(found.points) +
        " points, fingerprint " + found.fingerprint + "; this one: " + expected.sweep + ", " +
        std::to_string(expected.points) + " points, fingerprint " + expected.fingerprint +
        "); remove it to start over, or choose another output");
  }
  if (found.program_version != expected.program_version && !accept_other_version) {
    throw std::runtime_error(path + ": written by ipmc-swim " + found.program_version +
                             ", this is " + expected.program_version +
                             "; its points may differ from this version's: remove it to start "
                             "over, or resume it anyway with --resume-other-version "
                             "(Python: resume_other_version=True)");
  }
  if (complete_size < text.size()) file_.Truncate(complete_size);
  rows_ = std::move(contents.rows);
}

void SweepJournal::Remove() {
  file_.Remove();
  rows_.clear();
}

void SweepJournal::Record(const std::vector<std::string>& row) {
  const int point = std::stoi(row.at(0));
  const nlohmann::ordered_json json = {
      {kPointKey, point}, {kRowKey, row}, {kCheckKey, SweepRowCheck(fingerprint_, point, row)}};
  file_.Append(json.dump() + "\n");
  rows_.emplace(point, row);
}

ShardRecord CountRecorded(const SweepPlan& plan, const SweepShard& shard,
                          const SweepJournal& journal) {
  ShardRecord record;
  for (const SweepPoint& point : plan.points) {
    if (point.index % shard.count != shard.index - 1) continue;
    ++record.points;
    record.recorded += static_cast<int>(journal.rows().count(point.index));
  }
  return record;
}

JournaledSweep RunJournaledSweep(const SweepPlan& plan, SweepOptions options,
                                 SweepJournal* journal) {
  const std::map<int, std::vector<std::string>> finished = journal->rows();
  JournaledSweep result;
  const ShardRecord record = CountRecorded(plan, options.shard, *journal);
  result.shard_points = record.points;
  result.resumed = record.recorded;
  options.finished = &finished;
  const std::function<void(const SweepProgress&)> report = options.on_point_done;
  options.on_point_done = [&](const SweepProgress& progress) {
    journal->Record(*progress.row);
    if (report) report(progress);
  };
  result.table = RunSweep(plan, options);
  result.table.fingerprint = journal->fingerprint();  // its rows are checked when merged
  return result;
}

}  // namespace ipmc
