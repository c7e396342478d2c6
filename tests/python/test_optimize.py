"""ipmc_swim.optimize: the same files as ``ipmc-swim optimize`` (names and
bytes), the result as a dict, and the option table's checks."""

import pytest

import ipmc_swim
from conftest import SOURCE_DIR, run_cli

# Two short cycles at 0.5 Hz of the generated flagellum (a fraction of a
# second each); L1 free, L3 = 30 mm - L1 - L2; 2 starts of 3 evaluations.
BASE = f"""
model = "{SOURCE_DIR / 'models' / 'flagellum3.xml'}"
actuation = "distributed"
cycles = 2
timestep_s = 5e-4
[waveform]
frequency_Hz = 0.5
[metrics]
from_cycle = 2
"""

OPT = """
base = "base.toml"
[set]
link_lengths_mm = [10.0, 10.0, 10.0]
[[variable]]
key = "link_lengths_mm[0]"
lower = 8.0
upper = 13.0
initial = 10.0
[sum]
key = "link_lengths_mm[2]"
total = 20.0
lower = 6.0
upper = 13.0
[objective]
metric = "last_cycle_com_along_mm"
sense = "maximize"
[algorithm]
name = "subplex"
max_evaluations = 3
multistart = 1
"""


def files_of(folder):
    return {path.relative_to(folder).as_posix(): path.read_bytes()
            for path in sorted(folder.rglob("*")) if path.is_file()}


def test_optimize_writes_what_the_command_line_writes(tmp_path):
    (tmp_path / "base.toml").write_text(BASE)
    opt = tmp_path / "opt.toml"
    opt.write_text(OPT)
    run_cli("optimize", opt, "--out", tmp_path / "cli", "--jobs", "1")
    seen = []
    result = ipmc_swim.optimize(opt, out=tmp_path / "python", jobs=2,
                                progress=lambda done, total: seen.append(done))
    cli, python = files_of(tmp_path / "cli"), files_of(tmp_path / "python")
    assert "result.json" in cli and "best/summary.json" in cli
    assert sorted(python) == sorted(cli)
    for name in cli:
        if name != "optimize.journal":  # its records in the order the threads finished
            assert python[name] == cli[name], name
    assert result["algorithm"] == "subplex"
    assert result["evaluations"] == 6
    assert set(result["best"]["variables"]) == {"link_lengths_mm[0]", "link_lengths_mm[2]"}
    assert result["best"]["objective"] == result["best"]["metrics"]["last_cycle_com_along_mm"]
    assert seen


def test_optimize_refuses_a_journal_without_resume(tmp_path):
    (tmp_path / "base.toml").write_text(BASE)
    opt = tmp_path / "opt.toml"
    opt.write_text(OPT)
    first = ipmc_swim.optimize(opt, out=tmp_path / "out", jobs=1)
    with pytest.raises(ipmc_swim.Error, match="resume"):
        ipmc_swim.optimize(opt, out=tmp_path / "out", jobs=1)
    again = ipmc_swim.optimize(opt, out=tmp_path / "out", jobs=1, resume=True)
    assert again == first
    with pytest.raises(ipmc_swim.Error, match="jobs"):
        ipmc_swim.optimize(opt, out=tmp_path / "other", jobs=0)


def test_starts_apart_then_merged_give_the_command_lines_files(tmp_path):
    """optimize --slurm's tasks and merge, from Python: each start alone
    (start=K, no result but its journal), then journals= writes what one
    command-line run writes."""
    (tmp_path / "base.toml").write_text(BASE)
    opt = tmp_path / "opt.toml"
    opt.write_text(OPT)
    run_cli("optimize", opt, "--out", tmp_path / "cli", "--jobs", "1")
    for start in (0, 1):
        task = tmp_path / "starts" / f"start_{start}"
        assert ipmc_swim.optimize(opt, out=task, jobs=1, start=start) is None
        assert sorted(files_of(task)) == ["optimize.journal"]
    ipmc_swim.optimize(opt, out=tmp_path / "merged", jobs=1, journals=tmp_path / "starts")
    cli, merged = files_of(tmp_path / "cli"), files_of(tmp_path / "merged")
    assert sorted(merged) == sorted(cli)
    for name in cli:
        if name != "optimize.journal":
            assert merged[name] == cli[name], name
    with pytest.raises(ipmc_swim.Error, match="start"):
        ipmc_swim.optimize(opt, out=tmp_path / "bad", jobs=1, start=2)
