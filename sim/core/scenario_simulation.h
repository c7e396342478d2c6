// A scenario made into a simulation, in one place for every front end
// (`run`, sweeps, optimisation, films and the Python module): the model
// it names or generates, with the scenario's time step, viscosity and
// hinge damping, and the fluid settings and plants it imposes.
#pragma once

#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "sim/linear/ipmc_link_model.h"
#include "ipmc_swim/fields.h"
#include "sim/core/scenario.h"
#include "sim/core/simulation.h"

namespace ipmc {

// The MJCF text of the model the scenario's runs step: its file's, or the
// generated flagellum's, with the scenario's settings written into it (the
// time step, viscosity, hinge damping scale, plants, dynamics and the
// fluid's fields: sim/io/mjcf_edit.h). A run writes it as model.xml;
// attached as it is (ipmc::Attach) it steps as the run does, and
// `ipmc-swim run model.xml` is the same run. *source is set to the name
// used in messages. Throws std::runtime_error naming the file on bad input.
std::string ScenarioModelXml(const ScenarioConfig& scenario, std::string* source);

// ScenarioModelXml loaded (a model file's relative paths resolved from its
// folder).
ModelPtr LoadScenarioModel(const ScenarioConfig& scenario, std::string* source);

// The SHA-256 (sim/core/sha256.h) of the bytes of the scenario's model: its
// file, or the MJCF text of the generated flagellum it names. Throws
// InputError if the file cannot be read.
std::string ScenarioModelSha256(const ScenarioConfig& scenario);

// The scenario's model (LoadScenarioModel), attached: a caller stepping it
// with ipmc::Step gets the run's numbers.
std::unique_ptr<Simulation> LoadScenarioSimulation(const ScenarioConfig& scenario);
// The fluid settings the scenario imposes: fluid.rft_coefficients, and the
// wavelength in the RFT coefficients, fluid.rft_wavelength_mm or else the
// wave's (waveform.wavelength_mm), so that the drag follows the wave; and
// with fluid.wall_gap_mm the near-wall coefficients, for a wall that far
// below the strip's lower edge: the centreline is the gap plus half the
// strip's width (m's ipmc_strip_width_m, else 2 ipmc_rft_equivalent_radius_m)
// from it.
struct ScenarioFluidFields {
  std::optional<CoefficientModel> coefficients;  // ipmc_rft_coefficients
  std::optional<double> wavelength_m;            // ipmc_rft_wavelength_m
  std::optional<double> wall_distance_m;         // ipmc_rft_wall_distance_m
  std::optional<std::string> fluid_model;        // ipmc_fluid_model
  std::map<std::string, double> parameters;      // the fluid model's fields, SI
};
ScenarioFluidFields ScenarioFluidOverrides(const ScenarioConfig& scenario, const mjModel* m);

// The number of IPMC links of the scenario's model, read from its fields
// without building the simulation. Throws std::runtime_error naming the
// model if it has no IPMC actuators.
int ScenarioLinkCount(const ScenarioConfig& scenario);

// The plants of d's IPMC links as its coupling made them (ipmc::LinkPlantOf),
// one per link; empty for a d without actuators.
std::vector<IpmcLinkParams> AttachedLinkPlants(const mjData* d);

// The links' plants as the run gives them (the model's or the generated
// flagellum's, with the scenario's plant keys): the simulation's own.
// Throws std::runtime_error naming the scenario if it has no IPMC
// actuators.
std::vector<IpmcLinkParams> ScenarioLinkPlants(const ScenarioConfig& scenario);

}  // namespace ipmc
