// The <custom> fields a model declares for ipmc-swim (docs/LIBRARY.md
// lists every one, with its unit and range): their names, the words their
// text values take, and what a program that writes or checks a model needs
// to know of them before attaching it. Attach (ipmc_swim.h) reads them.
#pragma once

#include <mujoco/mujoco.h>

#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace ipmc {

// ---- The fluid (resistive-force theory and the dense models over its
// segments).
constexpr char kAttrViscosity[] = "ipmc_rft_viscosity_Pa_s";
constexpr char kAttrCoefficients[] = "ipmc_rft_coefficients";
constexpr char kAttrEquivalentRadius[] = "ipmc_rft_equivalent_radius_m";
constexpr char kAttrWavelength[] = "ipmc_rft_wavelength_m";
constexpr char kAttrXiNormal[] = "ipmc_rft_xi_normal_N_s_m2";
constexpr char kAttrXiTangential[] = "ipmc_rft_xi_tangential_N_s_m2";
constexpr char kAttrFluidDensity[] = "ipmc_rft_fluid_density_kg_m3";
constexpr char kAttrGeoms[] = "ipmc_rft_geoms";
constexpr char kAttrWallDistance[] = "ipmc_rft_wall_distance_m";
// All of the above.
inline const char* const kRftDragFields[] = {
    kAttrViscosity, kAttrCoefficients, kAttrEquivalentRadius, kAttrWavelength,
    kAttrXiNormal,  kAttrXiTangential, kAttrFluidDensity,     kAttrGeoms, kAttrWallDistance};
// The text naming the fluid model (FluidModelDescriptions).
constexpr char kAttrFluidModel[] = "ipmc_fluid_model";
// The strip width [m], > 0: the swim's Reynolds numbers use it; else twice
// ipmc_rft_equivalent_radius_m (StripWidth_m).
constexpr char kStripWidthField[] = "ipmc_strip_width_m";

// ipmc_rft_coefficients. kRibbon: calibrated on the flat plates, one set
// per segment: its share of the straight body's broadside and axial drag
// per length, and its own rotational drag. kRibbonFitted: the same with the
// broadside and rotational drags scaled by factors fitted to the plates'
// swim and fluid power in the paper's default job (docs/FLUIDS.md).
enum class CoefficientModel {
  kGrayHancock,
  kLighthill,
  kNearWall,
  kDirect,
  kRibbon,
  kRibbonFitted
};
// Throws std::invalid_argument naming the allowed set.
CoefficientModel ParseCoefficientModel(const std::string& text);
// The word ParseCoefficientModel reads ("gray_hancock", ...).
const char* CoefficientModelName(CoefficientModel model);

// A fluid model's setting, declared as MuJoCo's plugins declare their
// attributes: the model reads it from its own <custom> numeric `field` (SI
// units), and a program may offer it as a key (`key`, in the key's unit:
// the ipmc-swim scenario's fluid.<key>).
struct FluidParameter {
  enum class Type { kInteger, kNumber, kBoolean };
  const char* key;    // "stokeslet_blob_mm"
  const char* field;  // the <custom> numeric: "ipmc_fluid_stokeslet_blob_m"
  Type type;
  const char* unit;        // the key's: "mm", "1/mm", "rad", ""
  double field_per_key;    // the field's value per unit of the key's (1e-3: mm to m)
  double default_value;    // in the key's unit; NaN: the model derives it
  const char* default_text;  // the default as documented; nullptr: default_value
  double example;          // another allowed value, in the key's unit
  // The range in the key's unit: above `minimum` (at least it when
  // `minimum_included`) and at most `maximum` (inf: unbounded).
  double minimum;
  bool minimum_included;
  double maximum;
  const char* meaning;
  bool resolution;  // sets how many force points the model has
};
// The allowed values as messages and the key table state them: "[1, 16]",
// "> 0", ">= 0", "true or false".
std::string FluidParameterRange(const FluidParameter& parameter);

// A fluid model: its name (a value of ipmc_fluid_model), a phrase for the
// key's reference, its parameters, and whether it takes a no-slip wall
// (ipmc_rft_wall_distance_m with the near-wall coefficients).
struct FluidModelDescription {
  const char* name;
  const char* summary;
  std::vector<FluidParameter> parameters;
  bool wall;
};
// Every fluid model, "rft" first.
const std::vector<FluidModelDescription>& FluidModelDescriptions();
// The one called `name`, or nullptr.
const FluidModelDescription* FindFluidModelDescription(const std::string& name);
// The models' names as the key table lists its choices: "rft|stokeslets|...".
std::string FluidModelChoices();
// How many force points the model's fluid factors one dense mobility over
// (from its fields alone, before it is built, so that a program can refuse
// a resolution no machine factors); 0 for a model without drag or whose
// fluid has none. Throws std::invalid_argument as Attach does for
// malformed fields.
double FluidForcePoints(const mjModel* m);
// The strip's width w [m]: the model's ipmc_strip_width_m, else twice its
// ipmc_rft_equivalent_radius_m (0.8125 mm if absent).
double StripWidth_m(const mjModel* m);
// Throws std::invalid_argument naming the field and its range, as Attach
// would, if the coefficient set `coefficients` (ipmc_rft_coefficients)
// cannot take a slender segment of radius radius_m in a wave of
// wavelength_m.
void CheckRftSegment(const std::string& coefficients, double radius_m, double wavelength_m);

// ---- How the model is stepped: mj_step with the bodies' inertia, or the
// Stokes-flow step without it (docs/DYNAMICS.md).
// MJCF: text ipmc_dynamics, inertial (default) | stokes.
enum class Dynamics { kInertial, kStokes };
constexpr char kAttrDynamics[] = "ipmc_dynamics";
// Throws std::invalid_argument naming the field and its choices.
inline Dynamics ParseDynamics(const std::string& text) {
  if (text == "inertial") return Dynamics::kInertial;
  if (text == "stokes") return Dynamics::kStokes;
  throw std::invalid_argument(std::string(kAttrDynamics) + " must be inertial or stokes (got '" +
                              text + "')");
}
inline const char* DynamicsName(Dynamics dynamics) {
  return dynamics == Dynamics::kStokes ? "stokes" : "inertial";
}

// ---- The IPMC actuators.
constexpr char kAttrLinks[] = "ipmc_links";
constexpr char kAttrSegments[] = "ipmc_segments_per_link";
constexpr char kAttrPlants[] = "ipmc_plants";
constexpr char kAttrModel[] = "ipmc_model";
constexpr char kAttrActuation[] = "ipmc_actuation";
constexpr char kAttrBand[] = "ipmc_integrator_band_rad_s";
constexpr char kAttrPairs[] = "ipmc_integrator_pairs";
constexpr char kAttrRelTol[] = "ipmc_cvode_rel_tol";
constexpr char kAttrIntegration[] = "ipmc_actuator_integration";
// The largest |voltage| a link accepts [V]; kDefaultVoltageLimit_V if absent.
constexpr char kAttrVoltageLimit[] = "ipmc_voltage_limit_V";
// The per-link overrides of the paper's Table 2 parameters.
constexpr char kAttrA0[] = "ipmc_a0_mm_per_V";
constexpr char kAttrB1[] = "ipmc_b1";
constexpr char kAttrB2[] = "ipmc_b2_s2";
constexpr char kAttrAlpha[] = "ipmc_alpha";

// ipmc_actuation: every link driven (distributed), or the first link's
// voltage on all (single).
enum class Actuation { kDistributed, kSingle };

// The motor that applies the IPMC moment at hinge `joint`.
inline std::string IpmcMotorName(const std::string& joint) { return "ipmc_" + joint; }

// The links' voltage range without ipmc_voltage_limit_V: +-100 V, the
// bench's range, far beyond the few volts the paper's strips were driven
// with; a voltage outside it is a mistake, not an experiment.
constexpr double kDefaultVoltageLimit_V = 100.0;

// Largest ipmc_segments_per_link.
constexpr int kMaxSegmentsPerLink = 64;

// The number of IPMC links the model's fields declare (ipmc_links), 0
// without, and how they are driven (ipmc_actuation). Each throws
// std::invalid_argument as Attach does for malformed actuator fields.
int ModelLinkCount(const mjModel* m);
Actuation ModelActuation(const mjModel* m);

// ---- Any field.
// The scalar numeric field `name`, or nullopt if absent. Throws
// std::invalid_argument if it holds more than one value or is not finite.
std::optional<double> FindCustomScalar(const mjModel* m, const std::string& name);
// The text field `name`, or nullopt if absent.
std::optional<std::string> FindCustomText(const mjModel* m, const std::string& name);

}  // namespace ipmc
