"""Two writers at once into one output never mix their files: two runs into
one folder (the command line's, or Python's and the command line's), two
sweeps into one table prefix. Each case is tried 25 times and must end,
every time, in one of the outcomes the design allows (docs/RUNS.md, "Two
writers into one output"):
- two runs: the second is refused while the first holds the folder
  (sim/io/files.h DirectoryLock) and the folder holds the first one's
  files; or the first had finished, both succeed and the folder holds one
  run's files, whole;
- two sweeps: exactly one is refused before its first point, by the
  journal's lock while the other runs or by the other's finished journal,
  and the table is the other one's.
Never both refused, never another error, never one writer's file beside
the other's."""

import subprocess
import threading

import pytest

import ipmc_swim
from conftest import CLI, RUN_IN_USE, SHORT_SCENARIO, is_sweep_refusal, run_cli, table_files

TRIES = 25
RUN_FILES = ["timeseries.csv", "states.csv", "summary.json"]

# Two runs of the short scenario that differ in every file.
RUN_A = ["--cycles", "1", "--set", "waveform.frequency_Hz=0.5"]
RUN_B = ["--cycles", "1", "--set", "waveform.frequency_Hz=0.4"]
# Two sweeps of one point each that differ in every file.
SWEEP_A = 'base = "short.toml"\n[set]\ncycles = 1\n[grid]\n"waveform.frequency_Hz" = [0.5]\n'
SWEEP_B = 'base = "short.toml"\n[set]\ncycles = 1\n[grid]\n"waveform.frequency_Hz" = [0.4]\n'


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


def refused(process, is_refusal):
    """Whether the finished process was refused (exit 1, one line that
    is_refusal accepts); any other failure fails the test."""
    _, error = process.communicate()
    status = process.returncode
    if status == 0:
        return False
    lines = [line for line in error.splitlines() if line.startswith("ipmc-swim: error: ")]
    assert status == 1 and len(lines) == 1 and is_refusal(lines[0]), error
    return True


def winners(outcomes, references, attempt):
    """The references whose files a try may leave: of the writer that was
    not refused if one was, else of either (each took the output whole
    after the other had let go of it)."""
    assert sum(outcomes) < len(outcomes), f"attempt {attempt}: every writer refused"
    return [files for files, was_refused in zip(references, outcomes) if not was_refused]


def is_run_refusal(message):
    return RUN_IN_USE in message


def test_two_runs_into_one_folder_never_mix_their_files(tmp_path, references):
    folder, runs, _ = references
    refusals = 0
    for attempt in range(TRIES):
        out = tmp_path / f"shared{attempt}"
        processes = [start("run", folder / "short.toml", "--out", out, *RUN_A),
                     start("run", folder / "short.toml", "--out", out, *RUN_B)]
        outcomes = [refused(process, is_run_refusal) for process in processes]
        refusals += sum(outcomes)
        assert run_files(out) in winners(outcomes, [runs["a"], runs["b"]], attempt), \
            f"attempt {attempt}: files of two runs"
    print(f"{refusals} of {TRIES} second runs refused while the first held the folder")


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
        for error in failure:
            assert is_run_refusal(error), error
        outcomes = [bool(failure), refused(cli, is_run_refusal)]
        assert run_files(out) in winners(outcomes, [runs["python_a"], runs["b"]], attempt), \
            f"attempt {attempt}: files of two runs"


def test_two_sweeps_into_one_prefix_never_mix_their_tables(tmp_path, references):
    folder, _, tables = references
    for attempt in range(TRIES):
        prefix = tmp_path / f"shared{attempt}" / "table"
        processes = [start("sweep", folder / "a.toml", "--out", prefix, "--jobs", "1"),
                     start("sweep", folder / "b.toml", "--out", prefix, "--jobs", "1")]
        outcomes = [refused(process, is_sweep_refusal) for process in processes]
        assert sum(outcomes) == 1, f"attempt {attempt}: two sweeps into one prefix both ran"
        assert table_files(prefix) in winners(outcomes, [tables["a"], tables["b"]], attempt), \
            f"attempt {attempt}: the table of two sweeps"
