"""export: the scenario's controllers as C, compiled with the system C
compiler (double and float) and checked against the simulator's own, by
replaying a recorded run and by closing the loop on the simulated robot
(sim/python/examples/exported_controller.py, docs/PROTOTYPE.md)."""

import json
import sys

import numpy as np
import pytest

import ipmc_swim
from conftest import SOURCE_DIR, cli_error

sys.path.insert(0, str(SOURCE_DIR / "sim" / "python" / "examples"))
import exported_controller  # noqa: E402

FILES = ["ipmc_controller.h", "ipmc_controller.c", "coefficients.json", "coefficients.csv"]

# Two cycles of a 1 Hz wave, every controller sample recorded: quick, and
# fast enough for the clamp to act (the anti-windup is exercised).
FAST = {"cycles": 2, "waveform.frequency_Hz": 1.0, "output.samples_per_cycle": 1000}

# The user's two-link strip (12 + 12 mm, 5 mm x 200 um) with a plant and
# PID gains of its own per link and a derivative filter.
TWO_LINK = """
link_lengths_mm = [12.0, 12.0]
actuation = "distributed"
cycles = 2
timestep_s = 5e-4

[strip]
width_mm = 5.0
thickness_um = 200.0

[plant]
model = "g1"
link_a0_mm_per_V = [0.52, 0.47]
link_b1 = [0.029, 0.033]
link_b2_s2 = [0.0042, 0.0039]

[controller]
kind = "pid"
link_kp = [7.758, 6.9]
link_ki = [28.14, 33.0]
link_kd = [0.7181, 0.64]
derivative_filter_s = 0.002

[waveform]
kind = "polynomial"
c1_um_per_mm = 200.0
frequency_Hz = 1.0
wavelength_mm = 24.0
start_ramp_cycles = 0.25

[output]
samples_per_cycle = 1000
"""


@pytest.fixture(scope="module")
def two_link(tmp_path_factory):
    path = tmp_path_factory.mktemp("two_link") / "two_link.toml"
    path.write_text(TWO_LINK)
    return str(path)


def scenarios(two_link):
    return {"pid": (str(SOURCE_DIR / "scenarios" / "paper.toml"), FAST),
            "fractional": (str(SOURCE_DIR / "scenarios" / "paper_fractional.toml"), FAST),
            "two_link": (two_link, {})}


@pytest.fixture(scope="module")
def recorded(two_link, tmp_path_factory):
    """Each scenario's export and run (every sample recorded), by name."""
    done = {}
    for name, (scenario, overrides) in scenarios(two_link).items():
        folder = tmp_path_factory.mktemp(name)
        ipmc_swim.export(scenario, out=folder / "export", **overrides)
        run = ipmc_swim.run(scenario, out=folder / "run", **overrides)
        done[name] = (scenario, overrides, folder, run)
    return done


def test_the_files_and_what_python_returns(tmp_path):
    # The two front ends' bytes are compared in test_front_ends.py.
    scenario = SOURCE_DIR / "scenarios" / "paper_fractional.toml"
    coefficients = ipmc_swim.export(scenario, out=tmp_path / "py")
    assert sorted(p.name for p in (tmp_path / "py").iterdir()) == sorted(FILES)
    assert coefficients == json.loads((tmp_path / "py" / "coefficients.json").read_text())
    # eq. 14's integrator as 4 sections (N = 4 pairs), every coefficient commented.
    assert coefficients["controller"] == "fractional" and coefficients["links"] == 3
    assert [len(link["sections"]) for link in coefficients["per_link"]] == [4, 4, 4]
    source = (tmp_path / "py" / "ipmc_controller.c").read_text()
    assert source.count("section 4: alpha = 1 - pole") == 3
    assert "#include <stdlib.h>" not in source and "malloc" not in source


def test_bad_input_is_one_line_and_writes_nothing(tmp_path):
    scenario = SOURCE_DIR / "scenarios" / "paper.toml"
    message = cli_error("export", scenario, "--set", "controller.link_kp=[1.0, 2.0]",
                        "--out", tmp_path / "out")
    assert "controller.link_kp must hold one value per link (3; got 2)" in message
    message = cli_error("export", scenario, "--set", "controller.kp=-1", "--out", tmp_path / "out")
    assert "controller.kp" in message and ">= 0" in message
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("name", ["pid", "fractional", "two_link"])
def test_the_exported_double_replays_a_recorded_run(recorded, name):
    _, _, folder, _ = recorded[name]
    controller = exported_controller.ExportedController(folder / "export")
    try:
        worst, samples = exported_controller.replay(controller, folder / "run")
    finally:
        controller.close()
    assert samples == 2000
    # timeseries.csv prints the references and measurements at 10
    # significant digits: up to 5e-10 mm each at 5 mm, so e_k is known to
    # 1e-9 mm, which the PID's derivative takes twice at Kd / T = 610 V/mm:
    # (Kp + 2 Kd / T) 1e-9 mm = 1.2e-6 V. Measured: 1.16e-6 V (paper.toml),
    # 3.7e-7 V (the two links, Kd / (Tf + T) = 240 V/mm), 1.3e-9 V (the
    # integrator, whose gain at high frequency is 0.9 V/mm).
    assert max(worst) < {"pid": 2e-6, "two_link": 1e-6, "fractional": 1e-8}[name], worst


@pytest.mark.parametrize("name", ["pid", "fractional", "two_link"])
def test_the_exported_float_replays_a_recorded_run_within_10_mV(recorded, name):
    _, _, folder, _ = recorded[name]
    controller = exported_controller.ExportedController(folder / "export", use_float=True)
    try:
        assert controller.real_bytes == 4
        worst, _ = exported_controller.replay(controller, folder / "run")
    finally:
        controller.close()
    assert max(worst) < 0.01, worst


@pytest.mark.parametrize("name", ["pid", "fractional", "two_link"])
@pytest.mark.parametrize("use_float", [False, True])
def test_the_exported_controller_closes_the_loop_with_the_built_in_swim(recorded, name, use_float):
    scenario, overrides, folder, run = recorded[name]
    controller = exported_controller.ExportedController(folder / "export", use_float=use_float)
    try:
        swim, voltages = exported_controller.close_loop(controller, scenario, **overrides)
    finally:
        controller.close()
    ours = np.array([c["com_along_mm"] for c in swim["per_cycle"]])
    theirs = np.array([c["com_along_mm"] for c in run.summary["per_cycle"]])
    recorded_volts = np.column_stack([run.timeseries[f"voltage{q + 1}_V"]
                                      for q in range(len(voltages[0]))])
    if use_float:
        # float32 moves the swim by less than 0.1 % (the requirement; measured
        # 8e-7 at most) and the voltages by at most 4.5e-4 V (paper.toml).
        np.testing.assert_allclose(ours, theirs, rtol=1e-3, atol=0)
        assert np.max(np.abs(np.array(voltages) - recorded_volts)) < 5e-3
    elif name == "fractional":
        # The integrator's sections sum its modes in another order than the
        # simulator's state-space update: 6e-15 V apart; the swim's printed
        # digits are the same.
        np.testing.assert_allclose(ours, theirs, rtol=1e-12, atol=0)
        assert np.max(np.abs(np.array(voltages) - recorded_volts)) < 1e-12
    else:
        # The PID's operations are the simulator's, in its order: the same doubles.
        assert np.array_equal(np.array(voltages), recorded_volts)
        assert np.array_equal(ours, theirs)
