#include "plugin/mjcf/custom_fields.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace ipmc {
namespace {

int FindId(const mjModel* m, mjtObj type, const std::string& name) {
  return mj_name2id(m, type, name.c_str());
}

}  // namespace

bool HasCustomFieldWithPrefix(const mjModel* m, const std::string& prefix) {
  for (int i = 0; i < m->nnumeric; ++i) {
    if (std::string(m->names + m->name_numericadr[i]).rfind(prefix, 0) == 0) return true;
  }
  for (int i = 0; i < m->ntext; ++i) {
    if (std::string(m->names + m->name_textadr[i]).rfind(prefix, 0) == 0) return true;
  }
  return false;
}

std::optional<std::vector<double>> FindCustomVector(const mjModel* m, const std::string& name) {
  const int id = FindId(m, mjOBJ_NUMERIC, name);
  if (id < 0) return std::nullopt;
  const mjtNum* data = m->numeric_data + m->numeric_adr[id];
  std::vector<double> values(data, data + m->numeric_size[id]);
  for (double value : values) {
    if (!std::isfinite(value)) {
      throw std::invalid_argument("custom numeric '" + name + "' must be finite (got " +
                                  std::to_string(value) + ")");
    }
  }
  return values;
}

std::optional<double> FindCustomScalar(const mjModel* m, const std::string& name) {
  const std::optional<std::vector<double>> values = FindCustomVector(m, name);
  if (!values) return std::nullopt;
  if (values->size() != 1) {
    throw std::invalid_argument("custom numeric '" + name + "' must hold exactly one value (got " +
                                std::to_string(values->size()) + ")");
  }
  return values->front();
}

std::optional<int> FindCustomInteger(const mjModel* m, const std::string& name, int min,
                                     int max) {
  const std::optional<double> value = FindCustomScalar(m, name);
  if (!value) return std::nullopt;
  if (*value != std::floor(*value) || *value < min || *value > max) {
    std::ostringstream msg;
    msg.precision(17);
    msg << "custom numeric '" << name << "' must be a whole number in [" << min << ", " << max
        << "] (got " << *value << ")";
    throw std::invalid_argument(msg.str());
  }
  return static_cast<int>(*value);
}

void RequireKnownCustomFields(const mjModel* m, const std::string& prefix,
                              const std::vector<std::string>& known) {
  const auto check = [&](int count, mjtObj type) {
    for (int i = 0; i < count; ++i) {
      const char* name = mj_id2name(m, type, i);
      if (name == nullptr || std::string(name).rfind(prefix, 0) != 0) continue;
      if (std::find(known.begin(), known.end(), name) != known.end()) continue;
      std::string list;
      for (const std::string& field : known) list += (list.empty() ? "" : ", ") + field;
      throw std::invalid_argument("unknown custom field '" + std::string(name) + "' (known: " +
                                  list + ")");
    }
  };
  check(m->nnumeric, mjOBJ_NUMERIC);
  check(m->ntext, mjOBJ_TEXT);
}

std::optional<std::string> FindCustomText(const mjModel* m, const std::string& name) {
  const int id = FindId(m, mjOBJ_TEXT, name);
  if (id < 0) return std::nullopt;
  return std::string(m->text_data + m->text_adr[id]);
}

std::vector<std::string> SplitWords(const std::string& text) {
  std::istringstream in(text);
  std::vector<std::string> words;
  for (std::string word; in >> word;) words.push_back(word);
  return words;
}

}  // namespace ipmc
