// Strict access to a model's <custom><numeric>/<text> fields (and
// FindCustomScalar, ipmc_swim/fields.h).
#pragma once

#include <mujoco/mujoco.h>

#include <optional>
#include <string>
#include <vector>

#include "ipmc_swim/fields.h"

namespace ipmc {

// True if the model declares any numeric or text field whose name starts
// with `prefix`.
bool HasCustomFieldWithPrefix(const mjModel* m, const std::string& prefix);

// All values of the numeric field `name` (nullopt if absent). Throws if any
// value is not finite.
std::optional<std::vector<double>> FindCustomVector(const mjModel* m, const std::string& name);

// The whole-number scalar field `name`, or nullopt if absent. Throws
// std::invalid_argument naming it and [min, max] if it is not a whole
// number in that range (2.5 is not truncated, 1e20 does not overflow).
std::optional<int> FindCustomInteger(const mjModel* m, const std::string& name, int min, int max);

// Throws std::invalid_argument "unknown custom field 'NAME' (known: ...)"
// for the first numeric or text field whose name starts with `prefix` and
// is not one of `known`: a misspelt field would otherwise be ignored.
void RequireKnownCustomFields(const mjModel* m, const std::string& prefix,
                              const std::vector<std::string>& known);

// Splits on whitespace.
std::vector<std::string> SplitWords(const std::string& text);

}  // namespace ipmc
