"""Bad inputs and abuse of the ipmc-swim program, as data (cases.txt).

Each case runs the program in a scratch folder holding the fixtures made
below and checks: the exit code; for a failure, exactly one line on stderr
that starts with "ipmc-swim: " and contains the expected fragment; and
that nothing was left behind (no new file anywhere in the scratch folder:
no output, no temporary). Cases marked `full-disk` run with a 512-byte file
size limit (RLIMIT_FSIZE, SIGXFSZ ignored), so that every write beyond it
fails as on a full disk. Signal cases start a long run, send SIGINT or
SIGTERM once it is running, and expect 128 + signal and nothing left.

Usage: abuse_test.py PROGRAM MODELS_DIR SCENARIOS_DIR CASES [K/N]
(K/N: only every N-th case from the K-th, so that CTest runs them as N tests)
"""
import os
import resource
import shlex
import shutil
import signal
import subprocess
import sys
import tempfile
import time

PROGRAM, MODELS, SCENARIOS, CASES = sys.argv[1:5]
GOOD_MODEL = os.path.join(MODELS, "flagellum3.xml")
CLAMPED_MODEL = os.path.join(MODELS, "flagellum3_clamped.xml")
TIMEOUT_S = 60
FULL_DISK_BYTES = 512
FIXTURES = set()  # everything in the scratch folder before the cases
# {long} in a case: a name that fits in a folder (255 bytes) but not with
# its temporary's suffix.
LONG_NAME = "n" * 245


def write(path, text, mode="w"):
    with open(path, mode) as f:
        f.write(text)


def model_with(old, new, source=GOOD_MODEL):
    text = open(source).read()
    if old not in text:
        raise SystemExit(f"fixture: {old!r} not in {source}")
    return text.replace(old, new, 1)


# The short scenario: one 1 s cycle at 0.5 ms steps (2000 steps).
BASE_SCENARIO = {
    "": {"model": f'"{GOOD_MODEL}"', "cycles": "1", "timestep_s": "5e-4"},
    "controller": {"kind": '"pid"'},
    "waveform": {"frequency_Hz": "1.0"},
    "output": {"samples_per_cycle": "20"},
}


def scenario(**changes):
    """The short scenario with dotted keys ("waveform.frequency_Hz") set."""
    tables = {name: dict(entries) for name, entries in BASE_SCENARIO.items()}
    for key, value in changes.items():
        table, _, name = key.rpartition(".")
        tables.setdefault(table, {})[name] = value
    text = "".join(f"{k} = {v}\n" for k, v in tables[""].items())
    for table, entries in tables.items():
        if table:
            text += f"[{table}]\n" + "".join(f"{k} = {v}\n" for k, v in entries.items())
    return text


SHORT_SCENARIO = scenario()


def make_fixtures(d):
    shutil.copy(GOOD_MODEL, f"{d}/good.xml")
    shutil.copy(CLAMPED_MODEL, f"{d}/clamped.xml")
    write(f"{d}/empty.xml", "")
    write(f"{d}/binary.xml", bytes(range(256)) * 8, "wb")
    good = open(GOOD_MODEL).read()
    write(f"{d}/truncated.xml", good[: len(good) // 2])
    write(f"{d}/notxml.xml", "hello, not a model\n")
    os.mkdir(f"{d}/folder.xml")
    write(f"{d}/zero_timestep.xml", model_with('timestep="0.0001"', 'timestep="0"'))
    write(f"{d}/rk4_coarse.xml", model_with('timestep="0.0001" integrator="implicit"',
                                            'timestep="0.05" integrator="RK4"'))
    write(f"{d}/links_repeated.xml", model_with('data="j1 j2 j3"', 'data="j1 j1 j1"'))
    write(f"{d}/links_missing.xml", model_with('data="j1 j2 j3"', 'data="j1 j2 j9"'))
    write(f"{d}/width_zero.xml", model_with('name="ipmc_strip_width_m" data="0.003"',
                                            'name="ipmc_strip_width_m" data="0"'))
    write(f"{d}/width_negative.xml", model_with('name="ipmc_strip_width_m" data="0.003"',
                                                'name="ipmc_strip_width_m" data="-0.003"'))
    write(f"{d}/viscosity_nan.xml", model_with('data="0.001"', 'data="nan"'))
    write(f"{d}/viscosity_negative.xml", model_with('data="0.001"', 'data="-1"'))
    write(f"{d}/unknown_field.xml", model_with('<custom>',
                                               '<custom>\n    <numeric name="ipmc_bogus" data="1"/>'))
    write(f"{d}/pairs_fraction.xml", model_with('<custom>',
          '<custom>\n    <numeric name="ipmc_integrator_pairs" data="2.5"/>'))
    write(f"{d}/pairs_huge.xml", model_with('<custom>',
          '<custom>\n    <numeric name="ipmc_integrator_pairs" data="1e20"/>'))
    write(f"{d}/model_kind_bad.xml", model_with('name="ipmc_model" data="g1"',
                                                'name="ipmc_model" data="g7"'))
    write(f"{d}/actuation_bad.xml", model_with('name="ipmc_actuation" data="distributed"',
                                               'name="ipmc_actuation" data="everywhere"'))
    write(f"{d}/coefficients_bad.xml", model_with('data="gray_hancock"', 'data="stokes"'))
    # The links' voltage range (ipmc_voltage_limit_V): none, and 1 V.
    for name, limit in (("limit_zero", "0"), ("limit_low", "1")):
        write(f"{d}/{name}.xml", model_with('<custom>', '<custom>\n    <numeric '
              f'name="ipmc_voltage_limit_V" data="{limit}"/>', CLAMPED_MODEL))
    # Scenarios.
    write(f"{d}/short.toml", SHORT_SCENARIO)
    write(f"{d}/long.toml", scenario(**{"waveform.frequency_Hz": "0.01", "cycles": "3"}))
    write(f"{d}/empty.toml", "")
    write(f"{d}/binary.toml", bytes(range(256)) * 4, "wb")
    write(f"{d}/syntax.toml", "cycles = = 3\n")
    write(f"{d}/unknown_key.toml", scenario(colour='"blue"'))
    write(f"{d}/unknown_table.toml", SHORT_SCENARIO + "[nonsense]\nx = 1\n")
    # A model given over included keys that generate a flagellum: refused.
    write(f"{d}/strip_keys.toml", "link_lengths_mm = [12.0, 12.0]\n[strip]\nwidth_mm = 5.0\n")
    write(f"{d}/plant_keys.toml", "[plant]\na0_mm_per_V = 0.45\n")
    write(f"{d}/model_over_strip.toml", 'include = ["strip_keys.toml"]\n' + SHORT_SCENARIO)
    write(f"{d}/model_over_plant.toml", 'include = ["plant_keys.toml"]\n' + SHORT_SCENARIO)
    write(f"{d}/cycles_zero.toml", scenario(cycles="0"))
    write(f"{d}/cycles_negative.toml", scenario(cycles="-2"))
    write(f"{d}/cycles_float.toml", scenario(cycles="2.5"))
    write(f"{d}/cycles_string.toml", scenario(cycles='"three"'))
    write(f"{d}/cycles_huge.toml", scenario(cycles="1000000000"))
    write(f"{d}/frequency_tiny.toml", scenario(**{"waveform.frequency_Hz": "1e-300"}))
    write(f"{d}/frequency_huge.toml", scenario(**{"waveform.frequency_Hz": "1e300"}))
    write(f"{d}/frequency_zero.toml", scenario(**{"waveform.frequency_Hz": "0"}))
    write(f"{d}/frequency_nan.toml", scenario(**{"waveform.frequency_Hz": "nan"}))
    write(f"{d}/frequency_inf.toml", scenario(**{"waveform.frequency_Hz": "inf"}))
    write(f"{d}/timestep_zero.toml", scenario(timestep_s="0"))
    write(f"{d}/timestep_negative.toml", scenario(timestep_s="-1e-4"))
    write(f"{d}/timestep_big.toml", scenario(timestep_s="0.5"))
    write(f"{d}/timestep_odd.toml", scenario(timestep_s="3e-4"))
    write(f"{d}/controller_kind.toml", scenario(**{"controller.kind": '"bang-bang"'}))
    write(f"{d}/kp_negative.toml", scenario(**{"controller.kp": "-1"}))
    write(f"{d}/kp_nan.toml", scenario(**{"controller.kp": "nan"}))
    write(f"{d}/vmax_zero.toml", scenario(**{"controller.v_max_V": "0"}))
    write(f"{d}/rate_zero.toml", scenario(**{"controller.sample_rate_Hz": "0"}))
    write(f"{d}/rate_odd.toml", scenario(**{"controller.sample_rate_Hz": "1234.5"}))
    write(f"{d}/clamp_string.toml", scenario(**{"controller.clamp": '"yes"'}))
    write(f"{d}/waveform_kind.toml", scenario(**{"waveform.kind": '"zigzag"'}))
    write(f"{d}/wavelength_zero.toml", scenario(**{"waveform.wavelength_mm": "0"}))
    write(f"{d}/c1_nan.toml", scenario(**{"waveform.c1_um_per_mm": "nan"}))
    write(f"{d}/ramp_negative.toml", scenario(**{"waveform.start_ramp_cycles": "-1"}))
    write(f"{d}/ramp_long.toml", scenario(**{"waveform.start_ramp_cycles": "5"}))
    write(f"{d}/viscosity_zero.toml", scenario(**{"fluid.viscosity_Pa_s": "0"}))
    write(f"{d}/viscosity_nan.toml", scenario(**{"fluid.viscosity_Pa_s": "nan"}))
    write(f"{d}/samples_zero.toml", scenario(**{"output.samples_per_cycle": "0"}))
    write(f"{d}/samples_huge.toml", scenario(**{"output.samples_per_cycle": "1000000000"}))
    write(f"{d}/model_missing.toml", scenario(model='"no_such_model.xml"'))
    write(f"{d}/model_empty.toml", scenario(model='"empty.xml"'))
    write(f"{d}/model_folder.toml", scenario(model='"folder.xml"'))
    write(f"{d}/model_number.toml", scenario(model="42"))
    write(f"{d}/actuation_bad.toml", scenario(actuation='"everywhere"'))
    write(f"{d}/plants_bad.toml", scenario(plants='"rubber"'))
    write(f"{d}/links_empty.toml", scenario(link_lengths_mm="[]", segments_per_link="1"))
    write(f"{d}/links_negative.toml", scenario(link_lengths_mm="[10, -10, 10]"))
    write(f"{d}/links_many.toml", scenario(link_lengths_mm="[" + ", ".join(["1"] * 100) + "]"))
    write(f"{d}/segments_zero.toml", scenario(segments_per_link="-1"))
    write(f"{d}/outdir_number.toml", scenario(**{"output.dir": "7"}))
    write(f"{d}/fractional_order.toml", scenario(**{"controller.kind": '"fractional"',
                                                    "controller.order": "1.5"}))
    write(f"{d}/fractional_gain.toml", scenario(**{"controller.kind": '"fractional"',
                                                   "controller.gain": "-3"}))
    write(f"{d}/fractional_pairs.toml", scenario(**{"controller.kind": '"fractional"',
                                                    "controller.oustaloup_n": "0"}))
    # Sweeps.
    write(f"{d}/sweep_ok.toml", 'base = "short.toml"\n[grid]\ncycles = [1]\n')
    write(f"{d}/sweep_allfail.toml", 'base = "short.toml"\n[set]\ncycles = 0\n[grid]\n'
          '"waveform.frequency_Hz" = [1.0, 2.0]\n')
    write(f"{d}/sweep_nobase.toml", '[grid]\ncycles = [1, 2]\n')
    write(f"{d}/sweep_missingbase.toml", 'base = "nothing.toml"\n[grid]\ncycles = [1]\n')
    write(f"{d}/sweep_emptygrid.toml", 'base = "short.toml"\n[grid]\n')
    write(f"{d}/sweep_unknownkey.toml", 'base = "short.toml"\n[grid]\nbogus = [1, 2]\n')
    write(f"{d}/sweep_badtype.toml", 'base = "short.toml"\n[grid]\ncycles = ["a", "b"]\n')
    write(f"{d}/sweep_hugegrid.toml", 'base = "short.toml"\n[grid]\ncycles = [' +
          ", ".join(str(i) for i in range(1, 1002)) + ']\n"waveform.frequency_Hz" = [' +
          ", ".join(str(i) for i in range(1, 1001)) + "]\n")
    write(f"{d}/sweep_fast.toml", 'base = "short.toml"\n[grid]\n"waveform.frequency_Hz" = '
          '[1000.0, 2000.0]\n')
    write(f"{d}/sweep_syntax.toml", 'base = "short.toml"\n[grid\n')
    write(f"{d}/sweep_long.toml", 'base = "long.toml"\n[grid]\n"waveform.frequency_Hz" = '
          '[0.01, 0.011, 0.012, 0.013]\n')
    # Tables (merge) and data (identify, plot, gait csv).
    header = "point,cycles,status,error,mean_speed_along_mm_s\n"
    write(f"{d}/s1.csv", header + "0,1,ok,,0.5\n")
    write(f"{d}/s2.csv", header + "1,2,ok,,0.6\n")
    write(f"{d}/s_abc.csv", header + "1,2,ok,,abc\n")
    write(f"{d}/s_nan.csv", header + "1,2,ok,,nan\n")
    write(f"{d}/s_dup.csv", header + "0,1,ok,,0.5\n")
    write(f"{d}/s_otherheader.csv", "point,frequency,status,error,mean_speed_along_mm_s\n"
          "1,2,ok,,0.6\n")
    write(f"{d}/s_ragged.csv", header + "1,2,ok\n")
    write(f"{d}/s_empty.csv", "")
    # A broadband voltage and its first-order low-pass (pole near 105 rad/s)
    # as the response: coherent in identify's 8-50 rad/s band, so that the
    # cases below reach their output's failure.
    bench = ["time_s,voltage1_V,relative1_mm,zero_V"]
    response_mm = 0.0
    for i in range(4000):
        t = i / 1000.0
        voltage_V = ((i * 7919) % 1000) / 500.0 - 1.0
        response_mm = 0.9 * response_mm + 0.1 * voltage_V
        bench.append(f"{t:.3f},{voltage_V:.6f},{response_mm:.6f},0")
    write(f"{d}/bench.csv", "\n".join(bench) + "\n")
    write(f"{d}/bench_short.csv", "\n".join(bench[:20]) + "\n")
    write(f"{d}/bench_text.csv", bench[0] + "\n0,1,x,0\n0.001,1,2,0\n")
    write(f"{d}/bench_ragged.csv", bench[0] + "\n0,1\n")
    write(f"{d}/bench_header_only.csv", bench[0] + "\n")
    # Time columns that are not evenly sampled: a missing row, a step back, a repeat.
    write(f"{d}/bench_jump.csv", "\n".join(bench[:2001] + bench[2002:]) + "\n")
    backward = list(bench)
    backward[3001] = "2.998" + backward[3001][backward[3001].index(","):]
    write(f"{d}/bench_backward.csv", "\n".join(backward) + "\n")
    write(f"{d}/bench_repeat.csv", "\n".join(bench[:1001] + bench[1000:]) + "\n")
    write(f"{d}/gait_ok.csv", "time_s,q1,q2,q3\n0,0,0,0\n10,0.1,0.1,0.1\n20,0,0,0\n")
    write(f"{d}/gait_cols.csv", "time_s,q1,q2\n0,0,0\n1,0.1,0.1\n")
    write(f"{d}/gait_huge.csv", "time_s,q1,q2,q3\n0,0,0,0\n10,1e300,1e300,1e300\n20,0,0,0\n")
    write(f"{d}/gait_decreasing.csv", "time_s,q1,q2,q3\n0,0,0,0\n10,0.1,0.1,0.1\n5,0,0,0\n")
    write(f"{d}/gait_text.csv", "time_s,q1,q2,q3\n0,0,0,0\n10,a,b,c\n")
    write(f"{d}/gait_one.csv", "time_s,q1,q2,q3\n0,0,0,0\n")
    write(f"{d}/bode.csv", "w_rad_s,open_loop_dB,open_loop_deg\n1,0,-90\n10,-20,-120\n")
    # A UTF-8 byte order mark before the header hides nothing.
    for name, rows in (("bench_bom", bench), ("bench_bom_backward", backward),
                       ("bench_bom_repeat", bench[:1001] + bench[1000:])):
        write(f"{d}/{name}.csv", b"\xef\xbb\xbf" + ("\n".join(rows) + "\n").encode(), "wb")
    # Includes: seven one-line files, each including the next 12 times
    # (12^6 files without a bound on the total), and a plant.toml whose
    # error belongs to its own line 2.
    for k in range(6):
        write(f"{d}/fan{k}.toml", "include = [" + ", ".join([f'"fan{k + 1}.toml"'] * 12) + "]\n")
    write(f"{d}/fan6.toml", "cycles = 1\n")
    write(f"{d}/plant.toml", "[plant]\nlink_a0_mm_per_V = [0.2, 0.3]\n")
    write(f"{d}/uses_plant.toml", 'include = "plant.toml"\n# the bench\'s plant\n'
          "link_lengths_mm = [10.0, 10.0, 10.0]\n")
    write(f"{d}/include_nul.toml", 'include = "short.toml\\u0000.bak"\n' + SHORT_SCENARIO)
    write(f"{d}/model_nul.toml", scenario(model=f'"{GOOD_MODEL}\\u0000.bak"'))
    write(f"{d}/sweep_nul.toml", 'base = "short.toml\\u0000.bak"\n[grid]\ncycles = [1]\n')
    # Runs whose model file was edited after them: a closed-loop run and a gait.
    shutil.copy(GOOD_MODEL, f"{d}/run_model.xml")
    write(f"{d}/edited.toml", scenario(model='"run_model.xml"'))
    for args in (["run", "edited.toml", "--out", "run_edited"],
                 ["gait", "--model", "run_model.xml", "--cycles", "1", "--frequency-hz", "1",
                  "--out", "gait_edited"]):
        subprocess.run([PROGRAM] + args, cwd=d, check=True, capture_output=True,
                       timeout=TIMEOUT_S)
    write(f"{d}/run_model.xml", open(f"{d}/run_model.xml").read() + "<!-- edited -->\n")
    os.mkdir(f"{d}/readonly")
    os.chmod(f"{d}/readonly", 0o555)
    write(f"{d}/a_file", "not a folder\n")


def snapshot(d):
    """Every file below d, and every folder that holds one (an empty folder
    a failed command made is not an output)."""
    found = set()
    for root, dirs, files in os.walk(d):
        for name in files:
            path = os.path.relpath(os.path.join(root, name), d)
            found.add(path)
            parent = os.path.dirname(path)
            while parent:
                found.add(parent)
                parent = os.path.dirname(parent)
    return found


def listing(d):
    everything = set()
    for root, dirs, files in os.walk(d):
        for name in dirs + files:
            everything.add(os.path.relpath(os.path.join(root, name), d))
    return everything


def remove_new(d, fixtures):
    for path in sorted(listing(d) - fixtures, key=len, reverse=True):
        full = os.path.join(d, path)
        if os.path.isdir(full) and not os.path.islink(full):
            shutil.rmtree(full, ignore_errors=True)
        elif os.path.lexists(full):
            os.remove(full)


def full_disk_limits():
    signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
    resource.setrlimit(resource.RLIMIT_FSIZE, (FULL_DISK_BYTES, FULL_DISK_BYTES))


def blocks(pid, signum):
    """Whether process `pid` blocks `signum`: the program blocks the stop
    signals before its work and takes them at a safe point
    (sim/cli/interrupt.h); one sent earlier would kill it outright."""
    try:
        with open(f"/proc/{pid}/status") as status:
            for line in status:
                if line.startswith("SigBlk:"):
                    return (int(line.split()[1], 16) >> (signum - 1)) & 1 == 1
    except FileNotFoundError:
        pass
    return False


def run_case(d, case):
    # Root writes into a mode-555 folder: it gets /proc/self instead.
    readonly = "/proc/self" if os.geteuid() == 0 else f"{d}/readonly"
    args = [PROGRAM] + [a.format(d=d, models=MODELS, scenarios=SCENARIOS, readonly=readonly,
                                 long=LONG_NAME)
                        for a in shlex.split(case["args"])]
    mode = case["mode"].split()
    signal_name = mode[0] if mode[0] in ("SIGINT", "SIGTERM", "SIGHUP") else None
    preexec = full_disk_limits if mode[0] == "full-disk" else None
    if signal_name:
        process = subprocess.Popen(args, cwd=d, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                                   text=True)
        time.sleep(float(case.get("delay", 1.5)))
        signum = getattr(signal, signal_name)
        deadline = time.monotonic() + TIMEOUT_S  # a loaded machine may be that slow to start
        while (not blocks(process.pid, signum) and process.poll() is None
               and time.monotonic() < deadline):
            time.sleep(0.01)
        process.send_signal(signum)
        try:
            stdout, stderr = process.communicate(timeout=TIMEOUT_S)
        except subprocess.TimeoutExpired:
            process.kill()
            process.communicate()
            raise
        code = process.returncode
    else:
        result = subprocess.run(args, cwd=d, capture_output=True, text=True, timeout=TIMEOUT_S,
                                preexec_fn=preexec, stdin=subprocess.DEVNULL)
        code, stdout, stderr = result.returncode, result.stdout, result.stderr
    return code, stdout, stderr


def check(d, case, before):
    try:
        code, stdout, stderr = run_case(d, case)
    except subprocess.TimeoutExpired as timeout:
        remove_new(d, FIXTURES)
        return [f"did not finish within {timeout.timeout} s"], ""
    problems = []
    if code != case["exit"]:
        problems.append(f"exit code {code}, expected {case['exit']}")
    lines = [line for line in stderr.splitlines() if line.startswith("ipmc-swim: ")]
    if case["exit"] != 0:
        if len(lines) != 1:
            problems.append(f"{len(lines)} 'ipmc-swim: ' lines on stderr, expected 1")
        if not any(case["fragment"] in line for line in lines):
            problems.append(f"no 'ipmc-swim: ' line contains {case['fragment']!r}")
    elif case["fragment"] not in stdout + stderr:
        problems.append(f"output does not contain {case['fragment']!r}")
    left = sorted(snapshot(d) - before)
    mode = case["mode"].split()
    if len(mode) == 3 and mode[1] == "keep":  # what a stop keeps by design
        kept = [p for p in left if p.endswith(mode[2])]
        if not kept:
            problems.append(f"nothing ending in {mode[2]} kept")
        left = [p for p in left if p not in kept and not any(k.startswith(p + "/") for k in kept)]
    if case["exit"] != 0 and left:
        problems.append(f"left behind: {left}")
    temporaries = [p for p in left if ".tmp" in p or "ffmpeg" in p]
    if case["exit"] == 0 and temporaries:
        problems.append(f"temporaries left: {temporaries}")
    remove_new(d, FIXTURES)
    return problems, stderr


def read_cases(path):
    """Lines `EXIT | MODE | FRAGMENT | ARGS`; MODE is -, full-disk, SIGINT, SIGTERM or SIGHUP
    (optionally followed by `keep SUFFIX`: the files a stop keeps by design)."""
    cases = []
    for number, line in enumerate(open(path), 1):
        line = line.strip()
        if not line or line.startswith("#"):
            continue
        fields = [f.strip() for f in line.split("|", 3)]
        if len(fields) != 4:
            raise SystemExit(f"{path}:{number}: expected EXIT | MODE | FRAGMENT | ARGS")
        cases.append({"line": number, "exit": int(fields[0]), "mode": fields[1],
                      "fragment": fields[2], "args": fields[3]})
    return cases


def main():
    cases = read_cases(CASES)
    if len(sys.argv) > 5:
        shard, shards = map(int, sys.argv[5].split("/"))
        cases = cases[shard - 1::shards]
    failures = 0
    with tempfile.TemporaryDirectory(prefix="ipmc_swim_abuse_") as d:
        make_fixtures(d)
        FIXTURES.update(listing(d))
        before = snapshot(d)
        for case in cases:
            problems, stderr = check(d, case, before)
            if problems:
                failures += 1
                print(f"{CASES}:{case['line']}: {case['args']}")
                for problem in problems:
                    print(f"    {problem}")
                print("    stderr: " + stderr.strip().replace("\n", "\n            "))
        os.chmod(f"{d}/readonly", 0o755)
    print(f"{len(cases)} cases, {len(cases) - failures} held, {failures} failed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
