// Strict access to a model's <custom><numeric>/<text> fields.
#pragma once

#include <mujoco/mujoco.h>

#include <optional>
#include <string>
#include <vector>

namespace ipmc {

// True if the model declares any numeric or text field whose name starts
// with `prefix`.
bool HasCustomFieldWithPrefix(const mjModel* m, const std::string& prefix);

// The scalar numeric field `name`, or nullopt if absent. Throws
// std::invalid_argument if it holds more than one value or is not finite.
std::optional<double> FindCustomScalar(const mjModel* m, const std::string& name);

// All values of the numeric field `name` (nullopt if absent). Throws if any
// value is not finite.
std::optional<std::vector<double>> FindCustomVector(const mjModel* m, const std::string& name);

// The text field `name`, or nullopt if absent.
std::optional<std::string> FindCustomText(const mjModel* m, const std::string& name);

// Splits on whitespace.
std::vector<std::string> SplitWords(const std::string& text);

}  // namespace ipmc
