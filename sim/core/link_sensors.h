// What the test bench measures, read from the model's sensors: each IPMC
// link's relative tip deflection [mm], the tip's distance from the link's
// root tangent (the controller's measurement): L_q sin(theta_q) for a rigid
// link, sum_j l_j sin(theta_1 + ... + theta_j) for a chain of
// sub-segments (angles from the jointpos sensors angle_<joint>), and the
// lateral position of each tip [mm] (the laser; framepos sensor tipq_pos).
// MuJoCo fills sensordata during mj_step's forward pass, so after a step
// the values describe the state at the start of that step: a sensor delay
// of one time step.
#pragma once

#include <mujoco/mujoco.h>

#include <string>
#include <vector>

namespace ipmc {

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
    std::vector<int> angle_adr;  // one per hinge of the link, root first
    std::vector<double> segment_length_mm;
  };
  std::vector<LinkAngles> links_;
  std::vector<int> tip_y_adr_;
};

}  // namespace ipmc
