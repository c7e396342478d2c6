"""Bad input raises ipmc_swim.Error (a ValueError) with the command line's message."""

import re

import pytest

import ipmc_swim
from conftest import SHORT_SCENARIO, cli_error


def test_the_error_is_a_value_error():
    assert issubclass(ipmc_swim.Error, ValueError)


def test_a_bad_scenario_file_gives_the_command_lines_message(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text(SHORT_SCENARIO.replace("cycles = 2", "cycles = 0"))
    expected = cli_error("run", bad)
    assert re.search(r"bad\.toml:\d+: cycles", expected), expected
    with pytest.raises(ipmc_swim.Error) as error:
        ipmc_swim.run(str(bad))
    assert str(error.value) == expected


def test_a_bad_override_names_the_overrides_and_the_key_with_the_files_reason(short_scenario, tmp_path):
    # The reason is the scenario reader's, as for the file; the place is the
    # overrides of the scenario instead of a line.
    bad = tmp_path / "bad.toml"
    bad.write_text(SHORT_SCENARIO.replace("v_max_V = 6.0", "v_max_V = -1.0"))
    reason = re.sub(r"^.*?bad\.toml:\d+: ", "", cli_error("run", bad))
    with pytest.raises(ipmc_swim.Error) as error:
        ipmc_swim.run(short_scenario, controller={"v_max_V": -1.0})
    assert str(error.value) == f"{short_scenario} overrides: {reason}"
    with pytest.raises(ipmc_swim.Error, match=r"overrides: unknown key 'no_such_key'"):
        ipmc_swim.run(short_scenario, no_such_key=1)


def test_wrong_python_types_are_type_errors(short_scenario):
    with pytest.raises(TypeError, match="cycles"):
        ipmc_swim.run(short_scenario, cycles=object())
    with pytest.raises(TypeError, match="unexpected keyword argument 'duration'"):
        ipmc_swim.bench(duration=1.0)


def test_a_wrong_toml_type_is_the_scenario_readers_error(short_scenario):
    with pytest.raises(ipmc_swim.Error, match=r"overrides: cycles must be an integer \(got float\)"):
        ipmc_swim.run(short_scenario, cycles=1.5)


def with_flags(message, names):
    """A library message with the option names replaced by their flags, as
    the command line relocates it."""
    for name in names:
        message = re.sub(r"(?<![\w-])" + re.escape(name) + r"(?!\w)",
                         "--" + name.lower().replace("_", "-"), message)
    return message


def test_analysis_and_bench_errors_are_the_command_lines(tmp_path):
    # The library names the field (the keyword); the command line puts the
    # flag in its place.
    cases = [
        (lambda: ipmc_swim.bode("fractional", kp=1.0),
         ("bode", "--controller", "fractional", "--kp", "1"), ["kp", "controller"]),
        (lambda: ipmc_swim.step("pid", links=[4]), ("step", "--controller", "pid", "--links", "4"),
         ["links"]),
        (lambda: ipmc_swim.step("pid", v_max_V=0.0),
         ("step", "--controller", "pid", "--v-max-v", "0"), ["v_max_V"]),
        (lambda: ipmc_swim.design(phase_margin_deg=200.0), ("design", "--phase-margin-deg", "200"),
         ["phase_margin_deg"]),
        (lambda: ipmc_swim.bench(duration_s=-1.0),
         ("bench", "--duration-s", "-1", "--out", tmp_path / "bench.csv"), ["duration_s"]),
        (lambda: ipmc_swim.generate_model(gap_mm=-1.0), ("generate", "--gap-mm", "-1"), ["gap_mm"]),
    ]
    for call, command, names in cases:
        expected = cli_error(*command)
        with pytest.raises(ipmc_swim.Error) as error:
            call()
        assert with_flags(str(error.value), names) == expected
        for name in names:
            assert name in str(error.value)
    assert not (tmp_path / "bench.csv").exists()


def test_a_wrong_keyword_type_names_the_keyword():
    with pytest.raises(TypeError, match=r"step\(\): v_max_V must be a number \(int or float\) "
                                        r"\(got str\)"):
        ipmc_swim.step("pid", v_max_V="six")


def test_nothing_is_written_when_the_run_fails(short_scenario, tmp_path):
    with pytest.raises(ipmc_swim.Error):
        ipmc_swim.run(short_scenario, out=tmp_path / "out", cycles=0)
    assert not (tmp_path / "out").exists()
    with pytest.raises(ipmc_swim.Error, match="cannot open"):
        ipmc_swim.run(tmp_path / "missing.toml")
