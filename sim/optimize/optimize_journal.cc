#include "sim/optimize/optimize_journal.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
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

void WriteAll(int fd, const std::string& path, const std::string& line) {
  size_t written = 0;
  while (written < line.size()) {
    const ssize_t n = ::write(fd, line.data() + written, line.size() - written);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) Fail(path, std::string("cannot write the journal (") + std::strerror(errno) + ")");
    written += static_cast<size_t>(n);
  }
  if (::fdatasync(fd) != 0) Fail(path, std::string("cannot sync the journal (") + std::strerror(errno) + ")");
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
    : path_(path) {
  EnsureParentDirectory(path);
  fd_ = ::open(path.c_str(), O_RDWR | O_CREAT | O_APPEND | O_CLOEXEC | O_NOFOLLOW, 0644);
  if (fd_ < 0) Fail(path, std::string("cannot open the journal (") + std::strerror(errno) + ")");
  if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
    ::close(fd_);
    fd_ = -1;
    Fail(path, "in use by another optimisation");
  }
  std::string text;
  char buffer[65536];
  for (ssize_t n; (n = ::pread(fd_, buffer, sizeof(buffer), static_cast<off_t>(text.size()))) > 0;) {
    text.append(buffer, static_cast<size_t>(n));
  }
  try {
    if (text.empty()) {
      WriteAll(fd_, path, JournalHeader(fingerprint, columns).dump() + "\n");
      return;
    }
    records_ = ParseJournal(path, text, fingerprint, columns);
  } catch (...) {
    ::close(fd_);
    fd_ = -1;
    throw;
  }
}

OptimizeJournal::~OptimizeJournal() {
  if (fd_ >= 0) ::close(fd_);
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
  WriteAll(fd_, path_, line);
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
