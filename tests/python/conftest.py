"""Shared fixtures of the Python tests (run by CTest, tests/CMakeLists.txt).

IPMC_SWIM_CLI is the ipmc-swim program of the same build, IPMC_SWIM_SOURCE_DIR
the project; the module is imported from the build tree (PYTHONPATH).
"""

import os
import pathlib
import shutil
import subprocess

import pytest

SOURCE_DIR = pathlib.Path(os.environ.get("IPMC_SWIM_SOURCE_DIR", pathlib.Path(__file__).parents[2]))
CLI = os.environ.get("IPMC_SWIM_CLI", str(SOURCE_DIR / "build" / "sim" / "ipmc-swim"))

# scenarios/paper.toml made quick: 10 s cycles (0.1 Hz), two of them.
SHORT_SCENARIO = f"""
model = "{SOURCE_DIR / 'models' / 'flagellum3.xml'}"
plants = "uniform"
actuation = "distributed"
cycles = 2
timestep_s = 5e-4

[controller]
kind = "pid"
sample_rate_Hz = 1000.0
v_max_V = 6.0
clamp = true
kp = 8.12
ki = 53.36
kd = 0.61

[waveform]
kind = "polynomial"
c1_um_per_mm = 200.0
frequency_Hz = 0.1
wavelength_mm = 32.0
start_ramp_cycles = 0.25

[fluid]
viscosity_Pa_s = 1e-3

[output]
samples_per_cycle = 50
"""


def run_cli(*args, check=True):
    """Runs ipmc-swim; returns (exit status, stdout, stderr)."""
    done = subprocess.run([CLI, *map(str, args)], capture_output=True, text=True)
    if check and done.returncode != 0:
        raise AssertionError(f"ipmc-swim {' '.join(map(str, args))} failed: {done.stderr}")
    return done.returncode, done.stdout, done.stderr


def cli_error(*args):
    """The one-line message ipmc-swim prints for a failing command."""
    status, _, stderr = run_cli(*args, check=False)
    assert status != 0
    lines = [line for line in stderr.splitlines() if line.startswith("ipmc-swim: error: ")]
    assert len(lines) == 1, stderr
    return lines[0][len("ipmc-swim: error: "):]


# How a second writer into one output is refused (docs/RUNS.md, "Two
# writers into one output"): a run while another run holds its folder; a
# sweep while another sweep runs into its prefix, or once another sweep has
# finished into it (its journal stays, and records that other sweep).
RUN_IN_USE = "in use by another run (one run per output directory)"
SWEEP_REFUSALS = ("in use by another running sweep (one sweep per output prefix at a time)",
                  "records another sweep")


def is_sweep_refusal(message):
    return any(refusal in message for refusal in SWEEP_REFUSALS)


# A sweep table's files, and their bytes for a prefix.
TABLE_FILES = [".csv", ".json"]


def table_files(prefix):
    return {suffix: prefix.with_name(prefix.name + suffix).read_bytes() for suffix in TABLE_FILES}


# Three one-cycle points of SHORT_SCENARIO.
THREE_POINT_SWEEP = ('base = "short.toml"\n[set]\ncycles = 1\n[grid]\n'
                     '"waveform.frequency_Hz" = [0.5, 0.4, 0.3]\n')


@pytest.fixture(scope="module")
def shards(tmp_path_factory):
    """The shards 1/2 and 2/2 of THREE_POINT_SWEEP, from the command line:
    the folder and the two shard tables."""
    folder = tmp_path_factory.mktemp("shards")
    (folder / "short.toml").write_text(SHORT_SCENARIO)
    (folder / "sweep.toml").write_text(THREE_POINT_SWEEP)
    for k in (1, 2):
        run_cli("sweep", folder / "sweep.toml", "--shard", f"{k}/2", "--out",
                folder / f"shard_{k}", "--jobs", "1")
    return folder, [folder / "shard_1.csv", folder / "shard_2.csv"]


@pytest.fixture
def short_scenario(tmp_path):
    path = tmp_path / "short.toml"
    path.write_text(SHORT_SCENARIO)
    return path


def pytest_sessionfinish(session):
    """Removes tmp_path's folders with the session when CTest names them
    (--basetemp, tests/CMakeLists.txt): pytest keeps them otherwise."""
    basetemp = session.config.option.basetemp
    if basetemp:
        shutil.rmtree(basetemp, ignore_errors=True)
