"""run(): the closed-loop run from Python against the command line's."""

import csv
import json
import tomllib

import numpy as np
import pytest

import ipmc_swim
from conftest import SHORT_SCENARIO, run_cli


def read_csv(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    return rows[0], np.array(rows[1:], dtype=np.float64)


def test_run_equals_the_command_line_bit_for_bit(short_scenario, tmp_path):
    # The same library code on the same scenario: the files must be equal
    # byte for byte, and summary.json (17 significant digits, read back
    # exactly) must hold the very doubles the result holds.
    run_cli("run", short_scenario, "--out", tmp_path / "cli")
    result = ipmc_swim.run(str(short_scenario), out=tmp_path / "python")
    for name in ("summary.json", "timeseries.csv"):
        assert (tmp_path / "python" / name).read_bytes() == (tmp_path / "cli" / name).read_bytes()
    cli_summary = json.loads((tmp_path / "cli" / "summary.json").read_text())
    del cli_summary["inputs"]
    assert result.summary == cli_summary
    along = [cycle["com_along_mm"] for cycle in cli_summary["per_cycle"]]
    assert result.cycles["com_along_mm"].tolist() == along

    # The time series: the CSV's columns, in its order; the CSV holds 10
    # significant digits, so the values agree to 5e-10 relative.
    header, values = read_csv(tmp_path / "cli" / "timeseries.csv")
    assert list(result.timeseries) == header
    for k, name in enumerate(header):
        np.testing.assert_allclose(result.timeseries[name], values[:, k], rtol=1e-9, atol=0)


def test_result_arrays_have_the_documented_dtypes_and_shapes(short_scenario):
    result = ipmc_swim.run(short_scenario)
    samples = 2 * 50  # cycles x output.samples_per_cycle
    assert len(result.timeseries) == 6 + 3 * 3 + 2 * 3
    for name, column in result.timeseries.items():
        assert column.dtype == np.float64 and column.shape == (samples,), name
    assert result.cycles["cycle"].dtype == np.int64
    assert result.cycles["cycle"].tolist() == [1, 2]
    assert result.cycles["com_along_mm"].dtype == np.float64
    assert result.links["link"].tolist() == [1, 2, 3]
    assert result.links["iae_mm_s"].shape == (3,)
    assert np.all(np.diff(result.timeseries["time_s"]) > 0)
    # The swimmer swims head first (positive along) once the wave runs.
    assert result.cycles["com_along_mm"][-1] > 0


def test_overrides_are_the_sweep_files_dotted_keys(short_scenario, tmp_path):
    # A dotted override, the same as a nested dict, equals a scenario file
    # with the value changed; a dict scenario equals its file.
    changed = tmp_path / "changed.toml"
    changed.write_text(SHORT_SCENARIO.replace("frequency_Hz = 0.1", "frequency_Hz = 0.2")
                       .replace("cycles = 2", "cycles = 1"))
    expected = ipmc_swim.run(changed).summary
    dotted = ipmc_swim.run(short_scenario, cycles=1, **{"waveform.frequency_Hz": 0.2})
    nested = ipmc_swim.run(short_scenario, cycles=1, waveform={"frequency_Hz": 0.2})
    as_dict = ipmc_swim.run(tomllib.loads(changed.read_text()))
    assert dotted.summary == expected
    assert nested.summary == expected
    assert as_dict.summary == expected


def test_a_new_controller_kind_drops_the_other_kinds_keys(short_scenario):
    # As in sweeps: the PID gains of the base do not apply to the fractional
    # controller and are dropped; the run is the fractional one.
    result = ipmc_swim.run(short_scenario, cycles=1, controller={"kind": "fractional"})
    assert result.summary["controller"] == "fractional"


def test_progress_reports_simulated_seconds_and_ends_at_the_total(short_scenario):
    calls = []
    ipmc_swim.run(short_scenario, cycles=1, progress=lambda done, total: calls.append((done, total)))
    assert calls and calls[-1] == (10.0, 10.0)
    assert all(total == 10.0 and 0 <= done <= total for done, total in calls)


def test_an_exception_in_the_progress_callback_stops_the_run(short_scenario, tmp_path):
    def stop(done, total):
        raise KeyError("stop here")

    with pytest.raises(KeyError, match="stop here"):
        ipmc_swim.run(short_scenario, out=tmp_path / "never", progress=stop)
    assert not (tmp_path / "never").exists()


def test_version_is_the_programs():
    # One source for every version string, the CMake project version: the
    # module's __version__ is what `ipmc-swim --version` prints.
    _, out, _ = run_cli("--version")
    assert out == f"ipmc-swim {ipmc_swim.__version__}\n"


def test_electrical_power_is_in_the_results_when_the_model_is_on(short_scenario, tmp_path):
    # Off by default: no electrical keys. On: the same numbers as the
    # command line's summary.json, per cycle, per link and over the run.
    assert "electrical_power_W" not in ipmc_swim.run(short_scenario).summary
    result = ipmc_swim.run(short_scenario, **{"electrical.enabled": True})
    run_cli("run", short_scenario, "--set", "electrical.enabled=true", "--out", tmp_path / "cli")
    cli_summary = json.loads((tmp_path / "cli" / "summary.json").read_text())
    summary = result.summary
    assert summary["electrical_power_W"] == cli_summary["electrical_power_W"] > 0
    assert summary["electromechanical_efficiency"] == pytest.approx(
        summary["actuator_power_W"] / summary["electrical_power_W"], rel=1e-12)
    links = [link["electrical_power_W"] for link in summary["links"]]
    assert sum(links) == pytest.approx(summary["electrical_power_W"], rel=1e-12)
    assert all("link3_electrical_power_W" in cycle for cycle in summary["per_cycle"])
