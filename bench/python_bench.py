"""Benchmark of the Python module against the program and the built-in controller.

1. run() against the command line: ipmc_swim.run(SCENARIO, out=DIR) in this
   process and `ipmc-swim run SCENARIO --out DIR` as a child process, both
   writing timeseries.csv and summary.json, --repeats pairs run back to back
   (in turn first). The median of the pairs' ratios is run()'s overhead
   (target: < 5 %).
2. A controller in Python at 1 kHz against the built-in one: the same
   scenario for one cycle with the Python PID of
   sim/python/examples/python_pid.py (the built-in loop, stepped through
   ipmc_swim.Simulation) and with ipmc_swim.run(); cost per controller
   sample (two 0.5 ms physics steps in the paper scenario).

CPU time (user + system, of this process or of the child) holds better
than wall time on a loaded machine, both are printed. Run from the project
folder:

    PYTHONPATH=build/sim/python /usr/bin/python3 bench/python_bench.py [--repeats 3]

With --callgrind CYCLES, part 1 also counts the instructions of the two
(valgrind's callgrind, which no other load on the machine changes) on the
scenario cut to CYCLES cycles: the program's main() against run()'s
binding, each writing the two files (about 15 min for one paper cycle).
"""

import argparse
import os
import pathlib
import re
import resource
import statistics
import subprocess
import sys
import tempfile
import time

ROOT = pathlib.Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "sim" / "python" / "examples"))

import ipmc_swim  # noqa: E402
import python_pid  # noqa: E402


def children_cpu_s():
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def timed_cli(cli, scenario, out):
    cpu, wall = children_cpu_s(), time.perf_counter()
    subprocess.run([cli, "run", scenario, "--out", out], check=True, stdout=subprocess.DEVNULL)
    return children_cpu_s() - cpu, time.perf_counter() - wall


def instructions(command, toggle, env=None):
    """Instructions executed inside the functions matching `toggle`."""
    done = subprocess.run(["valgrind", "--tool=callgrind", "--callgrind-out-file=/dev/null",
                           f"--toggle-collect={toggle}", *command], env=env, check=True,
                          stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    return int(re.search(r"Collected : (\d+)", done.stderr).group(1))


def count_instructions(cli, scenario, cycles, work):
    """The program's main() and run()'s binding on `scenario` cut to `cycles`."""
    text = pathlib.Path(scenario).read_text()
    text = re.sub(r"^cycles = \d+", f"cycles = {cycles}", text, flags=re.M)
    folder = pathlib.Path(scenario).resolve().parent  # the model is relative to it
    text = re.sub(r'^model = "(.*)"', lambda m: f'model = "{folder / m.group(1)}"', text, flags=re.M)
    cut = os.path.join(work, "cut.toml")
    pathlib.Path(cut).write_text(text)
    program = instructions([cli, "run", cut, "--out", os.path.join(work, "cg_cli")], "main")
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(sys.path))
    code = f"import ipmc_swim; ipmc_swim.run({cut!r}, out={os.path.join(work, 'cg_py')!r})"
    module = instructions([sys.executable, "-c", code], "ipmc::python::*Run*", env)
    print(f"instructions, {cycles} cycle(s): ipmc-swim run {program}, ipmc_swim.run {module}, "
          f"ratio {module / program:.5f}")


def timed(call):
    cpu, wall = time.process_time(), time.perf_counter()
    value = call()
    return (time.process_time() - cpu, time.perf_counter() - wall), value


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scenario", default=str(ROOT / "scenarios" / "paper.toml"))
    parser.add_argument("--cli", default=str(ROOT / "build" / "sim" / "ipmc-swim"))
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--callgrind", type=int, metavar="CYCLES", default=0)
    args = parser.parse_args()

    cli_times, run_times = [], []
    with tempfile.TemporaryDirectory() as work:
        for k in range(args.repeats):
            for which in ("cli", "python") if k % 2 == 0 else ("python", "cli"):
                out = os.path.join(work, f"{which}{k}")
                if which == "cli":
                    cli_times.append(timed_cli(args.cli, args.scenario, out))
                else:
                    run_times.append(timed(lambda: ipmc_swim.run(args.scenario, out=out))[0])
        report("run() against the command line, " + args.scenario, args.repeats,
               ("ipmc-swim run", cli_times, 1.0, "s"), ("ipmc_swim.run", run_times, 1.0, "s"))
        if args.callgrind > 0:
            count_instructions(args.cli, args.scenario, args.callgrind, work)

    sim = ipmc_swim.Simulation(args.scenario, cycles=1)
    samples = -(-sim.steps_per_cycle // sim.steps_per_sample)
    python_times, builtin_times = [], []
    for k in range(args.repeats):
        for which in ("built-in", "python") if k % 2 == 0 else ("python", "built-in"):
            if which == "python":
                python_times.append(
                    timed(lambda: python_pid.run_python_pid(args.scenario, cycles=1))[0])
            else:
                builtin_times.append(timed(lambda: ipmc_swim.run(args.scenario, cycles=1))[0])
    report(f"controller at {1 / sim.sample_period_s:g} Hz, one {sim.period_s:g} s cycle "
           f"({samples} samples of {sim.steps_per_sample} steps), per sample", args.repeats,
           ("built-in PID", builtin_times, 1e6 / samples, "us"),
           ("Python PID", python_times, 1e6 / samples, "us"))


def report(title, repeats, first, second):
    """Medians of each and the median of the ratios of the pairs run
    back to back (which share the machine's load)."""
    print(f"{title}, medians of {repeats}:")
    for name, times, scale, unit in (first, second):
        print(f"  {name}: {statistics.median(t[0] for t in times) * scale:.3f} {unit} CPU, "
              f"{statistics.median(t[1] for t in times) * scale:.3f} {unit} wall")
    for k, measure in enumerate(("CPU", "wall")):
        ratios = [b[k] / a[k] for a, b in zip(first[1], second[1])]
        print(f"  ratio {second[0]} / {first[0]}, {measure}: median {statistics.median(ratios):.4f} "
              f"(pairs: {', '.join(f'{r:.3f}' for r in ratios)})")


if __name__ == "__main__":
    main()
