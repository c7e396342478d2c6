"""Simulation: stepping from Python, a Python controller, threads."""

import sys
import threading
import time

import numpy as np
import pytest

import ipmc_swim
from conftest import SOURCE_DIR

sys.path.insert(0, str(SOURCE_DIR / "sim" / "python" / "examples"))
import python_pid  # noqa: E402


def test_a_python_pid_reproduces_the_built_in_run(short_scenario):
    # The example's PID is eq. 12 transcribed, on the built-in loop: the
    # per-cycle displacement must agree within 1e-9 relative (the same
    # operations in the same order give the same doubles).
    swim, _ = python_pid.run_python_pid(short_scenario)
    built_in = ipmc_swim.run(short_scenario).summary
    ours = [c["com_along_mm"] for c in swim["per_cycle"]]
    theirs = [c["com_along_mm"] for c in built_in["per_cycle"]]
    assert len(ours) == 2
    np.testing.assert_allclose(ours, theirs, rtol=1e-9, atol=0)
    assert swim["peak_lateral_tip_speed_mm_s"] == pytest.approx(
        built_in["peak_lateral_tip_speed_mm_s"], rel=1e-9)


def test_a_python_pid_runs_each_links_own_gains(short_scenario):
    # Per-link Kp and Kd (as an optimisation that retunes each design's
    # controllers sets them): the example's PIDs take them from
    # sim.controller and swim as the built-in run, within 1e-9 relative.
    gains = {"controller.link_kp": [4.0, 8.12, 12.0], "controller.link_kd": [0.0, 0.01, 0.02]}
    swim, _ = python_pid.run_python_pid(short_scenario, **gains)
    built_in = ipmc_swim.run(short_scenario, **gains).summary
    ours = [c["com_along_mm"] for c in swim["per_cycle"]]
    theirs = [c["com_along_mm"] for c in built_in["per_cycle"]]
    default = [c["com_along_mm"] for c in ipmc_swim.run(short_scenario).summary["per_cycle"]]
    np.testing.assert_allclose(ours, theirs, rtol=1e-9, atol=0)
    # The per-link gains change the swim: the comparison could fail.
    assert abs(theirs[-1] - default[-1]) > 1e-6 * abs(default[-1])


def test_stepping_reads_and_writes_the_model(short_scenario):
    sim = ipmc_swim.Simulation(short_scenario)
    assert sim.links == 3
    assert sim.joint_names == ["j1", "j2", "j3"]
    assert sim.timestep == 5e-4 and sim.steps_per_sample == 2 and sim.sample_period_s == 1e-3
    assert sim.period_s == 10.0 and sim.steps_per_cycle == 20000 and sim.cycles == 2
    assert sim.controller["kind"] == "pid" and sim.controller["kp"] == 8.12
    np.testing.assert_array_equal(sim.relative_deflections_mm(), np.zeros(3))
    sim.set_voltages([1.0, -1.0, 0.5])
    sim.step(200)
    assert sim.time == pytest.approx(200 * 5e-4, rel=1e-12)
    state = sim.actuator_state()
    np.testing.assert_array_equal(state["voltage_V"], [1.0, -1.0, 0.5])
    # 0.1 s after a voltage step the free deflections have the voltage's sign.
    assert np.all(np.sign(state["free_deflection_mm"]) == [1, -1, 1])
    assert state["active_moment_N_m"].shape == (3,)
    angles = sim.joint_angles_rad()
    assert angles.dtype == np.float64 and angles.shape == (3,)
    assert sim.relative_deflections_mm().shape == (3,)
    assert sim.tip_lateral_mm().shape == (3,)
    pose = sim.pose()
    assert pose["t_s"] == sim.time and pose["tip_x_mm"].shape == (3,)
    assert sim.qpos().shape == (6,) and sim.qvel().shape == (6,)
    # The references fade in: zero at t = 0, the wave after the ramp.
    np.testing.assert_array_equal(sim.references_mm(0.0), np.zeros(3))
    assert np.max(np.abs(sim.references_mm(5.0))) > 1.0


def test_stepping_errors(short_scenario):
    sim = ipmc_swim.Simulation(short_scenario)
    with pytest.raises(ipmc_swim.Error, match="3"):
        sim.set_voltages([1.0, 2.0])
    with pytest.raises(ipmc_swim.Error, match="finite"):
        sim.set_voltages([1.0, float("nan"), 0.0])
    bare = ipmc_swim.Simulation.from_model(SOURCE_DIR / "models" / "flagellum3.xml")
    assert bare.links == 3
    with pytest.raises(ipmc_swim.Error, match="needs a simulation made from a scenario"):
        bare.references_mm()
    with pytest.raises(ipmc_swim.Error, match="cannot open"):
        ipmc_swim.Simulation.from_model("no_such_model.xml")


def test_a_diverged_simulation_raises_and_refuses_further_steps():
    """The flagellum with RK4 at a 50 ms step (the hinge mode needs < 5 ms)
    diverges under a voltage: step() raises, and so does every later step()
    or swim() (sim/python/bind_simulation.cc)."""
    xml = (SOURCE_DIR / "models" / "flagellum3.xml").read_text()
    xml = xml.replace('timestep="0.0001" integrator="implicit"', 'timestep="0.05" integrator="RK4"')
    sim = ipmc_swim.Simulation.from_xml(xml)
    sim.set_voltages([3.0, 3.0, 3.0])
    with pytest.raises(ipmc_swim.Error, match="diverged"):
        sim.step(1000)
    with pytest.raises(ipmc_swim.Error, match="diverged before"):
        sim.step(1)
    with pytest.raises(ipmc_swim.Error, match="diverged before"):
        sim.swim()


def test_reading_the_time_while_another_thread_steps_leaves_python_running(short_scenario):
    """time waits for a step in another thread without the GIL: the
    interpreter runs other threads meanwhile, so ticks recorded by a third
    thread fall before the step ends (holding the GIL they all came after)."""
    sim = ipmc_swim.Simulation(short_scenario)
    steps = 200000  # about 1 s of CPU
    finished = []
    stepping = threading.Thread(target=lambda: (sim.step(steps), finished.append(time.monotonic())))
    stepping.start()
    time.sleep(0.05)
    reader = threading.Thread(target=lambda: sim.time)
    reader.start()
    ticks = []
    ticker = threading.Thread(target=lambda: [ticks.append(time.monotonic()) or time.sleep(0.001)
                                              for _ in range(20)])
    ticker.start()
    for thread in (ticker, reader, stepping):
        thread.join(timeout=120)
    assert len(ticks) == 20 and finished
    assert min(ticks) < finished[0]
    assert sim.time == pytest.approx(steps * sim.timestep)


def test_a_generated_model_loads_from_its_text():
    sim = ipmc_swim.Simulation.from_xml(ipmc_swim.generate_model(link_lengths_mm=[8.0, 12.0]))
    assert sim.links == 2
    sim.step(10)
    assert sim.time == pytest.approx(10 * 1e-4)


def step_with_voltages(sim, volts, steps):
    sim.set_voltages(volts)
    sim.step(steps)
    return sim.qpos()


def test_two_simulations_in_two_threads_equal_them_run_one_after_the_other(short_scenario):
    # Different viscosities and voltages, so the two runs differ; each must
    # be bit-identical to the same run made alone.
    settings = [({"fluid.viscosity_Pa_s": 1e-3}, [2.0, -1.0, 1.0]),
                ({"fluid.viscosity_Pa_s": 2e-3}, [-1.5, 1.0, 2.0])]
    steps = 4000
    serial = [step_with_voltages(ipmc_swim.Simulation(short_scenario, **o), v, steps)
              for o, v in settings]
    sims = [ipmc_swim.Simulation(short_scenario, **o) for o, _ in settings]
    parallel = [None, None]

    def work(k):
        parallel[k] = step_with_voltages(sims[k], settings[k][1], steps)

    threads = [threading.Thread(target=work, args=(k,)) for k in range(2)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    assert not np.array_equal(serial[0], serial[1])
    for k in range(2):
        np.testing.assert_array_equal(parallel[k], serial[k])


def test_runs_in_two_threads_equal_them_run_one_after_the_other(short_scenario):
    overrides = [{"cycles": 1}, {"cycles": 1, "fluid.viscosity_Pa_s": 2e-3}]
    serial = [ipmc_swim.run(short_scenario, **o).summary for o in overrides]
    parallel = [None, None]

    def work(k):
        parallel[k] = ipmc_swim.run(short_scenario, **overrides[k]).summary

    threads = [threading.Thread(target=work, args=(k,)) for k in range(2)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    assert serial[0] != serial[1]
    assert parallel == serial


def test_ctrl_c_stops_a_long_step(short_scenario):
    """SIGINT during step(n) raises KeyboardInterrupt at a step boundary
    (checked every 2000 steps), not after the n steps."""
    import os
    import signal
    import subprocess

    program = ("import ipmc_swim, sys\n"
               f"s = ipmc_swim.Simulation({str(short_scenario)!r})\n"
               "print('stepping', flush=True)\n"
               "s.step(10**9)\n")
    child = subprocess.Popen([sys.executable, "-c", program], stdout=subprocess.PIPE,
                             stderr=subprocess.PIPE, text=True, env=os.environ)
    assert child.stdout.readline().strip() == "stepping"
    time.sleep(0.5)
    child.send_signal(signal.SIGINT)
    _, stderr = child.communicate(timeout=30)  # 10**9 steps would take an hour
    assert child.returncode != 0
    assert "KeyboardInterrupt" in stderr


def _drive(sim, steps):
    """Voltages that change every 10 steps; the qpos, qvel, actuator state
    and pose after each block."""
    trace = []
    for k in range(steps // 10):
        sim.set_voltages([np.sin(0.3 * k), -np.cos(0.2 * k), 0.5])
        sim.step(10)
        state = sim.actuator_state()
        trace.append(np.concatenate([[sim.time], sim.qpos(), sim.qvel(),
                                     state["free_deflection_mm"], state["active_moment_N_m"]]))
    return np.array(trace)


@pytest.mark.parametrize("dynamics", ["inertial", "stokes"])
def test_a_copy_continues_bit_for_bit(short_scenario, dynamics):
    # mj_copyData carries the coupling's state (mjData.userdata): the
    # branch and the original, given the same voltages, hold the same doubles.
    sim = ipmc_swim.Simulation(short_scenario, dynamics=dynamics)
    _drive(sim, 100)
    branch = sim.copy()
    assert branch.time == sim.time and branch.dynamics == dynamics
    expected = _drive(sim, 200)
    np.testing.assert_array_equal(_drive(branch, 200), expected)
    assert branch.swim()["per_cycle"] == sim.swim()["per_cycle"]
    # The two are independent: stepping the branch leaves the original.
    before = sim.qpos()
    branch.step(10)
    np.testing.assert_array_equal(sim.qpos(), before)


@pytest.mark.parametrize("dynamics", ["inertial", "stokes"])
def test_reset_then_stepping_equals_a_fresh_simulation(short_scenario, dynamics):
    used = ipmc_swim.Simulation(short_scenario, dynamics=dynamics)
    _drive(used, 150)
    used.reset()
    assert used.time == 0.0
    np.testing.assert_array_equal(used.actuator_state()["voltage_V"], np.zeros(3))
    fresh = ipmc_swim.Simulation(short_scenario, dynamics=dynamics)
    np.testing.assert_array_equal(_drive(used, 150), _drive(fresh, 150))


def test_controller_shows_the_per_link_gains_that_run(short_scenario):
    sim = ipmc_swim.Simulation(short_scenario, **{"controller.link_kp": [1.0, 2.0, 3.0]})
    controller = sim.controller
    np.testing.assert_array_equal(controller["link_kp"], [1.0, 2.0, 3.0])
    # No per-link Ki, Kd: every link runs the scalar keys'.
    np.testing.assert_array_equal(controller["link_ki"], [controller["ki"]] * 3)
    np.testing.assert_array_equal(controller["link_kd"], [controller["kd"]] * 3)
    fractional = ipmc_swim.Simulation(short_scenario, **{"controller.kind": "fractional",
                                                         "controller.link_order": [0.5, 0.6, 0.7]})
    np.testing.assert_array_equal(fractional.controller["link_order"], [0.5, 0.6, 0.7])
    np.testing.assert_array_equal(fractional.controller["link_gain"],
                                  [fractional.controller["gain"]] * 3)
    with pytest.raises(ipmc_swim.Error, match="controller.link_kp must hold one value per link"):
        ipmc_swim.Simulation(short_scenario, **{"controller.link_kp": [1.0, 2.0]})
