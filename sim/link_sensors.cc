#include "sim/link_sensors.h"

#include <cmath>
#include <stdexcept>

#include "plugin/coupling.h"

namespace ipmc {
namespace {

int SensorAddress(const mjModel* m, const std::string& name, const std::string& source) {
  const int id = mj_name2id(m, mjOBJ_SENSOR, name.c_str());
  if (id < 0) throw std::runtime_error(source + ": model has no sensor " + name);
  return m->sensor_adr[id];
}

}  // namespace

LinkSensors::LinkSensors(const mjModel* m, const mjData* d, const std::string& source) {
  const CouplingContext* coupling = FindCoupling(d);
  if (!coupling || !coupling->actuators) {
    throw std::runtime_error(source + ": model has no IPMC actuators (custom text ipmc_links)");
  }
  const IpmcActuators& actuators = *coupling->actuators;
  for (int q = 0; q < actuators.Links(); ++q) {
    angle_adr_.push_back(SensorAddress(m, "angle_" + actuators.joints()[q], source));
    tip_y_adr_.push_back(SensorAddress(m, "tip" + std::to_string(q + 1) + "_pos", source) + 1);
    length_mm_.push_back(actuators.LinkLengths_m()[q] * 1e3);
  }
}

double LinkSensors::RelativeDeflection_mm(const mjData* d, int link) const {
  return length_mm_[link] * std::sin(d->sensordata[angle_adr_[link]]);
}

double LinkSensors::TipLateral_mm(const mjData* d, int link) const {
  return d->sensordata[tip_y_adr_[link]] * 1e3;
}

}  // namespace ipmc
