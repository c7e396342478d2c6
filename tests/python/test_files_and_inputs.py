"""Outputs are regular files or nothing, inputs are regular files, and the
journals and tables a later command trusts are verified (docs/ERRORS.md,
"Files that are not regular files", "Verified journals and tables").

Each case is a row of a table: it makes its fixtures in its own folder
(device nodes with os.mknod as root: a char device 1,3 as /dev/null, 1,7
as /dev/full; FIFOs with os.mkfifo; a bound Unix socket), runs the
program there and checks the exit code, the one "ipmc-swim: " line and its
fragment, that the device, FIFO or socket is still what it was, and that
nothing new was left behind (no output, no temporary).
"""

import json
import os
import pathlib
import resource
import signal
import socket
import stat
import subprocess
import time

import pytest

from conftest import CLI, SOURCE_DIR

MODEL = SOURCE_DIR / "models" / "flagellum3.xml"
TIMEOUT_S = 60

# One 1 s cycle at 0.5 ms steps: 2000 steps, a fraction of a second.
BASE_KEYS = {"": {"model": f'"{MODEL}"', "cycles": "1", "timestep_s": "5e-4"},
             "controller": {"kind": '"pid"'},
             "waveform": {"frequency_Hz": "1.0"},
             "output": {"samples_per_cycle": "20"}}


def scenario(*lines, model=None):
    """The short scenario with "dotted.key = value" lines set."""
    tables = {name: dict(entries) for name, entries in BASE_KEYS.items()}
    if model is not None:
        tables[""]["model"] = f'"{model}"'
    for line in lines:
        key, value = (part.strip() for part in line.split("=", 1))
        table, _, name = key.rpartition(".")
        tables.setdefault(table, {})[name] = value
    text = "".join(f"{k} = {v}\n" for k, v in tables[""].items())
    for table, entries in tables.items():
        if table:
            text += f"[{table}]\n" + "".join(f"{k} = {v}\n" for k, v in entries.items())
    return text


SHORT = scenario()
SWEEP = 'base = "short.toml"\n[grid]\n"waveform.frequency_Hz" = [1.0, 2.0]\n'
TABLE_HEADER = "point,cycles,status,error,mean_speed_along_mm_s\n"

# Two evaluations of a one-variable problem on the generated flagellum.
OPT_BASE = f"""model = "{MODEL}"
cycles = 1
timestep_s = 5e-4
[waveform]
frequency_Hz = 1.0
"""
OPT = """base = "base.toml"
[set]
link_lengths_mm = [10.0, 10.0, 10.0]
[[variable]]
key = "link_lengths_mm[0]"
lower = 8.0
upper = 12.0
initial = 10.0
[objective]
metric = "last_cycle_com_along_mm"
sense = "maximize"
[algorithm]
name = "subplex"
max_evaluations = 2
multistart = 1
"""


def write(path, text):
    pathlib.Path(path).write_text(text)


def make_node(path, kind):
    """A device, FIFO, socket or folder at path; returns a check that it is
    still one."""
    path = str(path)
    if kind in ("null", "full"):
        if os.geteuid() != 0:
            pytest.skip("device nodes need root")
        os.mknod(path, 0o666 | stat.S_IFCHR, os.makedev(1, 3 if kind == "null" else 7))
        return lambda: stat.S_ISCHR(os.lstat(path).st_mode)
    if kind == "fifo":
        os.mkfifo(path)
        return lambda: stat.S_ISFIFO(os.lstat(path).st_mode)
    if kind == "socket":
        # A socket's address is limited to 107 bytes and the build tree may sit
        # deep: bind by the name relative to its folder.
        server = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
        here = os.getcwd()
        os.chdir(os.path.dirname(path))
        try:
            server.bind(os.path.basename(path))
        finally:
            os.chdir(here)
        make_node.sockets.append(server)
        return lambda: stat.S_ISSOCK(os.lstat(path).st_mode)
    os.mkdir(path)
    return lambda: os.path.isdir(path)


make_node.sockets = []

KIND_WORDS = {"null": "a character device", "full": "a character device",
              "fifo": "a FIFO (named pipe)", "socket": "a socket", "dir": "directory"}


def base_fixtures(d):
    write(d / "short.toml", SHORT)
    write(d / "sweep.toml", SWEEP)
    write(d / "s1.csv", TABLE_HEADER + "0,1,ok,,0.5\n")
    write(d / "s2.csv", TABLE_HEADER + "1,2,ok,,0.6\n")


def listing(d):
    return {p.relative_to(d).as_posix() for p in d.rglob("*")}


def run_in(d, args, preexec=None):
    return subprocess.run([CLI, *map(str, args)], cwd=d, capture_output=True, text=True,
                          timeout=TIMEOUT_S, stdin=subprocess.DEVNULL, preexec_fn=preexec)


def expect_refused(d, args, fragment, exit_code=1, preexec=None, kept=()):
    """Runs args in d; checks the exit code, the one error line holding
    fragment, and that nothing new is left (but the names in kept)."""
    before = listing(d)
    done = run_in(d, args, preexec)
    lines = [l for l in done.stderr.splitlines() if l.startswith("ipmc-swim: ")]
    assert done.returncode == exit_code, done.stderr
    assert len(lines) == 1, done.stderr
    assert fragment in lines[0], done.stderr
    left = sorted(p for p in listing(d) - before if not any(p.startswith(k) for k in kept))
    assert not left, f"left behind: {left}"
    return done


# ---- outputs: a device, FIFO or socket at the target is refused, never replaced

# (writer, the target's name, args): the target exists as the node.
WRITERS = [
    ("bench", "b.csv", ["bench", "--model", MODEL, "--out", "b.csv", "--duration-s", "1"]),
    ("generate", "g.xml", ["generate", "--out", "g.xml"]),
    ("run --video", "v.mp4", ["run", "short.toml", "--video", "v.mp4"]),
    ("render", "r.mp4", ["render", "short.toml", "--out", "r.mp4"]),
    ("plot", "p.png", ["plot", "sweep", "s1.csv", "--x", "cycles", "--y", "mean_speed_along_mm_s",
                       "--out", "p.png"]),
    ("sweep csv", "t.csv", ["sweep", "sweep.toml", "--out", "t", "--jobs", "1"]),
    ("sweep json", "t.json", ["sweep", "sweep.toml", "--out", "t", "--jobs", "1"]),
    ("merge json", "m.json", ["merge", "s1.csv", "s2.csv", "--out", "m"]),
]
OUTPUT_CASES = [(writer, target, args, kind)
                for writer, target, args in WRITERS for kind in ("null", "fifo", "socket")]
OUTPUT_CASES += [(writer, target, args, "full") for writer, target, args in WRITERS[:4]]


@pytest.mark.parametrize("writer,target,args,kind", OUTPUT_CASES,
                         ids=[f"{c[0]}-{c[3]}" for c in OUTPUT_CASES])
def test_an_output_that_is_not_a_regular_file_is_refused(tmp_path, writer, target, args, kind):
    base_fixtures(tmp_path)
    still = make_node(tmp_path / target, kind)
    expect_refused(tmp_path, args, f"{target}: cannot replace it, it is {KIND_WORDS[kind]}")
    assert still(), f"{target} was replaced"


@pytest.mark.parametrize("kind", ["fifo", "null"])
def test_a_run_output_in_its_folder_that_is_not_a_regular_file_is_refused(tmp_path, kind):
    """The run's files are written after the run: refused then, nothing
    replaced, nothing of the run left."""
    base_fixtures(tmp_path)
    (tmp_path / "out").mkdir()
    still = make_node(tmp_path / "out" / "timeseries.csv", kind)
    expect_refused(tmp_path, ["run", "short.toml", "--out", "out"],
                   f"timeseries.csv: cannot replace it, it is {KIND_WORDS[kind]}")
    assert still()


# ---- inputs: a FIFO or device is refused, never read (a FIFO would block)

# (reader, the input's name, args, what the message calls it)
READERS = [
    ("run", "in.toml", ["run", "in.toml"], "scenario file"),
    ("sweep", "in.toml", ["sweep", "in.toml", "--out", "t"], "sweep file"),
    ("optimize", "in.toml", ["optimize", "in.toml", "--out", "o"], "optimisation file"),
    ("merge", "in.csv", ["merge", "s1.csv", "in.csv", "--out", "m"], "sweep table"),
    ("bench --model", "in.xml", ["bench", "--model", "in.xml", "--out", "b.csv"], "model file"),
    ("gait --csv", "in.csv", ["gait", "--gait", "csv", "--csv", "in.csv"], "gait CSV"),
]
INPUT_CASES = [(reader, name, args, what, kind)
               for reader, name, args, what in READERS for kind in ("fifo", "null")]


@pytest.mark.parametrize("reader,name,args,what,kind", INPUT_CASES,
                         ids=[f"{c[0]}-{c[4]}" for c in INPUT_CASES])
def test_an_input_that_is_not_a_regular_file_is_refused(tmp_path, reader, name, args, what, kind):
    base_fixtures(tmp_path)
    still = make_node(tmp_path / name, kind)
    expect_refused(tmp_path, args, f"{name}: is {KIND_WORDS[kind]}, not a regular file (the {what}")
    assert still()


# ---- TOML: key paths nested too deep are refused before parsing

DEEP = 100_000


NESTING_CASES = [
    ("dotted key", "run", "a" + ".a" * DEEP + " = 1\n", "in.toml:1: a key nested more than 32"),
    ("table header", "run", "[" + "a." * 50_000 + "a]\nx = 1\n", "in.toml:1: a key nested"),
    ("array of tables", "run", "[[" + "a." * 50_000 + "a]]\n", "in.toml:1: a key nested"),
    ("inline table", "run", "x = {" + "a." * 1000 + "a = 1}\n", "in.toml:1: a key nested"),
    ("second line", "run", "cycles = 1\n" + "b." * 40 + "b = 2\n", "in.toml:2: a key nested"),
    ("sweep file", "sweep", 'base = "short.toml"\n' + "g." * DEEP + "g = 1\n",
     "in.toml:2: a key nested"),
    ("optimisation file", "optimize", "[" + "v." * DEEP + "v]\n", "in.toml:1: a key nested"),
    # Dots in strings and comments are no key path.
    ("dots in a string", "run", 'model = "' + "." * 500 + '"\n', "model: cannot open"),
    ("dots in a comment", "run", "# " + "." * 500 + "\ncolour = 1\n", "colour"),
    ("dots in a multi-line string", "run", 'model = """\n' + "a." * 500 + '"""\n',
     "model: cannot open"),
]


@pytest.mark.parametrize("name,command,text,fragment", NESTING_CASES,
                         ids=[case[0] for case in NESTING_CASES])
def test_deeply_nested_keys_are_refused(tmp_path, name, command, text, fragment):
    """(ids: the names; a test id holding the text would not fit in the
    environment pytest passes on.)"""
    base_fixtures(tmp_path)
    write(tmp_path / "in.toml", text)
    args = [command, "in.toml"] + (["--out", "o"] if command != "run" else [])
    expect_refused(tmp_path, args, fragment)


# ---- resolution keys: points, memory and time estimated before any work

STOKESLETS = 'fluid.model = "stokeslets"'


@pytest.mark.parametrize("lines,fragment", [
    ([STOKESLETS, "fluid.stokeslet_points_per_mm = 1e300"],
     "fluid.stokeslet_points_per_mm 1e+300: 3.1e+301 Stokeslet points"),
    ([STOKESLETS, "fluid.stokeslet_points_per_mm = 1e3"],
     "fluid.stokeslet_points_per_mm 1000: 3.1e+04 Stokeslet points"),
    ([STOKESLETS, "fluid.stokeslet_blob_mm = 1e-6"], "fluid.stokeslet_blob_mm 1e-06: "),
    ([STOKESLETS, "fluid.stokeslet_width_points = 16"],
     "fluid.stokeslet_width_points 16: 2.69e+03 Stokeslet points"),
])
def test_resolution_keys_beyond_the_machine_are_refused(tmp_path, lines, fragment):
    write(tmp_path / "in.toml", scenario(*lines))
    expect_refused(tmp_path, ["run", "in.toml"], fragment)


def test_a_slow_stokeslet_resolution_names_allow_long(tmp_path):
    write(tmp_path / "in.toml", scenario(STOKESLETS, "fluid.stokeslet_width_points = 16"))
    expect_refused(tmp_path, ["run", "in.toml"], "--allow-long to run it anyway")


# ---- scenario checks that now name what the user wrote

@pytest.mark.parametrize("lines,fragment", [
    # Controller samples per wave cycle, exactly: 9.9 at 101 Hz.
    (["waveform.frequency_Hz = 101"], "waveform.frequency_Hz 101 gives 9.901 controller samples"),
    (["waveform.frequency_Hz = 150"], "waveform.frequency_Hz 150 gives 6.667 controller samples"),
    (["waveform.frequency_Hz = 100.5"], "at most 100 Hz"),
    # The default sample rate and a time step the user wrote: the time step is named.
    (["timestep_s = 7e-4"], "in.toml:3: timestep_s must make a controller sample"),
    (["timestep_s = 7e-4"], "e.g. timestep_s = 0.0005"),
    (["controller.sample_rate_Hz = 1500"], "controller.sample_rate_Hz must make the sample"),
    (['model = ""'], "model: an empty path; name a model file (MJCF)"),
    (["controller.link_kp = []"], "controller.link_kp: an empty array"),
    (["controller.link_kd = []"], "controller.link_kd: an empty array"),
])
def test_scenario_values_are_refused_naming_the_key(tmp_path, lines, fragment):
    write(tmp_path / "in.toml", scenario(*lines))
    expect_refused(tmp_path, ["run", "in.toml"], fragment)


def test_the_frequency_at_the_edge_runs(tmp_path):
    """100 Hz at 1000 Hz: exactly 10 controller samples a cycle."""
    write(tmp_path / "in.toml", scenario("waveform.frequency_Hz = 100", "output.samples_per_cycle = 10"))
    done = run_in(tmp_path, ["run", "in.toml"])
    assert done.returncode == 0, done.stderr


def test_more_samples_per_cycle_than_the_controller_takes_is_a_warning(tmp_path):
    write(tmp_path / "in.toml", scenario("output.samples_per_cycle = 10000000"))
    done = run_in(tmp_path, ["run", "in.toml", "--out", "o"])
    assert done.returncode == 0, done.stderr
    assert ("output.samples_per_cycle 10000000 is more than the 1000 controller samples of a "
            "wave cycle") in done.stderr
    summary = json.loads((tmp_path / "o" / "summary.json").read_text())
    assert any("output.samples_per_cycle" in w for w in json.dumps(summary).split('"'))


@pytest.mark.parametrize("line", ["fluid.viscosity_Pa_s = 1e-3", "fluid.wall_gap_mm = 2.0"])
def test_a_model_without_drag_fields_is_named(tmp_path, line):
    text = MODEL.read_text()
    for field in ("ipmc_rft_viscosity_Pa_s", "ipmc_rft_coefficients", "ipmc_rft_equivalent_radius_m",
                  "ipmc_rft_wavelength_m", "ipmc_rft_fluid_density_kg_m3"):
        text = "\n".join(l for l in text.splitlines() if f'"{field}"' not in l)
    write(tmp_path / "nodrag.xml", text)
    write(tmp_path / "in.toml", scenario(line, model="nodrag.xml"))
    key = line.split("=")[0].strip()
    expect_refused(tmp_path, ["run", "in.toml"],
                   f"nodrag.xml: has no RFT drag (no <custom> numeric ipmc_rft_viscosity_Pa_s), "
                   f"which {key} in in.toml needs")


# ---- signals and file size limits

def test_sigint_is_seen_between_samples_far_apart(tmp_path):
    """At 1e-9 s steps one recorded sample is 1e12 steps away: the stop
    must not wait for it (the old check at recorded samples never came)."""
    write(tmp_path / "in.toml", scenario("timestep_s = 1e-9", "waveform.frequency_Hz = 0.001",
                                         "output.samples_per_cycle = 1"))
    process = subprocess.Popen([CLI, "run", "in.toml", "--allow-long"], cwd=tmp_path,
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    time.sleep(1.5)
    process.send_signal(signal.SIGINT)
    try:
        _, stderr = process.communicate(timeout=TIMEOUT_S)
    except subprocess.TimeoutExpired:
        process.kill()
        process.communicate()
        pytest.fail("SIGINT not seen")
    assert process.returncode == 130, stderr
    assert "ipmc-swim: interrupted by SIGINT: stopped at t = " in stderr


def file_size_limit():
    """512 bytes; SIGXFSZ left at its default (the program handles it)."""
    resource.setrlimit(resource.RLIMIT_FSIZE, (512, 512))


@pytest.mark.parametrize("args,kept", [
    (["run", "short.toml", "--out", "o"], ()),
    (["bench", "--model", MODEL, "--out", "b.csv", "--duration-s", "1"], ()),
    # A sweep keeps its journal by design (run it again to resume).
    (["sweep", "sweep.toml", "--out", "t", "--jobs", "1"], ("t.journal",)),
])
def test_a_file_size_limit_is_a_failed_write(tmp_path, args, kept):
    base_fixtures(tmp_path)
    expect_refused(tmp_path, args, "File too large", preexec=file_size_limit, kept=kept)


def test_optimize_under_a_file_size_limit_is_no_xml_error(tmp_path):
    write(tmp_path / "base.toml", OPT_BASE)
    write(tmp_path / "opt.toml", OPT)
    done = expect_refused(tmp_path, ["optimize", "opt.toml", "--out", "o"], "File too large",
                          preexec=file_size_limit)
    assert "XML" not in done.stderr


# ---- the optimisation journal: checksums, symbolic links, --journals

@pytest.fixture(scope="module")
def optimisation(tmp_path_factory):
    """A finished two-evaluation optimisation: its folder, stdout and journal."""
    d = tmp_path_factory.mktemp("optimisation")
    write(d / "base.toml", OPT_BASE)
    write(d / "opt.toml", OPT)
    done = run_in(d, ["optimize", "opt.toml", "--out", "o", "--jobs", "1"])
    assert done.returncode == 0, done.stderr
    return d, done.stdout, (d / "o" / "optimize.journal").read_text()


def copy_optimisation(optimisation, d, journal_text):
    source, _, _ = optimisation
    for name in ("base.toml", "opt.toml"):
        write(d / name, (source / name).read_text())
    (d / "o").mkdir()
    write(d / "o" / "optimize.journal", journal_text)


def test_the_summary_counts_evaluations_as_result_json_does(optimisation):
    d, stdout, _ = optimisation
    best = json.loads((d / "o" / "result.json").read_text())["best"]
    assert f"best (start {best['start']}, evaluation {best['evaluation']}):" in stdout


def edited_cell(text):
    lines = text.splitlines(keepends=True)
    record = json.loads(lines[1])
    cells = record["cells"]
    cells[-1] = "99.0" if cells[-1] != "99.0" else "98.0"
    lines[1] = json.dumps(record, separators=(",", ":")) + "\n"
    return "".join(lines)


def test_an_edited_optimisation_journal_is_refused(tmp_path, optimisation):
    copy_optimisation(optimisation, tmp_path, edited_cell(optimisation[2]))
    expect_refused(tmp_path, ["optimize", "opt.toml", "--out", "o", "--resume"],
                   "o/optimize.journal:2: the record fails its checksum", kept=("o",))


def test_a_journal_record_without_its_checksum_is_refused(tmp_path, optimisation):
    lines = optimisation[2].splitlines(keepends=True)
    record = json.loads(lines[1])
    del record["check"]
    lines[1] = json.dumps(record) + "\n"
    copy_optimisation(optimisation, tmp_path, "".join(lines))
    expect_refused(tmp_path, ["optimize", "opt.toml", "--out", "o", "--resume"],
                   "o/optimize.journal:2: not a journal record", kept=("o",))


def test_a_journal_of_format_1_is_refused(tmp_path, optimisation):
    lines = optimisation[2].splitlines(keepends=True)
    header = json.loads(lines[0])
    header["ipmc_swim_optimize_journal"] = 1
    copy_optimisation(optimisation, tmp_path, json.dumps(header) + "\n")
    expect_refused(tmp_path, ["optimize", "opt.toml", "--out", "o", "--resume"],
                   "an optimisation journal of format 1", kept=("o",))


def start_journals(d, text, link=False):
    starts = d / "starts" / "start_0"
    starts.mkdir(parents=True)
    if link:
        write(d / "elsewhere.journal", text)
        os.symlink(d / "elsewhere.journal", starts / "optimize.journal")
    else:
        write(starts / "optimize.journal", text)


@pytest.mark.parametrize("case,fragment", [
    ("symbolic link", "is a symbolic link; a journal is never read through one"),
    ("edited", "optimize.journal:2: the record fails its checksum"),
    ("garbage", "not an optimisation journal"),
    ("fifo", "is a FIFO"),
])
def test_a_start_journal_is_verified_and_leaves_no_journal(tmp_path, optimisation, case, fragment):
    _, _, text = optimisation
    source = optimisation[0]
    for name in ("base.toml", "opt.toml"):
        write(tmp_path / name, (source / name).read_text())
    if case == "fifo":
        (tmp_path / "starts" / "start_0").mkdir(parents=True)
        os.mkfifo(tmp_path / "starts" / "start_0" / "optimize.journal")
    else:
        start_journals(tmp_path, {"symbolic link": text, "edited": edited_cell(text),
                                  "garbage": "garbage\nmore\n"}[case], link=case == "symbolic link")
    expect_refused(tmp_path, ["optimize", "opt.toml", "--out", "o", "--journals", "starts",
                              "--jobs", "1"], fragment)
    assert not (tmp_path / "o").exists()


# ---- merge: shards of one sweep, rows as written

@pytest.fixture(scope="module")
def two_sweeps(tmp_path_factory):
    """Shard 1/2 and 2/2 of one sweep (a, b) and shard 2/2 of another (c)."""
    d = tmp_path_factory.mktemp("two_sweeps")
    base_fixtures(d)
    write(d / "other.toml", SWEEP.replace("[1.0, 2.0]", "[1.0, 3.0]"))
    for sweep, shard, prefix in (("sweep.toml", "1/2", "a"), ("sweep.toml", "2/2", "b"),
                                 ("other.toml", "2/2", "c")):
        done = run_in(d, ["sweep", sweep, "--shard", shard, "--out", prefix, "--jobs", "1"])
        assert done.returncode == 0, done.stderr
    return d


def copy_tables(source, d, names):
    for name in names:
        for suffix in (".csv", ".json"):
            write(d / f"{name}{suffix}", (source / f"{name}{suffix}").read_text())


def test_shards_of_one_sweep_merge(tmp_path, two_sweeps):
    copy_tables(two_sweeps, tmp_path, "ab")
    done = run_in(tmp_path, ["merge", "a.csv", "b.csv", "--out", "m"])
    assert done.returncode == 0, done.stderr
    merged = json.loads((tmp_path / "m.json").read_text())
    assert merged["fingerprint"] == json.loads((tmp_path / "a.json").read_text())["fingerprint"]
    assert [c["point"] for c in merged["row_checks"]] == [0, 1]


def test_shards_of_two_sweeps_are_refused(tmp_path, two_sweeps):
    copy_tables(two_sweeps, tmp_path, "ac")
    expect_refused(tmp_path, ["merge", "a.csv", "c.csv", "--out", "m"],
                   "c.csv: a shard of another sweep than a.csv")


@pytest.mark.parametrize("edit,fragment", [
    ("number", "b.json: the row of point 1 in its CSV fails its checksum"),
    ("status", "b.json: the row of point 1 in its CSV fails its checksum"),
    ("check", "b.json: the row of point 1 in its CSV fails its checksum"),
    ("no checks", "not a sweep table's JSON (row_checks missing or malformed)"),
])
def test_an_edited_shard_is_refused(tmp_path, two_sweeps, edit, fragment):
    copy_tables(two_sweeps, tmp_path, "ab")
    csv_path, json_path = tmp_path / "b.csv", tmp_path / "b.json"
    lines = csv_path.read_text().splitlines(keepends=True)
    cells = lines[1].rstrip("\n").split(",")
    if edit == "number":
        cells[-1] = "99.0"
    elif edit == "status":
        cells[cells.index("ok")] = "error"
    lines[1] = ",".join(cells) + "\n"
    csv_path.write_text("".join(lines))
    table = json.loads(json_path.read_text())
    if edit == "check":
        table["row_checks"][0]["check"] = "0" * 64
    elif edit == "no checks":
        del table["row_checks"]
    json_path.write_text(json.dumps(table))
    expect_refused(tmp_path, ["merge", "a.csv", "b.csv", "--out", "m"], fragment)
