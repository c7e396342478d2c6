"""Every output path is a plain file: a name that looks like a URL
("tcp://...", "http://...", "pipe:1") or an option ("-x.mp4") is written as
the file it names, and neither the program nor ffmpeg (renders/video.cc,
FfmpegFileUrl) ever connects anywhere. A listener of the test's own on
127.0.0.1 sees no connection; the test sends no traffic and waits at most
a few seconds for one."""

import pathlib
import select
import socket
import subprocess

import pytest

from conftest import CLI, SOURCE_DIR

# One 2 s cycle filmed at 4 frames: a fraction of a second.
FAST = ["--cycles", "1", "--set", "waveform.frequency_Hz=0.5", "--frames-per-cycle", "4",
        "--width-px", "320", "--height-px", "240"]


@pytest.fixture
def listener():
    server = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
    server.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
    server.bind(("127.0.0.1", 0))
    server.listen(8)
    server.setblocking(False)
    yield server
    server.close()


def connections(server, wait_s=0.5):
    """How many connections reached the listener (waiting at most wait_s)."""
    count = 0
    while select.select([server], [], [], wait_s)[0]:
        connection, _ = server.accept()
        connection.close()
        count += 1
        wait_s = 0.0
    return count


def run_in(folder, *args):
    return subprocess.run([CLI, *map(str, args)], cwd=folder, capture_output=True, text=True,
                          timeout=120)


@pytest.mark.parametrize("name", ["tcp://127.0.0.1:{port}/x.mp4", "http://127.0.0.1:{port}/up.mp4",
                                  "pipe:1", "-dash.mp4", "file:plain.mp4"])
def test_a_url_like_video_path_is_a_plain_file(tmp_path, short_scenario, listener, name):
    port = listener.getsockname()[1]
    target = name.format(port=port)
    done = run_in(tmp_path, "run", short_scenario, "--out", "run", f"--video={target}", *FAST)
    assert done.returncode == 0, done.stderr
    assert connections(listener) == 0
    # The file is where the name says, as a path relative to the folder.
    written = tmp_path / pathlib.Path(target)
    assert written.is_file() and written.stat().st_size > 0, sorted(tmp_path.rglob("*"))


def test_render_to_a_url_like_path_connects_nowhere(tmp_path, short_scenario, listener):
    port = listener.getsockname()[1]
    assert run_in(tmp_path, "run", short_scenario, "--out", "run", "--cycles", "1", "--set",
                  "waveform.frequency_Hz=0.5").returncode == 0
    target = f"http://127.0.0.1:{port}/up.mp4"
    done = run_in(tmp_path, "render", "run", "--out", target, "--frames-per-cycle", "4",
                  "--width-px", "320", "--height-px", "240")
    assert done.returncode == 0, done.stderr
    assert connections(listener) == 0
    assert (tmp_path / target).is_file()


# Every other output, by the command line and by Python: a URL-like name
# is a relative path like any other, written where it says, and nothing
# connects.
URL_NAMES = ["tcp:127.0.0.1:{port}", "http:127.0.0.1:{port}", "-dash"]


def command_outputs(folder, short_scenario, target):
    clamped = SOURCE_DIR / "models" / "flagellum3_clamped.xml"
    (folder / "sweep.toml").write_text(f'base = "{short_scenario}"\n[set]\ncycles = 1\n'
                                       '"waveform.frequency_Hz" = 0.5\n[grid]\n'
                                       'segments_per_link = [1]\n')
    return [
        # A chirp long enough for identify's coherence gate (12 bins in 8-50 rad/s).
        (["bench", "--model", clamped, "--signal", "chirp", "--start-hz", "0.5", "--end-hz", "20",
          "--duration-s", "8", f"--out={target}.csv"],
         [f"{target}.csv"]),
        (["generate", f"--out={target}.xml"], [f"{target}.xml"]),
        (["run", short_scenario, "--cycles", "1", "--set", "waveform.frequency_Hz=0.5",
          f"--out={target}_run"], [f"{target}_run/summary.json"]),
        (["sweep", "sweep.toml", "--jobs", "1", f"--out={target}_table"],
         [f"{target}_table.csv", f"{target}_table.json"]),
        # Inputs as ./NAME: a positional "-dash..." would be read as an option.
        (["merge", f"--out={target}_merged", f"./{target}_table.csv"], [f"{target}_merged.csv"]),
        (["identify", f"./{target}.csv", "--input", "voltage1_V", "--output", "relative1_mm",
          "--band-rad-s", "8,50", f"--out={target}_id"], [f"{target}_id/identification.json"]),
    ]


@pytest.mark.parametrize("name", URL_NAMES)
def test_no_output_of_any_command_connects_anywhere(tmp_path, short_scenario, listener, name):
    target = name.format(port=listener.getsockname()[1])
    for args, written in command_outputs(tmp_path, short_scenario, target):
        done = run_in(tmp_path, *args)
        assert done.returncode == 0, (args, done.stderr)
        assert connections(listener, wait_s=0.2) == 0, args
        for path in written:
            assert (tmp_path / pathlib.Path(path)).is_file(), (args, sorted(tmp_path.rglob("*")))


@pytest.mark.parametrize("name", URL_NAMES)
def test_no_python_output_connects_anywhere(tmp_path, short_scenario, listener, name, monkeypatch):
    import ipmc_swim

    monkeypatch.chdir(tmp_path)
    target = name.format(port=listener.getsockname()[1])
    clamped = str(SOURCE_DIR / "models" / "flagellum3_clamped.xml")
    ipmc_swim.bench(clamped, duration_s=0.5, out=f"{target}.csv")
    ipmc_swim.generate_model(out=f"{target}.xml")
    ipmc_swim.run(short_scenario, out=f"{target}_run", cycles=1, **{"waveform.frequency_Hz": 0.5})
    assert connections(listener, wait_s=0.2) == 0
    for path in (f"{target}.csv", f"{target}.xml", f"{target}_run/summary.json"):
        assert (tmp_path / pathlib.Path(path)).is_file(), sorted(tmp_path.rglob("*"))
