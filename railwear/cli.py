"""The ``railwear`` command (layer 5). Exit status: 0 success, 1 a run failed, 2 bad input."""

import os
import sys
from pathlib import Path
from typing import Annotated, Optional

import typer

from railwear.errors import NumericalInstabilityError, RailwearError, ScenarioError

# Help as plain text: rich markup would read A:B:STEP's ':B:' as an emoji and [...] as a style.
app = typer.Typer(add_completion=False, no_args_is_help=True, pretty_exceptions_enable=False,
                  rich_markup_mode=None, context_settings={"max_content_width": 120},
                  help="railwear: long-term wear of railway wheels and polygonalisation.")


_QUIET_COMMANDS = ("plot", "scenarios", "show")  # compile nothing: no numba import for them
_compile_notice = {"installed": False, "printed": False, "compiled": False}


def _print_version(value: bool):
    if value:
        from railwear import __version__

        typer.echo(f"railwear {__version__}")
        raise typer.Exit()


def _one_line_warning(message, category, filename, lineno, file=None, line=None):
    typer.echo(f"railwear: warning: {message}", err=True)


@app.callback()
def _announce_compiling(ctx: typer.Context, version: Annotated[bool, typer.Option(
        "--version", is_eager=True, callback=_print_version, help="print railwear's version and exit")] = False):
    """One line on standard error when numba compiles, i.e. its cache is cold (the first run
    after an install or a change): up to a minute that would otherwise look like a hang."""
    import warnings

    warnings.showwarning = _one_line_warning  # a warning before a run (the scenario's layout) in one line too
    if ctx.invoked_subcommand in _QUIET_COMMANDS or _compile_notice["installed"]:
        return
    from numba.core import event

    event.register("numba:compile", compile_listener())
    _compile_notice["installed"] = True


NOTICE_AFTER = 0.5  # s: a compile still going after this is a cold cache's, and the notice prints


def _failed(ev):
    """Whether a numba end event carries an exception. ``Event.is_failed`` of numba 0.68 reads the
    other way round (True when there is none), so the exception itself is read."""
    details = getattr(ev, "_exc_details", None)
    return details is not None and details[0] is not None


def compile_listener(delay=None, echo=None):
    """A numba ``numba:compile`` listener for the command line. numba fires the event on every
    miss of its in-memory table, and a miss can end at once without compiling (a kernel that asks
    for its argument as a literal raises ``ForceLiteralArg`` and is loaded from the disk cache
    with the literal type: on a warm cache, 2 such events of 6 ms each per run). So the notice
    'compiling kernels (first run only)...' prints only when a compile is still going after
    ``delay`` seconds (default :data:`NOTICE_AFTER` as it is when a compile starts; 0: at once),
    and ``_compile_notice['compiled']`` (what the report says) is set only by
    a compile that finished (the event not failed). On a terminal the progress bar (or a status
    line) names the kernel compiling and counts those done; in a log, one line per kernel that
    took 2 s or more. ``echo`` prints a line to standard error (tests pass their own)."""
    import threading
    import time

    from numba.core import event

    say = echo or (lambda text: typer.echo(text, err=True))

    class Notice(event.Listener):
        depth, done, started, timer = 0, 0, [], None

        def on_start(self, ev):
            self.depth += 1
            if self.depth == 1:
                self.started = [getattr(ev.data.get("dispatcher"), "__name__", "kernel").lstrip("_"), time.monotonic()]
                wait = NOTICE_AFTER if delay is None else delay
                if not _compile_notice["printed"] and wait <= 0:
                    self.announce()
                elif not _compile_notice["printed"]:
                    self.timer = threading.Timer(wait, self.announce)
                    self.timer.daemon = True
                    self.timer.start()

        def announce(self):
            if self.depth > 0 and not _compile_notice["printed"]:
                _compile_notice["printed"] = True
                say("compiling kernels (first run only)...")
                self.show(f"compiling {self.started[0]} ({self.done} kernels done)")

        def on_end(self, ev):
            self.depth -= 1
            if self.depth == 0:
                if self.timer is not None:
                    self.timer.cancel()
                    self.timer = None
                if _failed(ev):  # no compile: a literal asked for, or an error that is raised on
                    return
                _compile_notice["compiled"] = True
                self.done += 1
                seconds = time.monotonic() - self.started[1]
                if _compile_notice["printed"] and not sys.stderr.isatty() and seconds >= 2:
                    say(f"compiled {self.started[0]} in {seconds:.0f} s ({self.done} kernels done)")
                if _compile_notice["printed"]:
                    self.show("")

        @staticmethod
        def show(text):
            progress = _compile_notice.get("progress")
            if progress is not None and progress.bar is not None:
                progress.bar.update(progress.task, description=f"{progress.label}: {text}" if text else progress.label)
            elif sys.stderr.isatty():
                typer.echo(f"\r\033[K{text}", err=True, nl=False)

    return Notice()


_state = {"output": None,  # the output folder of the command running, for the log of a bug
          "own_process": False}  # run by main(): the process is the command's (not a test's), and may fork


def _fail(message, status):
    typer.echo(f"railwear: error: {' '.join(str(message).split())}", err=True)
    raise typer.Exit(status)


def _output(directory):
    """The command's output folder: remembered for a bug's log, cleared of the temporary files
    of killed runs (never read as results)."""
    from railwear import results

    _state["output"] = directory
    removed = results.clean_partial(directory)
    if removed:
        typer.echo(f"railwear: removed {len(removed)} temporary file(s) of a killed run from {directory}: "
                   f"{', '.join(sorted(removed)[:3])}{' ...' if len(removed) > 3 else ''}", err=True)
    return directory


def _parse_range(text, field):
    """``A:B:STEP`` (inclusive of B) or ``v1,v2,...``."""
    from railwear.sweep import parse_values

    try:
        return parse_values(text, field)
    except ScenarioError as e:
        _fail(str(e), 2)


def _option(value, name, low=None, high=None, low_open=False):
    """Refuse an option outside ``[low, high]`` (``(low, high]`` with ``low_open``) or not finite."""
    import math

    if value is None:
        return None
    if not math.isfinite(value) or (low is not None and (value <= low if low_open else value < low)) or (
            high is not None and value > high):
        bounds = f"{'(' if low_open else '['}{low:g}, {high:g}]" if high is not None else f"{'>' if low_open else '>='} {low:g}"
        _fail(f"{name} must be {'in ' if high is not None else ''}{bounds}, got {value:g}", 2)
    return value


Format = Annotated[str, typer.Option("--format", help="figure format: png, or pdf or svg (written beside the PNG)")]
Dpi = Annotated[int, typer.Option(help="dots per inch of the figures (30 to 1200)")]


def _figure_options(fmt, dpi):
    """Refuse a figure format or dpi that plots.save does not write."""
    from railwear.plots import FORMATS

    if fmt not in FORMATS:
        _fail(f"--format must be one of {', '.join(FORMATS)}, got {fmt!r}", 2)
    _option(dpi, "--dpi", 30, 1200)


class _Warnings:
    """Warnings of a run as one line each on standard error, after it."""

    def __enter__(self):
        import warnings

        self.context = warnings.catch_warnings(record=True)
        self.caught = self.context.__enter__()
        warnings.simplefilter("always")
        return self

    def __exit__(self, *exc):
        self.context.__exit__(*exc)
        for w in self.caught:
            typer.echo(f"railwear: warning: {w.message}", err=True)


class _Progress:
    """A rich progress bar on a terminal, a log line every 10 % otherwise."""

    def __init__(self, label):
        self.label, self.bar, self.last = label, None, -1

    def __enter__(self):
        _full_collections(True)  # the command's imports are done: its computation starts here
        if sys.stderr.isatty():
            from rich.progress import Progress

            self.bar = Progress(transient=True)
            self.bar.start()
            self.task = self.bar.add_task(self.label, total=1.0)
        _compile_notice["progress"] = self  # where the compile notice says what it compiles
        return self

    def __call__(self, fraction):
        if self.bar is not None:
            self.bar.update(self.task, completed=fraction)
        elif int(fraction * 10) > self.last:
            self.last = int(fraction * 10)
            typer.echo(f"{self.label}: {fraction:4.0%}", err=True)

    def __exit__(self, *exc):
        _compile_notice["progress"] = None
        if self.bar is not None:
            self.bar.stop()


# The files railwear writes besides result.nc: how each is known, its figure's name, the function
# of railwear.plots that draws it. The commands that write them and 'railwear plot' share it.
_FILES = (
    (lambda ds: "growth_rate" in ds and "order" in ds.dims and "u" not in ds, "stability", "stability"),  # stability
    (lambda ds: "base_scenario_hash" in ds.attrs and "regime" in ds, "sweep", "sweep"),  # sweep
    (lambda ds: "crossing_distance" in ds and "horizon_km" in ds.attrs, "forecast", "forecast"),  # forecast
    (lambda ds: "critical_speed" in ds and "conicity" in ds.dims, "hunting", "hunting_map"),  # hunting-map
    (lambda ds: "amplitude" in ds and "hopf_speed" in ds.attrs, "bifurcation", "bifurcation"),  # simulate
    (lambda ds: "lateral_displacement" in ds, "hunting", "lateral_motion"),
    (lambda ds: "contact_angle" in ds and "frictional_power" in ds, "contact-path", "contact_path"),
    (lambda ds: "receptance_magnitude" in ds, "track", "track_receptance"),  # track
)


# The maintenance files (plan.nc, fleet.nc, load.nc): how each is known and the module of
# railwear.maintenance that draws its figures and writes its one-file report.
_MAINTENANCE = (
    ("plan.nc", lambda ds: "distance_to_scrap" in ds and "policy" in ds.dims, "outputs"),
    ("fleet.nc", lambda ds: "distance_to_action" in ds and "wheel" in ds.dims, "fleet"),
    ("load.nc", lambda ds: "peak_force" in ds and "detector" in ds.dims and "sample" in ds.dims, "impact"),
)


def _draw_maintenance(ds, result, directory, fmt, dpi):
    """The figures and the HTML report of a plan.nc, fleet.nc or load.nc; None for another file.
    A file of the kind that lacks what its figures read is refused in one line naming it."""
    import importlib

    for name, known, module in _MAINTENANCE:
        if known(ds):
            make = importlib.import_module(f"railwear.maintenance.{module}")
            try:
                paths = make.draw_figures(ds, directory, fmt, dpi)
                return paths + [make.html_report(ds, Path(directory) / make.HTML, paths)]
            except (KeyError, AttributeError, IndexError) as e:
                missing = e.args[0] if isinstance(e, KeyError) and e.args else e
                _fail(f"{result}: looks like a {name} of railwear but cannot be drawn: {missing} is missing or broken", 2)
    return None


def _draw(ds, directory, fmt="png", dpi=120):
    """Save the figure of a file railwear wrote (not result.nc) in ``directory``; returns the
    paths (none for a sweep of which no point ran, or for a file of no known kind)."""
    from railwear import plots

    for known, name, make in _FILES:
        if known(ds):
            if name == "sweep" and not bool((ds.error == "").any()):
                return []  # a figure of no point at all would be empty
            return [plots.save(getattr(plots, make)(ds), Path(directory) / f"{name}.png", fmt, dpi)]
    return []


def _run_failed(error, output):
    """Exit 1 for a run that failed (a :class:`NumericalInstabilityError`), keeping its last good
    state as ``output/last_good_state.npy`` where it has one."""
    from railwear import results

    kept = ""
    if error.last_good is not None:
        results.write_array(error.last_good, output / "last_good_state.npy")
        kept = f"; the last good state (T = {error.last_time:.4g}) is in {output / 'last_good_state.npy'}"
    _fail(f"{error}{kept}", 1)


def _run_and_write(scenario, output, figures, checkpoint_every, resume_path=None, sets=(), fmt="png", dpi=120,
                   unsets=()):
    from railwear import api, plots, report, results

    checkpoint = _output(output) / "checkpoint.npz"
    try:
        sc = None if scenario is None and resume_path is not None else api.load_scenario(scenario, sets, unsets)
        # forked once the scenario is read, they import matplotlib while this process runs, then draw
        # while it writes result.nc
        drawers = plots.fork_drawers() if figures and _state["own_process"] else None
        label = f"railwear {sc.name if sc else 'resume'}"
        with _Warnings() as warned, _Progress(label) as progress:
            if resume_path is None and checkpoint.exists():  # an earlier run's: only the newest resumes
                checkpoint.unlink()
            ds = api.run(sc, progress=progress, checkpoint_path=checkpoint,
                         checkpoint_every=checkpoint_every, resume_path=resume_path)
    except ScenarioError as e:
        _fail(str(e), 2)
    except NumericalInstabilityError as e:
        _run_failed(e, output)
    if drawers is not None:
        drawers.send(ds, output, fmt, dpi)
    results.write_netcdf(ds, output / "result.nc")
    checkpoint.unlink(missing_ok=True)
    summary = results.write_summary(ds, output)
    paths = (drawers.wait() if drawers is not None else plots.write_figures(ds, output, fmt, dpi)) if figures else []
    report.write_report(ds, output / report.NAME, paths, warned.caught, _compile_notice["compiled"])
    typer.echo(results.summary_text(summary), nl=False)
    typer.echo(f"wrote {output / 'result.nc'}")


Sets = Annotated[list[str], typer.Option(
    "--set", metavar="FIELD=VALUE",
    help="set a scenario field, e.g. operation.speed_kmh=180 or strategy.kind=stepwise; the value is "
         "read as TOML (180, \"x\", [1, 2], true; a bare word is text); repeat for more")]


Unsets = Annotated[list[str], typer.Option(
    "--unset", metavar="FIELD",
    help="remove a scenario field or section as if the file had not given it, so it takes its default "
         "(track.ballast_stiffness_MN_m; track); applied before --set; repeat for more")]


def _scenario(scenario, sets, unsets=()):
    """The scenario (file or built-in name) with the ``--set`` and ``--unset`` fields, or None with none."""
    from railwear.scenario import load_scenario

    return scenario if not sets and not unsets else load_scenario(scenario, sets, unsets)


CheckpointEvery = Annotated[float, typer.Option(
    help="seconds of wall time between checkpoints (DIR/checkpoint.npz); 0 saves every output interval")]


@app.command()
def run(
    scenario: Annotated[Optional[str], typer.Argument(help="scenario file or built-in name")] = None,
    output: Annotated[Path, typer.Option("-o", "--output", help="output directory")] = Path("railwear-out"),
    figures: Annotated[bool, typer.Option(help="write the figures as PNG")] = True,
    checkpoint_every: CheckpointEvery = 30.0,
    sets: Sets = [],
    unsets: Unsets = [],
    fmt: Format = "png",
    dpi: Dpi = 120,
):
    """Run a scenario; write DIR/result.nc, summary.txt, summary.json and figures."""
    _option(checkpoint_every, "--checkpoint-every", 0, 1e9)
    _figure_options(fmt, dpi)
    _run_and_write(scenario, output, figures, checkpoint_every, sets=sets, fmt=fmt, dpi=dpi, unsets=unsets)


@app.command()
def resume(
    directory: Annotated[Path, typer.Argument(help="output directory of a run that was stopped")],
    figures: Annotated[bool, typer.Option(help="write the figures as PNG")] = True,
    checkpoint_every: CheckpointEvery = 30.0,
    fmt: Format = "png",
    dpi: Dpi = 120,
):
    """Continue a stopped run from DIR/checkpoint.npz to the same result as an uninterrupted run."""
    _option(checkpoint_every, "--checkpoint-every", 0, 1e9)
    _figure_options(fmt, dpi)
    path = _output(directory) / "checkpoint.npz"
    if not path.is_file():
        _fail(f"no checkpoint in {directory} (expected {path.name})", 2)
    _run_and_write(None, directory, figures, checkpoint_every, resume_path=path, fmt=fmt, dpi=dpi)


@app.command()
def plot(
    result: Annotated[Path, typer.Argument(help="a file railwear wrote: result.nc, stability.nc, sweep.nc, "
                                                "forecast.nc, hunting.nc, dynamics.nc, plan.nc, fleet.nc or load.nc")],
    output: Annotated[Optional[Path], typer.Option("-o", "--output", help="directory (default: beside RESULT)")] = None,
    fmt: Format = "png",
    dpi: Dpi = 120,
):
    """Draw the figures again from a file railwear wrote."""
    from railwear import plots, results

    _figure_options(fmt, dpi)
    if not result.is_file():
        _fail(f"result file {result} does not exist", 2)
    directory = _output(output or result.parent)
    try:
        ds = results.read_netcdf(result)
    except (OSError, ValueError) as e:
        _fail(f"{result} is not a railwear result: {e}", 2)
    maintenance = _draw_maintenance(ds, result, directory, fmt, dpi)
    if maintenance is not None:
        paths = maintenance
    elif any(known(ds) for known, _, _ in _FILES):
        try:
            paths = _draw(ds, directory, fmt, dpi)
        except ScenarioError as e:
            _fail(f"{result}: {e}", 2)
        if not paths:  # a sweep of which every point failed: a failed run railwear recorded, not bad input
            _fail(f"{result}: no point of the sweep ran: every point failed (the first: "
                  f"{ds.error.values.flat[0]}); nothing to draw", 1)
    else:
        from railwear.longterm.base import check_result

        try:
            check_result(ds)
        except ValueError as e:
            _fail(f"{result} is not a railwear result ({e}; railwear plot draws result.nc, stability.nc, sweep.nc, "
                  "forecast.nc, hunting.nc, dynamics.nc, track.nc, plan.nc, fleet.nc and load.nc)", 2)
        from railwear import report

        paths = plots.write_figures(ds, directory, fmt, dpi)
        paths.append(report.write_report(ds, directory / report.NAME, paths, warnings_known=False))
    for path in paths:
        typer.echo(f"wrote {path}")


@app.command()
def stability(
    scenario: Annotated[Optional[str], typer.Argument(help="scenario file or built-in name")] = None,
    speeds: Annotated[str, typer.Option(help="speeds in km/h, A:B:STEP or v1,v2,...")] = "20:300:10",
    orders: Annotated[str, typer.Option(help="polygon orders, A:B:STEP or list")] = "1:30:1",
    amplitude_um: Annotated[Optional[float], typer.Option(help="crest amplitude (µm) for the evolution equation; default the scenario's initial rms, 0 for the round wheel")] = None,
    output: Annotated[Path, typer.Option("-o", "--output")] = Path("railwear-out"),
    sets: Sets = [],
    unsets: Unsets = [],
    fmt: Format = "png",
    dpi: Dpi = 120,
):
    """Growth rate over speed x polygon order: DIR/stability.nc and stability.png.

    From the evolution equation's dispersion relation, or, for a scenario with the Fourier
    strategy, from the disk wheel's transfer functions (per km run).
    """
    from railwear import analysis, api, results
    from railwear.units import UM, m_s_to_kmh

    v = _parse_range(speeds, "--speeds")
    n = _parse_range(orders, "--orders")
    if v.min() <= 0 or n.min() < 1:
        _fail("--speeds must be > 0 and --orders >= 1", 2)
    _option(amplitude_um, "--amplitude-um", 0, 1e4)
    _figure_options(fmt, dpi)
    _output(output)
    try:
        sc = api.load_scenario(scenario, sets, unsets)
        ds = analysis.stability(sc, v, n, None if amplitude_um is None else amplitude_um * UM)
        ds.attrs.update(_map_marks(sc))
    except ScenarioError as e:
        _fail(str(e), 2)
    label = ds.attrs["source"]
    results.write_netcdf(ds, output / "stability.nc")
    _draw(ds, output, fmt, dpi)
    unstable = ds.growth_rate.max("order") > 0
    if bool(unstable.any()):
        first = m_s_to_kmh(float(ds.speed.values[unstable.values.argmax()]))
        typer.echo(f"growth from {first:g} km/h ({label})")
    else:
        typer.echo(f"no order grows in {v.min():g}-{v.max():g} km/h ({label})")
    typer.echo(f"wrote {output / 'stability.nc'}")


def _map_marks(sc):
    """What a stability map draws over the growth: the scenario's speed (km/h) and wheel diameter
    (m), and for a wheel on a track the P2 frequency and the wheelset modes' (Hz), whose orders
    ``n = f π D / V`` the map draws over the speed; the normed life (km), by which a map per unit
    normed time is drawn per 10 000 km."""
    from railwear.units import m_s_to_kmh

    marks = {"wheel_diameter_m": 2 * sc.wheel.radius_m, "life_distance_km": sc.operation.life_distance_km}
    if isinstance(sc.operation.speeds, float):
        marks["run_speed_kmh"] = round(m_s_to_kmh(sc.operation.speeds), 6)
    if "track" in sc.body.sections:
        from railwear.longterm.vehicle_track import VehicleTrackModel, p2_frequency
        from railwear.scenario import build

        case = sc.body.case(sc)
        model = VehicleTrackModel(case.wheel(build.one_speed(sc)), case.track, sc.track.bay_positions, case.wheel_modes)
        marks["p2_frequency_hz"] = float(p2_frequency(model))
        if case.wheel_modes:
            marks["wheel_mode_frequencies_hz"] = [float(m[0]) for m in case.wheel_modes]
    return marks


@app.command()
def track(
    scenario: Annotated[Optional[str], typer.Argument(help="scenario file or built-in name with body 'vehicle_track'")] = None,
    frequencies: Annotated[str, typer.Option(help="frequencies in Hz, A:B:STEP or list; default 10-3000 Hz, log-spaced")] = "",
    output: Annotated[Path, typer.Option("-o", "--output")] = Path("railwear-out"),
    sets: Sets = [],
    unsets: Unsets = [],
    fmt: Format = "png",
    dpi: Dpi = 120,
):
    """Rail receptance of the scenario's [track] and the wheel's |N/u| on it: DIR/track.nc and
    track.png, with the P2 and pinned-pinned frequencies marked."""
    from railwear import analysis, results

    f = _parse_range(frequencies, "--frequencies") if frequencies else None
    _figure_options(fmt, dpi)
    _output(output)
    try:
        ds = analysis.track_receptance(_scenario(scenario, sets, unsets), f)
    except ScenarioError as e:
        _fail(str(e), 2)
    results.write_netcdf(ds, output / "track.nc")
    _draw(ds, output, fmt, dpi)
    pinned = (f", pinned-pinned {float(ds.pinned_pinned_frequency):.0f} Hz" if "pinned_pinned_frequency" in ds else "")
    typer.echo(f"P2 {float(ds.p2_frequency):.1f} Hz{pinned} ({ds.attrs['track']})")
    typer.echo(f"wrote {output / 'track.nc'}")


def _executor(workers, scheduler, scheduler_file):
    """The sweep's executor the options ask for: a Dask cluster, local worker processes, or None
    (the command's own default)."""
    from railwear import sweep as sweeps

    if scheduler or scheduler_file:
        try:
            return sweeps.DaskExecutor(scheduler, scheduler_file)
        except ImportError:
            _fail("--scheduler needs Dask: pip install 'railwear[cluster]'", 2)
        except OSError as e:
            _fail(f"--scheduler: cannot reach the Dask scheduler: {e}", 2)
    if workers is not None:
        if workers < 1:
            _fail("--workers must be at least 1", 2)
        return sweeps.LocalExecutor(workers)
    return None


@app.command()
def sweep(
    scenario: Annotated[Optional[str], typer.Argument(help="scenario file or built-in name")] = None,
    vary: Annotated[list[str], typer.Option(help="NAME=A:B:STEP or NAME=v1,v2,... (a dotted scenario field), "
                                                 "or NAME=A:B with --samples; repeat for more")] = [],
    samples: Annotated[Optional[int], typer.Option(help="Latin hypercube of N points over the --vary ranges "
                                                        "(A:B needs no STEP) instead of the grid")] = None,
    seed: Annotated[int, typer.Option(help="seed of the random design")] = 0,
    output: Annotated[Path, typer.Option("-o", "--output", help="sweep store directory")] = Path("railwear-sweep"),
    workers: Annotated[Optional[int], typer.Option(help="local worker processes (default: all cores)")] = None,
    scheduler: Annotated[Optional[str], typer.Option(help="Dask scheduler address, tcp://HOST:PORT")] = None,
    scheduler_file: Annotated[Optional[Path], typer.Option(help="Dask scheduler file")] = None,
    batch: Annotated[bool, typer.Option(help="run a grid over the speed alone as one batched solve")] = True,
    sets: Sets = [],
    unsets: Unsets = [],
    fmt: Format = "png",
    dpi: Dpi = 120,
):
    """Run a scenario over a grid or sample of fields; DIR/sweep.nc, DIR/points/, sweep.png."""
    from railwear import api, sweep as sweeps

    _figure_options(fmt, dpi)
    if not vary:
        _fail("--vary: give at least one NAME=A:B:STEP", 2)
    try:
        _output(output)
        base = api.load_scenario(scenario, sets, unsets)
        varies = [sweeps.parse_vary(v) for v in vary]
        for assignment in sweeps.design(varies, samples, seed)[1][:1]:
            sweeps._assign(base, assignment)  # a field that is none fails here, before any worker starts
        executor = _executor(workers, scheduler, scheduler_file)
        with _Warnings(), _Progress(f"railwear sweep {base.name}") as progress:
            ds = sweeps.run_sweep(base, varies, output, samples, seed, executor, progress,
                                  batch="auto" if batch else False)
        if executor is not None:
            executor.close()
    except ScenarioError as e:
        _fail(str(e), 2)
    failed = int((ds.error != "").sum())
    if not _draw(ds, output, fmt, dpi):  # no point ran: an earlier sweep's figure here is not this one's
        from railwear.plots import FORMATS

        for suffix in FORMATS:
            (output / f"sweep.{suffix}").unlink(missing_ok=True)
    _print_sweep_table(ds)
    typer.echo(f"wrote {output / 'sweep.nc'}" + (f"; {failed} point(s) failed, see the error variable" if failed else ""))
    if failed == ds.error.size:  # a point refused by validation counts too: none ran, so the run failed
        _fail(f"every point of the sweep failed, so there is no figure; the first: {ds.error.values.flat[0]}", 1)


def _print_sweep_table(ds):
    """The sweep as a table: per point the regime, the dominant order and maxima at the end, the
    distance to the out-of-roundness limit (km; 'beyond' the distance run where the run did not
    reach it), the dominant order's growth per 10 000 km and the depth removed; the peak-to-peak
    ratio over the run where the scenario sets no limit."""
    import numpy as np
    from rich.console import Console
    from rich.table import Table

    from railwear.results import daily_distance_km, percent
    from railwear.units import MM

    fields = [c for c in ds.coords if c != "angle"]
    limit = "limit_distance" in ds
    head = [*fields, "regime", "order", "maxima"]
    if limit:
        head.append(f"to {float(ds.peak_to_peak_limit) / MM:g} mm p-p (km)" if "peak_to_peak_limit" in ds
                    else "to the limit (km)")
    if "limit_months" in ds:
        head.append(f"months at {daily_distance_km(ds) or 0:g} km/day")
    if "dominant_growth_per_10000_km" in ds:
        head.append("growth / 10 000 km")
    head.append("depth (mm)")
    if not limit:
        head.append("p-p end/start")
    table = Table(*head)
    flat = ds.drop_vars("u_final", errors="ignore").stack(point=list(ds.regime.dims)) if ds.regime.ndim > 1 else ds
    for i in range(flat.regime.size):
        p = flat.isel({flat.regime.dims[0]: i})
        ran = str(p.regime.values) != "failed"
        row = [*(f"{float(p[f]):g}" for f in fields), str(p.regime.values)]
        row += [f"{int(p.dominant_order)}" if ran else "-", f"{int(p.maxima)}" if ran else "-"]
        if limit:
            km = float(p.limit_distance)
            row.append(f"{km:,.0f}" if np.isfinite(km) else
                       f"beyond {float(p.distance_run):,.0f}" if ran and "distance_run" in p else "-")
        if "limit_months" in ds:
            row.append(f"{float(p.limit_months):.1f}" if np.isfinite(float(p.limit_months)) else "-")
        if "dominant_growth_per_10000_km" in ds:
            g = float(p.dominant_growth_per_10000_km)
            row.append(percent(g / 100) if np.isfinite(g) else ("undefined" if ran else "-"))
        row.append(f"{float(p.max_removed_depth) / MM:.3f}" if ran else "-")
        if not limit:
            start = float(p.peak_to_peak_initial)
            row.append(f"{float(p.peak_to_peak) / start:.2f}" if ran and start else "-")
        table.add_row(*row)
    Console(width=140).print(table)


@app.command()
def forecast(
    measured: Annotated[Path, typer.Argument(help="CSV of angle and radius deviation round the wheel")],
    scenario: Annotated[Optional[str], typer.Option(help="scenario file or built-in name: physics and [service] scatter")] = None,
    limit: Annotated[str, typer.Option(help="out-of-roundness limit: peak to peak with its unit (0.3mm), one level for "
                                            "every order (20dB, re 1 um), iso3095 (band levels), or a CSV table: "
                                            "order,level_db or wavelength_mm,level_db")] = "0.3mm",
    samples: Annotated[Optional[int], typer.Option(help="Monte Carlo samples (default: the scenario's service.samples)")] = None,
    seed: Annotated[Optional[int], typer.Option(help="seed (default: the scenario's service.seed)")] = None,
    horizon_km: Annotated[Optional[float], typer.Option(help="distance to look ahead (default: the scenario's life times solver.t_end)")] = None,
    angle_unit: Annotated[Optional[str], typer.Option(help="deg or rad, for a column named just 'angle'")] = None,
    deviation_unit: Annotated[Optional[str], typer.Option(help="um, mm or m, for a column named just 'deviation'")] = None,
    nominal_diameter: Annotated[Optional[str], typer.Option(help="nominal wheel diameter with its unit (840mm), for a "
                                                                 "file of absolute radius_* or diameter_* columns")] = None,
    output: Annotated[Path, typer.Option("-o", "--output")] = Path("railwear-forecast"),
    sets: Sets = [],
    unsets: Unsets = [],
    fmt: Format = "png",
    dpi: Dpi = 120,
):
    """When does this measured wheel pass its out-of-roundness limit? Median and 90 % band."""
    from railwear import forecast as forecasts
    from railwear import results

    _option(horizon_km, "--horizon-km", 0, 1e9, low_open=True)
    _figure_options(fmt, dpi)
    try:
        limits = forecasts.parse_limit(limit, "--limit")
        nominal = None if nominal_diameter is None else forecasts.parse_length(nominal_diameter, "--nominal-diameter", 4.0)
        _output(output)
        with _Warnings(), _Progress("railwear forecast") as progress:
            ds = forecasts.forecast_file(measured, _scenario(scenario, sets, unsets), limits, samples, seed, horizon_km,
                                         angle_unit, deviation_unit, progress=progress, nominal_diameter=nominal)
    except ScenarioError as e:
        _fail(str(e), 2)
    except NumericalInstabilityError as e:
        _run_failed(e, output)
    results.write_netcdf(ds, output / "forecast.nc")
    _draw(ds, output, fmt, dpi)
    text = forecasts.report(ds)
    results.write_text(text, output / "forecast.txt")
    typer.echo(text, nl=False)
    typer.echo(f"wrote {output / 'forecast.nc'}")


@app.command("plan")
def plan_policies(
    scenario: Annotated[Optional[str], typer.Argument(help="scenario file or built-in name whose body gives a "
                                                           "linear model (the Fourier technique; default metro) or "
                                                           "simulates the lateral profile (wheelset)")] = None,
    policy: Annotated[list[str], typer.Option("--policy", help="policy TOML file or built-in name (metro-interval, "
                                                               "metro-condition, metro-noise, wheelset-flange); repeat "
                                                               "to compare")] = [],
    samples: Annotated[int, typer.Option(help="wheels drawn from the scenario's [service] besides wheel 0 "
                                              "(0: the one wheel of the scenario's conditions)")] = 0,
    seed: Annotated[Optional[int], typer.Option(help="seed of the draw (default: the scenario's service.seed)")] = None,
    growth: Annotated[str, typer.Option(help="multipliers on the polygon growth rates, v1,v2,... or A:B:STEP "
                                             "(no field growth rate of a polygon is published)")] = "0.5,1,2",
    horizon_km: Annotated[float, typer.Option(help="a life not scrapped by then ends there, not scrapped")] = 1e7,
    output: Annotated[Path, typer.Option("-o", "--output")] = Path("railwear-plan"),
    figures: Annotated[bool, typer.Option(help="write the figure as PNG")] = True,
    checkpoint_every: Annotated[float, typer.Option(
        help="seconds of wall time between checkpoints of the finished lives (DIR/plan-checkpoint.npz)")] = 30.0,
    resume: Annotated[bool, typer.Option(help="keep the lives of DIR/plan-checkpoint.npz, written by a stopped run "
                                              "of the same plan, and run the rest")] = False,
    sets: Sets = [],
    fmt: Format = "png",
    dpi: Dpi = 120,
):
    """A wheel's life to scrap under maintenance policies: turnings, distance to scrap, km per mm of
    diameter; DIR/plan.nc, plan.txt, plan.csv, turnings.csv, plan.png."""
    from railwear.checkpoints import Periodic
    from railwear.maintenance import outputs
    from railwear.maintenance import plan as planning
    from railwear.maintenance.plan import plan

    _option(horizon_km, "--horizon-km", 1e3, 1e8)
    _option(checkpoint_every, "--checkpoint-every", 0, 1e9)
    _figure_options(fmt, dpi)
    if not policy:
        _fail("--policy: give at least one policy file or built-in name (metro-interval, metro-condition, metro-noise)", 2)
    multipliers = _parse_range(growth, "--growth")
    try:
        path = _output(output) / planning.CHECKPOINT
        if resume and not path.is_file():
            _fail(f"--resume: no plan checkpoint in {output} (expected {path.name})", 2)
        stopped = planning.read_checkpoint(path) if resume else None
        if not resume:
            path.unlink(missing_ok=True)  # an earlier run's: only the newest resumes
        save = Periodic(lambda state: planning.write_checkpoint(state, path), checkpoint_every)
        with _Warnings(), _Progress("railwear plan") as progress:
            ds = plan(_scenario(scenario, sets), policy, samples, seed, multipliers, horizon_km, progress=progress,
                      checkpoint=save, resume=stopped)
    except ScenarioError as e:
        _fail(str(e), 2)
    except NumericalInstabilityError as e:
        _run_failed(e, output)
    paths = outputs.write(ds, output, fmt, dpi, figures)
    path.unlink(missing_ok=True)
    typer.echo(outputs.report(ds), nl=False)
    typer.echo(f"wrote {', '.join(str(p) for p in paths)}")


@app.command("load")
def wheel_load(
    scenario: Annotated[Optional[str], typer.Argument(help="scenario file or built-in name with a vehicle_track body "
                                                           "(default metro)")] = None,
    wheel: Annotated[Optional[Path], typer.Option("--wheel", help="a measured wheel: CSV of angle and radius deviation "
                                                                  "(as railwear forecast reads it)")] = None,
    result: Annotated[Optional[Path], typer.Option("--result", help="a result.nc of railwear run: its wheel at the end "
                                                                    "of the run (default: the scenario's [initial] wheel)")] = None,
    speeds: Annotated[str, typer.Option(help="speeds in km/h, A:B:STEP or v1,v2,...")] = "40:120:10",
    revolutions: Annotated[int, typer.Option(help="wheel revolutions recorded at each speed (1 to 1000)")] = 8,
    transient_s: Annotated[float, typer.Option(help="seconds run before the record, whole revolutions (0 to 60)")] = 1.0,
    angle_unit: Annotated[Optional[str], typer.Option(help="deg or rad, for a column named just 'angle'")] = None,
    deviation_unit: Annotated[Optional[str], typer.Option(help="um, mm or m, for a column named just 'deviation'")] = None,
    nominal_diameter: Annotated[Optional[str], typer.Option(help="nominal wheel diameter with its unit (840mm), for a "
                                                                 "file of absolute radius_* or diameter_* columns")] = None,
    output: Annotated[Path, typer.Option("-o", "--output")] = Path("railwear-load"),
    figures: Annotated[bool, typer.Option(help="write the figures as PNG")] = True,
    sets: Sets = [],
    unsets: Unsets = [],
    fmt: Format = "png",
    dpi: Dpi = 120,
):
    """The vertical wheel-rail force a wheel-impact-load detector sees: peak, least force, contact
    loss and spectrum per speed on the time-domain track, against published detector thresholds;
    with body.wheel_positions_m (a bogie, a car) the peak at each wheel, the shaped one leading and
    the others round; DIR/load.nc, load.txt, load.csv, load-peak.png, load-trace.png."""
    from railwear.maintenance import impact

    v = _parse_range(speeds, "--speeds")
    low, high = impact.SPEED_KMH
    if v.size > 100 or not all(low <= x <= high for x in v):
        _fail(f"--speeds must be 1 to 100 speeds in [{low:g}, {high:g}] km/h, got {speeds}", 2)
    _option(revolutions, "--revolutions", 1, 1000)
    _option(transient_s, "--transient-s", 0, 60)
    _figure_options(fmt, dpi)
    try:
        nominal = None
        if nominal_diameter is not None:
            from railwear.forecast import parse_length

            nominal = parse_length(nominal_diameter, "--nominal-diameter", 4.0)
        _output(output)
        with _Warnings(), _Progress("railwear load") as progress:
            ds = impact.wheel_load(_scenario(scenario, sets, unsets), v, wheel, result, revolutions, transient_s,
                                   angle_unit, deviation_unit, nominal, progress=progress)
    except ScenarioError as e:
        _fail(str(e), 2)
    paths = impact.write(ds, output, fmt, dpi, figures)
    typer.echo(impact.report(ds), nl=False)
    typer.echo(f"wrote {', '.join(str(p) for p in paths)}")


@app.command("fleet")
def fleet_forecast(
    scenario: Annotated[str, typer.Argument(help="scenario file or built-in name whose body gives a linear model "
                                                 "(the Fourier technique), e.g. metro")],
    fleet: Annotated[str, typer.Argument(help="the fleet's manifest CSV (one row per measured line: wheel_id, car, "
                                              "axle, side, diameter_mm, mileage_km, date, file; docs/maintenance.md), "
                                              "or the built-in example-fleet")],
    policy: Annotated[str, typer.Option(help="policy TOML file or built-in name (metro-interval, metro-condition, "
                                             "metro-noise)")] = "metro-condition",
    daily_km: Annotated[float, typer.Option(help="km a wheel runs a day: the action's date")] = 500.0,
    growth: Annotated[str, typer.Option(help="multipliers on the polygon growth rates, v1,v2,... or A:B:STEP: the band "
                                             "of each distance (no field growth rate of a polygon is published)")] = "0.5,1,2",
    horizon_km: Annotated[float, typer.Option(help="look this far ahead of each measurement")] = 1e6,
    diameter_step_mm: Annotated[float, typer.Option(help="rate tables every this many mm of diameter, interpolated "
                                                         "between")] = 5.0,
    workers: Annotated[Optional[int], typer.Option(help="local worker processes (default: none, this process)")] = None,
    scheduler: Annotated[Optional[str], typer.Option(help="Dask scheduler address, tcp://HOST:PORT")] = None,
    scheduler_file: Annotated[Optional[Path], typer.Option(help="Dask scheduler file")] = None,
    load_speeds: Annotated[Optional[str], typer.Option(help="speeds in km/h (A:B:STEP or v1,v2,...): each wheel's "
                                                            "peak force now and when it passes each detector threshold")] = None,
    load_threshold_kn: Annotated[list[float], typer.Option(help="a detector threshold of your own (kN) besides the "
                                                                "published ones; repeat for more")] = [],
    output: Annotated[Path, typer.Option("-o", "--output")] = Path("railwear-fleet"),
    figures: Annotated[bool, typer.Option(help="write the figures as PNG")] = True,
    sets: Sets = [],
    fmt: Format = "png",
    dpi: Dpi = 120,
):
    """A fleet of measured wheels under a maintenance policy: per wheel its state now, the distance to
    each trigger with its band, the action and its date; DIR/fleet.nc, fleet.txt, wheels.csv, fleet-*.png,
    fleet.html."""
    from railwear.maintenance import fleet as fleets

    _option(daily_km, "--daily-km", 1, 1e5)
    _option(horizon_km, "--horizon-km", 1e3, 1e8)
    _option(diameter_step_mm, "--diameter-step-mm", 0.1, 100)
    _figure_options(fmt, dpi)
    multipliers = _parse_range(growth, "--growth")
    load_kmh = None if load_speeds is None else _parse_range(load_speeds, "--load-speeds")
    executor = None
    try:
        detectors = fleets.detectors_with(load_threshold_kn) if load_threshold_kn else None
        _output(output)
        sc = _scenario(scenario, sets)
        executor = _executor(workers, scheduler, scheduler_file)
        with _Warnings(), _Progress("railwear fleet") as progress:
            ds = fleets.fleet(sc, fleet, policy, daily_km, multipliers, horizon_km, diameter_step_mm,
                              executor=executor, progress=progress, load_speeds_kmh=load_kmh, detectors=detectors)
    except ScenarioError as e:
        _fail(str(e), 2)
    finally:
        if executor is not None:
            executor.close()
    paths = fleets.write(ds, output, fmt, dpi, figures)
    typer.echo(fleets.report(ds), nl=False)
    typer.echo(f"wrote {', '.join(str(p) for p in paths)}")


@app.command("hunting-map")
def hunting_map(
    scenario: Annotated[Optional[str], typer.Argument(help="scenario file or built-in name ([wheelset], [wheel], [contact])")] = None,
    conicity: Annotated[str, typer.Option(help="conicities, A:B:STEP or list")] = "0.02:0.4:0.02",
    yaw_stiffness: Annotated[str, typer.Option(help="yaw stiffnesses in N m/rad, A:B:STEP or list")] = "1e5:2e7:5e5",
    output: Annotated[Path, typer.Option("-o", "--output")] = Path("railwear-out"),
    fmt: Format = "png",
    dpi: Dpi = 120,
):
    """Hunting critical speed of the wheelset over conicity x yaw stiffness: DIR/hunting.nc, hunting.png."""
    import numpy as np

    from railwear import api, results
    from railwear import sweep as sweeps

    lam = _parse_range(conicity, "--conicity")
    kpsi = _parse_range(yaw_stiffness, "--yaw-stiffness")
    _figure_options(fmt, dpi)
    _output(output)
    try:
        ds = sweeps.hunting_map(api.load_scenario(scenario), lam, kpsi)
    except ScenarioError as e:
        _fail(str(e), 2)
    results.write_netcdf(ds, output / "hunting.nc")
    _draw(ds, output, fmt, dpi)
    v = ds.critical_speed_kmh.values
    low = np.unravel_index(np.argmin(v), v.shape)
    typer.echo(f"lowest critical speed {v[low]:.0f} km/h at conicity {lam[low[0]]:g}, "
               f"yaw stiffness {kpsi[low[1]]:g} N m/rad; stable at every speed at {np.isinf(v).sum()} of {v.size} points")
    typer.echo(f"wrote {output / 'hunting.nc'}")


@app.command()
def simulate(
    scenario: Annotated[str, typer.Argument(help="dynamics scenario file or built-in name (railwear scenarios)")],
    output: Annotated[Path, typer.Option("-o", "--output")] = Path("railwear-dynamics"),
    fmt: Format = "png",
    dpi: Dpi = 120,
):
    """Run a short-time dynamics scenario: DIR/dynamics.nc and its figure (paper Figs 1-3, bifurcation)."""
    from railwear import api, results
    from railwear.scenario import dynamics
    from railwear.units import m_s_to_kmh

    _figure_options(fmt, dpi)
    _output(output)
    try:
        sc = dynamics.load_dynamics_scenario(scenario)
        with _Warnings(), _Progress(f"railwear simulate {sc.name}") as progress:
            ds = api.simulate(sc, progress=progress)
    except ScenarioError as e:
        _fail(str(e), 2)
    except NumericalInstabilityError as e:
        _fail(str(e), 1)
    results.write_netcdf(ds, output / "dynamics.nc")
    (figure,) = _draw(ds, output, fmt, dpi)
    for key in ("linear_critical_speed_kmh",):
        if key in ds.attrs:
            typer.echo(f"linear critical speed {ds.attrs[key]:.1f} km/h")
    if "hopf_speed" in ds.attrs:
        typer.echo(f"Hopf point {m_s_to_kmh(ds.attrs['hopf_speed']):.1f} km/h, nonlinear critical speed "
                   f"{m_s_to_kmh(ds.attrs['nonlinear_critical_speed']):.1f} km/h")
        published = dynamics.published_hopf(sc)
        if published is not None:
            typer.echo(published_hopf_line(ds.attrs["hopf_speed"], *published))
    typer.echo(f"wrote {output / 'dynamics.nc'} and {figure}")


def published_hopf_line(hopf, published, source):
    """The line that says a model's Hopf point (m/s) is not the published one."""
    from railwear.units import m_s_to_kmh

    return (f"  not the published bogie's: its Hopf point is {m_s_to_kmh(published):.1f} km/h ({published:g} m/s; "
            f"{source}), and this model's is {abs(1 - hopf / published):.0%} {'lower' if hopf < published else 'higher'}: "
            "not reproduced (docs/dynamics.md, 'The published Cooperrider bogie')")


@app.command()
def figure(
    name: Annotated[str, typer.Argument(help="wear-surface (paper Fig. 4), teeth (Fig. 7) or fitted-h (Fig. 8)")],
    scenario: Annotated[Optional[str], typer.Argument(help="a disk-wheel scenario (default: the built-in 'stepwise')")] = None,
    output: Annotated[Path, typer.Option("-o", "--output")] = Path("railwear-figures"),
    fmt: Format = "png",
    dpi: Dpi = 120,
):
    """One of the paper's frozen-geometry figures from a disk-wheel scenario ([body] kind = "disk_wheel", [initial])."""
    from railwear import analysis, plots

    _figure_options(fmt, dpi)
    _output(output)
    try:
        fig = analysis.figure(name, scenario).figure
    except ScenarioError as e:
        _fail(str(e), 2)
    except NumericalInstabilityError as e:
        _fail(str(e), 1)
    path = plots.save(fig, output / f"{name}.png", fmt, dpi)
    typer.echo(f"wrote {path}")


@app.command()
def fit(
    scenario: Annotated[Optional[str], typer.Argument(help="a disk-wheel scenario (default: the built-in 'stepwise')")] = None,
    speeds: Annotated[Optional[str], typer.Option(help="speeds in km/h, A:B:STEP or list (default: the [service] peaks)")] = None,
    output: Annotated[Path, typer.Option("-o", "--output")] = Path("railwear-fit"),
    fmt: Format = "png",
    dpi: Dpi = 120,
):
    """Strategy 4: fit h(u_xx, v) to frozen-geometry statistics (paper Fig. 8) and write it as a
    scenario with the table form: DIR/fitted-h.toml (run it with 'railwear run') and fitted-h.png."""
    from railwear import analysis, plots, results
    from railwear.scenario import to_toml
    from railwear.units import m_s_to_kmh

    v = None if speeds is None else _parse_range(speeds, "--speeds")
    _figure_options(fmt, dpi)
    _output(output)
    try:
        stats, fitted, out = analysis.fit(scenario, v)
    except ScenarioError as e:
        _fail(str(e), 2)
    except NumericalInstabilityError as e:
        _fail(str(e), 1)
    results.write_text(to_toml(out), output / "fitted-h.toml")
    figure = plots.save(plots.fitted_relation(stats, fitted), output / "fitted-h.png", fmt, dpi)
    for speed, chi2 in zip(stats.speed.values, fitted.chi2):
        typer.echo(f"{m_s_to_kmh(speed):g} km/h: reduced chi2 {chi2:.2f} on the curvature bins")
    typer.echo(f"wrote {output / 'fitted-h.toml'} and {figure}")


@app.command()
def scenarios():
    """List the built-in scenarios (long-term runs, then short-time dynamics for 'simulate')."""
    from railwear.scenario import DEFAULT, builtin_names, builtin_text, dynamics, parse_scenario, parse_toml, validated

    for name in builtin_names():  # the built-ins themselves, whatever the current folder holds
        sc = parse_scenario(builtin_text(name), source=name)
        mark = " (default)" if name == DEFAULT else ""
        typer.echo(f"{name}{mark}: {sc.description}")
    for name in dynamics.builtin_names():
        text = (dynamics._builtin_dir() / f"{name}.toml").read_text()
        sc = validated(dynamics.DynamicsScenario, parse_toml(text, name), name)
        typer.echo(f"{name} (railwear simulate): {sc.description}")


@app.command()
def show(name: Annotated[str, typer.Argument(help="built-in scenario name")]):
    """Print a built-in scenario as TOML, to start a file from."""
    from railwear.scenario import builtin_text, dynamics

    try:
        if name in dynamics.builtin_names():
            typer.echo((dynamics._builtin_dir() / f"{name}.toml").read_text(), nl=False)
            return
        typer.echo(builtin_text(name), nl=False)
    except ScenarioError as e:
        _fail(str(e), 2)


LOG = "railwear-error.log"


def main():
    """The ``railwear`` command. A bug (an exception railwear did not raise on purpose) is exit
    status 1 with its traceback in ``LOG`` in the output folder and a one-line pointer to it.
    The process ends without the interpreter's teardown (:func:`_exit`)."""
    _hide_dask(sys.argv[1:])
    _full_collections(False)
    _state["own_process"] = True
    try:
        _main()
    except SystemExit as e:
        _exit(e.code)
    _exit(0)


def _hide_dask(args):
    """Make dask invisible to a command that does not run on a Dask cluster (no ``--scheduler``
    or ``--scheduler-file``), as if it were not installed. Installed, xarray imports it (and
    asks it for its scheduler, which imports distributed) when it wraps an array and when it
    writes a file: 0.5-2 s a command, for arrays that are never dask's."""
    if "dask" not in sys.modules and not any(a.startswith("--scheduler") for a in args):
        sys.modules["dask"] = None  # what 'import dask' then finds: ImportError


def _full_collections(on):
    """Hold (``on`` False, from :func:`main`) or restore the garbage collector's full passes. A
    command's start imports numpy, scipy, xarray, numba and railwear: about half a million objects
    that live to its end, which each full pass walks again (0.1-0.2 s of a warm ``railwear run``).
    Held, only the young generations are collected; restored (at the start of the computation, the
    progress line's), what exists then is frozen out of every later pass and the usual thresholds
    return. A command without a progress line keeps them held to its end."""
    import gc

    if not on:
        _state["collector"] = gc.get_threshold()
        gc.set_threshold(*_state["collector"][:2], 1 << 30)
    elif "collector" in _state:  # only after main() held them, never in a test's process
        gc.freeze()
        gc.set_threshold(*_state.pop("collector"))


def _exit(code):
    """End the process with ``code`` (as ``sys.exit`` reads it) once the files are closed and the
    streams flushed, skipping the interpreter's teardown: freeing every module and object of
    numba, matplotlib, xarray and scipy took 0.9-1.8 s after the last file was written. The
    ``atexit`` functions still run. With another thread still going (the interpreter would wait
    for it), the usual exit."""
    import atexit
    import threading

    if threading.active_count() > 1 or not hasattr(atexit, "_run_exitfuncs"):
        sys.exit(code)
    if code is None:
        status = 0
    elif isinstance(code, int):
        status = code
    else:  # sys.exit("text"): the text on standard error, status 1
        print(code, file=sys.stderr)
        status = 1
    atexit._run_exitfuncs()
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except (OSError, ValueError):  # a closed pipe: nothing left to say
            pass
    os._exit(status & 0xFF)


def _main():
    try:
        app(prog_name="railwear")
    except RailwearError as e:  # anything a command did not map itself
        typer.echo(f"railwear: error: {' '.join(str(e).split())}", err=True)
        sys.exit(2 if isinstance(e, ScenarioError) else 1)
    except Exception as e:  # noqa: BLE001  (written down whole, not hidden)
        import traceback

        from railwear import results

        log = Path(_state["output"] or ".") / LOG
        results.write_text(traceback.format_exc(), log)
        typer.echo(f"railwear: internal error ({type(e).__name__}); please report it with {log}", err=True)
        sys.exit(1)
