"""A run's output folder holds one run's files, whatever happens: a run that
fails leaves the previous results as they were, and files of an earlier
run's set that a new run does not write (run.mat, run.h5) go
(sim/io/files.h: WriteFilesTogether). Two runs at once into one folder:
test_concurrent_outputs.py."""

import os
import subprocess

import pytest

from conftest import run_cli

FILES = ["timeseries.csv", "states.csv", "summary.json", "model.xml"]

# Two runs of the short scenario that differ in every file.
RUN_A = ["--cycles", "1", "--set", "waveform.frequency_Hz=0.5"]
RUN_B = ["--cycles", "1", "--set", "waveform.frequency_Hz=0.4"]


def contents(folder):
    return {name: (folder / name).read_bytes() for name in FILES}


@pytest.fixture(scope="module")
def references(tmp_path_factory):
    from conftest import SHORT_SCENARIO

    folder = tmp_path_factory.mktemp("references")
    scenario = folder / "short.toml"
    scenario.write_text(SHORT_SCENARIO)
    outputs = {}
    for name, args in (("a", RUN_A), ("b", RUN_B)):
        run_cli("run", scenario, "--out", folder / name, *args)
        outputs[name] = contents(folder / name)
    assert outputs["a"]["timeseries.csv"] != outputs["b"]["timeseries.csv"]
    return scenario, outputs


def test_a_failed_run_leaves_the_previous_results_as_they_were(tmp_path, references):
    scenario, outputs = references
    out = tmp_path / "kept"
    run_cli("run", scenario, "--out", out, *RUN_A)
    # summary.json cannot be replaced: a directory of that name is in the way.
    (out / "summary.json").unlink()
    (out / "summary.json").mkdir()
    before = {name: (out / name).read_bytes() for name in FILES[:2]}
    status, _, error = run_cli("run", scenario, "--out", out, *RUN_B, check=False)
    assert status == 1
    assert "summary.json: cannot replace it, it is a directory" in error
    assert {name: (out / name).read_bytes() for name in FILES[:2]} == before
    assert sorted(p.name for p in out.iterdir()) == sorted(FILES)


def test_a_run_without_a_format_removes_the_earlier_runs_file_of_it(tmp_path, references):
    scenario, outputs = references
    out = tmp_path / "formats"
    run_cli("run", scenario, "--out", out, *RUN_A, "--format", "mat,h5")
    assert (out / "run.mat").exists() and (out / "run.h5").exists()
    run_cli("run", scenario, "--out", out, *RUN_B, "--format", "h5")
    assert not (out / "run.mat").exists()
    run_cli("run", scenario, "--out", out, *RUN_A)
    assert sorted(p.name for p in out.iterdir()) == sorted(FILES)
    assert contents(out) == outputs["a"]


def dead_pid():
    """The PID of a process that has ended (and been reaped)."""
    child = subprocess.Popen(["true"])
    child.wait()
    return child.pid


def test_a_killed_writers_temporaries_go_with_the_next_write(tmp_path, references):
    """A merge or run killed mid-write leaves NAME.tmp.PID.XXXXXX files; the
    next write of the same outputs removes those of processes that no
    longer run, and keeps those of one that runs (it may be writing)."""
    scenario, _ = references
    header = "point,cycles,status,error,mean_speed_along_mm_s\n"
    (tmp_path / "s1.csv").write_text(header + "0,1,ok,,0.5\n")
    (tmp_path / "s2.csv").write_text(header + "1,2,ok,,0.6\n")
    stale = [tmp_path / f"m.csv.tmp.{dead_pid()}.abcdef", tmp_path / f"m.json.tmp.{dead_pid()}.ghijkl"]
    out = tmp_path / "run"
    out.mkdir()
    stale += [out / f"{name}.tmp.{dead_pid()}.mnopqr" for name in FILES]
    alive = tmp_path / f"m.csv.tmp.{os.getpid()}.stuvwx"
    for path in stale + [alive]:
        path.write_text("half a table")
    run_cli("merge", tmp_path / "s1.csv", tmp_path / "s2.csv", "--out", tmp_path / "m")
    run_cli("run", scenario, "--out", out, *RUN_A)
    assert [path for path in stale if path.exists()] == []
    assert alive.exists()
    assert sorted(p.name for p in out.iterdir()) == sorted(FILES)
