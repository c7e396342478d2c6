"""The example study runs and draws its figure."""

import subprocess
import sys

from conftest import SOURCE_DIR


def test_the_frequency_study_draws_its_figure(short_scenario, tmp_path):
    figure = tmp_path / "study.png"
    done = subprocess.run(
        [sys.executable, SOURCE_DIR / "sim" / "python" / "examples" / "frequency_study.py",
         "--scenario", short_scenario, "--frequencies-hz", "0.1", "0.2", "--cycles", "1",
         "--out", figure], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert figure.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    lines = done.stdout.splitlines()
    assert lines[0].split() == ["frequency_Hz", "mean_speed_along_mm_s", "last_cycle_mm", "link3_clamped_fraction"]
    assert [line.split()[0] for line in lines[1:3]] == ["0.1", "0.2"]
