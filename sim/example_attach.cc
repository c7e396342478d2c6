// The library used alone, as a MuJoCo user would: load a model with ipmc_*
// fields, attach, drive its IPMC links, branch with mj_copyData, read the
// fluid's forces and change the viscosity. Usage: example_attach MODEL.xml [steps]
#include <ipmc_swim/ipmc_swim.h>
#include <mujoco/mujoco.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <stdexcept>
#include <vector>

// `steps` steps of a travelling wave: 1 V at 1 Hz, each link a quarter
// period behind the one before. False (and the reason) if a step failed.
static bool Swim(const mjModel* m, mjData* d, int steps) {
  const int links = ipmc::LinkCount(d);
  std::vector<double> voltage_V(links);
  for (int i = 0; i < steps; ++i) {
    for (int q = 0; q < links; ++q) voltage_V[q] = std::sin(2 * M_PI * d->time - q * M_PI / 2);
    ipmc::SetVoltages(d, voltage_V.data(), links);
    if (!ipmc::Step(m, d)) {  // mj_step with the coupling; false on divergence
      std::fprintf(stderr, "%s\n", ipmc::LastError(d));
      return false;
    }
  }
  return true;
}

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
  const int steps = argc > 2 ? std::atoi(argv[2]) : 1000;
  try {
    m->nuserdata += ipmc::UserdataSize(m);  // the coupling's state lives in mjData.userdata
    mjData* d = mj_makeData(m);
    if (!ipmc::Attach(m, d)) throw std::runtime_error("the model has no ipmc_* fields");
    std::printf("%d IPMC links (library %s)\n", ipmc::LinkCount(d), ipmc::Version());
    if (!Swim(m, d, steps)) return 1;

    // A branch: a copy of d, attached (it takes the state d holds), goes on as d does.
    mjData* branch = mj_copyData(nullptr, m, d);
    ipmc::Attach(m, branch);
    if (!Swim(m, d, steps) || !Swim(m, branch, steps)) return 1;
    bool identical = true;
    for (int i = 0; i < m->nq; ++i) identical = identical && branch->qpos[i] == d->qpos[i];
    std::printf("branch after %d more steps: %s\n", steps, identical ? "identical" : "differs");

    // The fluid's force on each body (world frame, N) and the power it takes.
    for (const ipmc::BodyFluidForce& f : ipmc::FluidForces(m, d)) {
      std::printf("body %d: fluid force (%.3e, %.3e, %.3e) N\n", f.body, f.force_N[0],
                  f.force_N[1], f.force_N[2]);
    }
    const double power_W = ipmc::FluidPower_W(m, d);
    // A parameter through the API: the branch swims on in a liquid 1000x as viscous.
    ipmc::SetFluidField(branch, "ipmc_rft_viscosity_Pa_s", 1.0);
    if (!Swim(m, d, steps) || !Swim(m, branch, steps)) return 1;
    std::printf("fluid power %.4e W; t = %g s, qvel[0] = %g m/s, in 1 Pa s %g m/s\n", power_W,
                d->time, d->qvel[0], branch->qvel[0]);
    ipmc::Detach(branch);
    ipmc::Detach(d);
    mj_deleteData(branch);
    mj_deleteData(d);
  } catch (const std::exception& e) {  // a malformed ipmc_* field, one line
    std::fprintf(stderr, "%s: %s\n", argv[1], e.what());
    return 1;
  }
  mj_deleteModel(m);
  return 0;
}
