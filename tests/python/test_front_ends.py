"""Every command that both front ends offer, run through each into its own
folder: the files (names and bytes) must be the same. The options are one
table per command (docs/OPTIONS.md); the keyword is the option's name, the
flag its lower-case spelling with '-' for '_'."""

import numpy as np
import pytest

import ipmc_swim
from conftest import SOURCE_DIR, run_cli

SCENARIOS = SOURCE_DIR / "scenarios"


def flag(name):
    return "--" + name.lower().replace("_", "-")


def cli_arguments(options):
    """Keyword options as the command line's flags (lists comma-separated,
    True as a bare flag)."""
    args = []
    for name, value in options.items():
        if value is True:
            args.append(flag(name))
        elif isinstance(value, (list, tuple)):
            args += [flag(name), ",".join(str(v) for v in value)]
        else:
            args += [flag(name), str(value)]
    return args


def files_of(folder):
    return {path.relative_to(folder).as_posix(): path.read_bytes()
            for path in sorted(folder.rglob("*")) if path.is_file()}


def assert_same_files(cli_folder, python_folder):
    cli, python = files_of(cli_folder), files_of(python_folder)
    assert cli, "the command line wrote nothing"
    assert sorted(python) == sorted(cli)
    for name in cli:
        assert python[name] == cli[name], name


BENCH = {"signal": "chirp", "duration_s": 1.0, "end_Hz": 20.0, "links": [1, 3],
         "sample_rate_Hz": 1000.0}
BODE = {"links": [3], "plant": "g2", "w_min_rad_s": 0.1, "w_max_rad_s": 100.0,
        "points_per_decade": 20}
STEP = {"links": [3, 1], "horizon_s": 1.0, "max_horizon_s": 3.0, "v_max_V": 5.0,
        "sample_rate_Hz": 2000.0}
RUN = {"formats": ["mat"], "allow_long": True}
SWEEP = {"jobs": 2, "shard": "1/1", "formats": ["mat", "h5"]}
CONVERGE = {"max_segments": 2, "halvings": 1, "max_plates_k": 0, "cycles": 1, "jobs": 2}
GENERATE = {"link_lengths_mm": [5.0, 10.0, 15.0], "head_length_mm": 0.5, "clamped": True}


def test_bench(tmp_path):
    (tmp_path / "cli").mkdir()
    (tmp_path / "python").mkdir()
    run_cli("bench", *cli_arguments(BENCH), "--out", tmp_path / "cli" / "bench.csv")
    ipmc_swim.bench(out=tmp_path / "python" / "bench.csv", **BENCH)
    assert_same_files(tmp_path / "cli", tmp_path / "python")


def test_bode(tmp_path):
    run_cli("bode", "--controller", "fractional-oustaloup", *cli_arguments(BODE),
            "--out", tmp_path / "cli")
    ipmc_swim.bode("fractional-oustaloup", out=tmp_path / "python", **BODE)
    assert_same_files(tmp_path / "cli", tmp_path / "python")


def test_step(tmp_path):
    run_cli("step", "--controller", "fractional", *cli_arguments(STEP), "--out", tmp_path / "cli")
    ipmc_swim.step("fractional", out=tmp_path / "python", **STEP)
    assert_same_files(tmp_path / "cli", tmp_path / "python")


def test_generate(tmp_path):
    (tmp_path / "cli").mkdir()
    (tmp_path / "python").mkdir()
    run_cli("generate", *cli_arguments(GENERATE), "--out", tmp_path / "cli" / "model.xml")
    ipmc_swim.generate_model(out=tmp_path / "python" / "model.xml", **GENERATE)
    assert_same_files(tmp_path / "cli", tmp_path / "python")


def test_resistance(tmp_path):
    (tmp_path / "cli").mkdir()
    (tmp_path / "python").mkdir()
    model = SOURCE_DIR / "models" / "helices" / "rodenborn_9.811.xml"
    options = {"fluid": "stokeslets", "stokeslet_points_per_mm": 2.0, "axis": "x"}
    run_cli("resistance", model, *cli_arguments(options), "--out", tmp_path / "cli" / "R.json")
    result = ipmc_swim.resistance(model, out=tmp_path / "python" / "R.json", **options)
    assert_same_files(tmp_path / "cli", tmp_path / "python")
    assert result.R.shape == (6, 6)
    assert np.allclose(result.R, result.R.T, rtol=0, atol=1e-12 * abs(result.R).max())
    assert result.A_N_s_m == -result.R[0, 0]


def test_export(tmp_path):
    scenario = SCENARIOS / "paper_fractional.toml"
    run_cli("export", scenario, "--set", "controller.gain=14.6", "--out", tmp_path / "cli")
    ipmc_swim.export(scenario, out=tmp_path / "python", **{"controller.gain": 14.6})
    assert_same_files(tmp_path / "cli", tmp_path / "python")


def test_identify(tmp_path):
    csv = tmp_path / "chirp.csv"
    run_cli("bench", "--signal", "chirp", "--duration-s", "8", "--end-hz", "50", "--out", csv)
    options = {"band_rad_s": [5.0, 50.0], "sample_rate_Hz": 1000.0}
    run_cli("identify", csv, "--input", "voltage1_V", "--output", "relative1_mm",
            *cli_arguments(options), "--out", tmp_path / "cli")
    data = np.genfromtxt(csv, delimiter=",", names=True)
    ipmc_swim.identify(data, "voltage1_V", "relative1_mm", name=str(csv),
                       out=tmp_path / "python", **options)
    assert_same_files(tmp_path / "cli", tmp_path / "python")


def test_run(short_scenario, tmp_path):
    # summary.json records the inputs as given: a scenario file alone here
    # (the command line's --set and Python's overrides are recorded each in
    # its own words).
    scenario = tmp_path / "one_cycle.toml"
    scenario.write_text(short_scenario.read_text().replace("cycles = 2", "cycles = 1"))
    run_cli("run", scenario, *cli_arguments(RUN), "--out", tmp_path / "cli")
    ipmc_swim.run(scenario, out=tmp_path / "python", **RUN)
    assert_same_files(tmp_path / "cli", tmp_path / "python")


def test_run_open_loop(tmp_path):
    # The head-and-tail swimmer driven open loop (drive.mode = "sine"), one
    # 2 s cycle: the same files from both front ends.
    scenario = tmp_path / "open_loop.toml"
    scenario.write_text(f'include = "{SCENARIOS / "head_and_tail_open_loop.toml"}"\n'
                        "cycles = 1\n[waveform]\nfrequency_Hz = 0.5\n")
    run_cli("run", scenario, "--out", tmp_path / "cli")
    ipmc_swim.run(scenario, out=tmp_path / "python")
    assert_same_files(tmp_path / "cli", tmp_path / "python")


def test_sweep(short_scenario, tmp_path):
    sweep_file = tmp_path / "sweep.toml"
    sweep_file.write_text(f'base = "{short_scenario.name}"\n[set]\ncycles = 1\n'
                          '[grid]\nactuation = ["single", "distributed"]\n')
    (tmp_path / "cli").mkdir()
    (tmp_path / "python").mkdir()
    run_cli("sweep", sweep_file, *cli_arguments(SWEEP), "--out", tmp_path / "cli" / "table")
    ipmc_swim.sweep(sweep_file, out=tmp_path / "python" / "table", **SWEEP)
    # Both keep the resume journal: the same header and records, in the
    # order the points finished (which two jobs do not fix).
    journals = [sorted((tmp_path / side / "table.journal").read_text().splitlines())
                for side in ("cli", "python")]
    assert journals[0] == journals[1] and len(journals[0]) == 3
    for side in ("cli", "python"):
        (tmp_path / side / "table.journal").unlink()
    assert_same_files(tmp_path / "cli", tmp_path / "python")


def test_converge(tmp_path):
    scenario = SCENARIOS / "own_two_link.toml"
    run_cli("converge", scenario, *cli_arguments(CONVERGE), "--out", tmp_path / "cli")
    studies = ipmc_swim.converge(scenario, out=tmp_path / "python", **CONVERGE)
    assert [study.study for study in studies] == ["segments", "timestep"]
    # The cost column is wall time: the same bytes without it.
    for side in ("cli", "python"):
        table = tmp_path / side / "converge.csv"
        rows = [line.split(",") for line in table.read_text().splitlines()]
        cost = rows[0].index("cost_s_per_simulated_s")
        table.write_text("".join(",".join(r[:cost] + r[cost + 1:]) + "\n" for r in rows))
    assert_same_files(tmp_path / "cli", tmp_path / "python")


def test_output_checks_are_the_librarys(tmp_path):
    # bench never writes over its model, from either front end.
    model = tmp_path / "model.xml"
    model.write_text(ipmc_swim.generate_model(clamped=True))
    before = model.read_bytes()
    status, _, stderr = run_cli("bench", "--model", model, "--out", model, "--duration-s", "1",
                                check=False)
    assert status != 0 and "--out" in stderr and "would overwrite the input" in stderr
    with pytest.raises(ipmc_swim.Error, match="bench: out .* would overwrite the input"):
        ipmc_swim.bench(model=model, out=model, duration_s=1.0)
    assert model.read_bytes() == before


def test_run_checks_its_output_folder_first(short_scenario, tmp_path):
    # A scenario file where the run would write its states.csv: refused
    # before the run by both front ends, the input untouched.
    scenario = tmp_path / "states.csv"
    scenario.write_text(short_scenario.read_text())
    status, _, stderr = run_cli("run", scenario, "--out", tmp_path, check=False)
    assert status != 0 and "would overwrite the input" in stderr
    with pytest.raises(ipmc_swim.Error, match="run: out .* would overwrite the input"):
        ipmc_swim.run(scenario, out=tmp_path)
    assert scenario.read_text() == short_scenario.read_text()
    assert not (tmp_path / "summary.json").exists()
