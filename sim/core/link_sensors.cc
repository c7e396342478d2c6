#include "sim/core/link_sensors.h"

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
    const LinkChain& chain = actuators.chains()[q];
    LinkAngles link;
    for (size_t i = 0; i < chain.joints.size(); ++i) {
      const std::string joint = m->names + m->name_jntadr[chain.joints[i]];
      link.angle_adr.push_back(SensorAddress(m, "angle_" + joint, source));
      link.segment_length_mm.push_back(chain.segment_length_m[i] * 1e3);
    }
    links_.push_back(std::move(link));
    tip_y_adr_.push_back(SensorAddress(m, "tip" + std::to_string(q + 1) + "_pos", source) + 1);
  }
}

double LinkSensors::RelativeDeflection_mm(const mjData* d, int link) const {
  const LinkAngles& angles = links_[link];
  if (angles.angle_adr.size() == 1) {
    return angles.segment_length_mm[0] * std::sin(d->sensordata[angles.angle_adr[0]]);
  }
  double angle_rad = 0.0, deflection_mm = 0.0;
  for (size_t j = 0; j < angles.angle_adr.size(); ++j) {
    angle_rad += d->sensordata[angles.angle_adr[j]];
    deflection_mm += angles.segment_length_mm[j] * std::sin(angle_rad);
  }
  return deflection_mm;
}

double LinkSensors::TipLateral_mm(const mjData* d, int link) const {
  return d->sensordata[tip_y_adr_[link]] * 1e3;
}

}  // namespace ipmc
