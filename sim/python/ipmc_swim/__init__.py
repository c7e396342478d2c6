"""ipmc-swim from Python: the three-link IPMC flagellum in Stokes flow.

The calls mirror the ipmc-swim commands and compute exactly what they
compute (the same library code), returning numpy arrays and dicts instead
of printing; each writes the command's files only when given ``out``, the
same bytes as the command line. Their keywords are the names of the
command's option table (``ipmc-swim options``, docs/OPTIONS.md; the flag
is the name in lower case with ``-`` for ``_``: ``sample_rate_Hz`` is
``--sample-rate-hz``), spelt as docs/CONVENTIONS.md says.

- ``run(scenario, **overrides)``: a closed-loop swimming run (``ipmc-swim run``);
- ``sweep(sweep_file)``: a sweep's table (``ipmc-swim sweep``);
- ``merge(tables, out=...)``: the shards' tables joined (``ipmc-swim merge``);
- ``bench(...)``: a voltage experiment on the test bench (``ipmc-swim bench``);
- ``bode(controller, ...)``, ``step(controller, ...)``: one link's loop;
- ``identify(data, input, output)``, ``design(...)``: identification and design;
- ``export(scenario, out=DIR)``: the scenario's controllers as C99, JSON and CSV;
- ``generate_model(...)``: the MJCF of an N-link flagellum;
- ``keys()``, ``options()``: the scenario-key and option references
  (``ipmc-swim keys``, ``ipmc-swim options``);
- ``plot(kind, input, out=...)``: a figure (``ipmc-swim plot``), e.g.
  ``plot("compare", [run_dir, other_run_dir], out="compare.pdf")``;
- ``Simulation(scenario, **overrides)``: one model to step from a controller
  written in Python.

Long calls release the GIL (simulations in different threads run in
parallel) and take ``progress``, a callable ``progress(done, total)``
called every 0.2 s or so (simulated seconds, or points of a sweep); Ctrl-C
interrupts them. Bad input raises ``ipmc_swim.Error``, a ``ValueError``
whose message is the command line's one line naming the file, key and
allowed range; nothing is half-written. MuJoCo's warnings arrive as
``RuntimeWarning``.
"""

import os

import numpy as np

from . import _core
from ._core import Error, Simulation, __version__
from ._paths import MODELS_DIR, SCENARIOS_DIR, VERSION as _PACKAGE_VERSION

if __version__ != _PACKAGE_VERSION:
    raise ImportError(f"ipmc_swim: the package {os.path.dirname(__file__)} is version "
                      f"{_PACKAGE_VERSION} but its extension ipmc_swim._core is {__version__}; "
                      "rebuild and reinstall the package from one source tree")

__all__ = ["Error", "Result", "Simulation", "bench", "bode", "converge", "design", "export",
           "generate_model", "identify", "keys", "merge", "optimize", "options", "plot",
           "resistance", "run", "step", "sweep",
           "MODELS_DIR", "SCENARIOS_DIR"]


class Result(dict):
    """A dict whose keys are also attributes (``result.summary``)."""

    def __getattr__(self, name):
        try:
            return self[name]
        except KeyError:
            raise AttributeError(name) from None

    def __dir__(self):
        return list(self.keys()) + dir(dict)


def _columns(rows):
    """Rows (dicts with the same keys) as a dict of numpy arrays, one per key:
    int64 for integers, float64 for numbers (NaN where a value is None),
    object arrays for anything else."""
    names = list(rows[0].keys()) if rows else []
    columns = {}
    for name in names:
        values = [row.get(name) for row in rows]
        numbers = [v for v in values if v is not None]
        if all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in numbers):
            if all(isinstance(v, int) for v in numbers) and len(numbers) == len(values):
                columns[name] = np.array(values, dtype=np.int64)
            else:
                columns[name] = np.array([np.nan if v is None else v for v in values],
                                         dtype=np.float64)
        else:
            columns[name] = np.array(values, dtype=object)
    return columns


def _options(options, **arguments):
    """The keyword options with the call's own arguments, those not None."""
    merged = dict(options)
    merged.update({name: value for name, value in arguments.items() if value is not None})
    return merged


def run(scenario, *, out=None, formats=(), allow_long=False, progress=None, **overrides):
    """Runs a closed-loop scenario, as ``ipmc-swim run SCENARIO [--out DIR]``.

    scenario: a scenario file (TOML, see scenarios/paper.toml) or a dict of
    its keys (relative paths from the working directory). overrides: scenario
    keys by their dotted names, as in sweep files, e.g.
    ``run("scenarios/paper.toml", cycles=1, **{"waveform.frequency_Hz": 0.02})``
    or ``controller={"kind": "fractional"}``. out: a directory for
    timeseries.csv and summary.json (the scenario's output.dir is not used).
    formats: also write the run as run.mat ("mat") or run.h5 ("h5") into
    out, as ``run --format`` does (docs/MATLAB.md). allow_long: run even
    beyond 1e8 steps or 2 GB of recorded samples (docs/OPTIONS.md, run).

    Returns a Result with ``timeseries`` (a numpy array per column of
    timeseries.csv: time_s, com_x_mm, ..., reference1_mm, measured1_mm,
    voltage1_V, ..., tip1_x_mm, ...), ``cycles`` (the per-cycle displacement
    table: cycle, com_along_mm, com_across_mm, head_along_mm, head_across_mm),
    ``links`` (per-link metrics: link, iae_mm_s, itae_mm_s2, ...) and
    ``summary`` (summary.json's contents, without its inputs, as a dict).
    """
    raw = _core.run(scenario, overrides,
                    _options({}, out=out, formats=formats, allow_long=allow_long), progress)
    summary = raw["summary"]
    return Result(timeseries=raw["timeseries"], cycles=_columns(summary["per_cycle"]),
                  links=_columns(summary["links"]), summary=summary)


def converge(scenario, *, out=None, **options):
    """Is a scenario's swim converged in its settings, as ``ipmc-swim converge SCENARIO``.

    scenario: a scenario file. options: max_segments, halvings,
    max_plates_k, cycles, jobs (docs/OPTIONS.md, converge). out: a folder
    for converge.csv and converge.png. Returns a list, one Result per study
    (segments, timestep, plates): study, the converged swim_mm and
    fluid_power_W with swim_uncertainty_mm and fluid_power_uncertainty_W,
    scenario (the scenario as given) and runs, each a Result of setting,
    resolution, swim_mm, swim_error, fluid_power_W, fluid_power_error (both
    relative to the study's reference), cost_s_per_simulated_s, warnings.
    """
    studies = _core.converge(scenario, _options(options, out=out))
    return [Result(study, scenario=Result(study["scenario"]),
                   runs=[Result(run) for run in study["runs"]]) for study in studies]


def sweep(sweep_file, *, jobs=None, shard="1/1", out=None, formats=(), keep_runs=None,
          runs_dir=None, resume_other_version=None, progress=None):
    """Runs a sweep file, as ``ipmc-swim sweep SWEEP --out PREFIX``.

    jobs: threads (default: the CPUs this process may use); shard: "i/n" runs the points
    with index % n == i - 1; out: writes PREFIX.csv and PREFIX.json, and with
    formats ("mat", "h5") PREFIX.mat and PREFIX.h5; keep_runs=True (or
    keep_runs = true in the sweep file) also keeps each point's run directory
    as PREFIX_runs/point_N (to plot, film or run again), or as
    RUNS_DIR/point_N with runs_dir.
    With out, each finished point is recorded in PREFIX.journal, as by the
    command line: the journal is the output's lock (a second sweep into the
    same prefix, from Python or the command line, raises Error "... in use
    by another running sweep" before any point runs), and a sweep stopped
    by either front end (Ctrl-C, a killed job) goes on where it stopped when
    either runs it again, giving the same table byte for byte;
    resume_other_version=True resumes a journal another version wrote.
    progress(done, total) is called after each point (total: the points
    left to run). Returns the table as a
    dict of numpy arrays, one per column (point, the swept keys, status,
    error, link<q>_iae_mm_s, ..., reynolds_swim; for a sweep of prescribed
    gaits, a [gait] table instead of base, the gait's metrics period_s, ...,
    max_reference_rad; NaN for a failed point's results).
    """
    table = _core.sweep(sweep_file, _options({}, jobs=jobs, shard=shard, out=out,
                                             formats=formats, keep_runs=keep_runs,
                                             runs_dir=runs_dir,
                                             resume_other_version=resume_other_version),
                        progress)
    return _table(table)


def _table(table):
    """A sweep table (its JSON) as a dict of numpy arrays, one per column."""
    columns = _columns(table["points"])
    return {name: columns.get(name, np.array([], dtype=object)) for name in table["columns"]}


def optimize(file, *, out, jobs=None, resume=None, start=None, journals=None, progress=None):
    """Optimises a scenario's design, as ``ipmc-swim optimize OPT --out DIR``.

    file: an optimisation file (TOML, docs/OPTIMIZE.md). out: the folder for
    history.csv, convergence.csv, convergence.png, result.json, best/ and
    optimize.journal. jobs: threads for the starts (default: the CPUs this
    process may use; the result does not depend on it). resume=True goes on
    with the journal in out. start=K runs that start alone and writes only
    its journal (returns None): one task of ``optimize --slurm``.
    journals=FOLDER takes the evaluations FOLDER/start_K/optimize.journal
    record (the tasks' merge). progress(done, total) is called after each
    evaluation. Returns result.json as a dict (best.variables,
    best.objective, best.metrics, evaluations, algorithm, converged,
    stop_reason, starts).
    """
    options = _options({}, out=out, jobs=jobs, resume=resume, start=start, journals=journals)
    return _core.optimize(file, options, progress)


def merge(tables, *, out):
    """Joins the tables of a sweep's shards, as ``ipmc-swim merge --out PREFIX A.csv B.csv ...``.

    tables: the shards' PREFIX.csv files (a list, or one path); out: writes
    PREFIX.csv and PREFIX.json, the command line's bytes. The same checks:
    a table that does not exist, tables with different columns, a point in
    two tables or a gap in the indices raise Error, and nothing is written.
    (``merge --partial`` is the command line's alone.) Returns the merged
    table as sweep() does.
    """
    return _table(_core.merge(tables, {"out": out}))


def keys(*, format="text"):
    """The reference of every scenario and sweep-file key, as ``ipmc-swim keys`` prints it.

    format: "text" or "markdown" (docs/SCENARIO_KEYS.md). Returns the text.
    """
    return _core.keys({"format": format})


def options(*, format="text"):
    """Every command's options (the keywords of these calls), as ``ipmc-swim options``.

    format: "text" or "markdown" (docs/OPTIONS.md). Returns the text.
    """
    return _core.options({"format": format})


def bench(model=None, *, out=None, progress=None, **signal):
    """A voltage experiment on the test bench, as ``ipmc-swim bench``.

    model: the MJCF (default models/flagellum3_clamped.xml). signal: the
    bench's options, signal="sine" or "chirp", amplitude_V, frequency_Hz
    (sine), start_Hz and end_Hz (chirp), duration_s, sample_rate_Hz, links
    (driven, 1-based), allow_long. out: the CSV file to write (never the
    model). Returns the record, a numpy array per column of the bench CSV
    (time_s, voltage1_V, relative1_mm, tip1_lateral_mm, free1_mm,
    voltage2_V, ...).
    """
    if model is None:
        model = os.path.join(MODELS_DIR, "flagellum3_clamped.xml")
    return _core.bench(_options(signal, model=model, out=out), progress)


def bode(controller, *, out=None, **options):
    """The open loop and margins of each link, as ``ipmc-swim bode``.

    controller: pid, fractional, fractional-eq15, fractional-oustaloup or
    none. options: links, plant, kp, ki, kd, gain, order, oustaloup_pairs,
    band_rad_s, w_min_rad_s, w_max_rad_s, points_per_decade, plant_file
    (identify's plant.toml: each link's own plant), gains_file (design's
    gains.toml: each link's own gains) (an option the controller does not
    take is an error). out: a folder for bode.csv and
    bode.json (with one link). Returns a list, one Result per link: link,
    the descriptions, the margins, the values at 5 rad/s and the response
    (bode.csv's columns as arrays).
    """
    links = _core.bode(_options(options, controller=controller, out=out))
    return [Result(link) for link in links]


def step(controller, *, out=None, **options):
    """Closed-loop unit steps of the links, as ``ipmc-swim step``.

    controller: pid or fractional. options: links, plant, kp, ki, kd, gain,
    order, horizon_s, max_horizon_s, sample_rate_Hz, no_clamp, v_max_V,
    plant_file, gains_file (each link's own plant and gains, as for bode),
    bench (a scenario: each link's step also on its multibody simulation).
    out: a folder for step.csv and step.json. Returns per link its record
    (time_s, output_mm, control_V), step metrics, whether the record
    determines them, the largest voltage, J of eq. 11 and Table 5's IAE
    and ITAE (iae_mm_s, itae_mm_s2); the same per link on the bench
    (bench, empty without one); and the reference model's step.
    """
    return _core.step(_options(options, controller=controller, out=out))


def identify(data, input, output, *, out=None, **options):
    """Frequency response and Levy fits of G1 and G2, as ``ipmc-swim identify``.

    data: the record, anything indexed by column names (a bench() result, a
    dict of arrays, numpy.genfromtxt(path, delimiter=",", names=True) of a
    bench CSV); input, output: the columns [V] and [mm]; a time_s column, if
    present, must agree with the sample rate. options: sample_rate_Hz,
    band_rad_s, name (the record's name in messages and
    identification.json; the command line's is the file's path). out: a
    folder for response.csv and identification.json. Returns
    identification.json's contents and the response (w_rad_s, measured,
    coherence, p1, p2, ...).
    """
    return _core.identify(data, _options(options, input=input, output=output, out=out))


def design(**options):
    """The fractional integrator and the tuned PID of each link, as ``ipmc-swim design``.

    options: links, plant, crossover_rad_s, phase_margin_deg,
    reference_order, horizon_s, sample_rate_Hz (1 kHz), derivative_bandwidth_rad_s,
    sensor_noise_mm and derivative_noise_V (the derivative filter from the
    sensor's noise), plant_file, scenario (every link of its run, at its
    sample rate), out. Returns a list, one Result per link (link,
    fractional, pid with its sample_rate_Hz, derivative_filter_s and
    derivative_noise_V, tuning_s).
    """
    return [Result(link) for link in _core.design(options)]


def export(scenario, *, out, **overrides):
    """A scenario's controllers as code, as ``ipmc-swim export SCENARIO --out DIR``.

    scenario: a scenario file or a dict of its keys; overrides: scenario keys
    by their dotted names, as for run(). Writes DIR/ipmc_controller.h and
    DIR/ipmc_controller.c (C99: the controllers as the simulator runs them),
    DIR/coefficients.json and DIR/coefficients.csv (docs/PROTOTYPE.md).
    Returns coefficients.json's contents as a dict.
    """
    return _core.export(scenario, overrides, _options({}, out=out))


def generate_model(*, out=None, **spec):
    """The MJCF of an N-link flagellum, as ``ipmc-swim generate``.

    spec: the generator's fields (link_lengths_mm, segments_per_link,
    gap_mm, width_mm, thickness_um, head_length_mm, density_kg_m3,
    bending_modulus_Pa, hinge_damping_ratio, clamped, timestep_s, integrator,
    viscosity_Pa_s, coefficients, wavelength_mm, equivalent_radius_mm,
    xi_normal_N_s_m2, xi_tangential_N_s_m2, fluid_density_kg_m3,
    ipmc_actuators, plants, ipmc_model, actuation, name). out: a file to
    write. Returns the XML text (``Simulation.from_xml`` loads it).
    """
    return _core.generate_model(_options(spec, out=out))


def resistance(model, *, out=None, **options):
    """The resistance of a model held rigid, as ``ipmc-swim resistance MODEL``.

    model: an MJCF file with ipmc_rft_ fields (held at qpos0). options:
    fluid, coefficients, stokeslet_points_per_mm, stokeslet_blob_mm, axis
    (docs/OPTIONS.md, resistance). out: a JSON file (key "R"). Returns a
    Result with ``R`` (6 x 6 numpy array: rows Fx Fy Fz [N], Tx Ty Tz
    [N m] about the world origin; columns vx vy vz [m/s], wx wy wz
    [rad/s]) and Purcell's A_N_s_m, B_N_s, D_N_m_s for the axis.
    """
    result = _core.resistance(os.fspath(model), _options(options, out=out))
    result["R"] = np.array(result["R"])
    return Result(result)


def plot(kind, input, *, out, **options):
    """A figure, as ``ipmc-swim plot KIND INPUT... --out OUT`` draws it (the same bytes).

    kind: bode, step, tracking, waveform, surface, trajectory,
    identification, sweep or compare. input: the file the kind draws
    (bode.csv, step.csv, timeseries.csv, response.csv, a sweep table), or
    for compare a list of two or more run directories (their
    timeseries.csv and summary.json). out: FILE.pdf, FILE.svg or FILE.png.
    options: title, width_px, height_px, and the kind's own (curves,
    instants, times_s, period_s, max_lines, x, y, group, log_x, log_y, labels; one
    the kind does not use is an error). Returns a Result with the title
    (title, title_lines) and what the figure found (notes: for compare,
    each run's last-cycle displacement and steady tracking error).
    """
    inputs = [input] if isinstance(input, (str, os.PathLike)) else list(input)
    return Result(_core.plot(kind, inputs, out, options))
