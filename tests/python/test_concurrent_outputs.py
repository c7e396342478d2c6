"""Two writers at once into one output never mix their files: two runs into
one folder (the command line's, or Python's and the command line's), two
sweeps into one table prefix. Each case is tried 25 times and must hold
every time: the second writer is refused while the first holds the output
(sim/io/files.h DirectoryLock, the sweep journal's lock), or, for a sweep,
because the first one's finished journal records another sweep; or it
replaces the first one's files whole. Never one writer's file beside the
other's."""

import subprocess
import threading

import pytest

import ipmc_swim
from conftest import CLI, SHORT_SCENARIO, run_cli, table_files

TRIES = 25
RUN_FILES = ["timeseries.csv", "states.csv", "summary.json"]

# Two runs of the short scenario that differ in every file.
RUN_A = ["--cycles", "1", "--set", "waveform.frequency_Hz=0.5"]
RUN_B = ["--cycles", "1", "--set", "waveform.frequency_Hz=0.4"]
# Two sweeps of one point each that differ in every file.
SWEEP_A = 'base = "short.toml"\n[set]\ncycles = 1\n[grid]\n"waveform.frequency_Hz" = [0.5]\n'
SWEEP_B = 'base = "short.toml"\n[set]\ncycles = 1\n[grid]\n"waveform.frequency_Hz" = [0.4]\n'

REFUSED = ("in use by another run", "in use by another running sweep",
           # a second sweep that starts once the first has finished
           "records another sweep")


def run_files(folder):
    return {name: (folder / name).read_bytes() for name in RUN_FILES}


@pytest.fixture(scope="module")
def references(tmp_path_factory):
    folder = tmp_path_factory.mktemp("references")
    (folder / "short.toml").write_text(SHORT_SCENARIO)
    (folder / "a.toml").write_text(SWEEP_A)
    (folder / "b.toml").write_text(SWEEP_B)
    runs, tables = {}, {}
    for name, args in (("a", RUN_A), ("b", RUN_B)):
        run_cli("run", folder / "short.toml", "--out", folder / f"run_{name}", *args)
        runs[name] = run_files(folder / f"run_{name}")
        run_cli("sweep", folder / f"{name}.toml", "--out", folder / f"table_{name}", "--jobs", "1")
        tables[name] = table_files(folder / f"table_{name}")
    # Python's run A: the same results, its own record of how it was asked
    # for in summary.json's inputs (keyword overrides, not --set).
    python_run_a(folder / "short.toml", folder / "run_python_a")
    runs["python_a"] = run_files(folder / "run_python_a")
    assert runs["a"]["timeseries.csv"] != runs["b"]["timeseries.csv"]
    assert tables["a"][".csv"] != tables["b"][".csv"]
    return folder, runs, tables


def python_run_a(scenario, out):
    ipmc_swim.run(scenario, out=out, cycles=1, **{"waveform.frequency_Hz": 0.5})


def start(*args):
    return subprocess.Popen([CLI, *map(str, args)], stdout=subprocess.DEVNULL,
                            stderr=subprocess.PIPE, text=True)


def finish(processes):
    """Each process's (status, stderr); a failure must be a refusal."""
    results = [(p.wait(), p.stderr.read()) for p in processes]
    for status, error in results:
        assert status == 0 or any(reason in error for reason in REFUSED), error
    return results


def test_two_runs_into_one_folder_never_mix_their_files(tmp_path, references):
    folder, runs, _ = references
    refused = 0
    for attempt in range(TRIES):
        out = tmp_path / f"shared{attempt}"
        results = finish([start("run", folder / "short.toml", "--out", out, *RUN_A),
                          start("run", folder / "short.toml", "--out", out, *RUN_B)])
        refused += sum(status != 0 for status, _ in results)
        assert run_files(out) in (runs["a"], runs["b"]), f"attempt {attempt}: files of two runs"
    print(f"{refused} of {TRIES} second runs refused while the first held the folder")


def test_a_python_run_and_a_command_line_run_never_mix_their_files(tmp_path, references):
    folder, runs, _ = references
    for attempt in range(TRIES):
        out = tmp_path / f"shared{attempt}"
        failure = []

        def python_run():
            try:
                python_run_a(folder / "short.toml", out)
            except ipmc_swim.Error as error:
                failure.append(str(error))

        thread = threading.Thread(target=python_run)
        thread.start()
        cli = start("run", folder / "short.toml", "--out", out, *RUN_B)
        thread.join()
        finish([cli])
        for error in failure:
            assert "in use by another run" in error, error
        assert run_files(out) in (runs["python_a"], runs["b"]), \
            f"attempt {attempt}: files of two runs"


def test_two_sweeps_into_one_prefix_never_mix_their_tables(tmp_path, references):
    folder, _, tables = references
    for attempt in range(TRIES):
        prefix = tmp_path / f"shared{attempt}" / "table"
        finish([start("sweep", folder / "a.toml", "--out", prefix, "--jobs", "1"),
                start("sweep", folder / "b.toml", "--out", prefix, "--jobs", "1")])
        assert table_files(prefix) in (tables["a"], tables["b"]), \
            f"attempt {attempt}: the table of two sweeps"
