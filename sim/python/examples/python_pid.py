"""The built-in PID run, with the PID written in Python.

Steps a scenario's model with ipmc_swim.Simulation and closes every link's
loop at the scenario's 1 kHz with PythonPid, a line-by-line transcription
of the PID of eq. 12 (controllers/pid.h: parallel form, backward-Euler
integral, backward-difference derivative, conditional-integration
anti-windup, +-V_max clamp). The loop is the built-in run's
(sim/runs/closed_loop_run.cc): at each sample the references, the measured
relative tip deflections, one controller update per link and the voltages
held until the next sample; a cycle's displacement at the end of each
cycle. So its per-cycle displacement is the built-in run's, which

    PYTHONPATH=build/sim/python /usr/bin/python3 sim/python/examples/python_pid.py \\
        scenarios/paper.toml --cycles 1

prints side by side (about 1 + 3 s for a 100 s cycle).
"""

import argparse
import math
import time

import ipmc_swim


class PythonPid:
    """u_k = Kp e_k + I_k + D_k at sample period T (controllers/pid.h):
    I_k = I_(k-1) + Ki T e_k, D_k = (Tf D_(k-1) + Kd (e_k - e_(k-1))) / (Tf + T);
    with the clamp, the integral advances into saturation only as far as the
    limit and holds if the output is already beyond it."""

    def __init__(self, kp, ki, kd, derivative_filter_s, sample_period_s, clamp, v_max_V):
        self.kp, self.ki, self.kd = kp, ki, kd
        self.filter_s = derivative_filter_s
        self.period_s = sample_period_s
        self.clamp = clamp
        self.v_max = v_max_V
        self.integral = 0.0
        self.derivative = 0.0
        self.previous_error = 0.0

    def update(self, error):
        self.derivative = ((self.filter_s * self.derivative + self.kd * (error - self.previous_error))
                           / (self.filter_s + self.period_s))
        self.previous_error = error
        proportional = self.kp * error
        increment = self.ki * self.period_s * error
        integral = self.integral + increment
        output = proportional + integral + self.derivative
        if self.clamp:
            headroom = math.copysign(self.v_max, increment) - proportional - self.derivative
            if increment > 0 and output > self.v_max:
                integral = max(self.integral, min(integral, headroom))
            elif increment < 0 and output < -self.v_max:
                integral = min(self.integral, max(integral, headroom))
            output = min(max(proportional + integral + self.derivative, -self.v_max), self.v_max)
        self.integral = integral
        return output


def run_python_pid(scenario, **overrides):
    """Runs the scenario with Python PIDs; returns the swim metrics (as
    summary.json has them) and the wall time of the loop [s]."""
    sim = ipmc_swim.Simulation(scenario, **overrides)
    c = sim.controller
    if c["kind"] != "pid" or c["actuation"] != "distributed":
        raise ValueError("this example closes the loop of a PID scenario with distributed actuation")
    # Each link's own gains (the scalar keys' unless the scenario sets them per link).
    pids = [PythonPid(kp, ki, kd, c["derivative_filter_s"], c["sample_period_s"],
                      c["clamp"], c["v_max_V"])
            for kp, ki, kd in zip(c["link_kp"], c["link_ki"], c["link_kd"])]
    steps_per_sample = sim.steps_per_sample
    start = time.perf_counter()
    for _ in range(sim.cycles):
        steps_left = sim.steps_per_cycle
        while steps_left > 0:
            references = sim.references_mm()
            measured = sim.relative_deflections_mm()
            sim.set_voltages([pid.update(r - y) for pid, r, y in zip(pids, references, measured)])
            steps = min(steps_per_sample, steps_left)
            sim.step(steps)
            steps_left -= steps
        sim.end_cycle()
    return sim.swim(), time.perf_counter() - start


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scenario", help="a PID scenario, e.g. scenarios/paper.toml")
    parser.add_argument("--cycles", type=int, default=1)
    args = parser.parse_args()
    swim, loop_s = run_python_pid(args.scenario, cycles=args.cycles)
    start = time.perf_counter()
    built_in = ipmc_swim.run(args.scenario, cycles=args.cycles).summary
    built_in_s = time.perf_counter() - start
    print(f"{'cycle':>5} {'python_pid_mm':>22} {'built_in_mm':>22} {'relative_difference':>20}")
    for ours, theirs in zip(swim["per_cycle"], built_in["per_cycle"]):
        a, b = ours["com_along_mm"], theirs["com_along_mm"]
        print(f"{ours['cycle']:>5} {a:>22.17g} {b:>22.17g} {abs(a - b) / abs(b):>20.3g}")
    print(f"wall time: Python PID loop {loop_s:.2f} s, built-in run {built_in_s:.2f} s")


if __name__ == "__main__":
    main()
