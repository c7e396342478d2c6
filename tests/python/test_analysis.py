"""bench, bode, step, identify, design and generate_model against their commands."""

import json

import numpy as np
import pytest

import ipmc_swim
from conftest import run_cli


def test_generate_model_is_the_generators_text(tmp_path):
    _, stdout, _ = run_cli("generate", "--link-lengths-mm", "5,10,15", "--head-length-mm", "0.5")
    assert ipmc_swim.generate_model(link_lengths_mm=[5, 10, 15], head_length_mm=0.5) == stdout
    ipmc_swim.generate_model(out=tmp_path / "m.xml")
    assert (tmp_path / "m.xml").read_text() == run_cli("generate")[1]


def test_bench_equals_the_command_line(tmp_path):
    run_cli("bench", "--signal", "chirp", "--duration-s", "1", "--end-hz", "20", "--links", "1,3",
            "--out", tmp_path / "cli.csv")
    record = ipmc_swim.bench(signal="chirp", duration_s=1.0, end_Hz=20.0, links=[1, 3],
                             out=tmp_path / "python.csv")
    assert (tmp_path / "python.csv").read_bytes() == (tmp_path / "cli.csv").read_bytes()
    header = (tmp_path / "cli.csv").read_text().splitlines()[0].split(",")
    assert list(record) == header
    assert record["time_s"].shape == (1000,) and record["time_s"].dtype == np.float64
    # Link 2 is not driven.
    assert np.all(record["voltage2_V"] == 0) and np.any(record["voltage3_V"] != 0)


def test_bode_equals_the_command_line(tmp_path):
    _, stdout, _ = run_cli("bode", "--controller", "pid", "--links", "3", "--out", tmp_path / "cli")
    [result] = ipmc_swim.bode("pid", links=[3], out=tmp_path / "python")
    for name in ("bode.csv", "bode.json"):
        assert (tmp_path / "python" / name).read_bytes() == (tmp_path / "cli" / name).read_bytes()
    assert result.link == 3
    margins = result["margins"]
    assert f"gain crossover: {margins['gain_crossover_rad_s']:.3f} rad/s" in stdout
    assert f"phase margin: {margins['phase_margin_deg']:.2f} deg" in stdout
    assert margins["gain_margin_dB"] is None
    assert result["controller"] in stdout and result["plant"] in stdout
    response = result["response"]
    assert response["w_rad_s"].shape == response["open_loop_dB"].shape
    # The open loop is the product: dB add.
    np.testing.assert_allclose(response["open_loop_dB"],
                               response["plant_dB"] + response["controller_dB"], atol=1e-9)


def test_step_equals_the_command_line(tmp_path):
    args = ["--links", "3,1", "--horizon-s", "1", "--max-horizon-s", "3", "--no-clamp"]
    _, stdout, _ = run_cli("step", "--controller", "pid", *args, "--out", tmp_path / "cli")
    result = ipmc_swim.step("pid", links=[3, 1], horizon_s=1.0, max_horizon_s=3.0, no_clamp=True,
                            out=tmp_path / "python")
    for name in ("step.csv", "step.json"):
        assert (tmp_path / "python" / name).read_bytes() == (tmp_path / "cli" / name).read_bytes()
    rows = {line.split()[0]: line.split() for line in stdout.splitlines() if line[:4].strip() in ("1", "3")}
    for link in result["links"]:
        row = rows[str(link["link"])]
        assert row[1].rstrip("*") == f"{link['metrics']['overshoot_percent']:.3f}"
        assert row[7] == f"{link['cost']:.4f}"
        assert link["time_s"].shape == link["output_mm"].shape == link["control_V"].shape
    assert result["reference"]["output_mm"].shape == result["reference"]["time_s"].shape


def test_identify_equals_the_command_line(tmp_path):
    # A chirp long enough for a band from 5 rad/s; the CLI reads the CSV's
    # 10 digits, so the Python call gets the same numbers parsed from it.
    csv = tmp_path / "chirp.csv"
    run_cli("bench", "--signal", "chirp", "--duration-s", "8", "--end-hz", "50", "--out", csv)
    run_cli("identify", csv, "--input", "voltage1_V", "--output", "relative1_mm",
            "--band-rad-s", "5,50", "--out", tmp_path / "cli")
    data = np.genfromtxt(csv, delimiter=",", names=True)
    result = ipmc_swim.identify(data, "voltage1_V", "relative1_mm", band_rad_s=[5.0, 50.0],
                                name=str(csv), out=tmp_path / "python")
    for name in ("identification.json", "response.csv"):
        assert (tmp_path / "python" / name).read_bytes() == (tmp_path / "cli" / name).read_bytes()
    expected = json.loads((tmp_path / "cli" / "identification.json").read_text())
    assert {k: result[k] for k in expected} == expected
    response = result["response"]
    assert response["measured"].dtype == np.complex128
    assert response["p1"].shape == response["w_rad_s"].shape
    # From a dict of arrays too (a bench() record), with its own name.
    record = {name: data[name] for name in data.dtype.names}
    again = ipmc_swim.identify(record, "voltage1_V", "relative1_mm", band_rad_s=[5.0, 50.0])
    assert again["g1"] == expected["g1"] and again["data"] == "data"
    with pytest.raises(ipmc_swim.Error, match="data: no column 'voltage9_V'"):
        ipmc_swim.identify(record, "voltage9_V", "relative1_mm")


def test_design_equals_the_command_line():
    args = ["--links", "3", "--horizon-s", "0.5", "--sample-rate-hz", "2000"]
    _, stdout, _ = run_cli("design", *args)
    [result] = ipmc_swim.design(links=[3], horizon_s=0.5, sample_rate_Hz=2000.0)
    fractional = result["fractional"]
    assert f"C_I(s) = {fractional['gain']:.4f} / s^{fractional['order']:.4f}" in stdout
    pid = result["pid"]
    assert (f"tuned:          C(s) = {pid['kp']:.4g} + {pid['ki']:.4g}/s + {pid['kd']:.4g} s, "
            f"J = {pid['cost']:.6f}") in stdout
    assert f"J = {pid['paper_cost']:.6f}" in stdout
    assert len(pid["runs"]) == 5 and pid["cost"] == min(run["cost"] for run in pid["runs"])


# The user's two-link strip: identify's plant.toml with one plant per link
# and design's gains.toml with one PID per link and a derivative filter.
PLANTS = """[plant]
model = "g1"
link_a0_mm_per_V = [0.52, 0.47]
link_b1 = [0.029, 0.033]
link_b2_s2 = [0.0042, 0.0039]
"""
GAINS = """[controller]
link_kp = [7.758, 6.9]
link_ki = [28.14, 33.0]
link_kd = [0.7181, 0.64]
derivative_filter_s = 0.002
"""


def test_bode_and_step_on_the_users_plants_and_gains(tmp_path):
    (tmp_path / "plant.toml").write_text(PLANTS)
    (tmp_path / "gains.toml").write_text(GAINS)
    files = {"plant_file": tmp_path / "plant.toml", "gains_file": tmp_path / "gains.toml"}
    links = ipmc_swim.bode("pid", **files)
    assert [link["link"] for link in links] == [1, 2]  # every link of the files
    assert "0.52 / (0.0042 s^2 + 0.029 s + 1)" in links[0]["plant"]
    assert "6.9 + 33/s + 0.64 s / (0.002 s + 1)" in links[1]["controller"]
    # The loop gain at 5 rad/s is the product of the link's own C and P,
    # evaluated here from the keys: C = Kp + Ki/s + Kd s/(Tf s + 1),
    # P = s^-0.5 a0 / (b2 s^2 + b1 s + 1).
    s = 5j
    c = 6.9 + 33.0 / s + 0.64 * s / (0.002 * s + 1)
    p = s ** -0.5 * 0.47 / (0.0039 * s * s + 0.033 * s + 1)
    assert links[1]["at_design"]["open_loop"] == pytest.approx(c * p, rel=1e-12)
    step = ipmc_swim.step("pid", **files)
    assert [link["link"] for link in step["links"]] == [1, 2]
    # Table 2's link 1 under the same gains rises far slower than the
    # strip's own link (a0 0.52 against 0.06 mm/V).
    table2 = ipmc_swim.step("pid", links=[1], kp=7.758, ki=28.14, kd=0.7181)
    assert step["links"][0]["metrics"]["rise_time_s"] < 0.1 * table2["links"][0]["metrics"]["rise_time_s"]
    with pytest.raises(ipmc_swim.Error, match="kp does not apply with gains_file"):
        ipmc_swim.step("pid", kp=3.0, **files)
    with pytest.raises(ipmc_swim.Error, match="links must be in 1..2, got 3"):
        ipmc_swim.bode("pid", links=[3], **files)


def test_design_takes_links_and_rate_from_a_scenario(tmp_path):
    (tmp_path / "plant.toml").write_text(PLANTS)
    scenario = tmp_path / "strip.toml"
    scenario.write_text('include = ["plant.toml"]\nlink_lengths_mm = [12.0, 12.0]\n'
                        '[strip]\nwidth_mm = 5.0\nthickness_um = 200.0\n'
                        '[controller]\nsample_rate_Hz = 500.0\n')
    designs = ipmc_swim.design(scenario=scenario, derivative_bandwidth_rad_s=500.0,
                               horizon_s=1.0)
    assert [d["link"] for d in designs] == [1, 2]
    status, printed, _ = run_cli("design", "--scenario", scenario, "--derivative-bandwidth-rad-s",
                                 "500", "--horizon-s", "1", "--out", tmp_path / "gains.toml")
    assert printed.count("loop sampled at 500 Hz (linear, no clamp, derivative filter "
                         "Tf = 0.002 s)") == 2
    gains = (tmp_path / "gains.toml").read_text()
    assert "derivative_filter_s = 0.002" in gains and "in a 500 Hz loop" in gains
    # The plants are the scenario's own (its plant keys).
    assert "a0 = 0.47 mm/V" in printed


def test_design_defaults_to_the_controllers_1_kHz_loop():
    [result] = ipmc_swim.design(links=[3], horizon_s=0.5)
    assert result["pid"]["sample_rate_Hz"] == 1000.0
    assert "loop sampled at 1000 Hz (linear, no clamp):" in run_cli(
        "design", "--links", "3", "--horizon-s", "0.5")[1]


def test_design_filters_the_derivative_for_the_sensor_noise(tmp_path):
    (tmp_path / "plant.toml").write_text(PLANTS)
    options = {"plant_file": tmp_path / "plant.toml", "horizon_s": 1.0, "sensor_noise_mm": 0.002,
               "derivative_noise_V": 0.1}
    designs = ipmc_swim.design(out=tmp_path / "python.toml", **options)
    run_cli("design", "--plant-file", tmp_path / "plant.toml", "--horizon-s", "1",
            "--sensor-noise-mm", "0.002", "--derivative-noise-v", "0.1",
            "--out", tmp_path / "cli.toml")
    assert (tmp_path / "python.toml").read_bytes() == (tmp_path / "cli.toml").read_bytes()
    # One Tf for every link, the smallest (to 1 %) that keeps each link's
    # derivative noise Kd sigma sqrt(2 / ((Tf + T) (2 Tf + T))) within the
    # bound at the Kd tuned with it (docs/IDENTIFICATION.md).
    T = 1e-3
    [tf] = {d["pid"]["derivative_filter_s"] for d in designs}
    assert tf > 0
    for d in designs:
        kd = d["pid"]["kd"]
        noise = kd * 0.002 * (2 / ((tf + T) * (2 * tf + T))) ** 0.5
        assert d["pid"]["derivative_noise_V"] == pytest.approx(noise, rel=1e-12)
        assert noise <= 0.1
    assert max(d["pid"]["derivative_noise_V"] for d in designs) > 0.1 / 1.02 ** 2
    assert f"derivative_filter_s = {tf!r}" in (tmp_path / "cli.toml").read_text()
    with pytest.raises(ipmc_swim.Error, match="derivative_bandwidth_rad_s does not apply with "
                                              "sensor_noise_mm"):
        ipmc_swim.design(derivative_bandwidth_rad_s=100.0, **options)
    with pytest.raises(ipmc_swim.Error, match="derivative_noise_V applies only with "
                                              "sensor_noise_mm"):
        ipmc_swim.design(links=[3], derivative_noise_V=0.1)


def test_step_reports_table5s_indices_alike_on_table2_and_a_plant_file(tmp_path):
    # Eq. 7's plant (Table 2's link 3) written as plant keys: the same
    # computation on the user's plant gives the same numbers.
    (tmp_path / "plant.toml").write_text(
        '[plant]\nmodel = "g1"\na0_mm_per_V = 0.37609\nb1 = 0.02331\nb2_s2 = 0.00213\n')
    table2 = ipmc_swim.step("pid", links=[3], horizon_s=2.0)["links"][0]
    own = ipmc_swim.step("pid", links=[3], horizon_s=2.0,
                         plant_file=tmp_path / "plant.toml")["links"][0]
    assert own["iae_mm_s"] == table2["iae_mm_s"] and own["itae_mm_s2"] == table2["itae_mm_s2"]
    # Table 5's rectangle rule over the samples t_k = k T < 2 s of the record.
    t, y = own["time_s"], own["output_mm"]
    before = t < 2.0 - 1e-9
    assert before.sum() == 2000
    error = np.abs(1.0 - y[before])
    assert own["iae_mm_s"] == pytest.approx(np.sum(error) * 1e-3, rel=1e-12)
    assert own["itae_mm_s2"] == pytest.approx(np.sum(t[before] * error) * 1e-3, rel=1e-12)
    _, printed, _ = run_cli("step", "--controller", "pid", "--links", "3", "--horizon-s", "2",
                            "--plant-file", tmp_path / "plant.toml")
    row = next(line.split() for line in printed.splitlines() if line.startswith("   3 "))
    assert row[-2:] == [f"{own['iae_mm_s']:.6f}", f"{own['itae_mm_s2']:.6f}"]


def test_step_on_the_bench_beside_the_linear_loop(tmp_path):
    (tmp_path / "plant.toml").write_text(PLANTS)
    (tmp_path / "gains.toml").write_text(GAINS)
    bench = tmp_path / "strip.toml"
    bench.write_text('include = ["plant.toml"]\nlink_lengths_mm = [12.0, 12.0]\n'
                     'dynamics = "stokes"\ntimestep_s = 1e-3\n'
                     '[strip]\nwidth_mm = 5.0\nthickness_um = 200.0\n')
    args = ["step", "--controller", "pid", "--plant-file", tmp_path / "plant.toml",
            "--gains-file", tmp_path / "gains.toml", "--horizon-s", "2"]
    _, linear, _ = run_cli(*args)
    _, both, _ = run_cli(*args, "--bench", bench)
    # The linear loop's lines are the plain step's, the bench's table follows.
    assert both.startswith(linear)
    bench_part = both[len(linear):]
    assert f"on the multibody bench {bench} " in bench_part
    rows = [line.split() for line in bench_part.splitlines() if line.startswith("   ")]
    assert [row[0] for row in rows] == ["1", "2"]
    result = ipmc_swim.step("pid", plant_file=tmp_path / "plant.toml",
                            gains_file=tmp_path / "gains.toml", horizon_s=2.0, bench=bench)
    for row, link in zip(rows, result["bench"]):
        assert row[1].rstrip("*") == f"{link['metrics']['overshoot_percent']:.3f}"
        # One record point per controller sample, 0 to the horizon, the
        # stepped link's measured deflection starting at rest.
        assert link["time_s"].shape == (2001,) and link["time_s"][-1] == pytest.approx(2.0)
        assert link["output_mm"][0] == 0.0
    with pytest.raises(ipmc_swim.Error, match="links must be in 1..2, got 3"):
        ipmc_swim.step("pid", links=[3], bench=bench)


def test_a_plant_file_without_link_arrays_takes_the_gains_files_links(tmp_path):
    # identify's plant.toml of one record: the same plant for every link.
    (tmp_path / "plant.toml").write_text(
        '[plant]\nmodel = "g1"\na0_mm_per_V = 0.52\nb1 = 0.029\nb2_s2 = 0.0042\n')
    (tmp_path / "gains.toml").write_text(GAINS)
    files = {"plant_file": tmp_path / "plant.toml", "gains_file": tmp_path / "gains.toml"}
    assert [link["link"] for link in ipmc_swim.bode("pid", **files)] == [1, 2]
    step = ipmc_swim.step("pid", horizon_s=1.0, **files)
    assert [link["link"] for link in step["links"]] == [1, 2]
    # Alone it holds for the paper's three links.
    alone = ipmc_swim.step("pid", horizon_s=1.0, plant_file=tmp_path / "plant.toml")
    assert [link["link"] for link in alone["links"]] == [1, 2, 3]
