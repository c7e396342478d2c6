"""run.mat and run.h5 (run --format mat,h5) hold the same numbers as the
run's CSV and JSON files, read by scipy.io.loadmat and h5py: the time
series as written (10 significant digits, so equal to the CSV's text),
the states in millimetres (states.csv's metres times 1000), the per-cycle
and per-link tables and the summary (sim/runs/output.h, RunResultTree)."""

import csv
import json

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
