// What the test bench measures, read from the model's sensors: each IPMC
// link's relative tip deflection [mm], the tip's distance from the link's
// root tangent (the controller's measurement): L_q sin(theta_q) for a rigid
// link, sum_j l_j sin(theta_1 + ... + theta_j) for a chain of
// sub-segments (angles from the jointpos sensors angle_<joint>), and the
// lateral position of each tip [mm] (the laser; framepos sensor tipq_pos).
// MuJoCo fills sensordata during mj_step's forward pass, so after a step
// the values describe the state at the start of that step: a sensor delay
// of one time step. A model without those sensors is measured without the
// delay: the hinge angles from qpos, the tip from LinkTips.
#pragma once

#include <mujoco/mujoco.h>

#include <string>
#include <vector>

namespace ipmc {

// A point fixed on a body that stands for an IPMC link's tip: the site
// tip<q> where the model has one (the paper's naming), else the far end of
// the geom of the link's last body, the end farther from the link's last
// hinge at rest: along a box's longest side, a capsule's or cylinder's
// axis (a capsule's end cap included).
struct LinkTip {
  int site = -1;                     // tip<q>, or -1
  int geom = -1;                     // else the geom, and the point in its frame
  double local_m[3] = {0, 0, 0};
  int Body(const mjModel* m) const {
    return site >= 0 ? m->site_bodyid[site] : m->geom_bodyid[geom];
  }
  // The point in the world frame [m] from d's kinematics.
  void Position_W(const mjData* d, double position_m[3]) const;
};

// Every IPMC link's tip, in link order, for an attached d (after
// kinematics); none for a d without IPMC actuators. Throws
// std::runtime_error naming `source` and the link if a link without a
// tip<q> site has no box, capsule or cylinder on its last body.
std::vector<LinkTip> LinkTips(const mjModel* m, const mjData* d, const std::string& source);

class LinkSensors {
 public:
  // Throws std::runtime_error naming `source` if d has no IPMC actuators or
  // a sensor is missing.
  LinkSensors(const mjModel* m, const mjData* d, const std::string& source);

  int Links() const { return static_cast<int>(links_.size()); }
  double RelativeDeflection_mm(const mjData* d, int link) const;
  double TipLateral_mm(const mjData* d, int link) const;

 private:
  struct LinkAngles {
    // One per hinge of the link, root first: in sensordata, or (no
    // angle_<joint> sensor) in qpos.
    std::vector<int> angle_adr;
    bool from_qpos = false;
    std::vector<double> segment_length_mm;
  };
  std::vector<LinkAngles> links_;
  std::vector<int> tip_y_adr_;  // in sensordata; -1: tips_ instead
  std::vector<LinkTip> tips_;
};

}  // namespace ipmc
