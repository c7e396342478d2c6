"""Ctrl-C stops run(), sweep() and bench() at a safe point, as it stops the
command line: the work runs without the GIL while the calling thread looks
for signals (convert.h, Interruptible), so SIGINT raises KeyboardInterrupt
at the next recorded sample of a run or bench, or between a sweep's
points, and nothing is written but a sweep's journal, which the command
line resumes to the uninterrupted table. SIGTERM and SIGHUP stop the call
the same way where the program handles them (a Python handler that
raises; without one Python's default ends the interpreter). Each call
runs in a child interpreter that reports its first progress and waits
there until the signal's handler has run; the test sends the signal then
and waits a bounded time for the child to end. design() has no progress
to report: Ctrl-C stops its tuning at the next evaluation of J, within a
second of the signal."""

import os
import signal
import subprocess
import sys
import time
from contextlib import contextmanager

import pytest

from conftest import SOURCE_DIR, run_cli

MODELS = SOURCE_DIR / "models"

# 300 s of swimming at 0.5 ms steps: minutes of work, stopped in seconds.
LONG_SCENARIO = f"""
model = "{MODELS / 'flagellum3.xml'}"
cycles = 3
timestep_s = 5e-4
[controller]
kind = "pid"
[waveform]
frequency_Hz = 0.01
[output]
samples_per_cycle = 20
"""

# Six points of one 1 s cycle each, run one at a time.
SHORT_POINT = LONG_SCENARIO.replace("cycles = 3", "cycles = 1").replace(
    "frequency_Hz = 0.01", "frequency_Hz = 1.0")
SWEEP = ('base = "point.toml"\n[grid]\n"waveform.frequency_Hz" = '
         '[1.0, 0.9, 0.8, 0.7, 0.6, 0.5, 0.45, 0.4, 0.35, 0.3]\n')

CALLS = {
    "run": "ipmc_swim.run('long.toml', out='out', progress=progress)",
    "sweep": "ipmc_swim.sweep('sweep.toml', jobs=1, out='out/table', progress=progress)",
    "bench": ("ipmc_swim.bench(os.path.join(ipmc_swim.MODELS_DIR, 'flagellum3_clamped.xml'), "
              "duration_s=2000, out='out/bench.csv', progress=progress)"),
}

# The first progress report waits until the signal's handler has run, so
# the call is stopped at its next safe point whatever the machine's load
# (a sweep's points would otherwise go on while the signal is on its way).
# SIGINT keeps Python's own handler, which raises KeyboardInterrupt.
PROGRAM = """
import os, signal, sys, threading
import ipmc_swim
seen = threading.Event()
def stop(signum, frame):
    seen.set()
    raise KeyboardInterrupt
def interrupt(signum, frame):
    seen.set()
    signal.default_int_handler(signum, frame)
signal.signal(signal.SIGINT, interrupt)
signal.signal(signal.SIGTERM, stop)
signal.signal(signal.SIGHUP, stop)
calls = []
def progress(done, total):
    calls.append(done)
    print(f"progress {{done}} {{total}}", flush=True)
    if len(calls) == 1:
        seen.wait({wait_s})
try:
    {call}
except KeyboardInterrupt:
    print(f"interrupted after {{len(calls)}} reports", flush=True)
    sys.exit(130)
print("finished", flush=True)
"""

STOP_TIMEOUT_S = 60


@contextmanager
def child_interpreter(program, cwd):
    """A child Python running `program` in cwd (text pipes), killed if it
    still runs when the block ends."""
    child = subprocess.Popen([sys.executable, "-c", program], cwd=cwd, stdout=subprocess.PIPE,
                             stderr=subprocess.PIPE, text=True, env=os.environ)
    try:
        yield child
    finally:
        if child.poll() is None:
            child.kill()
            child.communicate()


@pytest.mark.parametrize("sent", ["SIGINT", "SIGTERM", "SIGHUP"])
@pytest.mark.parametrize("function", sorted(CALLS))
def test_a_signal_stops_the_call_at_a_safe_point(tmp_path, function, sent):
    (tmp_path / "long.toml").write_text(LONG_SCENARIO)
    (tmp_path / "point.toml").write_text(SHORT_POINT)
    (tmp_path / "sweep.toml").write_text(SWEEP)
    program = PROGRAM.format(call=CALLS[function], wait_s=STOP_TIMEOUT_S)
    with child_interpreter(program, tmp_path) as child:
        first = child.stdout.readline()
        assert first.startswith("progress "), first + child.stderr.read()
        if function == "sweep":  # the first report comes after the first point
            total = int(float(first.split()[2]))
        child.send_signal(getattr(signal, sent))
        stdout, stderr = child.communicate(timeout=STOP_TIMEOUT_S)
    assert child.returncode == 130, stdout + stderr
    assert "interrupted after" in stdout, stdout + stderr
    assert "finished" not in stdout
    if function == "sweep":
        reports = [line for line in (first + stdout).splitlines() if line.startswith("progress")]
        assert int(float(reports[-1].split()[1])) < total, "every point ran"
    # Nothing written: no table, no run folder, no bench CSV, no temporary;
    # a sweep's journal holds the points that finished.
    left = sorted(p.relative_to(tmp_path).as_posix() for p in (tmp_path / "out").rglob("*")) \
        if (tmp_path / "out").exists() else []
    assert left == (["out/table.journal"] if function == "sweep" else []), left
    if function == "sweep":
        # The command line goes on from the journal: the uninterrupted table.
        _, _, stderr = run_cli("sweep", tmp_path / "sweep.toml", "--out", tmp_path / "out/table",
                               "--jobs", "1")
        assert "points done before" in stderr, stderr
        run_cli("sweep", tmp_path / "sweep.toml", "--out", tmp_path / "whole/table", "--jobs", "1")
        for suffix in (".csv", ".json"):
            assert (tmp_path / f"out/table{suffix}").read_bytes() == \
                (tmp_path / f"whole/table{suffix}").read_bytes(), suffix


# design() in a 10 kHz loop tunes for about 8 s a link (its 1 kHz default
# less than one); the child reports when the call has begun, and how long
# after the parent's signal it raised.
DESIGN_PROGRAM = """
import os, sys, time
import ipmc_swim
print("designing", flush=True)
try:
    ipmc_swim.design(out="gains.toml", sample_rate_Hz=10000.0)
except KeyboardInterrupt:
    print(f"interrupted at {time.monotonic()!r}", flush=True)
    sys.exit(130)
print("finished", flush=True)
"""
# The tuning evaluates J every few ms and the call looks for signals every
# 0.1 s: a Ctrl-C ends it within a second, as it ends the command line's.
DESIGN_STOP_S = 1.0
DESIGN_STARTED_S = 2.0  # the call is well into its tuning then


def test_ctrl_c_stops_design_within_a_second(tmp_path):
    with child_interpreter(DESIGN_PROGRAM, tmp_path) as child:
        assert child.stdout.readline() == "designing\n"
        time.sleep(DESIGN_STARTED_S)
        assert child.poll() is None, "design ended before the signal"
        sent = time.monotonic()
        child.send_signal(signal.SIGINT)
        stdout, stderr = child.communicate(timeout=STOP_TIMEOUT_S)
    assert child.returncode == 130, stdout + stderr
    assert "finished" not in stdout
    stopped = float(stdout.split("interrupted at ")[1])
    assert stopped - sent < DESIGN_STOP_S, f"stopped {stopped - sent:.2f} s after Ctrl-C"
    assert list(tmp_path.iterdir()) == [], "an interrupted design wrote gains.toml"
