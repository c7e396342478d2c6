"""keys(), options() and merge() are the commands `ipmc-swim keys`,
`ipmc-swim options` and `ipmc-swim merge` (the same library calls and
option tables): the references are the command's stdout byte for byte, in
both formats, and the merged table's files are the command's bytes; bad
input is the command's one-line message, with nothing written."""

import subprocess

import pytest

import ipmc_swim
from conftest import CLI, cli_error, run_cli



def cli_stdout(*args):
    return subprocess.run([CLI, *map(str, args)], capture_output=True, check=True).stdout


@pytest.mark.parametrize("format", ["text", "markdown"])
@pytest.mark.parametrize("command", ["keys", "options"])
def test_the_references_are_the_command_line_s_bytes(command, format):
    text = getattr(ipmc_swim, command)(format=format)
    assert text.encode() == cli_stdout(command, "--format", format)
    assert getattr(ipmc_swim, command)() == getattr(ipmc_swim, command)(format="text")


def test_the_options_reference_lists_python_s_own_new_keywords():
    text = ipmc_swim.options(format="markdown")
    for keyword in ("`resume_other_version`", "`runs_dir`", "`partial`"):
        assert keyword in text, keyword


@pytest.mark.parametrize("command", ["keys", "options"])
def test_a_reference_format_that_is_not_one_is_refused(command):
    with pytest.raises(ipmc_swim.Error, match="format must be text or markdown"):
        getattr(ipmc_swim, command)(format="html")


def test_merge_writes_the_command_line_s_files(tmp_path, shards):
    _, tables = shards
    run_cli("merge", "--out", tmp_path / "cli", *tables)
    table = ipmc_swim.merge(tables, out=tmp_path / "python")
    for suffix in (".csv", ".json"):
        assert (tmp_path / f"python{suffix}").read_bytes() == \
            (tmp_path / f"cli{suffix}").read_bytes(), suffix
    assert list(table["point"]) == [0, 1, 2]
    assert list(table["waveform.frequency_Hz"]) == [0.5, 0.4, 0.3]


def test_merge_refuses_what_the_command_line_refuses(tmp_path, shards):
    _, tables = shards
    cases = [
        ([tables[0], tmp_path / "missing.csv"], "does not exist"),
        ([tables[0], tables[0]], None),  # a point in two tables
        ([tables[0]], None),             # a gap in the indices
    ]
    for given, fragment in cases:
        expected = cli_error("merge", "--out", tmp_path / "cli", *given)
        if fragment:
            assert fragment in expected, expected
        with pytest.raises(ipmc_swim.Error) as raised:
            ipmc_swim.merge(given, out=tmp_path / "python")
        assert str(raised.value) == expected
        assert not (tmp_path / "python.csv").exists()
