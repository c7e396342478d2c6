"""The scenario's dynamics key reaches the Python Simulation (docs/DYNAMICS.md)."""
import ipmc_swim


def test_a_scenario_override_chooses_the_stokes_step(short_scenario):
    inertial = ipmc_swim.Simulation(short_scenario)
    stokes = ipmc_swim.Simulation(short_scenario, dynamics="stokes", timestep_s=1e-3)
    assert inertial.dynamics == "inertial"
    assert stokes.dynamics == "stokes"
    for sim in (inertial, stokes):
        sim.set_voltages([2.0, 2.0, 2.0])
        sim.step(round(1.0 / sim.timestep))
        assert abs(sim.time - 1.0) < 1e-9
    # 1 s of 2 V bends the links alike: the two dynamics differ only by the
    # hinges' inertia (within 1 %; docs/DYNAMICS.md).
    a, b = inertial.joint_angles_rad(), stokes.joint_angles_rad()
    assert all(abs(x - y) < 0.01 * abs(x) + 1e-6 for x, y in zip(a, b)), (a, b)
