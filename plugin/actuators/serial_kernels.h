// Serial N_Vector kernels compiled with the project, installed on the
// vector that the actuators' CVODE integrates
// (plugin/actuators/cvode_integrator.cc). Why they exist: see serial_kernels.cc.
#ifndef IPMC_SWIM_PLUGIN_SERIAL_KERNELS_H_
#define IPMC_SWIM_PLUGIN_SERIAL_KERNELS_H_

#include <nvector/nvector_serial.h>

namespace ipmc::serial_kernels {

// Replaces the operations of the serial vector v listed below with the
// project's loops. Vectors cloned from v afterwards (N_VClone copies the
// operations; CVODE makes all its work vectors so) use them too; other
// vectors are untouched. Each computes what its N_V*_Serial counterpart
// defines: the same value, except that N_VLinearSum for a = +-b (|a| != 1)
// forms a x + b y where N_VLinearSum_Serial forms a (x +- y), and so
// N_VLinearCombination with two vectors and c[0] = +-c[1] (a few units in
// the last place). Aliased arguments (z == x, Z == Y) behave as in
// SUNDIALS.
//
//   linearsum const prod div scale abs inv addconst dotprod maxnorm
//   wrmsnorm wrmsnormmask min wl2norm l1norm compare invtest
//   linearcombination scaleaddmulti scalevectorarray
//   dotprodlocal maxnormlocal minlocal l1normlocal invtestlocal
//   wsqrsumlocal wsqrsummasklocal
void Install(N_Vector v);

}  // namespace ipmc::serial_kernels

#endif  // IPMC_SWIM_PLUGIN_SERIAL_KERNELS_H_
