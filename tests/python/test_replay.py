"""A run's model.xml stepped from Python (Simulation.from_model) with the
voltages the run applied at every controller sample gives the run's
states: the library steps a model as the program does (tests/replay_test.cc
does the same in C++, for a flexible strip and Stokes dynamics too)."""

import re

import numpy as np

import ipmc_swim
from conftest import SOURCE_DIR


def test_from_model_replays_the_default_job(tmp_path):
    # The default job's model and controllers over one 2 s cycle, every
    # 1 kHz controller sample recorded.
    out = tmp_path / "run"
    result = ipmc_swim.run(str(SOURCE_DIR / "scenarios" / "paper.toml"), out=out, cycles=1,
                           **{"waveform.frequency_Hz": 0.5, "output.samples_per_cycle": 2000})
    volts = np.column_stack([result.timeseries[f"voltage{q}_V"] for q in (1, 2, 3)])
    header = (out / "states.csv").read_text().splitlines()[0].split(",")
    states = np.loadtxt(out / "states.csv", delimiter=",", skiprows=1)
    sim = ipmc_swim.Simulation.from_model(out / "model.xml")
    assert sim.timestep == 5e-4
    coordinates = header[1:]
    worst = 0.0
    for k in range(len(volts)):
        assert abs(sim.time - states[k, 0]) < 1e-12
        worst = max(worst, np.max(np.abs(sim.qpos() - states[k, 1:])))
        sim.set_voltages(volts[k].tolist())
        sim.step(2)
    largest = np.max(np.abs(states[:, 1:]))
    print(f"{len(coordinates)} coordinates, largest {largest:.6g}, largest difference {worst:.3g}")
    # Measured 0: the run's doubles replayed bit for bit.
    assert worst <= 1e-9 * largest


def test_fluid_forces_of_a_towed_body_as_arrays():
    # The paper's model towed along x at 1 mm/s, straight: the fluid's
    # forces sum to -U times the towing drag's slope along x, and the
    # power to U^2 times it (the head and three links, RFT).
    sim = ipmc_swim.Simulation.from_model(SOURCE_DIR / "models" / "flagellum3.xml")
    qvel = np.zeros(len(sim.qvel()))
    qvel[0] = 1e-3
    sim.set_qvel(qvel.tolist())
    bodies, force, torque = sim.fluid_forces()
    assert force.shape == (len(bodies), 3) and torque.shape == (len(bodies), 3)
    drag = force[:, 0].sum()
    assert drag < 0 and abs(force[:, 1].sum()) < 1e-12 * abs(drag)
    assert abs(sim.fluid_power_W() + drag * 1e-3) < 1e-12 * abs(drag) * 1e-3


def test_from_model_swims_an_open_loop_run(tmp_path):
    # The head-and-tail swimmer driven open loop by `run` (drive.mode =
    # "sine") over two 2 s cycles, every 1 kHz sample recorded; from_model
    # on the run's model.xml with the same voltages, computed here from
    # their formula (A sin(2 pi f t - q phi), faded in over a quarter
    # period), gives the run's states and swim per cycle.
    out = tmp_path / "run"
    result = ipmc_swim.run(str(SOURCE_DIR / "scenarios" / "head_and_tail_open_loop.toml"),
                           out=out, cycles=2,
                           **{"waveform.frequency_Hz": 0.5, "output.samples_per_cycle": 2000,
                              "drive.amplitude_V": 3.0, "drive.phase_lag_rad": 1.25})
    assert result.summary["controller"] == "sine"
    f, amplitude, lag, ramp = 0.5, 3.0, 1.25, 0.25 / 0.5
    states = np.loadtxt(out / "states.csv", delimiter=",", skiprows=1)
    sim = ipmc_swim.Simulation.from_model(out / "model.xml")
    steps = round(1e-3 / sim.timestep)
    worst = 0.0
    for k in range(len(states)):
        t = sim.time
        assert abs(t - states[k, 0]) < 1e-12
        worst = max(worst, np.max(np.abs(sim.qpos() - states[k, 1:])))
        fade = 0.5 * (1 - np.cos(np.pi * t / ramp)) if t < ramp else 1.0
        sim.set_voltages([fade * amplitude * np.sin(2 * np.pi * f * t - q * lag)
                          for q in range(sim.links)])
        sim.step(steps)
        if (k + 1) % 2000 == 0:
            sim.end_cycle()
    largest = np.max(np.abs(states[:, 1:]))
    along = [cycle["com_along_mm"] for cycle in sim.swim()["per_cycle"]]
    print(f"swim per cycle: run {result.cycles['com_along_mm'].tolist()}, from_model {along}; "
          f"largest coordinate {largest:.6g}, largest difference {worst:.3g}")
    # Measured 0: the voltages the formula gives are the run's to the last
    # bit (the states, then the swim meter's cycles, agree exactly).
    assert worst <= 1e-9 * largest
    np.testing.assert_allclose(along, result.cycles["com_along_mm"], rtol=1e-9, atol=0)
    assert along[1] > 0


def unnamed_head_and_tail(path):
    # models/head_and_tail.xml without the paper's naming: hinges h1..h4
    # (ipmc_links and the ipmc_<joint> motors follow), no sites, no sensors.
    xml = (SOURCE_DIR / "models" / "head_and_tail.xml").read_text()
    xml = re.sub(r"<sensor>.*?</sensor>", "", xml, flags=re.S)
    xml = re.sub(r'<site name="tip\d"[^>]*/>', "", xml)
    xml = re.sub(r'"(ipmc_)?j(\d)"', r'"\1h\2"', xml)
    xml = xml.replace('data="j1 j2 j3 j4"', 'data="h1 h2 h3 h4"')
    assert '"tip1' not in xml and '"angle_' not in xml and '"j1"' not in xml
    path.write_text(xml)
    return path


def test_python_runs_a_model_without_the_papers_names_as_the_named_one(tmp_path):
    # As tests/open_loop_test.cc for the program: open loop, the links, tips
    # and angles found from ipmc_links and the geometry swim bit for bit as
    # the named model's sites and sensors give them; from_model attaches it.
    model = unnamed_head_and_tail(tmp_path / "unnamed.xml")
    scenario = str(SOURCE_DIR / "scenarios" / "head_and_tail_open_loop.toml")
    settings = {"waveform.frequency_Hz": 0.5}
    named = ipmc_swim.run(scenario, out=tmp_path / "named", cycles=2, **settings)
    plain = ipmc_swim.run(scenario, out=tmp_path / "plain", cycles=2, model=str(model), **settings)
    assert list(plain.cycles["com_along_mm"]) == list(named.cycles["com_along_mm"])
    assert plain.cycles["com_along_mm"][1] > 0
    sim = ipmc_swim.Simulation.from_model(model)
    assert sim.links == 4
    sim.set_voltages([1.0, -1.0, 1.0, -1.0])
    sim.step(100)
    assert np.max(np.abs(sim.qpos())) > 0
