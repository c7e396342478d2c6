"""Bad input from Python, as a table: every call with a wrong value raises
ipmc_swim.Error (a ValueError) with the command line's one line, every
wrong type a TypeError naming the keyword and the type it takes (never
pybind11's "Unable to cast"), before any work and with nothing written;
numpy scalars and arrays count as the numbers and lists they hold. The
command line's table is tests/cli_abuse/cases.txt."""

import os
import pathlib

import numpy as np
import pytest

import ipmc_swim
from conftest import SHORT_SCENARIO

CLAMPED = os.path.join(ipmc_swim.MODELS_DIR, "flagellum3_clamped.xml")
FREE = os.path.join(ipmc_swim.MODELS_DIR, "flagellum3.xml")
# One 2 s cycle: quick enough for the cases that run.
QUICK = {"cycles": 1, "waveform.frequency_Hz": 0.5}
OK = None  # the call succeeds


def bench(**options):
    return lambda d: ipmc_swim.bench(CLAMPED, **{"duration_s": 0.2, **options})


def run(**options):
    return lambda d: ipmc_swim.run(d / "short.toml", **{**QUICK, **options})


def sweep(**options):
    return lambda d: ipmc_swim.sweep(d / "sweep.toml", **{"jobs": 1, **options})


def generate(**options):
    return lambda d: ipmc_swim.generate_model(**options)


def simulation(*voltages):
    def call(d):
        s = ipmc_swim.Simulation(d / "short.toml")
        for volts in voltages:
            s.set_voltages(volts)
        s.step(10)
    return call


def identify(time_s, record=False, drop=None, **options):
    """identify on a dict of columns (or, record=True, a numpy record array
    as numpy.genfromtxt reads a CSV), time_s=None leaving that column out
    (drop: another column left out)."""
    def call(d):
        k = np.arange(4000 if time_s is None else len(time_s))
        data = {"voltage1_V": np.sin(0.37 * k) + np.sin(1.3 * k),
                "relative1_mm": np.sin(0.37 * k - 0.2) + 0.5 * np.sin(1.3 * k - 0.4)}
        if time_s is not None:
            data = {"time_s": np.asarray(time_s, dtype=float), **data}
        data.pop(drop, None)
        if record:
            data = np.rec.fromarrays(list(data.values()), names=list(data))
        return ipmc_swim.identify(data, "voltage1_V", "relative1_mm", band_rad_s=[8.0, 50.0],
                                  **{"sample_rate_Hz": 1000.0, **options})
    return call


EVEN = np.arange(4000) / 1000.0
JUMP = EVEN.copy()
JUMP[2000:] += 1e-3  # one sample missing
BACKWARD = EVEN.copy()
BACKWARD[3000] = BACKWARD[2999] - 1e-3

# (name, call, exception, fragment of the message).
CASES = [
    # Scenario keys: numbers, numpy, the range of a scenario integer.
    ("cycles 2**70", run(cycles=2 ** 70), TypeError, "cycles: the int 1180591620717411303424 is beyond"),
    ("cycles -2**70", run(cycles=-2 ** 70), TypeError, "cycles: the int"),
    ("cycles float", run(cycles=1.5), ipmc_swim.Error, "cycles must be an integer (got float)"),
    ("cycles bool", run(cycles=True), TypeError, "cycles must be an int (got bool"),
    ("cycles str", run(cycles="1"), ipmc_swim.Error, "cycles must be an integer"),
    ("cycles object", run(cycles=object()), TypeError, "cycles"),
    ("cycles np.int64", run(cycles=np.int64(1)), OK, ""),
    ("cycles np.float32", run(cycles=np.float32(1.5)), ipmc_swim.Error, "cycles must be an integer"),
    ("frequency np.float32", run(**{"waveform.frequency_Hz": np.float32(0.5)}), OK, ""),
    ("frequency np.float64", run(**{"waveform.frequency_Hz": np.float64(0.5)}), OK, ""),
    ("frequency array", run(**{"waveform.frequency_Hz": np.array([0.5])}), ipmc_swim.Error,
     "frequency_Hz"),
    ("frequency two steps", run(**{"waveform.frequency_Hz": 1000.0}), ipmc_swim.Error,
     "at least 10 controller samples"),
    ("frequency nan", run(**{"waveform.frequency_Hz": float("nan")}), ipmc_swim.Error,
     "frequency_Hz"),
    ("frequency str", run(**{"waveform.frequency_Hz": "fast"}), ipmc_swim.Error, "frequency_Hz"),
    ("kp np.float32", run(controller={"kp": np.float32(8.0)}), OK, ""),
    ("kp list", run(controller={"kp": [1.0, 2.0]}), ipmc_swim.Error, "kp"),
    ("v_max_V negative", run(controller={"v_max_V": -1.0}), ipmc_swim.Error, "v_max_V"),
    ("controller not a table", run(controller=3), ipmc_swim.Error, "controller"),
    ("unknown key", run(colour="blue"), ipmc_swim.Error, "unknown key 'colour'"),
    ("key not a str", lambda d: ipmc_swim.run({1: 2}), TypeError, "scenario keys must be strings"),
    ("link lengths array", run(link_lengths_mm=np.array([10.0, 10.0, 10.0]),
                               segments_per_link=1), OK, ""),
    ("link lengths with str", run(link_lengths_mm=[10.0, "x", 10.0], segments_per_link=1),
     ipmc_swim.Error, "link_lengths_mm"),
    # run's own arguments.
    ("run out empty", run(out=""), ipmc_swim.Error, "out must name a path (got '')"),
    ("run out int", run(out=5), TypeError, "out must be a path"),
    ("run out is the scenario", lambda d: ipmc_swim.run(d / "short.toml", out=d / "short.toml"),
     ipmc_swim.Error, "short.toml"),
    ("run scenario empty", lambda d: ipmc_swim.run(""), ipmc_swim.Error, "scenario must name a path"),
    ("run scenario int", lambda d: ipmc_swim.run(7), TypeError, "scenario must be a path"),
    ("run formats unknown", run(out="x", formats=["xls"]), ipmc_swim.Error, "format"),
    ("run formats mat without out", run(formats=["mat"]), ipmc_swim.Error, "need an output folder (out)"),
    ("run progress not callable", run(progress=5), TypeError, "progress must be callable"),
    # sweep
    ("sweep jobs 1.5", sweep(jobs=1.5), TypeError, "sweep(): jobs must be an int"),
    ("sweep jobs 2**70", sweep(jobs=2 ** 70), TypeError, "jobs must be an int (within"),
    ("sweep jobs str", sweep(jobs="2"), TypeError, "jobs must be an int"),
    ("sweep jobs bool", sweep(jobs=True), TypeError, "jobs must be an int"),
    ("sweep jobs np.int64", sweep(jobs=np.int64(1)), OK, ""),
    ("sweep jobs 0", sweep(jobs=0), ipmc_swim.Error, "jobs"),
    ("sweep formats int", sweep(formats=5), TypeError, "formats must be a list of strs (got int 5)"),
    ("run formats str", run(out="x", formats="mat"), TypeError, "formats must be a list of strs"),
    ("sweep shard 3/2", sweep(shard="3/2"), ipmc_swim.Error, "shard"),
    ("sweep shard text", sweep(shard="x"), ipmc_swim.Error, "shard"),
    ("sweep out empty", sweep(out=""), ipmc_swim.Error, "out must name a path (got '')"),
    ("sweep out dir/", sweep(out="tables/"), ipmc_swim.Error, "must name the table's files"),
    ("sweep out a folder", lambda d: ipmc_swim.sweep(d / "sweep.toml", jobs=1, out=d),
     ipmc_swim.Error, "must name the table's files"),
    ("sweep out name too long", lambda d: ipmc_swim.sweep(d / "sweep.toml", jobs=1,
                                                          out=d / ("t" * 240)),
     ipmc_swim.Error, "name too long"),
    ("sweep file missing", lambda d: ipmc_swim.sweep(d / "none.toml"), ipmc_swim.Error,
     "cannot open"),
    ("sweep file empty path", lambda d: ipmc_swim.sweep(""), ipmc_swim.Error, "must name a path"),
    # bench: the option table's types.
    ("bench duration str", bench(duration_s="1"), TypeError,
     "bench(): duration_s must be a number (int or float) (got str)"),
    ("bench duration bool", bench(duration_s=True), TypeError, "duration_s must be a number"),
    ("bench duration np.float32", bench(duration_s=np.float32(0.2)), OK, ""),
    ("bench duration np.int64", bench(duration_s=np.int64(1)), OK, ""),
    ("bench amplitude 1e6", bench(amplitude_V=1e6), ipmc_swim.Error, "amplitude_V"),
    ("bench amplitude nan", bench(amplitude_V=float("nan")), ipmc_swim.Error, "amplitude_V"),
    ("bench amplitude 2**70", bench(amplitude_V=2 ** 70), ipmc_swim.Error, "amplitude_V"),
    ("bench links array", bench(links=np.array([1, 3])), OK, ""),
    ("bench links floats", bench(links=[1.5]), TypeError, "links must be a list of ints"),
    ("bench links int", bench(links=1), TypeError, "links must be a list of ints"),
    ("bench links str", bench(links="1"), TypeError, "links must be a list of ints"),
    ("bench links 2**70", bench(links=[2 ** 70]), TypeError, "links must be a list of ints"),
    ("bench links float array", bench(links=np.array([1.0])), TypeError,
     "links must be a list of ints"),
    ("bench links 4", bench(links=[4]), ipmc_swim.Error, "driven link"),
    ("bench allow_long str", bench(allow_long="yes"), TypeError, "allow_long must be a bool"),
    ("bench allow_long np.bool_", bench(allow_long=np.bool_(False)), OK, ""),
    ("bench signal int", bench(signal=3), TypeError, "signal must be a str"),
    ("bench signal square", bench(signal="square"), ipmc_swim.Error, "signal"),
    ("bench unknown keyword", bench(duration=1.0), TypeError, "unexpected keyword argument 'duration'"),
    ("bench out empty", bench(out=""), ipmc_swim.Error, "must name a path (got '')"),
    ("bench out is the model", bench(out=CLAMPED), ipmc_swim.Error, "would overwrite the input"),
    ("bench out a folder", lambda d: ipmc_swim.bench(CLAMPED, duration_s=0.2, out=d),
     ipmc_swim.Error, "is a directory"),
    ("bench out name too long", lambda d: ipmc_swim.bench(CLAMPED, duration_s=0.2,
                                                          out=d / ("b" * 250 + ".csv")),
     ipmc_swim.Error, "name too long"),
    # Simulation: voltages within the model's range (ipmc_voltage_limit_V).
    ("voltages 1e6", simulation([1e6] * 3), ipmc_swim.Error, "outside the model's range [-100, 100] V"),
    ("voltages 101", simulation([0.0, 101.0, 0.0]), ipmc_swim.Error, "voltage of link 2 is 101 V"),
    ("voltages -101", simulation([-101.0, 0.0, 0.0]), ipmc_swim.Error, "outside the model's range"),
    ("voltages at the limit", simulation([100.0, -100.0, 0.0]), OK, ""),
    ("voltages array", simulation(np.array([1.0, 2.0, 3.0])), OK, ""),
    ("voltages float32", simulation([np.float32(1.0)] * 3), OK, ""),
    ("voltages nan", simulation([float("nan"), 0.0, 0.0]), ipmc_swim.Error, "not finite"),
    ("voltages inf", simulation([0.0, float("inf"), 0.0]), ipmc_swim.Error, "not finite"),
    ("voltages two", simulation([1.0, 2.0]), ipmc_swim.Error, "2 voltages for 3 links"),
    ("voltages str", simulation(["a", "b", "c"]), TypeError, "voltages_V"),
    # generate_model: what the loader would reject is refused.
    ("generate wavelength 0.5 mm", generate(wavelength_mm=0.5), ipmc_swim.Error,
     "wavelength_mm = 0.5 is too short"),
    ("generate lighthill wavelength 2 mm", generate(coefficients="lighthill", wavelength_mm=2.0),
     ipmc_swim.Error, "wavelength_mm = 2 is too short"),
    ("generate 64 x 2 segments", generate(link_lengths_mm=[0.4] * 64, segments_per_link=2),
     ipmc_swim.Error, "segments_per_link must be <= 1"),
    ("generate segments float", generate(segments_per_link=1.5), TypeError,
     "segments_per_link must be an int"),
    ("generate segments 2**70", generate(segments_per_link=2 ** 70), TypeError,
     "segments_per_link must be an int"),
    ("generate lengths array", generate(link_lengths_mm=np.array([10.0, 10.0])), OK, ""),
    ("generate lengths str", generate(link_lengths_mm="10,10"), TypeError,
     "link_lengths_mm must be a list of numbers"),
    ("generate name int", generate(name=5), TypeError, "name must be a str"),
    ("generate out empty", generate(out=""), ipmc_swim.Error, "must name a path (got '')"),
    ("generate out a folder", lambda d: ipmc_swim.generate_model(out=d), ipmc_swim.Error,
     "is a directory"),
    # The analyses.
    ("bode kp np.float32", lambda d: ipmc_swim.bode("pid", links=[1], kp=np.float32(2.0)), OK, ""),
    ("bode links array", lambda d: ipmc_swim.bode("pid", links=np.array([1, 2])), OK, ""),
    ("bode kp str", lambda d: ipmc_swim.bode("pid", kp="2"), TypeError, "kp must be a number"),
    ("bode links 2**70", lambda d: ipmc_swim.bode("pid", links=[2 ** 70]), TypeError,
     "links must be a list of ints"),
    ("step horizon bool", lambda d: ipmc_swim.step("pid", horizon_s=True), TypeError,
     "horizon_s must be a number"),
    ("design links floats", lambda d: ipmc_swim.design(links=[1.0]), TypeError,
     "links must be a list of ints"),
    ("identify even time", identify(EVEN), OK, ""),
    ("identify time jumps", identify(JUMP), ipmc_swim.Error, "jumps at data row 2001"),
    ("identify time backward", identify(BACKWARD), ipmc_swim.Error, "runs backward at data row 3001"),
    ("identify rate np.float64", identify(EVEN, sample_rate_Hz=np.float64(1000.0)), OK, ""),
    ("identify rate str", identify(EVEN, sample_rate_Hz="1000"), TypeError,
     "sample_rate_Hz must be a number"),
    # Paths with a NUL byte: the system would end them there and open or
    # write another file (b.csv for "b.csv\0.txt"); one check where Python
    # strings become paths (PathText) refuses them in every call.
    ("bench out NUL", bench(out="b.csv\x00.txt"), ipmc_swim.Error,
     "bench(): out must name a path without NUL bytes (got 'b.csv\\x00...')"),
    ("bench model NUL", lambda d: ipmc_swim.bench(CLAMPED + "\x00.bak", duration_s=0.2),
     ipmc_swim.Error, "model must name a path without NUL bytes"),
    ("from_model NUL", lambda d: ipmc_swim.Simulation.from_model(CLAMPED + "\x00.bak"),
     ipmc_swim.Error, "model must name a path without NUL bytes"),
    ("Simulation scenario NUL", lambda d: ipmc_swim.Simulation(str(d / "short.toml") + "\x00x"),
     ipmc_swim.Error, "scenario must name a path without NUL bytes"),
    ("run scenario NUL", lambda d: ipmc_swim.run(str(d / "short.toml") + "\x00.bak"),
     ipmc_swim.Error, "run(): scenario must name a path without NUL bytes"),
    ("run scenario PathLike NUL",
     lambda d: ipmc_swim.run(pathlib.Path(str(d / "short.toml") + "\x00.bak")),
     ipmc_swim.Error, "run(): scenario must name a path without NUL bytes"),
    ("run out NUL", run(out="o\x00ut"), ipmc_swim.Error, "out must name a path without NUL bytes"),
    ("run model key NUL", run(model=FREE + "\x00.bak"), ipmc_swim.Error,
     "overrides: model: a string with a NUL byte (a path would end there)"),
    ("run dict include NUL", lambda d: ipmc_swim.run({"include": "short.toml\x00.bak", "cycles": 1}),
     ipmc_swim.Error, "scenario dict: include: a string with a NUL byte"),
    ("sweep file NUL", lambda d: ipmc_swim.sweep(str(d / "sweep.toml") + "\x00x"),
     ipmc_swim.Error, "sweep must name a path without NUL bytes"),
    ("sweep out NUL", sweep(out="t\x00able"), ipmc_swim.Error,
     "out must name a path without NUL bytes"),
    ("merge tables NUL", lambda d: ipmc_swim.merge(["a.csv\x00", "b.csv"], out="m.csv"),
     ipmc_swim.Error, "merge(): tables must name a path without NUL bytes"),
    ("generate out NUL", generate(out="m.xml\x00.txt"), ipmc_swim.Error,
     "generate_model(): out must name a path without NUL bytes"),
    ("identify out NUL", identify(EVEN, out="id\x00x"), ipmc_swim.Error,
     "out must name a path without NUL bytes"),
    ("design out NUL", lambda d: ipmc_swim.design(links=[1], out="g.toml\x00x"), ipmc_swim.Error,
     "design(): out must name a path without NUL bytes"),
    ("plot out NUL", lambda d: ipmc_swim.plot("bode", "bode.csv", out="f.png\x00x"),
     ipmc_swim.Error, "plot(): out must name a path without NUL bytes"),
    # identify: time_s is optional, the samples sample_rate_Hz apart.
    ("identify dict without time_s", identify(None), OK, ""),
    ("identify record without time_s", identify(None, record=True), OK, ""),
    ("identify record with time_s", identify(EVEN, record=True), OK, ""),
    ("identify record time backward", identify(BACKWARD, record=True), ipmc_swim.Error,
     "runs backward at data row 3001"),
    ("identify dict without time_s or a column", identify(None, drop="relative1_mm"),
     ipmc_swim.Error, "no column 'relative1_mm'"),
    # generate_model: IPMC actuators need a hinge on link 1.
    ("generate no head", generate(head_length_mm=0.0), ipmc_swim.Error,
     "head_length_mm = 0 leaves link 1 no hinge for its IPMC actuator"),
    ("generate no head, actuators asked", generate(head_length_mm=0, ipmc_actuators=True),
     ipmc_swim.Error, "give a head (head_length_mm > 0), clamp the chain (clamped)"),
    ("generate no head, clamped", generate(head_length_mm=0.0, clamped=True), OK, ""),
    ("generate no head, passive", generate(head_length_mm=0.0, ipmc_actuators=False), OK, ""),
    # controller.link_gain, like gain, has no place in the printed eq. 15.
    ("link_gain under eq15", run(controller={"kind": "fractional", "realisation": "eq15",
                                             "link_gain": [1.0, 1.0, 1.0]}),
     ipmc_swim.Error, "controller.link_gain applies only to realisation = \"oustaloup\""),
    ("link_order under eq15", run(controller={"kind": "fractional", "realisation": "eq15",
                                              "link_order": [0.5, 0.5, 0.5]}),
     ipmc_swim.Error, "controller.link_order applies only to realisation = \"oustaloup\""),
    # Includes: a bound on the files read in all; errors placed in their file.
    ("include fan-out", lambda d: ipmc_swim.run(d / "fan0.toml"), ipmc_swim.Error,
     "fan5.toml:1: include reads more than 64 files in all"),
    ("include plant of the wrong length", lambda d: ipmc_swim.run(d / "uses_plant.toml"),
     ipmc_swim.Error, "plant.toml:2: plant.link_a0_mm_per_V: a0_mm_per_V must hold one value"),
]


# Seven one-line files, each including the next 12 times: 12^6 files
# without a bound on the files read in all.
FAN_OUT = 7


@pytest.fixture
def folder(tmp_path):
    (tmp_path / "short.toml").write_text(SHORT_SCENARIO)
    for k in range(FAN_OUT - 1):
        (tmp_path / f"fan{k}.toml").write_text(f'include = {[f"fan{k + 1}.toml"] * 12}\n'.replace(
            "'", '"'))
    (tmp_path / f"fan{FAN_OUT - 1}.toml").write_text("cycles = 1\n")
    # An included plant with one a0 for three links: placed at plant.toml's line.
    (tmp_path / "plant.toml").write_text("[plant]\nlink_a0_mm_per_V = [0.2, 0.3]\n")
    (tmp_path / "uses_plant.toml").write_text(
        'include = "plant.toml"\n# the plant identified on the bench\n'
        "link_lengths_mm = [10.0, 10.0, 10.0]\n")
    (tmp_path / "sweep.toml").write_text('base = "short.toml"\n[set]\ncycles = 1\n'
                                         '"waveform.frequency_Hz" = 0.5\n[grid]\n'
                                         'segments_per_link = [1]\n')
    return tmp_path


@pytest.mark.parametrize("name, call, error, fragment", CASES, ids=[case[0] for case in CASES])
def test_bad_input(folder, monkeypatch, name, call, error, fragment):
    monkeypatch.chdir(folder)
    before = sorted(folder.rglob("*"))
    if error is OK:
        call(folder)
        return
    with pytest.raises(error) as raised:
        call(folder)
    message = str(raised.value)
    assert fragment in message, message
    assert "Unable to cast" not in message
    assert "\n" not in message.strip(), message
    assert sorted(folder.rglob("*")) == before, "a failed call left files"
