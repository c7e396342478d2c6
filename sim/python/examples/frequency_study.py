"""A small study from Python: how fast the flagellum swims against the wave's frequency.

Runs scenarios/paper.toml (PID, +-6 V, distributed actuation) at a few wave
frequencies, two runs at a time in threads (run() releases the GIL), and
draws the mean swimming speed and the fraction of samples link 3 spends at
the +-6 V clamp against the frequency, with link 3's tracking at the
highest frequency beside them:

    PYTHONPATH=build/sim/python /usr/bin/python3 sim/python/examples/frequency_study.py \\
        --out out/frequency_study.png

(2 cycles at 0.005, 0.01, 0.02 and 0.04 Hz; 24 s of CPU time.)
"""

import argparse
import concurrent.futures
import os

import matplotlib

matplotlib.use("Agg")  # files only, no display
import matplotlib.pyplot as plt  # noqa: E402

import ipmc_swim  # noqa: E402


def run_at(scenario, frequency_Hz, cycles):
    return ipmc_swim.run(scenario, cycles=cycles, **{"waveform.frequency_Hz": frequency_Hz})


def main():
    default_scenario = os.path.join(ipmc_swim.SCENARIOS_DIR or ".", "paper.toml")
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scenario", default=default_scenario)
    parser.add_argument("--frequencies-hz", type=float, nargs="+", default=[0.005, 0.01, 0.02, 0.04])
    parser.add_argument("--cycles", type=int, default=2)
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--out", default="frequency_study.png")
    args = parser.parse_args()

    with concurrent.futures.ThreadPoolExecutor(max_workers=args.jobs) as pool:
        results = list(pool.map(lambda f: run_at(args.scenario, f, args.cycles),
                                args.frequencies_hz))

    print(f"{'frequency_Hz':>12} {'mean_speed_along_mm_s':>22} {'last_cycle_mm':>14} {'link3_clamped_fraction':>23}")
    for f, r in zip(args.frequencies_hz, results):
        print(f"{f:>12g} {r.summary['mean_speed_along_mm_s']:>22.4g} "
              f"{r.cycles['com_along_mm'][-1]:>14.4g} {r.links['clamped_fraction'][-1]:>23.4f}")

    figure, (speed, tracking) = plt.subplots(1, 2, figsize=(10, 4))
    speed.plot(args.frequencies_hz, [r.summary["mean_speed_along_mm_s"] for r in results], "o-",
               label="mean speed")
    speed.set_xlabel("wave frequency [Hz]")
    speed.set_ylabel("mean speed along the axis [mm/s]")
    clamp = speed.twinx()
    clamp.plot(args.frequencies_hz, [100 * r.links["clamped_fraction"][-1] for r in results],
               "s--", color="tab:red", label="link 3 at the clamp")
    clamp.set_ylabel("link 3 samples at the +-6 V clamp [%]", color="tab:red")
    speed.set_title("PID, +-6 V, distributed actuation")

    last = results[-1].timeseries
    tracking.plot(last["time_s"], last["reference3_mm"], label="reference")
    tracking.plot(last["time_s"], last["measured3_mm"], label="measured")
    tracking.set_xlabel("time [s]")
    tracking.set_ylabel("link 3 relative tip deflection [mm]")
    tracking.set_title(f"link 3 at {args.frequencies_hz[-1]:g} Hz")
    tracking.legend()
    figure.tight_layout()
    os.makedirs(os.path.dirname(os.path.abspath(args.out)), exist_ok=True)
    partial = args.out + ".partial.png"  # the figure appears whole or not at all
    figure.savefig(partial, dpi=100)
    os.replace(partial, args.out)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
