"""plot() draws what ``ipmc-swim plot`` draws, the same bytes, and returns
the command's title and notes; compare names the runs by what differs
between their scenarios."""

import pytest

import ipmc_swim
from conftest import SHORT_SCENARIO, cli_error, run_cli


@pytest.fixture
def two_runs(short_scenario, tmp_path):
    """The short PID run and the same with the fractional integrator of eq. 14."""
    pid, fractional = tmp_path / "pid", tmp_path / "fractional"
    ipmc_swim.run(short_scenario, out=pid)
    scenario = tmp_path / "fractional.toml"
    scenario.write_text(SHORT_SCENARIO.replace('kind = "pid"', 'kind = "fractional"').replace(
        "kp = 8.12\nki = 53.36\nkd = 0.61", "gain = 15.62\norder = 0.62"))
    ipmc_swim.run(scenario, out=fractional)
    return pid, fractional


def test_compare_is_the_command_lines(two_runs, tmp_path):
    pid, fractional = two_runs
    result = ipmc_swim.plot("compare", [pid, fractional], out=tmp_path / "python.png")
    _, stdout, _ = run_cli("plot", "compare", pid, fractional, "--out", tmp_path / "cli.png")
    assert (tmp_path / "python.png").read_bytes() == (tmp_path / "cli.png").read_bytes()
    assert result.title == "Comparison of 2 runs: differing in controller.kind"
    assert result.title in stdout
    assert "controller.kind = pid" in result.notes[0]
    assert "controller.kind = fractional" in result.notes[1]
    for note in result.notes:
        assert note in stdout


def test_one_input_kind(two_runs, tmp_path):
    pid, _ = two_runs
    result = ipmc_swim.plot("tracking", pid / "timeseries.csv", out=tmp_path / "tracking.svg")
    assert result.title_lines[0] == "Tracking of each link's relative tip deflection"
    assert (tmp_path / "tracking.svg").read_text().rstrip().endswith("</svg>")


def test_refusals_are_the_command_lines(two_runs, tmp_path):
    pid, _ = two_runs
    with pytest.raises(ipmc_swim.Error) as python:
        ipmc_swim.plot("tracking", pid / "timeseries.csv", out=tmp_path / "t.png", instants=3)
    assert str(python.value) == cli_error("plot", "tracking", pid / "timeseries.csv", "--out",
                                          tmp_path / "t.png", "--instants", "3")
    with pytest.raises(ipmc_swim.Error, match="needs 2 to 8 run directories, got 1"):
        ipmc_swim.plot("compare", [pid], out=tmp_path / "c.png")
    with pytest.raises(TypeError, match="colour"):
        ipmc_swim.plot("compare", [pid, pid], out=tmp_path / "c.png", colour="red")
    assert not list(tmp_path.glob("*.png"))
