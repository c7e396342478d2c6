// One simulated model for controllers written in Python: the scenario's
// model (or any MJCF) with the coupling attached, stepped n steps at a
// time, its link voltages set and its sensors, actuators and swim meter
// read between steps (sim/core/simulation.h, sim/core/link_sensors.h,
// sim/core/swim_meter.h). Stepping releases the GIL, so simulations in
// different Python threads run in parallel; one simulation is used by one
// thread at a time (a mutex serialises the calls).
#include <algorithm>
#include <cmath>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "controllers/controller_names.h"
#include "ipmc_swim/ipmc_swim.h"
#include "sim/core/link_sensors.h"
#include "sim/core/simulation.h"
#include "sim/core/swim_meter.h"
#include "sim/python/convert.h"
#include "sim/runs/closed_loop_run.h"
#include "sim/runs/output.h"

namespace ipmc::python {
namespace {

class PythonSimulation {
 public:
  PythonSimulation(std::unique_ptr<Simulation> sim, std::optional<ScenarioConfig> scenario)
      : sim_(std::move(sim)),
        scenario_(std::move(scenario)),
        meter_(sim_->model(), sim_->data()) {
    const mjData* d = sim_->data();
    if (IsAttached(d) && LinkCount(d) > 0) {
      sensors_ = std::make_unique<LinkSensors>(sim_->model(), d, sim_->source());
      for (int q = 0; q < LinkCount(d); ++q) {
        for (int joint : LinkJoints(d, q)) {
          joint_qpos_.push_back(sim_->model()->jnt_qposadr[joint]);
          joint_names_.emplace_back(mj_id2name(sim_->model(), mjOBJ_JOINT, joint));
        }
      }
    }
    if (scenario_) {
      CheckLinkGains(*scenario_, Links());
      geometry_ = ModelLinkGeometry(*sim_);
      steps_per_sample_ = StepsPerSample(scenario_->controller.sample_rate_Hz,
                                         sim_->model()->opt.timestep, scenario_->source);
    }
    meter_.Start(sim_->data());
  }

  // mj_resetData: the model's initial state, the coupling's state (in
  // mjData.userdata) at rest, time 0, the swim meter started again; then
  // mj_forward, as a new simulation starts.
  void Reset() {
    std::lock_guard<std::mutex> lock(mutex_);
    mj_resetData(sim_->model(), sim_->data());
    mj_forward(sim_->model(), sim_->data());
    meter_ = SwimMeter(sim_->model(), sim_->data());
    meter_.Start(sim_->data());
    diverged_.clear();
  }

  // A branch: a copy of the model with its own attached mjData, into which
  // mj_copyData copies this one's (the coupling's state included), and the
  // swim meter so far; stepped as this one, it continues bit for bit.
  std::unique_ptr<PythonSimulation> Copy() {
    std::lock_guard<std::mutex> lock(mutex_);
    ModelPtr model(mj_copyModel(nullptr, sim_->model()));
    auto sim = std::make_unique<Simulation>(std::move(model), sim_->source());
    mj_copyData(sim->data(), sim->model(), sim_->data());
    auto copy = std::make_unique<PythonSimulation>(std::move(sim), scenario_);
    copy->meter_ = meter_;
    copy->diverged_ = diverged_;
    return copy;
  }

  // Called without the GIL. Ctrl-C (a pending Python signal) stops it at a
  // step boundary, every kSignalCheckSteps steps, raising KeyboardInterrupt.
  // A diverged simulation raises, and refuses every later step: its state
  // is MuJoCo's reset one, not the run's.
  void Step(long steps) {
    if (steps < 0) {
      throw std::invalid_argument("step: n must be >= 0 (got " + std::to_string(steps) + ")");
    }
    std::lock_guard<std::mutex> lock(mutex_);
    RequireNotDiverged("step");
    for (long k = 0; k < steps; ++k) {
      if (k % kSignalCheckSteps == kSignalCheckSteps - 1) {
        py::gil_scoped_acquire acquire;
        if (PyErr_CheckSignals() != 0) throw py::error_already_set();
      }
      try {
        sim_->Step();
      } catch (const std::runtime_error& error) {
        diverged_ = error.what();
        throw;
      }
      meter_.Observe(sim_->model(), sim_->data());
    }
  }

  void RequireNotDiverged(const char* call) const {
    if (!diverged_.empty()) {
      throw std::runtime_error(std::string(call) + ": the simulation diverged before (" +
                               diverged_ + "); make a new Simulation");
    }
  }

  // Each within the model's range (ipmc_voltage_limit_V, +-100 V by
  // default): the actuators refuse any other.
  void SetVoltages(const py::object& given) {
    std::vector<double> volts;
    try {
      volts = Cast<std::vector<double>>(given);
    } catch (const py::cast_error&) {
      throw py::type_error("set_voltages(): voltages_V must be " +
                           ExpectedType<std::vector<double>>() + " (got " + Described(given) + ")");
    }
    std::lock_guard<std::mutex> lock(mutex_);
    RequireActuators("set_voltages");
    ipmc::SetVoltages(sim_->data(), volts.data(), static_cast<int>(volts.size()));
  }

  // Waits for a step running in another thread without holding the GIL,
  // so the interpreter goes on meanwhile.
  double Time() {
    py::gil_scoped_release release;
    std::lock_guard<std::mutex> lock(mutex_);
    return sim_->data()->time;
  }
  double Timestep() const { return sim_->model()->opt.timestep; }
  std::string DynamicsText() const {
    const mjData* d = sim_->data();
    return IsAttached(d) && StokesDynamics(d) ? "stokes" : "inertial";
  }
  int Links() const { return sensors_ ? sensors_->Links() : 0; }
  const std::string& Source() const { return sim_->source(); }
  const std::vector<std::string>& JointNames() const { return joint_names_; }

  std::vector<double> JointAngles_rad() {
    std::lock_guard<std::mutex> lock(mutex_);
    std::vector<double> angles;
    for (int adr : joint_qpos_) angles.push_back(sim_->data()->qpos[adr]);
    return angles;
  }

  std::vector<double> RelativeDeflections_mm() {
    std::lock_guard<std::mutex> lock(mutex_);
    RequireActuators("relative_deflections_mm");
    std::vector<double> values;
    for (int q = 0; q < sensors_->Links(); ++q) {
      values.push_back(sensors_->RelativeDeflection_mm(sim_->data(), q));
    }
    return values;
  }

  std::vector<double> TipLateral_mm() {
    std::lock_guard<std::mutex> lock(mutex_);
    RequireActuators("tip_lateral_mm");
    std::vector<double> values;
    for (int q = 0; q < sensors_->Links(); ++q) {
      values.push_back(sensors_->TipLateral_mm(sim_->data(), q));
    }
    return values;
  }

  py::dict ActuatorState() {
    std::lock_guard<std::mutex> lock(mutex_);
    RequireActuators("actuator_state");
    const mjData* d = sim_->data();
    std::vector<double> voltages_V, free_mm, moments_N_m;
    for (int q = 0; q < LinkCount(d); ++q) {
      voltages_V.push_back(LinkVoltage_V(d, q));
      free_mm.push_back(LinkFreeDeflection_mm(d, q));
      for (double moment_N_m : LinkActiveMoments_N_m(d, q)) moments_N_m.push_back(moment_N_m);
    }
    py::dict state;
    state["voltage_V"] = Array(voltages_V);
    state["free_deflection_mm"] = Array(free_mm);
    state["active_moment_N_m"] = Array(moments_N_m);
    state["clamp_count"] = ClampCount(d);
    return state;
  }

  py::dict Pose() {
    std::lock_guard<std::mutex> lock(mutex_);
    const BodyPose pose = meter_.Pose(sim_->data());
    py::dict dict;
    dict["t_s"] = pose.t_s;
    for (const auto& [name, value] : BodyPoseValues(pose)) dict[name] = value;
    dict["tip_x_mm"] = Array(pose.tip_x_mm);
    dict["tip_y_mm"] = Array(pose.tip_y_mm);
    return dict;
  }

  std::vector<double> Qpos() {
    std::lock_guard<std::mutex> lock(mutex_);
    return std::vector<double>(sim_->data()->qpos, sim_->data()->qpos + sim_->model()->nq);
  }
  std::vector<double> Qvel() {
    std::lock_guard<std::mutex> lock(mutex_);
    return std::vector<double>(sim_->data()->qvel, sim_->data()->qvel + sim_->model()->nv);
  }
  // Sets qpos or qvel (`what`), `size` values.
  void SetState(const char* what, double* target, int size, const std::vector<double>& values) {
    if (static_cast<int>(values.size()) != size) {
      throw std::invalid_argument(std::string("set_") + what + ": needs " + std::to_string(size) +
                                  " values (got " + std::to_string(values.size()) + ")");
    }
    for (double value : values) {
      if (!std::isfinite(value)) {
        throw std::invalid_argument(std::string("set_") + what + ": values must be finite");
      }
    }
    std::copy(values.begin(), values.end(), target);
  }
  void SetQpos(const std::vector<double>& values) {
    std::lock_guard<std::mutex> lock(mutex_);
    SetState("qpos", sim_->data()->qpos, sim_->model()->nq, values);
  }
  void SetQvel(const std::vector<double>& values) {
    std::lock_guard<std::mutex> lock(mutex_);
    SetState("qvel", sim_->data()->qvel, sim_->model()->nv, values);
  }
  // ipmc::FluidForces as (bodies, force [N], torque [N m]) arrays.
  py::tuple FluidForces() {
    std::vector<BodyFluidForce> forces;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      forces = ipmc::FluidForces(sim_->model(), sim_->data());
    }
    const py::ssize_t n = static_cast<py::ssize_t>(forces.size());
    py::array_t<int> bodies(n);
    py::array_t<double> force({n, py::ssize_t{3}}), torque({n, py::ssize_t{3}});
    for (py::ssize_t i = 0; i < n; ++i) {
      bodies.mutable_at(i) = forces[i].body;
      for (int k = 0; k < 3; ++k) {
        force.mutable_at(i, k) = forces[i].force_N[k];
        torque.mutable_at(i, k) = forces[i].torque_N_m[k];
      }
    }
    return py::make_tuple(bodies, force, torque);
  }
  double FluidPower_W() {
    std::lock_guard<std::mutex> lock(mutex_);
    return ipmc::FluidPower_W(sim_->model(), sim_->data());
  }

  std::vector<double> References_mm(std::optional<double> t_s) {
    std::lock_guard<std::mutex> lock(mutex_);
    const ScenarioConfig& scenario = RequireScenario("references_mm");
    return LinkReferences_mm(scenario, geometry_, t_s.value_or(sim_->data()->time));
  }

  void EndCycle() {
    std::lock_guard<std::mutex> lock(mutex_);
    meter_.EndCycle(sim_->data());
  }

  py::object Swim() {
    std::lock_guard<std::mutex> lock(mutex_);
    RequireNotDiverged("swim");
    return ToPython(SwimMetricsJson(meter_.Finish(sim_->data())));
  }

  // The scenario's timing and controller.
  long StepsPerSample_() const {
    RequireScenario("steps_per_sample");
    return steps_per_sample_;
  }
  double SamplePeriod_s() const { return StepsPerSample_() * Timestep(); }
  double Period_s() const {
    return 1.0 / std::abs(RequireScenario("period_s").waveform.frequency_Hz);
  }
  long StepsPerCycle() const { return std::lround(Period_s() / Timestep()); }
  int Cycles() const { return RequireScenario("cycles").run.cycles; }

  py::dict Controller() const {
    const ScenarioConfig& s = RequireScenario("controller");
    py::dict dict;
    const bool pid = s.controller.kind == ControllerKind::kPid;
    dict["kind"] = pid ? controller_names::kPid : controller_names::kFractional;
    dict["sample_rate_Hz"] = s.controller.sample_rate_Hz;
    if (pid) {
      dict["kp"] = s.controller.pid.kp;
      dict["ki"] = s.controller.pid.ki;
      dict["kd"] = s.controller.pid.kd;
      std::vector<double> kp, ki, kd;
      for (int q = 0; q < Links(); ++q) {
        const PidController::Config link = s.controller.LinkPid(q);
        kp.push_back(link.kp);
        ki.push_back(link.ki);
        kd.push_back(link.kd);
      }
      dict["link_kp"] = Array(kp);
      dict["link_ki"] = Array(ki);
      dict["link_kd"] = Array(kd);
      dict["derivative_filter_s"] = s.controller.pid.derivative_filter_time_s;
      dict["sample_period_s"] = s.controller.pid.sample_period_s;
      dict["clamp"] = s.controller.pid.clamp_enabled;
      dict["v_max_V"] = s.controller.pid.v_max;
    } else {
      dict["gain"] = s.controller.fractional.gain;
      dict["order"] = s.controller.fractional.order;
      std::vector<double> gain, order;
      for (int q = 0; q < Links(); ++q) {
        const FractionalIntegrator::Config link = s.controller.LinkFractional(q);
        gain.push_back(link.gain);
        order.push_back(link.order);
      }
      dict["link_gain"] = Array(gain);
      dict["link_order"] = Array(order);
      dict["sample_period_s"] = s.controller.fractional.sample_period_s;
      dict["clamp"] = s.controller.fractional.clamp_enabled;
      dict["v_max_V"] = s.controller.fractional.v_max;
    }
    dict["actuation"] = ChoiceText(kActuationNames, s.actuation);
    return dict;
  }

 private:
  void RequireActuators(const char* call) const {
    if (!sensors_) {
      throw std::invalid_argument(sim_->source() + ": " + call +
                                  " needs a model with IPMC actuators");
    }
  }
  const ScenarioConfig& RequireScenario(const char* call) const {
    if (!scenario_) {
      throw std::invalid_argument(sim_->source() + ": " + call +
                                  " needs a simulation made from a scenario");
    }
    return *scenario_;
  }

  std::unique_ptr<Simulation> sim_;
  std::optional<ScenarioConfig> scenario_;
  SwimMeter meter_;
  std::unique_ptr<LinkSensors> sensors_;
  LinkGeometry geometry_;
  long steps_per_sample_ = 0;
  std::vector<int> joint_qpos_;
  std::vector<std::string> joint_names_;
  std::mutex mutex_;
  std::string diverged_;  // what diverged, once it has
  static constexpr long kSignalCheckSteps = 2000;
};

std::unique_ptr<PythonSimulation> FromScenario(const py::object& scenario_arg,
                                               const py::dict& overrides) {
  ScenarioConfig scenario = ReadScenarioArgument(scenario_arg, overrides, "Simulation").scenario;
  auto sim = WithoutGil([&] { return LoadScenarioSimulation(scenario); });
  return std::make_unique<PythonSimulation>(std::move(sim), std::move(scenario));
}

std::unique_ptr<PythonSimulation> FromModel(const py::object& path_arg) {
  const std::string path = PathText(path_arg, "model");
  auto sim = WithoutGil([&] { return std::make_unique<Simulation>(LoadModelFile(path), path); });
  return std::make_unique<PythonSimulation>(std::move(sim), std::nullopt);
}

std::unique_ptr<PythonSimulation> FromXml(const std::string& xml) {
  auto sim = WithoutGil(
      [&] { return std::make_unique<Simulation>(LoadModelString(xml), "inline model"); });
  return std::make_unique<PythonSimulation>(std::move(sim), std::nullopt);
}

}  // namespace

void BindSimulation(py::module_& m) {
  py::class_<PythonSimulation>(m, "Simulation", R"(One simulated model to step from Python.

Simulation(scenario, **overrides) loads a scenario's model (a scenario file
or a dict of its keys, with overrides by dotted key as for run()) with the
scenario's time step, viscosity and plants; from_model(path) and
from_xml(text) load any MJCF. The coupling (RFT drag, IPMC actuators) is
attached. A controller reads the sensors, sets the link voltages (held
until set again) and steps: at the scenario's 1 kHz that is
steps_per_sample steps per sample. The swim meter starts at t = 0;
end_cycle() records a cycle's displacement, swim() returns the swim
metrics. step() releases the GIL: simulations in different threads run in
parallel.)")
      .def(py::init([](const py::object& scenario, const py::kwargs& overrides) {
             return FromScenario(scenario, overrides);
           }),
           py::arg("scenario"))
      .def_static("from_model", &FromModel, py::arg("path"), "A simulation of an MJCF file.")
      .def_static("from_xml", &FromXml, py::arg("xml"), "A simulation of MJCF text.")
      .def("reset", &PythonSimulation::Reset,
           "Starts again from the model's initial state (mj_resetData): time 0, the link "
           "models at rest, voltages 0, the swim meter restarted.")
      .def("copy", &PythonSimulation::Copy,
           "A branch: a new Simulation holding this one's state (mj_copyData into a new "
           "attached mjData) and swim meter; stepped alike, the two agree bit for bit.")
      .def("step", [](PythonSimulation& s, long n) { WithoutGil([&] { s.Step(n); }); },
           py::arg("n") = 1, "Advances n physics steps (the GIL released).")
      .def("set_voltages", &PythonSimulation::SetVoltages, py::arg("voltages_V"),
           "Sets every link's voltage [V] from now on (one value per link).")
      .def_property_readonly("time", &PythonSimulation::Time, "Simulated time [s].")
      .def_property_readonly("timestep", &PythonSimulation::Timestep, "Physics step [s].")
      .def_property_readonly("dynamics", &PythonSimulation::DynamicsText,
                             "How a step advances: \"inertial\" (mj_step) or \"stokes\" "
                             "(docs/DYNAMICS.md).")
      .def_property_readonly("links", &PythonSimulation::Links, "IPMC links.")
      .def_property_readonly("source", &PythonSimulation::Source, "The model, for messages.")
      .def_property_readonly("joint_names", &PythonSimulation::JointNames,
                             "The links' hinges, link by link, root first.")
      .def("joint_angles_rad", [](PythonSimulation& s) { return Array(s.JointAngles_rad()); },
           "The links' hinge angles [rad], in joint_names' order.")
      .def("relative_deflections_mm",
           [](PythonSimulation& s) { return Array(s.RelativeDeflections_mm()); },
           "Each link's relative tip deflection [mm], the controllers' measurement (from "
           "the sensors, one step late).")
      .def("tip_lateral_mm", [](PythonSimulation& s) { return Array(s.TipLateral_mm()); },
           "Each tip's lateral position [mm] (the bench's laser).")
      .def("actuator_state", &PythonSimulation::ActuatorState,
           "The IPMC actuators: voltage_V, free_deflection_mm (each link model's free tip "
           "deflection), active_moment_N_m (per hinge), clamp_count.")
      .def("pose", &PythonSimulation::Pose,
           "Time, centre of mass, head, yaw and tips [mm, rad] (the swim meter's).")
      .def("qpos", [](PythonSimulation& s) { return Array(s.Qpos()); }, "MuJoCo's qpos.")
      .def("qvel", [](PythonSimulation& s) { return Array(s.Qvel()); }, "MuJoCo's qvel.")
      .def("set_qpos", &PythonSimulation::SetQpos, py::arg("qpos"), "Sets MuJoCo's qpos.")
      .def("set_qvel", &PythonSimulation::SetQvel, py::arg("qvel"), "Sets MuJoCo's qvel.")
      .def("fluid_forces", &PythonSimulation::FluidForces,
           "The fluid's force on each body it acts on (ipmc::FluidForces): (bodies, "
           "force_N (n, 3), torque_N_m (n, 3)), world frame, the torque about each body's "
           "origin, from the current qpos and qvel.")
      .def("fluid_power_W", &PythonSimulation::FluidPower_W,
           "The power the body loses to the fluid [W] (ipmc::FluidPower_W).")
      .def("references_mm",
           [](PythonSimulation& s, std::optional<double> t) { return Array(s.References_mm(t)); },
           py::arg("t_s") = py::none(),
           "Each link's reference [mm] at t_s (default: now): the scenario's wave, "
           "discretised and faded in.")
      .def("end_cycle", &PythonSimulation::EndCycle,
           "Ends a cycle: records its net displacement.")
      .def("swim", &PythonSimulation::Swim,
           "The swim metrics so far, as summary.json has them (per_cycle, mean speed, "
           "Reynolds numbers).")
      .def_property_readonly("steps_per_sample", &PythonSimulation::StepsPerSample_,
                             "Physics steps per controller sample.")
      .def_property_readonly("sample_period_s", &PythonSimulation::SamplePeriod_s,
                             "Controller sample period [s].")
      .def_property_readonly("period_s", &PythonSimulation::Period_s, "Wave period [s].")
      .def_property_readonly("steps_per_cycle", &PythonSimulation::StepsPerCycle,
                             "Physics steps per wave cycle.")
      .def_property_readonly("cycles", &PythonSimulation::Cycles, "The scenario's cycles.")
      .def_property_readonly("controller", &PythonSimulation::Controller,
                             "The scenario's controller settings (kind, gains, clamp) and the gains each "
                             "link's controller runs with, link by link: link_kp, link_ki, "
                             "link_kd (PID) or link_gain, link_order (fractional), the "
                             "scalar key's where the scenario gives no per-link value.");
}

}  // namespace ipmc::python
