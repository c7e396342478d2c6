"""run.mat and run.h5 (run --format mat,h5) hold the same numbers as the
run's CSV and JSON files, read by scipy.io.loadmat and h5py: the time
series as written (10 significant digits, so equal to the CSV's text),
the states in millimetres (states.csv's metres times 1000), the per-cycle
and per-link tables and the summary (sim/runs/output.h, RunResultTree)."""

import csv
import json
import pathlib

import h5py
import numpy as np
import pytest
import scipy.io

from conftest import cli_error, run_cli


def read_csv(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    header, body = rows[0], rows[1:]
    return {name: np.array([float(r[i]) for r in body]) for i, name in enumerate(header)}


@pytest.fixture(scope="module")
def run_dir(tmp_path_factory):
    from conftest import SHORT_SCENARIO

    folder = tmp_path_factory.mktemp("formats")
    scenario = folder / "short.toml"
    scenario.write_text(SHORT_SCENARIO)
    out = folder / "run"
    run_cli("run", scenario, "--out", out, "--format", "mat,h5", "--cycles", "1")
    return out


def test_the_mat_file_equals_the_csv_and_json(run_dir):
    run = scipy.io.loadmat(run_dir / "run.mat", squeeze_me=True, struct_as_record=False)["run"]
    series = read_csv(run_dir / "timeseries.csv")
    assert sorted(run.timeseries._fieldnames) == sorted(series)
    for name, values in series.items():
        np.testing.assert_array_equal(getattr(run.timeseries, name), values)
    states = read_csv(run_dir / "states.csv")
    for name, values in states.items():
        if name.endswith("_m"):  # metres in the CSV, millimetres in the file
            np.testing.assert_allclose(getattr(run.states, name + "m"), values * 1e3, rtol=1e-15)
        else:
            np.testing.assert_array_equal(getattr(run.states, name), values)
    summary = json.loads((run_dir / "summary.json").read_text())
    assert run.summary.mean_speed_along_mm_s == summary["mean_speed_along_mm_s"]
    assert run.summary.controller == summary["controller"]
    assert run.summary.inputs.resolved_scenario == summary["inputs"]["resolved_scenario"]
    cycles = np.atleast_1d(run.cycles.com_along_mm)
    assert list(cycles) == [c["com_along_mm"] for c in summary["per_cycle"]]
    links = summary["links"]
    np.testing.assert_array_equal(run.links.itae_mm_s2, [l["itae_mm_s2"] for l in links])
    np.testing.assert_array_equal(run.links.link, [1, 2, 3])


def test_the_hdf5_file_equals_the_csv_and_carries_units(run_dir):
    series = read_csv(run_dir / "timeseries.csv")
    summary = json.loads((run_dir / "summary.json").read_text())
    with h5py.File(run_dir / "run.h5", "r") as f:
        assert set(f["timeseries"].keys()) == set(series)
        for name, values in series.items():
            np.testing.assert_array_equal(f["timeseries"][name][()], values)
        assert f["timeseries/com_x_mm"].attrs["units"] == "mm"
        assert f["timeseries/time_s"].attrs["units"] == "s"
        assert f["timeseries/voltage1_V"].attrs["units"] == "V"
        assert f["summary/mean_speed_along_mm_s"].attrs["units"] == "mm/s"
        assert f["links/iae_mm_s"].attrs["units"] == "mm s"
        assert f["summary/mean_speed_along_mm_s"][()] == summary["mean_speed_along_mm_s"]
        assert f["summary/controller"][()].decode() == summary["controller"]
        np.testing.assert_array_equal(
            f["cycles/head_along_mm"][()], [c["head_along_mm"] for c in summary["per_cycle"]])


def test_an_unknown_format_is_refused_before_any_work(tmp_path, short_scenario):
    out = tmp_path / "never"
    message = cli_error("run", short_scenario, "--out", out, "--format", "xlsx")
    assert message == "format must be csv, mat or h5 (hdf5), got 'xlsx'"
    assert not out.exists()


def test_a_sweeps_mat_and_hdf5_files_equal_its_table(tmp_path, short_scenario):
    """sweep --format mat,h5: the table as columns (a swept list as a matrix,
    a row per point; a failed point's results NaN) and a group per point
    with its provenance (sim/batch/sweep_table.h, SweepResultTree)."""
    sweep = tmp_path / "lengths.toml"
    sweep.write_text(f'base = "{short_scenario.name}"\n[set]\ncycles = 1\n'
                     '"waveform.frequency_Hz" = 0.5\n'
                     "[[point]]\nlink_lengths_mm = [10, 10, 10]\n"
                     "[[point]]\nlink_lengths_mm = [12, 8, 10]\n"
                     "[[point]]\nlink_lengths_mm = [12, 8, -10]\n")
    prefix = tmp_path / "out" / "table"
    run_cli("sweep", sweep, "--out", prefix, "--format", "mat,h5", "--jobs", "1")
    with open(f"{prefix}.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    speeds = [float(r["mean_speed_along_mm_s"]) if r["mean_speed_along_mm_s"] else np.nan
              for r in rows]
    assert [r["status"] for r in rows] == ["ok", "ok", "error"]
    table = scipy.io.loadmat(f"{prefix}.mat", squeeze_me=True, struct_as_record=False)["sweep"].table
    np.testing.assert_array_equal(table.link_lengths_mm, [[10, 10, 10], [12, 8, 10], [12, 8, -10]])
    np.testing.assert_array_equal(table.mean_speed_along_mm_s, speeds)
    assert list(table.status) == ["ok", "ok", "error"]
    with h5py.File(f"{prefix}.h5", "r") as f:
        np.testing.assert_array_equal(f["table/mean_speed_along_mm_s"][()], speeds)
        assert f["table/mean_speed_along_mm_s"].attrs["units"] == "mm/s"
        assert set(f["points"].keys()) == {"point_0", "point_1", "point_2"}
        assert f["points/point_1/mean_speed_along_mm_s"][()] == speeds[1]
        assert "link_lengths_mm = [12.0, 8.0, 10.0]" in f["points/point_1/resolved_scenario"][()].decode()
    # The same sweep again (resumed from its journal) without --format: the
    # table is written again and its .mat and .h5 go.
    run_cli("sweep", sweep, "--out", prefix, "--jobs", "1")
    assert not pathlib.Path(f"{prefix}.mat").exists()
    assert not pathlib.Path(f"{prefix}.h5").exists()


def test_python_writes_the_same_files_as_the_command_line(tmp_path, short_scenario):
    """ipmc_swim.run(..., out=DIR, formats=["mat", "h5"]) writes run.mat and
    run.h5 byte for byte as `run --format mat,h5` does (one writer,
    sim/runs/output.h)."""
    import ipmc_swim

    cli_dir, python_dir = tmp_path / "cli", tmp_path / "python"
    run_cli("run", short_scenario, "--out", cli_dir, "--format", "mat,h5")
    ipmc_swim.run(str(short_scenario), out=str(python_dir), formats=["mat", "h5"])
    for name in ("run.mat", "run.h5", "timeseries.csv", "states.csv"):
        assert (cli_dir / name).read_bytes() == (python_dir / name).read_bytes(), name
    with pytest.raises(ipmc_swim.Error, match="format must be csv, mat or h5"):
        ipmc_swim.run(str(short_scenario), out=str(tmp_path / "never"), formats=["xlsx"])
    assert not (tmp_path / "never").exists()
