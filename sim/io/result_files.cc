#include "sim/io/result_files.h"

#include <hdf5.h>
#include <matio.h>
#include <unistd.h>

#include <cctype>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <utility>
#include <vector>

namespace ipmc {
namespace {

using Json = nlohmann::ordered_json;

constexpr size_t kMatlabNameLength = 63;  // namelengthmax
constexpr char kMatHeader[] = "MATLAB 5.0 MAT-file, written by ipmc-swim";

bool EndsWith(const std::string& text, const std::string& end) {
  return text.size() >= end.size() && text.compare(text.size() - end.size(), end.size(), end) == 0;
}

bool IsNumberArray(const Json& value) {
  if (!value.is_array()) return false;
  for (const Json& item : value) {
    if (!item.is_number()) return false;
  }
  return true;
}

bool IsStringArray(const Json& value) {
  if (!value.is_array() || value.empty()) return false;
  for (const Json& item : value) {
    if (!item.is_string()) return false;
  }
  return true;
}

// A non-empty array of objects with the same keys in the same order.
bool IsTable(const Json& value) {
  if (!value.is_array() || value.empty() || !value.front().is_object()) return false;
  std::vector<std::string> keys;
  for (const auto& [key, item] : value.front().items()) keys.push_back(key);
  for (const Json& row : value) {
    if (!row.is_object() || row.size() != keys.size()) return false;
    size_t k = 0;
    for (const auto& [key, item] : row.items()) {
      if (key != keys[k++]) return false;
    }
  }
  return true;
}

// A table as one object of columns: {"a": [a0, a1, ...], "b": [...]}. A
// cell left empty (null) is NaN in a column of numbers, [] of NaN in a
// column of number lists, "" in a column of texts; a column of flags is
// one of numbers, 1 and 0.
Json TableColumns(const Json& table) {
  Json columns = Json::object();
  for (const auto& [key, item] : table.front().items()) {
    Json column = Json::array();
    for (const Json& row : table) column.push_back(row.at(key));
    size_t width = 0;
    bool numbers = true, lists = true, texts = true, flags = true;
    for (const Json& cell : column) flags = flags && (cell.is_null() || cell.is_boolean());
    if (flags) {  // a column of flags: 1 and 0 (NaN where empty)
      for (Json& cell : column) {
        if (cell.is_boolean()) cell = cell.get<bool>() ? 1.0 : 0.0;
      }
    }
    for (const Json& cell : column) {
      if (cell.is_null()) continue;
      numbers = numbers && cell.is_number();
      texts = texts && cell.is_string();
      const bool list = IsNumberArray(cell) && !cell.empty() && (width == 0 || cell.size() == width);
      if (list) width = cell.size();
      lists = lists && list;
    }
    for (Json& cell : column) {
      if (!cell.is_null()) continue;
      if (numbers) {
        cell = std::numeric_limits<double>::quiet_NaN();
      } else if (texts) {
        cell = "";
      } else if (lists && width > 0) {
        cell = Json(std::vector<double>(width, std::numeric_limits<double>::quiet_NaN()));
      }
    }
    columns[key] = std::move(column);
  }
  return columns;
}

// A non-empty array of number arrays of one length: a matrix, a row each.
bool IsNumberMatrix(const Json& value) {
  if (!value.is_array() || value.empty() || !IsNumberArray(value.front()) ||
      value.front().empty()) {
    return false;
  }
  for (const Json& row : value) {
    if (!IsNumberArray(row) || row.size() != value.front().size()) return false;
  }
  return true;
}

std::invalid_argument NoPlaceFor(const std::string& path) {
  return std::invalid_argument(path +
                               ": a value that a MAT or HDF5 file has no place for (nested "
                               "arrays, mixed arrays, or a table whose rows differ)");
}

std::vector<double> Numbers(const Json& array) {
  std::vector<double> numbers;
  numbers.reserve(array.size());
  for (const Json& item : array) numbers.push_back(item.get<double>());
  return numbers;
}

// ---- MAT-file (libmatio) ----

struct MatVarDeleter {
  void operator()(matvar_t* var) const { Mat_VarFree(var); }
};
using MatVar = std::unique_ptr<matvar_t, MatVarDeleter>;

MatVar MatDoubles(const std::string& name, const std::vector<double>& values, size_t rows,
                  size_t cols) {
  size_t dims[2] = {rows, cols};
  return MatVar(Mat_VarCreate(name.c_str(), MAT_C_DOUBLE, MAT_T_DOUBLE, 2, dims,
                              const_cast<double*>(values.data()), 0));
}

MatVar MatText(const std::string& name, const std::string& text) {
  size_t dims[2] = {1, text.size()};
  return MatVar(Mat_VarCreate(name.c_str(), MAT_C_CHAR, MAT_T_UTF8, 2, dims,
                              const_cast<char*>(text.data()), 0));
}

MatVar MatValue(const std::string& name, const Json& value, const std::string& path);

MatVar MatStruct(const std::string& name, const Json& object, const std::string& path) {
  std::vector<std::string> names;
  for (const auto& [key, item] : object.items()) names.push_back(MatlabName(key));
  std::vector<const char*> fields;
  for (const std::string& field : names) fields.push_back(field.c_str());
  fields.push_back(nullptr);  // the list's end
  const size_t dims[2] = {1, 1};
  MatVar result(Mat_VarCreateStruct2(name.c_str(), 2, dims, fields.data()));
  if (!result) throw std::runtime_error(path + ": libmatio cannot create a struct");
  size_t k = 0;
  for (const auto& [key, item] : object.items()) {
    MatVar field = MatValue(names[k], item, path + "." + key);
    if (!field) throw std::runtime_error(path + "." + key + ": libmatio cannot create it");
    Mat_VarSetStructFieldByName(result.get(), names[k].c_str(), 0, field.release());
    ++k;
  }
  return result;
}

MatVar MatValue(const std::string& name, const Json& value, const std::string& path) {
  if (value.is_object()) return MatStruct(name, value, path);
  if (value.is_null()) return MatDoubles(name, {}, 0, 0);
  if (value.is_boolean()) {
    unsigned char flag = value.get<bool>() ? 1 : 0;
    size_t dims[2] = {1, 1};
    return MatVar(
        Mat_VarCreate(name.c_str(), MAT_C_UINT8, MAT_T_UINT8, 2, dims, &flag, MAT_F_LOGICAL));
  }
  if (value.is_number()) return MatDoubles(name, {value.get<double>()}, 1, 1);
  if (value.is_string()) return MatText(name, value.get<std::string>());
  if (IsNumberArray(value)) return MatDoubles(name, Numbers(value), value.size(), 1);
  if (IsTable(value)) return MatStruct(name, TableColumns(value), path);
  if (IsNumberMatrix(value)) {
    const size_t rows = value.size(), cols = value.front().size();
    std::vector<double> column_major(rows * cols);
    for (size_t i = 0; i < rows; ++i) {
      for (size_t j = 0; j < cols; ++j) column_major[j * rows + i] = value[i][j].get<double>();
    }
    return MatDoubles(name, column_major, rows, cols);
  }
  if (IsStringArray(value)) {
    // The cell array takes a copy of the pointers and owns the cells.
    std::vector<matvar_t*> cells;
    for (const Json& item : value) cells.push_back(MatText("", item.get<std::string>()).release());
    size_t dims[2] = {value.size(), 1};
    MatVar array(Mat_VarCreate(name.c_str(), MAT_C_CELL, MAT_T_CELL, 2, dims, cells.data(), 0));
    if (!array) {
      for (matvar_t* cell : cells) Mat_VarFree(cell);
    }
    return array;
  }
  throw NoPlaceFor(path);
}

// A private temporary file, removed when this goes.
class ScratchFile {
 public:
  ScratchFile() {
    const char* dir = std::getenv("TMPDIR");
    path_ = std::string(dir && *dir ? dir : "/tmp") + "/ipmc_swim_result_XXXXXX";
    const int fd = mkstemp(path_.data());
    if (fd < 0) throw std::runtime_error(path_ + ": cannot create a temporary file");
    close(fd);
  }
  ~ScratchFile() { std::remove(path_.c_str()); }
  ScratchFile(const ScratchFile&) = delete;
  ScratchFile& operator=(const ScratchFile&) = delete;
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

std::string ReadBytes(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  std::ostringstream bytes;
  bytes << file.rdbuf();
  return bytes.str();
}

// ---- HDF5 ----

// Closes an HDF5 identifier with its own close function.
class Hid {
 public:
  Hid(hid_t id, herr_t (*close)(hid_t), const std::string& what) : id_(id), close_(close) {
    if (id_ < 0) throw std::runtime_error("HDF5: cannot create " + what);
  }
  ~Hid() {
    if (id_ >= 0) close_(id_);
  }
  Hid(Hid&& other) noexcept : id_(other.id_), close_(other.close_) { other.id_ = -1; }
  Hid(const Hid&) = delete;
  Hid& operator=(const Hid&) = delete;
  hid_t get() const { return id_; }

 private:
  hid_t id_;
  herr_t (*close_)(hid_t);
};

void Check(herr_t status, const std::string& what) {
  if (status < 0) throw std::runtime_error("HDF5: cannot write " + what);
}

// A creation property list (H5P_DATASET_CREATE or H5P_GROUP_CREATE) that
// records no modification times, so that the same results give the same
// bytes.
Hid Untimed(hid_t property_class) {
  Hid list(H5Pcreate(property_class), H5Pclose, "a creation property list");
  Check(H5Pset_obj_track_times(list.get(), 0), "the creation property list");
  return list;
}

// A variable-length UTF-8 string, which h5py reads as str.
void WriteTextAttribute(hid_t object, const char* name, const std::string& text) {
  const Hid type(H5Tcopy(H5T_C_S1), H5Tclose, "a string type");
  Check(H5Tset_size(type.get(), H5T_VARIABLE), name);
  Check(H5Tset_cset(type.get(), H5T_CSET_UTF8), name);
  const Hid space(H5Screate(H5S_SCALAR), H5Sclose, "a dataspace");
  const Hid attribute(H5Acreate2(object, name, type.get(), space.get(), H5P_DEFAULT, H5P_DEFAULT),
                      H5Aclose, std::string("the attribute ") + name);
  const char* pointer = text.c_str();
  Check(H5Awrite(attribute.get(), type.get(), &pointer), name);
}

void LabelUnits(hid_t dataset, const std::string& name) {
  const std::string unit = UnitOfName(name);
  if (!unit.empty()) WriteTextAttribute(dataset, "units", unit);
}

// `values` as a scalar, a vector, or (columns > 0) a matrix of
// values.size() / columns rows in row-major order.
void WriteDoubles(hid_t group, const std::string& name, const std::vector<double>& values,
                  bool scalar, const std::string& path, size_t columns = 0) {
  const hsize_t size[2] = {columns > 0 ? values.size() / columns : values.size(), columns};
  const Hid space(scalar ? H5Screate(H5S_SCALAR)
                         : H5Screate_simple(columns > 0 ? 2 : 1, size, nullptr),
                  H5Sclose, "the dataspace of " + path);
  const Hid dataset(H5Dcreate2(group, name.c_str(), H5T_IEEE_F64LE, space.get(), H5P_DEFAULT,
                               Untimed(H5P_DATASET_CREATE).get(), H5P_DEFAULT),
                    H5Dclose, path);
  if (!values.empty()) {
    Check(H5Dwrite(dataset.get(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()),
          path);
  }
  LabelUnits(dataset.get(), name);
}

void WriteStrings(hid_t group, const std::string& name, const std::vector<std::string>& texts,
                  bool scalar, const std::string& path) {
  const Hid type(H5Tcopy(H5T_C_S1), H5Tclose, "a string type");
  Check(H5Tset_size(type.get(), H5T_VARIABLE), path);
  Check(H5Tset_cset(type.get(), H5T_CSET_UTF8), path);
  const hsize_t size = texts.size();
  const Hid space(scalar ? H5Screate(H5S_SCALAR) : H5Screate_simple(1, &size, nullptr), H5Sclose,
                  "the dataspace of " + path);
  const Hid dataset(H5Dcreate2(group, name.c_str(), type.get(), space.get(), H5P_DEFAULT,
                               Untimed(H5P_DATASET_CREATE).get(), H5P_DEFAULT),
                    H5Dclose, path);
  std::vector<const char*> pointers;
  for (const std::string& text : texts) pointers.push_back(text.c_str());
  Check(H5Dwrite(dataset.get(), type.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, pointers.data()), path);
}

void WriteHdf5Value(hid_t group, const std::string& name, const Json& value,
                    const std::string& path);

void WriteHdf5Group(hid_t parent, const std::string& name, const Json& object,
                    const std::string& path) {
  const Hid group(H5Gcreate2(parent, name.c_str(), H5P_DEFAULT, Untimed(H5P_GROUP_CREATE).get(),
                             H5P_DEFAULT),
                  H5Gclose, "the group " + path);
  for (const auto& [key, item] : object.items()) {
    WriteHdf5Value(group.get(), key, item, path + "/" + key);
  }
}

void WriteHdf5Value(hid_t group, const std::string& name, const Json& value,
                    const std::string& path) {
  if (value.is_object()) return WriteHdf5Group(group, name, value, path);
  if (value.is_null()) return WriteDoubles(group, name, {}, false, path);
  if (value.is_boolean()) {
    const unsigned char flag = value.get<bool>() ? 1 : 0;
    const Hid space(H5Screate(H5S_SCALAR), H5Sclose, "the dataspace of " + path);
    const Hid dataset(H5Dcreate2(group, name.c_str(), H5T_STD_U8LE, space.get(), H5P_DEFAULT,
                                 Untimed(H5P_DATASET_CREATE).get(), H5P_DEFAULT),
                      H5Dclose, path);
    Check(H5Dwrite(dataset.get(), H5T_NATIVE_UCHAR, H5S_ALL, H5S_ALL, H5P_DEFAULT, &flag), path);
    return;
  }
  if (value.is_number()) return WriteDoubles(group, name, {value.get<double>()}, true, path);
  if (value.is_string()) return WriteStrings(group, name, {value.get<std::string>()}, true, path);
  if (IsNumberArray(value)) return WriteDoubles(group, name, Numbers(value), false, path);
  if (IsTable(value)) return WriteHdf5Group(group, name, TableColumns(value), path);
  if (IsNumberMatrix(value)) {
    std::vector<double> row_major;
    for (const Json& row : value) {
      for (const Json& cell : row) row_major.push_back(cell.get<double>());
    }
    return WriteDoubles(group, name, row_major, false, path, value.front().size());
  }
  if (IsStringArray(value)) {
    return WriteStrings(group, name, value.get<std::vector<std::string>>(), false, path);
  }
  throw NoPlaceFor(path);
}

}  // namespace

std::string MatlabName(const std::string& key) {
  std::string name;
  for (char c : key) {
    name += std::isalnum(static_cast<unsigned char>(c)) || c == '_' ? c : '_';
  }
  if (name.empty() || !std::isalpha(static_cast<unsigned char>(name[0]))) name = "x" + name;
  if (name.size() > kMatlabNameLength) name.resize(kMatlabNameLength);
  return name;
}

std::string UnitOfName(const std::string& name) {
  // Longest suffixes first: "_mm_s2" before "_mm_s" before "_s".
  static const std::pair<const char*, const char*> kSuffixes[] = {
      {"_um_per_mm", "um/mm"}, {"_mm_per_V", "mm/V"}, {"_N_s_m2", "N s/m^2"},
      {"_kg_m3", "kg/m^3"},    {"_Pa_s", "Pa s"},     {"_mm_s2", "mm s^2"},
      {"_rad_s", "rad/s"},     {"_mm", "mm"},         {"_rad", "rad"},
      {"_deg", "deg"},         {"_dB", "dB"},         {"_Hz", "Hz"},
      {"_V", "V"},             {"_m", "m"},           {"_s", "s"}};
  if (EndsWith(name, "_mm_s")) {
    // A speed is mm/s; an integral over time of a deflection (IAE) mm s.
    return name.find("speed") != std::string::npos ? "mm/s" : "mm s";
  }
  for (const auto& [suffix, unit] : kSuffixes) {
    if (EndsWith(name, suffix)) return unit;
  }
  return "";
}

std::string MatFileBytes(const std::string& variable, const nlohmann::ordered_json& tree) {
  if (!tree.is_object()) throw std::invalid_argument(variable + ": a MAT-file holds a struct");
  MatVar root = MatStruct(MatlabName(variable), tree, variable);
  const ScratchFile scratch;
  // A fixed header text (libmatio's default holds the creation date), so
  // that the same results give the same bytes.
  mat_t* file = Mat_CreateVer(scratch.path().c_str(), kMatHeader, MAT_FT_MAT5);
  if (!file) throw std::runtime_error(scratch.path() + ": libmatio cannot create a MAT-file");
  const int status = Mat_VarWrite(file, root.get(), MAT_COMPRESSION_ZLIB);
  Mat_Close(file);
  if (status != 0) throw std::runtime_error(scratch.path() + ": libmatio cannot write " + variable);
  return ReadBytes(scratch.path());
}

std::string Hdf5FileBytes(const nlohmann::ordered_json& tree) {
  if (!tree.is_object()) throw std::invalid_argument("an HDF5 file's root holds an object");

  // The core driver keeps the file in memory (no backing store): its
  // image is read back whole and written by the caller like any output.
  const Hid access(H5Pcreate(H5P_FILE_ACCESS), H5Pclose, "a file access list");
  Check(H5Pset_fapl_core(access.get(), 1 << 16, 0), "the in-memory driver");
  // HDF5 (built thread-safe by Debian) refuses two open files of one
  // name; the address of this call's own access list (on its thread's
  // stack) names it uniquely among the calls running at once.
  const std::string name =
      "ipmc_swim_result_" + std::to_string(reinterpret_cast<std::uintptr_t>(&access)) + ".h5";
  const Hid file(H5Fcreate(name.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, access.get()), H5Fclose,
                 "an in-memory file");
  for (const auto& [key, item] : tree.items()) WriteHdf5Value(file.get(), key, item, "/" + key);
  Check(H5Fflush(file.get(), H5F_SCOPE_GLOBAL), "the file");
  const ssize_t size = H5Fget_file_image(file.get(), nullptr, 0);
  if (size < 0) throw std::runtime_error("HDF5: cannot read back the file image");
  std::string bytes(static_cast<size_t>(size), '\0');
  if (H5Fget_file_image(file.get(), bytes.data(), bytes.size()) != size) {
    throw std::runtime_error("HDF5: cannot read back the file image");
  }
  return bytes;
}

}  // namespace ipmc
