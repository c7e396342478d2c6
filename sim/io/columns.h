// The column names of every CSV file the program writes, defined once for
// the writers and the readers (plots, identification, merge). Per-link and
// per-tip columns are numbered from 1.
#pragma once

#include <string>

namespace ipmc::columns {

// Time of a sample [s]: time series, bench records, step responses.
constexpr char kTime[] = "time_s";

// timeseries.csv of gait and closed-loop runs (sim/runs/output.h).
constexpr char kComX[] = "com_x_mm";
constexpr char kComY[] = "com_y_mm";
constexpr char kHeadX[] = "head_x_mm";
constexpr char kHeadY[] = "head_y_mm";
constexpr char kYaw[] = "yaw_rad";
inline std::string TipX(int tip) { return "tip" + std::to_string(tip) + "_x_mm"; }
inline std::string TipY(int tip) { return "tip" + std::to_string(tip) + "_y_mm"; }
// Gaits: reference and measured joint angle.
inline std::string JointReference(int joint) { return "q_ref" + std::to_string(joint) + "_rad"; }
inline std::string JointAngle(int joint) { return "q" + std::to_string(joint) + "_rad"; }
// Closed loop: each link's reference and measured relative tip deflection,
// and its voltage.
inline std::string Reference(int link) { return "reference" + std::to_string(link) + "_mm"; }
inline std::string Measured(int link) { return "measured" + std::to_string(link) + "_mm"; }
inline std::string Voltage(int link) { return "voltage" + std::to_string(link) + "_V"; }

// Bench records (sim/runs/bench_run.h), besides time_s and voltage<q>_V.
inline std::string Relative(int link) { return "relative" + std::to_string(link) + "_mm"; }
inline std::string TipLateral(int link) {
  return "tip" + std::to_string(link) + "_lateral_mm";
}
inline std::string Free(int link) { return "free" + std::to_string(link) + "_mm"; }

// Frequency responses: angular frequency, and a curve's magnitude and
// phase (bode.csv of "ipmc-swim bode": curves plant, controller,
// open_loop, reference_open_loop).
constexpr char kFrequency[] = "w_rad_s";
constexpr char kPlantCurve[] = "plant";
constexpr char kControllerCurve[] = "controller";
constexpr char kOpenLoopCurve[] = "open_loop";
constexpr char kReferenceOpenLoopCurve[] = "reference_open_loop";
inline std::string MagnitudeDb(const std::string& curve) { return curve + "_dB"; }
inline std::string PhaseDeg(const std::string& curve) { return curve + "_deg"; }
// One response alone (WriteBodeCsv, sim/identify/loop_analysis.h).
constexpr char kMagnitudeDb[] = "magnitude_dB";
constexpr char kPhaseDeg[] = "phase_deg";

// step.csv of "ipmc-swim step": the reference model and each link's
// output [mm] and voltage [V].
constexpr char kReferenceModel[] = "reference_model";
inline std::string StepOutput(int link) { return "y_link" + std::to_string(link); }
inline std::string StepVoltage(int link) { return "u_link" + std::to_string(link); }

// response.csv of "ipmc-swim identify" and the pipeline.
constexpr char kFrequencyHz[] = "frequency_Hz";
constexpr char kCoherence[] = "coherence";
constexpr char kMeasuredRe[] = "measured_re_mm_per_V";
constexpr char kMeasuredIm[] = "measured_im_mm_per_V";
constexpr char kMeasuredCurve[] = "measured";
constexpr char kP1Curve[] = "p1";
constexpr char kP2Curve[] = "p2";
constexpr char kInBand[] = "in_band";

// Sweep tables (sim/batch/sweep_table.h): point, the swept keys, status, error,
// then per-link and swimming results.
constexpr char kPoint[] = "point";
constexpr char kStatus[] = "status";
constexpr char kError[] = "error";
constexpr char kStatusOk[] = "ok";
constexpr char kStatusError[] = "error";
// Energy (sim/core/energy.h): mean powers, also per link and per cycle in
// summary.json.
constexpr char kActuatorPower[] = "actuator_power_W";
constexpr char kFluidPower[] = "fluid_power_W";
constexpr char kHingeDampingPower[] = "hinge_damping_power_W";
constexpr char kSteppingPower[] = "stepping_power_W";
constexpr char kElasticEnergy[] = "elastic_energy_J";
constexpr char kStoredEnergyChange[] = "stored_energy_change_J";
constexpr char kTowingDrag[] = "towing_drag_N";
constexpr char kLighthillEfficiency[] = "lighthill_efficiency";
constexpr char kCostOfTransport[] = "cost_of_transport_J_m";
// With the electrical model on (scenario key electrical.enabled) only.
constexpr char kElectricalPower[] = "electrical_power_W";
constexpr char kElectromechanicalEfficiency[] = "electromechanical_efficiency";
constexpr const char* kLinkResults[] = {"iae_mm_s", "itae_mm_s2", "rms_voltage_V",
                                        "clamped_fraction", kActuatorPower};
inline std::string LinkResult(int link, const std::string& result) {
  return "link" + std::to_string(link) + "_" + result;
}
constexpr char kLastCycleComAlong[] = "last_cycle_com_along_mm";
constexpr char kMeanSpeedAlong[] = "mean_speed_along_mm_s";
constexpr char kReynoldsTip[] = "reynolds_tip";
constexpr char kReynoldsSwim[] = "reynolds_swim";
constexpr const char* kSwimResults[] = {
    kLastCycleComAlong, kMeanSpeedAlong,      kReynoldsTip,     kReynoldsSwim,
    kActuatorPower,     kFluidPower,          kHingeDampingPower, kSteppingPower, kLighthillEfficiency,
    kCostOfTransport,   kElectricalPower,     kElectromechanicalEfficiency};

// table5.csv of "ipmc-swim table5".
constexpr char kIndex[] = "index";
constexpr char kLink[] = "link";
constexpr char kController[] = "controller";
constexpr char kHere[] = "here";
constexpr char kPaper[] = "paper";
constexpr char kRelativeError[] = "relative_error";

}  // namespace ipmc::columns
