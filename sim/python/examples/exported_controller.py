"""The exported controller (ipmc-swim export) compiled and checked.

Compiles DIR/ipmc_controller.c with the system C compiler (double, or
float with --float) into a shared library and runs it, from Python
(ctypes), in the two checks of docs/PROTOTYPE.md:

  --replay RUN_DIR   every recorded sample of a run's timeseries.csv (its
                     references and measurements) through the exported
                     update; prints the largest difference from the run's
                     voltages per link. The run must record every
                     controller sample (output.samples_per_cycle at least
                     the samples of a cycle).
  --loop SCENARIO    the scenario's run with the exported controller
                     closing the loop on the simulated robot (the built-in
                     run's loop, as python_pid.py), beside the built-in
                     controller's run: the per-cycle swim of both.

    build/sim/ipmc-swim export scenarios/paper.toml --out out/export
    PYTHONPATH=build/sim/python /usr/bin/python3 sim/python/examples/exported_controller.py \\
        out/export --loop scenarios/paper.toml --cycles 1
"""

import argparse
import csv
import ctypes
import os
import pathlib
import shutil
import subprocess
import tempfile

# What the test program needs beyond the exported API: the state's size
# and the update with double arguments (converted as a float build's caller
# would convert its sensor readings).
_SHIM = r"""
#include "ipmc_controller.h"
unsigned long shim_state_size(void) { return sizeof(ipmc_controller_state); }
int shim_links(void) { return IPMC_CONTROLLER_LINKS; }
double shim_sample_rate_hz(void) { return IPMC_CONTROLLER_SAMPLE_RATE_HZ; }
int shim_real_size(void) { return (int)sizeof(ipmc_real); }
double shim_update(ipmc_controller_state* s, int link, double reference_mm, double measured_mm) {
    return (double)ipmc_controller_update(s, link, (ipmc_real)reference_mm, (ipmc_real)measured_mm);
}
"""


class ExportedController:
    """DIR's ipmc_controller.c compiled (in a temporary folder) and loaded."""

    def __init__(self, export_dir, use_float=False, compiler=None):
        export_dir = pathlib.Path(export_dir)
        compiler = compiler or os.environ.get("CC") or shutil.which("cc") or "gcc"
        self._build = tempfile.mkdtemp(prefix="ipmc_controller_")
        shim = pathlib.Path(self._build) / "shim.c"
        shim.write_text(_SHIM)
        library = pathlib.Path(self._build) / "libipmc_controller.so"
        # C99 with every warning an error; no FMA contraction (the
        # simulator's doubles are computed without it).
        command = [compiler, "-std=c99", "-O2", "-Wall", "-Wextra", "-pedantic", "-Werror",
                   "-ffp-contract=off", "-shared", "-fPIC", "-I", str(export_dir),
                   str(export_dir / "ipmc_controller.c"), str(shim), "-o", str(library)]
        if use_float:
            command.insert(1, "-DIPMC_CONTROLLER_FLOAT")
        subprocess.run(command, check=True)
        self._lib = ctypes.CDLL(str(library))
        self._lib.shim_state_size.restype = ctypes.c_ulong
        self._lib.shim_sample_rate_hz.restype = ctypes.c_double
        self._lib.shim_update.restype = ctypes.c_double
        self._lib.shim_update.argtypes = [ctypes.c_void_p, ctypes.c_int, ctypes.c_double,
                                          ctypes.c_double]
        self._lib.ipmc_controller_reset.argtypes = [ctypes.c_void_p]
        self.links = self._lib.shim_links()
        self.sample_rate_Hz = self._lib.shim_sample_rate_hz()
        self.real_bytes = self._lib.shim_real_size()
        self._state = ctypes.create_string_buffer(self._lib.shim_state_size())
        self.reset()

    def reset(self):
        self._lib.ipmc_controller_reset(self._state)

    def update(self, link, reference_mm, measured_mm):
        """The voltage [V] of `link` (0-based) for this sample."""
        return self._lib.shim_update(self._state, link, reference_mm, measured_mm)

    def close(self):
        shutil.rmtree(self._build, ignore_errors=True)


def replay(controller, run_dir):
    """Each link's largest |exported - recorded| voltage [V] over the run's
    timeseries.csv, and the number of samples."""
    with open(pathlib.Path(run_dir) / "timeseries.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    period_s = 1.0 / controller.sample_rate_Hz
    times = [float(row["time_s"]) for row in rows]
    for earlier, later in zip(times, times[1:]):
        if abs(later - earlier - period_s) > 1e-6 * period_s:
            raise ValueError(f"{run_dir}: timeseries.csv holds a row every {later - earlier:g} s, "
                             f"not every controller sample ({period_s:g} s): run it with "
                             "output.samples_per_cycle at least the samples of a cycle")
    links = sum(1 for name in rows[0] if name.startswith("voltage"))
    worst = [0.0] * links
    controller.reset()
    for row in rows:
        for q in range(links):
            u = controller.update(q, float(row[f"reference{q + 1}_mm"]),
                                  float(row[f"measured{q + 1}_mm"]))
            worst[q] = max(worst[q], abs(u - float(row[f"voltage{q + 1}_V"])))
    return worst, len(rows)


def close_loop(controller, scenario, **overrides):
    """The scenario's run with `controller` at every sample (the built-in
    run's loop); returns the swim metrics as summary.json has them and every
    sample's voltages."""
    import ipmc_swim

    sim = ipmc_swim.Simulation(scenario, **overrides)
    if abs(sim.sample_period_s * controller.sample_rate_Hz - 1.0) > 1e-12:
        raise ValueError(f"the exported controller runs at {controller.sample_rate_Hz:g} Hz, "
                         f"the scenario at {1.0 / sim.sample_period_s:g} Hz")
    controller.reset()
    voltages = []
    for _ in range(sim.cycles):
        steps_left = sim.steps_per_cycle
        while steps_left > 0:
            references = sim.references_mm()
            measured = sim.relative_deflections_mm()
            volts = [controller.update(q, references[q], measured[q]) for q in range(sim.links)]
            voltages.append(volts)
            sim.set_voltages(volts)
            steps = min(sim.steps_per_sample, steps_left)
            sim.step(steps)
            steps_left -= steps
        sim.end_cycle()
    return sim.swim(), voltages


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("export_dir", help="the folder ipmc-swim export wrote")
    parser.add_argument("--float", action="store_true", help="compile with -DIPMC_CONTROLLER_FLOAT")
    parser.add_argument("--replay", metavar="RUN_DIR", help="a run recorded at every sample")
    parser.add_argument("--loop", metavar="SCENARIO", help="the scenario exported")
    parser.add_argument("--cycles", type=int, help="with --loop: cycles to run")
    args = parser.parse_args()
    controller = ExportedController(args.export_dir, use_float=args.float)
    real = "float" if controller.real_bytes == 4 else "double"
    try:
        if args.replay:
            worst, samples = replay(controller, args.replay)
            print(f"replayed {samples} samples ({real}): largest |u - recorded u| per link [V]:")
            for q, value in enumerate(worst):
                print(f"  link {q + 1}: {value:.3g}")
        if args.loop:
            import ipmc_swim

            overrides = {} if args.cycles is None else {"cycles": args.cycles}
            swim, _ = close_loop(controller, args.loop, **overrides)
            built_in = ipmc_swim.run(args.loop, **overrides).summary
            print(f"{'cycle':>5} {'exported_' + real + '_mm':>22} {'built_in_mm':>22} "
                  f"{'relative_difference':>20}")
            for ours, theirs in zip(swim["per_cycle"], built_in["per_cycle"]):
                a, b = ours["com_along_mm"], theirs["com_along_mm"]
                print(f"{ours['cycle']:>5} {a:>22.17g} {b:>22.17g} {abs(a - b) / abs(b):>20.3g}")
    finally:
        controller.close()


if __name__ == "__main__":
    main()
