"""`ipmc-swim view` under Xvfb: the window opens, a scripted key sequence
reaches a known frame, its screenshot is not blank and equals the film's
frame of the same time (`ipmc-swim render --png-dir`, the off-screen
renderer) within a small pixel tolerance, and `q` closes it with exit 0;
without a display it says so in one line and exits 1.

Usage: view_test.py CASE IPMC_SWIM SOURCE_DIR
CASE: no_display (also: --help lists the keys) | default_run | flexible_run |
live_scenario
Each case starts its own Xvfb on a free display (-displayfd) and stops it
whatever the outcome.
"""
import os
import re
import shutil
import subprocess
import sys
import tempfile

import numpy as np
from PIL import Image

CASE, PROGRAM, SOURCE_DIR = sys.argv[1:4]
PAPER = os.path.join(SOURCE_DIR, "scenarios", "paper.toml")
SIZE = ["--width-px", "640", "--height-px", "480"]
# 20 frames per 100 s cycle: frame 10 is t = 50 s, the middle of cycle 1.
FRAMES = ["--frames-per-cycle", "20"]
FRAME = 10
# The window and the film draw with the same Mesa rasteriser and were
# measured identical (0 of 307200 pixels differ); the tolerance leaves room
# for a driver that rounds colours differently, not for a different picture.
MAX_MEAN_DIFFERENCE = 1.0       # mean |difference| over all channels [levels of 255]
MAX_DIFFERING_FRACTION = 0.002  # pixels off by more than 24 levels in a channel
# The live panel adds one overlay row ("simulated: 90.5 s of 100 s", as far
# as the run has gone), which the film has not: the overlay's panel (the
# top 150 rows at 640 x 480) is left out of the comparison.
LIVE_OVERLAY_ROWS = 150


def run(command, **kwargs):
    done = subprocess.run(command, capture_output=True, text=True, timeout=300, **kwargs)
    if done.returncode != 0:
        sys.exit(f"FAILED ({done.returncode}): {' '.join(command)}\n{done.stdout}\n{done.stderr}")
    return done.stdout


class Xvfb:
    """An X server on a display number it picks itself, stopped on exit."""

    def __enter__(self):
        read, write = os.pipe()
        self.process = subprocess.Popen(
            ["Xvfb", "-displayfd", str(write), "-screen", "0", "1920x1080x24", "-nolisten", "tcp"],
            pass_fds=(write,), stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        os.close(write)
        with os.fdopen(read) as pipe:
            number = pipe.readline().strip()
        if not number:
            self.__exit__()
            sys.exit("FAILED: Xvfb did not start")
        return f":{number}"

    def __exit__(self, *args):
        self.process.terminate()
        try:
            self.process.wait(timeout=10)
        except subprocess.TimeoutExpired:
            self.process.kill()
            self.process.wait()


def image(path):
    return np.asarray(Image.open(path).convert("RGB")).astype(np.int16)


def compare(shot, film_frame, from_row=0):
    a, b = image(shot), image(film_frame)
    assert a.shape == b.shape == (480, 640, 3), (a.shape, b.shape)
    # Not blank: the light background, the grid, the blue strip and the
    # overlay's dark text are all there.
    colours = len(np.unique(a.reshape(-1, 3), axis=0))
    blue = np.sum((a[:, :, 2] > 180) & (a[:, :, 0] < 100))
    assert colours > 50 and blue > 500, f"{shot} looks blank ({colours} colours, {blue} blue px)"
    difference = np.abs(a - b)[from_row:]
    mean = difference.mean()
    differing = np.mean(difference.max(axis=2) > 24)
    print(f"{os.path.basename(shot)}: {colours} colours, {blue} blue px; against the film's frame: "
          f"mean |difference| {mean:.4f}, {100 * differing:.3f} % of pixels differ")
    assert mean <= MAX_MEAN_DIFFERENCE, mean
    assert differing <= MAX_DIFFERING_FRACTION, differing


def view(display, inputs, script, cwd, extra=()):
    env = dict(os.environ, DISPLAY=display)
    out = run([PROGRAM, "view", *inputs, *SIZE, *FRAMES, "--paused", "--script", script, *extra],
              env=env, cwd=cwd)
    return out


def check_recorded(scratch, run_args):
    run([PROGRAM, "run", PAPER, "--cycles", "1", *run_args, "--out", "run"], cwd=scratch)
    run([PROGRAM, "render", "run", "--out", "film.mp4", *SIZE, *FRAMES, "--png-dir", "film"],
        cwd=scratch)
    with Xvfb() as display:
        out = view(display, ["run"], f"h,right*{FRAME},shot:view.png,q", scratch)
    assert re.search(r"view: view.png at 50\.0000 s", out), out
    compare(os.path.join(scratch, "view.png"), os.path.join(scratch, "film", f"frame_{FRAME:05d}.png"))


def check_live(scratch):
    # The follow camera: a live panel frames the run from its first state,
    # the film from all of them, so only a camera on the body agrees.
    follow = ["--camera", "follow"]
    run([PROGRAM, "render", PAPER, "--cycles", "1", "--out", "film.mp4", *SIZE, *FRAMES, *follow,
         "--png-dir", "film"], cwd=scratch)
    with Xvfb() as display:
        out = view(display, [PAPER], f"h,right*{FRAME},shot:live.png,q", scratch,
                   ["--cycles", "1", *follow])
    assert "view: live.png at 50.0000 s" in out, out
    compare(os.path.join(scratch, "live.png"), os.path.join(scratch, "film", f"frame_{FRAME:05d}.png"),
            LIVE_OVERLAY_ROWS)


def check_help():
    # The keys the window's key panel lists (renders/viewer.cc ViewerKeys), in --help.
    out = run([PROGRAM, "view", "--help"])
    for key, action in (("space", "play / pause"), ("right", "next frame (pauses)"),
                        ("pageup", "previous cycle"), ("up", "twice as fast"),
                        ("h", "this key panel on / off"), ("q", "quit (also Esc)")):
        assert re.search(rf"^  {re.escape(key)} +{re.escape(action)}$", out, re.M), (key, out)
    assert "scroll to zoom" in out, out


def check_no_display(scratch):
    env = {k: v for k, v in os.environ.items() if k not in ("DISPLAY", "WAYLAND_DISPLAY")}
    done = subprocess.run([PROGRAM, "view", PAPER], capture_output=True, text=True, env=env,
                          cwd=scratch, timeout=60)
    assert done.returncode == 1, done
    assert done.stdout == "", done.stdout
    lines = done.stderr.splitlines()
    assert len(lines) == 1 and lines[0].startswith("ipmc-swim: error: view: no display"), lines


def main():
    scratch = tempfile.mkdtemp(prefix=f"view_{CASE}_")
    try:
        if CASE == "no_display":
            check_help()
            check_no_display(scratch)
        elif CASE == "default_run":
            check_recorded(scratch, [])
        elif CASE == "flexible_run":
            check_recorded(scratch, ["--set", "segments_per_link=16", "--set", 'dynamics="stokes"',
                                     "--set", "timestep_s=1e-3"])
        elif CASE == "live_scenario":
            check_live(scratch)
        else:
            sys.exit(f"unknown case {CASE}")
    finally:
        # IPMC_VIEW_TEST_KEEP=DIR keeps the screenshots and the film's frame to look at.
        keep = os.environ.get("IPMC_VIEW_TEST_KEEP")
        if keep:
            for name in ("view.png", "live.png", f"film/frame_{FRAME:05d}.png"):
                if os.path.isfile(os.path.join(scratch, name)):
                    shutil.copy(os.path.join(scratch, name),
                                os.path.join(keep, f"{CASE}_{os.path.basename(name)}"))
        shutil.rmtree(scratch, ignore_errors=True)


if __name__ == "__main__":
    main()
