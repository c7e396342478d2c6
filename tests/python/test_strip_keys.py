"""The strip and plant keys reach Python through the key table: keyword
overrides give the command line's run byte for byte, and bad values are
the command line's one-line errors."""

import ipmc_swim
import pytest

from conftest import run_cli


def test_plant_and_strip_overrides_equal_the_command_line(short_scenario, tmp_path):
    keys = {"plant.a0_mm_per_V": 0.6, "plant.link_b2_s2": [0.002, 0.003, 0.004],
            "strip.thickness_um": 200.0}
    run_cli("run", short_scenario, "--set", "plant.a0_mm_per_V=0.6",
            "--set", "plant.link_b2_s2=[0.002, 0.003, 0.004]",
            "--set", "strip.thickness_um=200.0", "--out", tmp_path / "cli")
    ipmc_swim.run(short_scenario, out=tmp_path / "python", **keys)
    for name in ("timeseries.csv", "states.csv"):
        assert (tmp_path / "python" / name).read_bytes() == (tmp_path / "cli" / name).read_bytes()


def test_a_bad_plant_key_is_the_command_lines_error(short_scenario):
    with pytest.raises(ipmc_swim.Error, match="plant.a0_mm_per_V must be > 0"):
        ipmc_swim.run(short_scenario, **{"plant.a0_mm_per_V": 0.0})
