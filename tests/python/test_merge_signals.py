"""A signal stops `merge` before it writes: SIGINT exits 130, SIGTERM 143
and SIGHUP, treated as SIGTERM, 143 too, with no merged table and no
temporary left. The signal is sent without timing: the merge starts with
it blocked and already pending (as one sent while the merge reads its
tables), so the stop is requested before the merge's only safe point, the
write (sim/cli/interrupt.h). Python's merge() shares the stop flag that
the sweep's interrupt tests exercise (test_interrupt.py)."""

import os
import signal
import subprocess

import pytest

from conftest import CLI

EXIT = {"SIGINT": 130, "SIGTERM": 143, "SIGHUP": 143}
TIMEOUT_S = 60


@pytest.fixture(scope="module")
def shard_dir(shards):
    """The folder of the command line's two shards (conftest.py)."""
    return shards[0]


def signal_pending_at_start(sent):
    """For Popen's preexec_fn: blocks `sent` in the child and sends it to
    itself, so it is pending when the program starts (exec keeps both)."""
    number = getattr(signal, sent)

    def block_and_send():
        signal.pthread_sigmask(signal.SIG_BLOCK, {number})
        os.kill(os.getpid(), number)

    return block_and_send


@pytest.mark.parametrize("sent", sorted(EXIT))
def test_a_signal_stops_the_merge_before_it_writes(tmp_path, shard_dir, sent):
    out = tmp_path / "merged"
    child = subprocess.run(
        [CLI, "merge", "--out", str(out), str(shard_dir / "shard_1.csv"),
         str(shard_dir / "shard_2.csv")],
        capture_output=True, text=True, timeout=TIMEOUT_S,
        preexec_fn=signal_pending_at_start(sent))
    assert child.returncode == EXIT[sent], child.stderr
    assert "interrupted: stopping before the merged table is written" in child.stderr
    assert f"ipmc-swim: interrupted by {sent}: nothing written" in child.stderr, child.stderr
    assert list(tmp_path.iterdir()) == []


def test_a_fifo_table_is_refused_without_blocking(tmp_path, shard_dir):
    fifo = tmp_path / "late.csv"
    os.mkfifo(fifo)
    child = subprocess.run([CLI, "merge", "--out", str(tmp_path / "merged"),
                            str(shard_dir / "shard_1.csv"), str(fifo)],
                           capture_output=True, text=True, timeout=TIMEOUT_S)
    assert child.returncode == 1, child.stderr
    assert "late.csv: is a FIFO (named pipe), not a regular file" in child.stderr
    assert sorted(p.name for p in tmp_path.iterdir()) == ["late.csv"]
