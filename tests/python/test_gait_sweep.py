"""Sweeps of prescribed gaits (a [gait] table instead of base,
sim/batch/sweep_gait.h): the table does not depend on --jobs, a point is
exactly `ipmc-swim gait` with the point's options (its metrics to the last
digit and, with --keep-runs, its run directory byte for byte), shards merge
into the whole sweep, a stopped sweep resumes to the same table, Python's
sweep writes the command line's bytes, and a bad gait option stops the
sweep with one line naming the sweep file, its line and the key."""

import json
import math
import shutil

import pytest

import ipmc_swim
from conftest import SOURCE_DIR, cli_error, run_cli

MODEL = SOURCE_DIR / "models" / "flagellum3.xml"

# Six quick points (one 2 s cycle each); the last phase lag is the
# standalone run below.
SWEEP = f"""
[gait]
model = "{MODEL}"
gait = "sine"
frequency_Hz = 0.5
cycles = 1
samples_per_cycle = 20
[grid]
amplitude_rad = [0.2, 0.3]
phase_lag_rad = [0.0, 1.0, 2.0]
"""
GAIT_COLUMNS = ["point", "amplitude_rad", "phase_lag_rad", "status", "error", "period_s",
                "last_cycle_com_along_mm", "mean_speed_along_mm_s",
                "peak_lateral_tip_speed_mm_s", "reynolds_tip", "reynolds_swim",
                "max_tracking_error_rad", "max_reference_rad"]
# Point 5 (amplitude 0.3, lag 2) as the gait command runs it.
STANDALONE = ["gait", "--model", MODEL, "--gait", "sine", "--frequency-hz", "0.5", "--cycles",
              "1", "--samples-per-cycle", "20", "--amplitude-rad", "0.3", "--phase-lag-rad", "2"]


def table_files(prefix):
    return {suffix: prefix.with_name(prefix.name + suffix).read_bytes()
            for suffix in (".csv", ".json")}


@pytest.fixture(scope="module")
def sweep(tmp_path_factory):
    folder = tmp_path_factory.mktemp("gait_sweep")
    (folder / "sweep.toml").write_text(SWEEP)
    run_cli("sweep", folder / "sweep.toml", "--out", folder / "one" / "t", "--jobs", "1",
            "--keep-runs")
    return folder


def test_the_table_has_the_gait_s_columns_and_does_not_depend_on_jobs(sweep):
    run_cli("sweep", sweep / "sweep.toml", "--out", sweep / "two" / "t", "--jobs", "2")
    assert table_files(sweep / "two" / "t") == table_files(sweep / "one" / "t")
    lines = (sweep / "one" / "t.csv").read_text().splitlines()
    assert lines[0].split(",") == GAIT_COLUMNS
    assert len(lines) == 7 and all(",ok,," in line for line in lines[1:])


def test_a_point_is_the_gait_command(sweep, tmp_path):
    _, stdout, _ = run_cli(*STANDALONE, "--out", tmp_path / "standalone")
    summary = json.loads((tmp_path / "standalone" / "summary.json").read_text())
    row = dict(zip(GAIT_COLUMNS, (sweep / "one" / "t.csv").read_text().splitlines()[6].split(",")))
    assert (row["amplitude_rad"], row["phase_lag_rad"]) == ("0.3", "2")
    for column in ("period_s", "mean_speed_along_mm_s", "peak_lateral_tip_speed_mm_s",
                   "reynolds_tip", "reynolds_swim", "max_tracking_error_rad",
                   "max_reference_rad"):
        assert float(row[column]) == summary[column], column
    assert float(row["last_cycle_com_along_mm"]) == summary["per_cycle"][-1]["com_along_mm"]
    assert not math.isnan(float(row["mean_speed_along_mm_s"]))
    # --keep-runs: the point's run directory is the gait command's --out.
    kept = sweep / "one" / "t_runs" / "point_5"
    for name in ("timeseries.csv", "states.csv", "summary.json"):
        assert (kept / name).read_bytes() == (tmp_path / "standalone" / name).read_bytes(), name


def test_shards_merge_into_the_whole_gait_sweep(sweep, tmp_path):
    for k in (1, 2, 3):
        run_cli("sweep", sweep / "sweep.toml", "--shard", f"{k}/3", "--out", tmp_path / f"s{k}",
                "--jobs", "1")
    run_cli("merge", "--out", tmp_path / "merged", *[tmp_path / f"s{k}.csv" for k in (1, 2, 3)])
    assert table_files(tmp_path / "merged") == table_files(sweep / "one" / "t")


def test_a_stopped_gait_sweep_resumes_to_the_same_table(sweep, tmp_path):
    lines = (sweep / "one" / "t.journal").read_text().splitlines(True)
    assert len(lines) == 7  # the header and six points
    (tmp_path / "resumed").mkdir()
    (tmp_path / "resumed" / "t.journal").write_text("".join(lines[:3]))
    _, _, stderr = run_cli("sweep", sweep / "sweep.toml", "--out", tmp_path / "resumed" / "t",
                           "--jobs", "2")
    assert "2 of 6 points done before" in stderr, stderr
    assert table_files(tmp_path / "resumed" / "t") == table_files(sweep / "one" / "t")


def test_python_s_gait_sweep_writes_the_command_line_s_bytes(sweep, tmp_path):
    table = ipmc_swim.sweep(sweep / "sweep.toml", out=tmp_path / "t", jobs=2)
    assert table_files(tmp_path / "t") == table_files(sweep / "one" / "t")
    assert list(table) == GAIT_COLUMNS
    assert list(table["phase_lag_rad"]) == [0.0, 1.0, 2.0, 0.0, 1.0, 2.0]


def test_the_journal_knows_a_changed_gait(sweep, tmp_path):
    (tmp_path / "sweep.toml").write_text(SWEEP.replace("cycles = 1", "cycles = 2"))
    (tmp_path / "out").mkdir()
    shutil.copy(sweep / "one" / "t.journal", tmp_path / "out" / "t.journal")
    message = cli_error("sweep", tmp_path / "sweep.toml", "--out", tmp_path / "out" / "t")
    assert "records another sweep" in message, message


@pytest.mark.parametrize("change, fragment", [
    (("phase_lag_rad = [", "phase_lags_rad = ["), "sweep.toml:10: grid: unknown gait option 'phase_lags_rad'"),
    (("cycles = 1", "cycles = 1.5"), "sweep.toml:6: gait.cycles must be an integer (got float)"),
    (('gait = "sine"', 'gait = "zigzag"'), "sweep.toml:4: gait.gait must be one of sine, square, csv"),
    (("[gait]", 'base = "paper.toml"\n[gait]'), "base and gait cannot be combined"),
    (("amplitude_rad = [0.2, 0.3]", "amplitude_rad = 0.2"), "grid.amplitude_rad must be a non-empty array"),
    (("[grid]", "[set]\ncycles = 2\n[grid]"), "set.cycles is set in [gait] already"),
])
def test_a_bad_gait_option_is_one_line_naming_the_file_line_and_key(tmp_path, change, fragment):
    (tmp_path / "sweep.toml").write_text(SWEEP.replace(*change))
    message = cli_error("sweep", tmp_path / "sweep.toml", "--out", tmp_path / "t")
    assert fragment in message, message
    with pytest.raises(ipmc_swim.Error) as raised:
        ipmc_swim.sweep(tmp_path / "sweep.toml", out=tmp_path / "t")
    assert str(raised.value) == message
    assert sorted(p.name for p in tmp_path.iterdir()) == ["sweep.toml"]


def test_a_gait_out_of_range_fails_its_point_only(tmp_path):
    (tmp_path / "sweep.toml").write_text(
        SWEEP.replace("amplitude_rad = [0.2, 0.3]", "amplitude_rad = [0.2, 4.0]"))
    _, _, stderr = run_cli("sweep", tmp_path / "sweep.toml", "--out", tmp_path / "t")
    rows = (tmp_path / "t.csv").read_text().splitlines()[1:]
    assert [row.split(",")[3] for row in rows] == ["ok"] * 3 + ["error"] * 3
    assert "amplitude_rad must be finite and in [-pi, pi] (got 4)" in rows[3], rows[3]


def test_runs_dir_keeps_the_same_runs_from_python(sweep, tmp_path):
    ipmc_swim.sweep(sweep / "sweep.toml", out=tmp_path / "t", jobs=2, keep_runs=True,
                    runs_dir=tmp_path / "kept")
    kept = sorted(p.relative_to(tmp_path / "kept").as_posix()
                  for p in (tmp_path / "kept").rglob("*") if p.is_file())
    assert len(kept) == 18, kept  # six points, three files each
    for name in kept:
        assert (tmp_path / "kept" / name).read_bytes() == \
            (sweep / "one" / "t_runs" / name).read_bytes(), name
    assert not (tmp_path / "t_runs").exists()
    with pytest.raises(ipmc_swim.Error, match="runs_dir needs keep_runs"):
        ipmc_swim.sweep(sweep / "sweep.toml", out=tmp_path / "u", runs_dir=tmp_path / "other")
