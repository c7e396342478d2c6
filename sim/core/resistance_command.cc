#include "sim/core/resistance_command.h"

#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "sim/base/error.h"
#include "sim/base/numbers.h"
#include "sim/core/simulation.h"
#include "sim/io/files.h"

namespace ipmc {
namespace {

using C = ResistanceCommand;

OptionTable<ResistanceCommand> MakeResistanceOptions() {
  OptionTable<ResistanceCommand> table(
      "resistance",
      "The 6 x 6 resistance of a model held rigid: the fluid's force and torque about the world "
      "origin per velocity and angular velocity, with Purcell's propulsion matrix");
  OptionInfo model{"model", "", "an MJCF file with ipmc_rft_ fields", "The model (at qpos0)"};
  model.positional = true;
  model.required = true;
  table.AddPath(model, [](C& s) -> std::string& { return s.model; });
  OptionInfo fluid{"fluid", "", "rft | stokeslets | ribbon | plates",
                   "Fluid model over the model's ipmc_fluid_model"};
  fluid.default_text = "the model's (rft)";
  table.Add<std::string>(fluid, [](C& s) -> std::string& { return s.fluid; });
  OptionInfo coefficients{"coefficients", "",
                          "gray_hancock | lighthill | near_wall | direct | ribbon | ribbon_fitted",
                          "RFT coefficient set over the model's ipmc_rft_coefficients"};
  coefficients.default_text = "the model's";
  table.Add<std::string>(coefficients, [](C& s) -> std::string& { return s.coefficients; });
  OptionInfo points{"stokeslet_points_per_mm", "1/mm", ">= 0",
                    "Stokeslet points per mm along each segment (0: the model's, or one per "
                    "blob)"};
  table.Add<double>(points, [](C& s) -> double& { return s.stokeslet_points_per_mm; });
  OptionInfo blob{"stokeslet_blob_mm", "mm", ">= 0",
                  "Stokeslet blob (0: the model's, or sqrt(e) a)"};
  table.Add<double>(blob, [](C& s) -> double& { return s.stokeslet_blob_mm; });
  OptionInfo axis{"axis", "", "x | y | z", "World axis of the propulsion matrix"};
  axis.choices = {"x", "y", "z"};
  table.Add<std::string>(axis, [](C& s) -> std::string& { return s.axis; });
  OptionInfo out{"out", "", "a file", "JSON file of R (key \"R\") and A, B, D"};
  out.aliases = {"o"};
  table.AddPath(out, [](C& s) -> std::string& { return s.out; });
  return table;
}

void RequireNonNegative(double value, const char* option) {
  if (!(value >= 0.0) || !std::isfinite(value)) {
    throw FieldError(std::string("resistance: ") + option + " must be finite and >= 0 (got " +
                         FormatShortest(value) + ")",
                     option, ">= 0");
  }
}

int AxisIndex(const std::string& axis) {
  if (axis == "x") return 0;
  if (axis == "y") return 1;
  if (axis == "z") return 2;
  throw FieldError("resistance: axis must be x, y or z (got '" + axis + "')", "axis",
                   "x | y | z");
}

ResistanceSettings SettingsOf(const ResistanceCommand& command) {
  RequireNonNegative(command.stokeslet_points_per_mm, "stokeslet_points_per_mm");
  RequireNonNegative(command.stokeslet_blob_mm, "stokeslet_blob_mm");
  ResistanceSettings settings;
  settings.fluid_model = command.fluid;
  settings.coefficients = command.coefficients;
  if (command.stokeslet_points_per_mm > 0.0) {
    settings.fluid_parameters.emplace_back("ipmc_fluid_stokeslet_points_per_m",
                                           command.stokeslet_points_per_mm * 1e3);
  }
  if (command.stokeslet_blob_mm > 0.0) {
    settings.fluid_parameters.emplace_back("ipmc_fluid_stokeslet_blob_m",
                                           command.stokeslet_blob_mm * 1e-3);
  }
  return settings;
}

std::string ResistanceJson(const ResistanceCommand& command, const ResistanceOutcome& outcome) {
  nlohmann::ordered_json json;
  json["model"] = command.model;
  json["fluid"] = command.fluid.empty() ? "model's" : command.fluid;
  json["units"] = "rows Fx Fy Fz [N] Tx Ty Tz [N m] about the world origin; columns vx vy vz "
                  "[m/s] wx wy wz [rad/s]";
  nlohmann::ordered_json rows = nlohmann::ordered_json::array();
  for (int i = 0; i < 6; ++i) {
    nlohmann::ordered_json row = nlohmann::ordered_json::array();
    for (int j = 0; j < 6; ++j) row.push_back(outcome.resistance[6 * i + j]);
    rows.push_back(row);
  }
  json["R"] = rows;
  json["axis"] = command.axis;
  json["A_N_s_m"] = outcome.propulsion.a_N_s_m;
  json["B_N_s"] = outcome.propulsion.b_N_s;
  json["D_N_m_s"] = outcome.propulsion.d_N_m_s;
  return json.dump(2) + "\n";
}

}  // namespace

const OptionTable<ResistanceCommand>& ResistanceOptions() {
  static const OptionTable<ResistanceCommand> table = MakeResistanceOptions();
  return table;
}

ResistanceOutcome RunResistanceCommand(const ResistanceCommand& command) {
  const ResistanceSettings settings = SettingsOf(command);
  const int axis = AxisIndex(command.axis);
  if (!command.out.empty()) RequireWritableParent(command.out);
  const ModelPtr m = LoadModelFile(command.model);
  mjData* d = mj_makeData(m.get());
  ResistanceOutcome outcome;
  try {
    outcome.resistance = RigidBodyResistance(m.get(), d, settings);
  } catch (...) {
    mj_deleteData(d);
    throw;
  }
  mj_deleteData(d);
  outcome.propulsion = Propulsion(outcome.resistance, axis);
  outcome.json = ResistanceJson(command, outcome);
  if (!command.out.empty()) WriteFileAtomically(command.out, outcome.json);
  return outcome;
}

std::string ResistanceText(const ResistanceCommand& command, const ResistanceOutcome& outcome) {
  std::string text = "R of " + command.model +
                     " (rows Fx Fy Fz [N], Tx Ty Tz [N m] about the origin; columns vx vy vz "
                     "[m/s], wx wy wz [rad/s]):\n";
  char line[64];
  for (int i = 0; i < 6; ++i) {
    for (int j = 0; j < 6; ++j) {
      std::snprintf(line, sizeof line, "%14.6e", outcome.resistance[6 * i + j]);
      text += line;
    }
    text += "\n";
  }
  text += "Purcell's propulsion matrix along " + command.axis + ": A = " +
          FormatDouble(outcome.propulsion.a_N_s_m, 6) + " N s/m, B = " +
          FormatDouble(outcome.propulsion.b_N_s, 6) + " N s, D = " +
          FormatDouble(outcome.propulsion.d_N_m_s, 6) + " N m s\n";
  return text;
}

}  // namespace ipmc
