"""sweep(): the table from Python against the command line's."""

import csv

import numpy as np

import ipmc_swim
from conftest import run_cli


def test_sweep_equals_the_command_line(short_scenario, tmp_path):
    sweep_file = tmp_path / "sweep.toml"
    sweep_file.write_text(f'base = "{short_scenario.name}"\n[set]\ncycles = 1\n'
                          '[grid]\n"waveform.frequency_Hz" = [0.1, 0.2]\n'
                          'actuation = ["single", "distributed"]\n')
    run_cli("sweep", sweep_file, "--jobs", "2", "--out", tmp_path / "cli")
    calls = []
    table = ipmc_swim.sweep(sweep_file, jobs=2, out=tmp_path / "python",
                            progress=lambda done, total: calls.append((done, total)))
    for suffix in (".csv", ".json"):
        python_file = tmp_path / ("python" + suffix)
        assert python_file.read_bytes() == (tmp_path / ("cli" + suffix)).read_bytes()
    assert sorted(calls) == [(1, 4), (2, 4), (3, 4), (4, 4)]

    # The table's cells: numbers with 17 significant digits read back
    # exactly, so the arrays equal the CSV's values.
    with open(tmp_path / "cli.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    assert list(table) == list(rows[0])
    assert table["point"].dtype == np.int64 and table["point"].tolist() == [0, 1, 2, 3]
    assert table["status"].tolist() == ["ok"] * 4
    assert table["actuation"].tolist() == ["single", "distributed"] * 2
    for name in ("waveform.frequency_Hz", "link3_iae_mm_s", "last_cycle_com_along_mm"):
        assert table[name].dtype == np.float64
        assert table[name].tolist() == [float(row[name]) for row in rows]
    # Distributed actuation swims; single does not (a reciprocal stroke).
    along = table["last_cycle_com_along_mm"]
    # (first cycles, the start ramp breaks the symmetry: measured 8.5e-4 and
    # 1.5e-3 of the distributed runs)
    assert np.all(np.abs(along[0::2]) < 1e-2 * along[1::2])


def test_a_shard_is_every_nth_point(short_scenario, tmp_path):
    sweep_file = tmp_path / "sweep.toml"
    sweep_file.write_text(f'base = "{short_scenario.name}"\n[set]\ncycles = 1\n'
                          '[grid]\n"waveform.frequency_Hz" = [0.1, 0.2, 0.4]\n')
    table = ipmc_swim.sweep(sweep_file, jobs=1, shard="2/2")
    assert table["point"].tolist() == [1]


def test_kept_runs_are_the_command_lines(short_scenario, tmp_path):
    """keep_runs=True (sweep --keep-runs) keeps each point's run directory,
    the same bytes from both front ends; without out it is refused."""
    sweep_file = tmp_path / "sweep.toml"
    sweep_file.write_text(f'base = "{short_scenario.name}"\n[set]\ncycles = 1\n'
                          '[grid]\nactuation = ["single", "distributed"]\n')
    run_cli("sweep", sweep_file, "--keep-runs", "--out", tmp_path / "cli")
    table = ipmc_swim.sweep(sweep_file, out=tmp_path / "python", keep_runs=True)
    for point in (0, 1):
        for name in ("timeseries.csv", "states.csv"):
            cli = tmp_path / "cli_runs" / f"point_{point}" / name
            assert cli.read_bytes() == (tmp_path / "python_runs" / f"point_{point}" /
                                        name).read_bytes()
    result = ipmc_swim.plot("compare", [tmp_path / "python_runs" / "point_0",
                                        tmp_path / "python_runs" / "point_1"],
                            out=tmp_path / "compare.png")
    assert result.title == "Comparison of 2 runs: differing in actuation"
    assert str(table["last_cycle_com_along_mm"][1])[:6] in result.notes[1]
    try:
        ipmc_swim.sweep(sweep_file, keep_runs=True)
    except ipmc_swim.Error as error:
        assert "keep_runs needs out" in str(error)
    else:
        raise AssertionError("keep_runs without out was accepted")
