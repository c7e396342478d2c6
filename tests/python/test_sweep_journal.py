"""Python's sweep() and the command line's sweep run through one library
call (sim/batch/sweep_command.h, SweepCommandRun): the journal PREFIX.journal
is the lock of the output prefix and the record a stopped sweep resumes
from, whichever front end wrote it.

- A Python sweep and a command-line sweep started together on one prefix,
  25 times: every time exactly one of them is refused before running a
  point, with the lock error if the other one was running then, or because
  the journal records the other sweep if that one had already finished
  (docs/RUNS.md, "Two writers into one output"); the table is the other
  one's, whole.
- A journal cut after its first point (what a sweep stopped after one
  point leaves) is resumed by the other front end: only the points it does
  not hold run, and the table is byte for byte the uninterrupted one's."""

import shutil
import subprocess
import threading

import pytest

import ipmc_swim
from conftest import CLI, SHORT_SCENARIO, is_sweep_refusal, run_cli, table_files

TRIES = 25

# One 20 s cycle per point (most of a second of work), so that in most
# tries both sweeps are running when the second one opens the journal (the
# lock refuses it); in the others the first one has finished by then (its
# journal refuses the second).
SWEEP_A = 'base = "short.toml"\n[set]\ncycles = 1\n[grid]\n"waveform.frequency_Hz" = [0.05]\n'
SWEEP_B = 'base = "short.toml"\n[set]\ncycles = 1\n[grid]\n"waveform.frequency_Hz" = [0.045]\n'
# Three quick points, for resuming.
SWEEP_RESUME = ('base = "short.toml"\n[set]\ncycles = 1\n[grid]\n'
                '"waveform.frequency_Hz" = [0.5, 0.4, 0.3]\n')


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    folder = tmp_path_factory.mktemp("sweeps")
    (folder / "short.toml").write_text(SHORT_SCENARIO)
    (folder / "a.toml").write_text(SWEEP_A)
    (folder / "b.toml").write_text(SWEEP_B)
    (folder / "resume.toml").write_text(SWEEP_RESUME)
    return folder


@pytest.fixture(scope="module")
def references(folder):
    """Each sweep's table, from the command line and from Python."""
    tables = {}
    for name in ("a", "b", "resume"):
        run_cli("sweep", folder / f"{name}.toml", "--out", folder / f"cli_{name}" / "t",
                "--jobs", "1")
        tables[("cli", name)] = table_files(folder / f"cli_{name}" / "t")
        ipmc_swim.sweep(folder / f"{name}.toml", out=folder / f"python_{name}" / "t", jobs=1)
        tables[("python", name)] = table_files(folder / f"python_{name}" / "t")
    assert tables[("cli", "a")][".csv"] != tables[("cli", "b")][".csv"]
    return tables


def test_the_front_ends_write_the_same_table(references):
    for name in ("a", "b", "resume"):
        assert references[("python", name)] == references[("cli", name)], name


def test_a_python_and_a_command_line_sweep_never_share_a_prefix(tmp_path, folder, references):
    for attempt in range(TRIES):
        prefix = tmp_path / f"shared{attempt}" / "table"
        python_error = []

        def python_sweep():
            try:
                ipmc_swim.sweep(folder / "a.toml", out=prefix, jobs=1)
            except ipmc_swim.Error as error:
                python_error.append(str(error))

        thread = threading.Thread(target=python_sweep)
        thread.start()
        cli = subprocess.run([CLI, "sweep", str(folder / "b.toml"), "--out", str(prefix),
                              "--jobs", "1"], capture_output=True, text=True)
        thread.join()
        refusals = [message for message in python_error + [cli.stderr]
                    if is_sweep_refusal(message)]
        assert len(refusals) == 1, f"attempt {attempt}: {python_error} {cli.stderr}"
        if python_error:
            assert cli.returncode == 0, cli.stderr
            assert table_files(prefix) == references[("cli", "b")], f"attempt {attempt}"
        else:
            assert cli.returncode == 1 and "ipmc-swim: error: " in cli.stderr, cli.stderr
            assert table_files(prefix) == references[("python", "a")], f"attempt {attempt}"


def cut_journal(source_prefix, prefix, records):
    """PREFIX.journal with the header and the first `records` records of
    SOURCE_PREFIX.journal, as a sweep stopped after them leaves it."""
    lines = source_prefix.with_name(source_prefix.name + ".journal").read_text().splitlines(True)
    assert len(lines) == 4, lines  # the header and three points
    prefix.parent.mkdir(parents=True)
    prefix.with_name(prefix.name + ".journal").write_text("".join(lines[:1 + records]))


def test_python_resumes_a_command_line_journal(tmp_path, folder, references):
    prefix = tmp_path / "resumed" / "t"
    cut_journal(folder / "cli_resume" / "t", prefix, 1)
    reports = []
    ipmc_swim.sweep(folder / "resume.toml", out=prefix, jobs=1,
                    progress=lambda done, total: reports.append((done, total)))
    assert reports[-1] == (2, 2), reports  # the two points the journal did not hold
    assert table_files(prefix) == references[("cli", "resume")]


def test_the_command_line_resumes_a_python_journal(tmp_path, folder, references):
    prefix = tmp_path / "resumed" / "t"
    cut_journal(folder / "python_resume" / "t", prefix, 1)
    _, _, stderr = run_cli("sweep", folder / "resume.toml", "--out", prefix, "--jobs", "1")
    assert "1 of 3 points done before" in stderr, stderr
    assert stderr.count("done (point") == 2, stderr
    assert table_files(prefix) == references[("python", "resume")]


def test_a_journal_of_another_sweep_is_refused_from_python(tmp_path, folder, references):
    prefix = tmp_path / "other" / "t"
    prefix.parent.mkdir()
    shutil.copy(folder / "cli_a" / "t.journal", prefix.with_name("t.journal"))
    with pytest.raises(ipmc_swim.Error, match="records another sweep"):
        ipmc_swim.sweep(folder / "b.toml", out=prefix, jobs=1)
    assert not prefix.with_name("t.csv").exists()
