// `export`: a scenario's closed-loop controllers as the simulator runs them
// (ControllerScenario::LinkPid / LinkFractional, sim/core/controller_keys.h,
// the objects the run's LinkController is made of), at its sample rate,
// written for a processor's fixed-rate loop:
//
//   DIR/ipmc_controller.h, DIR/ipmc_controller.c
//       C99 without allocation or library calls: ipmc_controller_state,
//       ipmc_controller_reset(&s), ipmc_controller_update(&s, link,
//       reference_mm, measured_mm) -> the voltage [V] to hold until the next
//       sample (clamp and anti-windup included), IPMC_CONTROLLER_LINKS,
//       IPMC_CONTROLLER_SAMPLE_RATE_HZ; double, or float with
//       -DIPMC_CONTROLLER_FLOAT. The PID is controllers/pid.h's update,
//       operation for operation (so its doubles are the simulator's); the
//       fractional integrator its ZOH discretisation (FractionalIntegrator::
//       discrete()) as parallel first-order sections
//       (controllers/first_order_sections.h), each coefficient commented.
//   DIR/coefficients.json, DIR/coefficients.csv
//       every gain and section coefficient with its difference equation
//       and the sign convention (MATLAB/SciPy's and CMSIS-DSP's a1).
//
//   ipmc-swim export SCENARIO.toml [--set KEY=VALUE ...] --out DIR
//   ipmc_swim.export(scenario, out=DIR, **overrides)
//
// docs/PROTOTYPE.md gives the equations and how to check an
// implementation against a recorded run.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "sim/core/scenario.h"
#include "sim/io/option_table.h"

namespace ipmc {

inline constexpr const char* kExportFiles[] = {"ipmc_controller.h", "ipmc_controller.c",
                                               "coefficients.json", "coefficients.csv"};

struct ExportCommand {
  std::string scenario;          // a scenario file (TOML)
  std::vector<std::string> set;  // KEY=VALUE scenario settings (command line)
  std::string out;               // the folder of kExportFiles
};

const OptionTable<ExportCommand>& ExportOptions();

// The four files' texts, in kExportFiles' order, and the coefficients.
struct ExportedController {
  std::vector<std::string> texts;
  nlohmann::ordered_json coefficients;  // coefficients.json
};

// The scenario's driven links' controllers (one in single actuation) as the
// files' texts. Throws std::runtime_error naming the scenario and key if a
// controller.link_* array does not hold one value per link, and
// std::invalid_argument if a realisation has no first-order sections
// (complex or repeated poles: the eq15 realisation).
ExportedController ExportControllers(const ScenarioConfig& scenario);

// The command line's export: the scenario with its settings, checked,
// written into command.out together (all four or none).
ExportedController RunExportCommand(const ExportCommand& command);
// Python's: a scenario already read.
ExportedController RunExportCommand(const std::string& out, const ScenarioConfig& scenario);

}  // namespace ipmc
