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

// The whole-number scalar field `name`, or nullopt if absent. Throws
// std::invalid_argument naming it and [min, max] if it is not a whole
// number in that range (2.5 is not truncated, 1e20 does not overflow).
std::optional<int> FindCustomInteger(const mjModel* m, const std::string& name, int min, int max);

// Throws std::invalid_argument "unknown custom field 'NAME' (known: ...)"
// for the first numeric or text field whose name starts with `prefix` and
// is not one of `known`: a misspelt field would otherwise be ignored.
void RequireKnownCustomFields(const mjModel* m, const std::string& prefix,
                              const std::vector<std::string>& known);

// The strip width [m], > 0: the swim meter's Reynolds number uses it
// (sim/core/swim_meter.h); the generator writes it.
constexpr char kStripWidthField[] = "ipmc_strip_width_m";

// Splits on whitespace.
std::vector<std::string> SplitWords(const std::string& text);

}  // namespace ipmc
