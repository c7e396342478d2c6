#include "sim/core/link_sensors.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "ipmc_swim/ipmc_swim.h"

namespace ipmc {
namespace {

// The sensor's address in sensordata, or -1 if the model has none of that name.
int SensorAddress(const mjModel* m, const std::string& name) {
  const int id = mj_name2id(m, mjOBJ_SENSOR, name.c_str());
  return id < 0 ? -1 : m->sensor_adr[id];
}

// The far end of geom g in its own frame: the half-length along its
// axis (a box's longest side), on the side away from `from_W`.
bool FarEnd(const mjModel* m, const mjData* d, int g, const mjtNum* from_W, double local_m[3]) {
  const mjtNum* size = m->geom_size + 3 * g;
  double axis[3] = {0, 0, 0};
  double half_m = 0.0;
  switch (m->geom_type[g]) {
    case mjGEOM_BOX: {
      const int longest =
          size[0] >= size[1] && size[0] >= size[2] ? 0 : (size[1] >= size[2] ? 1 : 2);
      axis[longest] = 1.0;
      half_m = size[longest];
      break;
    }
    case mjGEOM_CAPSULE:
      axis[2] = 1.0;
      half_m = size[1] + size[0];
      break;
    case mjGEOM_CYLINDER:
      axis[2] = 1.0;
      half_m = size[1];
      break;
    default:
      return false;
  }
  // The axis in the world frame, and the end farther from from_W.
  const mjtNum* xmat = d->geom_xmat + 9 * g;
  const mjtNum* xpos = d->geom_xpos + 3 * g;
  double along = 0.0;
  for (int i = 0; i < 3; ++i) {
    double axis_W = 0.0;
    for (int j = 0; j < 3; ++j) axis_W += xmat[3 * i + j] * axis[j];
    along += axis_W * (xpos[i] - from_W[i]);
  }
  const double sign = along >= 0.0 ? 1.0 : -1.0;
  for (int j = 0; j < 3; ++j) local_m[j] = sign * half_m * axis[j];
  return true;
}

}  // namespace

void LinkTip::Position_W(const mjData* d, double position_m[3]) const {
  if (site >= 0) {
    for (int i = 0; i < 3; ++i) position_m[i] = d->site_xpos[3 * site + i];
    return;
  }
  const mjtNum* xmat = d->geom_xmat + 9 * geom;
  for (int i = 0; i < 3; ++i) {
    position_m[i] = d->geom_xpos[3 * geom + i];
    for (int j = 0; j < 3; ++j) position_m[i] += xmat[3 * i + j] * local_m[j];
  }
}

std::vector<LinkTip> LinkTips(const mjModel* m, const mjData* d, const std::string& source) {
  std::vector<LinkTip> tips;
  if (!IsAttached(d)) return tips;
  for (int q = 0; q < LinkCount(d); ++q) {
    LinkTip tip;
    tip.site = mj_name2id(m, mjOBJ_SITE, ("tip" + std::to_string(q + 1)).c_str());
    if (tip.site < 0) {
      const int hinge = LinkJoints(d, q).back();
      const int body = m->jnt_bodyid[hinge];
      for (int g = 0; g < m->ngeom && tip.geom < 0; ++g) {
        if (m->geom_bodyid[g] == body && FarEnd(m, d, g, d->xanchor + 3 * hinge, tip.local_m)) {
          tip.geom = g;
        }
      }
      if (tip.geom < 0) {
        throw std::runtime_error(source + ": link " + std::to_string(q + 1) +
                                 " has no site tip" + std::to_string(q + 1) +
                                 " and no box, capsule or cylinder on its last body (" +
                                 mj_id2name(m, mjOBJ_BODY, body) + ") to find its tip by");
      }
    }
    tips.push_back(tip);
  }
  return tips;
}

LinkSensors::LinkSensors(const mjModel* m, const mjData* d, const std::string& source) {
  if (!IsAttached(d) || LinkCount(d) == 0) {
    throw std::runtime_error(source + ": model has no IPMC actuators (custom text ipmc_links)");
  }
  tips_ = LinkTips(m, d, source);
  for (int q = 0; q < LinkCount(d); ++q) {
    const std::vector<int> joints = LinkJoints(d, q);
    const std::vector<double> segment_length_m = LinkSegmentLengths_m(d, q);
    LinkAngles link;
    for (size_t i = 0; i < joints.size(); ++i) {
      const std::string joint = m->names + m->name_jntadr[joints[i]];
      link.angle_adr.push_back(SensorAddress(m, "angle_" + joint));
      link.segment_length_mm.push_back(segment_length_m[i] * 1e3);
    }
    // Every hinge's sensor, or none of them: the angles from qpos.
    link.from_qpos = std::find(link.angle_adr.begin(), link.angle_adr.end(), -1) !=
                     link.angle_adr.end();
    if (link.from_qpos) {
      for (size_t i = 0; i < joints.size(); ++i) link.angle_adr[i] = m->jnt_qposadr[joints[i]];
    }
    links_.push_back(std::move(link));
    const int tip_adr = SensorAddress(m, "tip" + std::to_string(q + 1) + "_pos");
    tip_y_adr_.push_back(tip_adr < 0 ? -1 : tip_adr + 1);
  }
}

double LinkSensors::RelativeDeflection_mm(const mjData* d, int link) const {
  const LinkAngles& angles = links_[link];
  const mjtNum* values = angles.from_qpos ? d->qpos : d->sensordata;
  if (angles.angle_adr.size() == 1) {
    return angles.segment_length_mm[0] * std::sin(values[angles.angle_adr[0]]);
  }
  double angle_rad = 0.0, deflection_mm = 0.0;
  for (size_t j = 0; j < angles.angle_adr.size(); ++j) {
    angle_rad += values[angles.angle_adr[j]];
    deflection_mm += angles.segment_length_mm[j] * std::sin(angle_rad);
  }
  return deflection_mm;
}

double LinkSensors::TipLateral_mm(const mjData* d, int link) const {
  if (tip_y_adr_[link] >= 0) return d->sensordata[tip_y_adr_[link]] * 1e3;
  double tip_m[3];
  tips_[link].Position_W(d, tip_m);
  return tip_m[1] * 1e3;
}

}  // namespace ipmc
