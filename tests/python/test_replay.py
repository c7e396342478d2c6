"""A run's model.xml stepped from Python (Simulation.from_model) with the
voltages the run applied at every controller sample gives the run's
states: the library steps a model as the program does (tests/replay_test.cc
does the same in C++, for a flexible strip and Stokes dynamics too)."""

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
