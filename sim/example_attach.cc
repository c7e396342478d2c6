// Minimal use of the installed library: load a model, attach, step.
// Usage: example_attach MODEL.xml [steps]
#include <ipmc_swim/ipmc_swim.h>
#include <mujoco/mujoco.h>

#include <cstdio>
#include <cstdlib>
#include <exception>

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s MODEL.xml [steps]\n", argv[0]);
    return 2;
  }
  char error[1000] = "";
  mjModel* m = mj_loadXML(argv[1], nullptr, error, sizeof(error));
  if (!m) {
    std::fprintf(stderr, "%s: %s\n", argv[1], error);
    return 1;
  }
  mjData* d = nullptr;
  try {
    // The coupling keeps its state in the last values of mjData.userdata.
    m->nuserdata += ipmc::UserdataSize(m);
    d = mj_makeData(m);
    if (!ipmc::Attach(m, d)) std::printf("model has no ipmc_* fields: plain MuJoCo\n");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: %s\n", argv[1], e.what());
    return 1;
  }
  d->qvel[0] = 1e-3;  // push the root along x [m/s] and let the drag stop it
  const int steps = argc > 2 ? std::atoi(argv[2]) : 1000;
  for (int i = 0; i < steps; ++i) {
    if (!ipmc::Step(m, d)) {  // mj_step with the coupling; false if a callback failed
      std::fprintf(stderr, "%s: %s\n", argv[1], ipmc::LastError(d));
      return 1;
    }
  }
  std::printf("t = %g s, qvel[0] = %g m/s (library %s)\n", d->time, d->qvel[0], ipmc::Version());
  ipmc::Detach(d);
  mj_deleteData(d);
  mj_deleteModel(m);
  return 0;
}
