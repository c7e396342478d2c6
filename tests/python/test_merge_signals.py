"""A signal stops `merge` before it writes: SIGINT exits 130, SIGTERM 143
and SIGHUP, treated as SIGTERM, 143 too, with no merged table and no
temporary left; Python's merge() stops the same way where the program
handles the signal. The merge is held at a known point without timing: its
second table is a FIFO, which it reads until the test has sent the signal,
seen the program take it, and only then written the table and closed it."""

import os
import signal
import subprocess
import sys

import pytest

from conftest import CLI

EXIT = {"SIGINT": 130, "SIGTERM": 143, "SIGHUP": 143}
TIMEOUT_S = 60

# The handler says "taken" from a thread of its own, which gets the GIL
# only when the call's waiting thread lets it go, after it has set the
# call's stop flag (convert.h, Interruptible); the long switch interval
# keeps the handler's own thread from handing the GIL over earlier.
PYTHON_MERGE = """
import _thread, signal, sys
import ipmc_swim
sys.setswitchinterval(1000)
def taken():
    print("taken", flush=True)
def stop(signum, frame):
    _thread.start_new_thread(taken, ())
    raise KeyboardInterrupt
for sent in (signal.SIGINT, signal.SIGTERM, signal.SIGHUP):
    signal.signal(sent, stop)
try:
    ipmc_swim.merge(sys.argv[1:3], out=sys.argv[3])
except KeyboardInterrupt:
    print("interrupted", flush=True)
    sys.exit(130)
print("finished", flush=True)
"""


@pytest.fixture(scope="module")
def shard_dir(shards):
    """The folder of the command line's two shards (conftest.py)."""
    return shards[0]


def held_merge(tmp_path, shard_dir, command, sent, taken):
    """Runs `command` (a merge of shard 1 and a FIFO), sends `sent` once it
    reads the FIFO and, once the line `taken` shows it took the signal,
    feeds the FIFO shard 2's table. Returns (exit code, stdout, stderr)."""
    fifo = tmp_path / "late.csv"
    os.mkfifo(fifo)
    child = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        with open(fifo, "w") as feed:  # returns once the merge opens it
            child.send_signal(getattr(signal, sent))
            stream = child.stderr if taken.startswith("interrupted:") else child.stdout
            seen = ""
            while taken not in seen:
                line = stream.readline()
                assert line, f"the merge ended before taking {sent}: {seen}"
                seen += line
            feed.write((shard_dir / "shard_2.csv").read_text())
        stdout, stderr = child.communicate(timeout=TIMEOUT_S)
    finally:
        if child.poll() is None:
            child.kill()
            child.communicate()
    return child.returncode, seen + stdout, stderr


# A table that is a FIFO is now refused before it is opened (docs/ERRORS.md,
# "Files that are not regular files"), so the FIFO no longer holds the
# merge mid-read: these wait for another way to hold it.
HELD_BY_FIFO = pytest.mark.skip(reason="merge refuses a FIFO table; it cannot be held by one")


@HELD_BY_FIFO
@pytest.mark.parametrize("sent", sorted(EXIT))
def test_a_signal_stops_the_merge_before_it_writes(tmp_path, shard_dir, sent):
    out = tmp_path / "merged"
    code, _, stderr = held_merge(
        tmp_path, shard_dir,
        [CLI, "merge", "--out", str(out), str(shard_dir / "shard_1.csv"), str(tmp_path / "late.csv")],
        sent, "interrupted: stopping before the merged table is written")
    assert code == EXIT[sent], stderr
    assert f"ipmc-swim: interrupted by {sent}: nothing written" in stderr, stderr
    assert sorted(p.name for p in tmp_path.iterdir()) == ["late.csv"]


def test_a_fifo_table_is_refused_without_blocking(tmp_path, shard_dir):
    fifo = tmp_path / "late.csv"
    os.mkfifo(fifo)
    child = subprocess.run([CLI, "merge", "--out", str(tmp_path / "merged"),
                            str(shard_dir / "shard_1.csv"), str(fifo)],
                           capture_output=True, text=True, timeout=TIMEOUT_S)
    assert child.returncode == 1, child.stderr
    assert "late.csv: is a FIFO (named pipe), not a regular file" in child.stderr
    assert sorted(p.name for p in tmp_path.iterdir()) == ["late.csv"]


@HELD_BY_FIFO
@pytest.mark.parametrize("sent", sorted(EXIT))
def test_python_s_merge_stops_before_it_writes(tmp_path, shard_dir, sent):
    out = tmp_path / "merged"
    code, stdout, stderr = held_merge(
        tmp_path, shard_dir,
        [sys.executable, "-c", PYTHON_MERGE, str(shard_dir / "shard_1.csv"),
         str(tmp_path / "late.csv"), str(out)],
        sent, "taken")
    # The stop was asked while the merge read; it stopped at its next safe
    # point, before writing.
    assert code == 130, stdout + stderr
    assert "interrupted" in stdout and "finished" not in stdout, stdout + stderr
    assert sorted(p.name for p in tmp_path.iterdir()) == ["late.csv"]
