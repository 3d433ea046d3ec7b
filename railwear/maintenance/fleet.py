"""``railwear fleet``: a fleet of measured wheels under a maintenance policy, on the Fourier technique
(layer 4; docs/maintenance.md, "Fleets").

Each measured line (:mod:`railwear.maintenance.fleet_input`) is put on the scenario's grid and
evolved exactly, order by order, as a life's segment of :mod:`railwear.maintenance.turning` is,
at the wheel's own diameter ``D``: ``û_n(s) = û_n(0) exp(g λ_n(D) s / V)``. The rates are built
once per diameter *node* (every ``diameter_step_mm``, default 5 mm, over the fleet's diameters)
and a wheel's rates are interpolated linearly between its two nodes, so a fleet of a thousand
wheels costs a dozen builds of the technique and FFTs.

For each line the distance to each trigger of the policy is found at growth 1 on a scan (every
``resolution_km`` up to 100 times that, then every 1 % of the distance) and located by bisection.
The triggers (peak to peak, level per order, band levels) ignore the mean radius, and a growth
multiplier ``g`` scales every rate of the polygon, so the polygon at ``s`` under ``g`` is the
polygon at ``g s`` under 1: the distance under ``g`` is the distance under 1 divided by ``g``,
exactly, and the band over the growth multipliers costs nothing more. An interval trigger counts
from the last turning; wear to the last-turning diameter goes at the unscaled mean rate. The
first of them is the action: a turning (with the cut the policy's rule takes from the polygon
there) or, when the cut would take the wheel below its last-turning diameter or wear takes it
there first, a replacement. A wheel with several lines is governed by the line that asks first.
"""

import datetime
from dataclasses import dataclass

import numpy as np
import xarray as xr

from railwear.errors import MeasuredFileError, OptionError
from railwear.geometry import roundness
from railwear.longterm.spectra import UNDEFINED
from railwear.maintenance.detectors import flag_batch
from railwear.maintenance.turning import evolve_batch
from railwear.maintenance.fleet_input import EXAMPLE, read_fleet
from railwear.maintenance.plan import GROWTH, WheelRates, _checked_growth, _policies, re_profiled
from railwear.maintenance.turning import BELOW, WORN, RateTable
from railwear.scenario import load_scenario, scenario_hash, to_toml
from railwear.units import KM, MM, UM, m_s_to_kmh

HORIZON_KM = 1e6  # look this far ahead: at 500 km a day, five and a half years
DAILY_KM = 500.0
DIAMETER_STEP_MM = 5.0  # rate-table nodes; a wheel's rates are interpolated between its two
RESOLUTION_KM = 500.0  # scan step near the wheel's present
STEP_FRACTION = 0.01  # beyond 100 scan steps, a step of 1 % of the distance
BISECTIONS = 48
CHUNK = 128  # scan points evolved together
BATCH = 64  # lines to a task of the executor
DIAMETER_MATCH = 0.01  # a wheel larger than the scenario's new wheel by more than this is another wheel
TURN, REPLACE, NONE = "turn", "replace", "none"
NOT_WITHIN = "not within the horizon (the distance is beyond it)"
WINDOWS_DAYS = (0, 30, 90, 365)  # the summary counts actions due within these


def diameter_nodes(diameters, step):
    """Nodes (m) every ``step`` (m) spanning ``diameters`` (m): the diameters the rates are built at."""
    low = np.floor(np.min(diameters) / step + 1e-9)
    high = np.ceil(np.max(diameters) / step - 1e-9)
    return np.arange(low, high + 1) * step


def interpolated(tables, nodes, diameter):
    """The :class:`RateTable` of a wheel of ``diameter`` (m): linear between the tables at the two
    ``nodes`` (m, increasing) around it (the node's own table on a node)."""
    k = int(np.clip(np.searchsorted(nodes, diameter, side="right") - 1, 0, nodes.size - 1))
    if k == nodes.size - 1 or diameter <= nodes[k]:
        a = tables[k]
        return RateTable(a.table, a.mean_rate, a.speed, diameter / 2)
    w = (diameter - nodes[k]) / (nodes[k + 1] - nodes[k])
    a, b = tables[k], tables[k + 1]
    return RateTable((1 - w) * a.table + w * b.table, (1 - w) * a.mean_rate + w * b.mean_rate, a.speed, diameter / 2)


def scan_grid(end, resolution, fraction=STEP_FRACTION):
    """Distances (m) from 0 to ``end``: every ``resolution`` up to ``resolution / fraction``, then
    growing by ``1 + fraction`` a step."""
    knee = resolution / fraction
    linear = np.arange(0.0, min(knee, end), resolution)
    grid = linear
    if end > knee:
        steps = int(np.ceil(np.log(end / knee) / np.log1p(fraction)))
        grid = np.append(linear, knee * (1 + fraction) ** np.arange(steps + 1))
    return np.append(grid[grid < end], end)


def _reached(limit, u, diameters):
    """Whether ``u`` (wheels × distances × angles, m) has reached ``limit``: a level at or above it,
    or a state that is no longer finite. Band levels are read on each wheel's own ``diameters``."""
    finite = np.all(np.isfinite(u), axis=-1)
    u = np.where(finite[..., None], u, 0.0)
    if limit.kind == "band_level":
        excess = np.stack([limit.excess(row, d)[0] for row, d in zip(u, diameters)])
    else:  # peak to peak and levels per order do not depend on the diameter
        excess = limit.excess(u, float(diameters[0]))[0]
    return (excess >= 0) | ~finite


def crossings(u0, tables, diameters, limits, end, resolution, fraction=STEP_FRACTION):
    """Distance (m, wheels × limits) from now at which each wheel ``u0`` (rows, m on the grid)
    under its table (:class:`RateTable`) first reaches each of ``limits``
    (:class:`~railwear.forecast.Limit`) within ``end`` (m): found on :func:`scan_grid` and located
    by :data:`BISECTIONS` halvings; 0 for one reached now, ``inf`` for one not reached."""
    u0 = np.asarray(u0, float)
    points = u0.shape[-1]
    spectra = np.fft.rfft(u0, axis=-1)
    rates = np.array([t.rates(np.arange(1, spectra.shape[-1])) / t.speed for t in tables])
    slope = np.array([t.mean_rate / t.speed for t in tables])
    diameters = np.asarray(diameters, float)
    grid = scan_grid(end, resolution, fraction)
    shape = (u0.shape[0], len(limits))
    found, lo, hi = np.full(shape, np.inf), np.full(shape, np.nan), np.full(shape, np.nan)
    pending = np.ones(shape, bool)
    for first in range(0, grid.size, CHUNK):
        active = np.flatnonzero(pending.any(axis=1))
        if not active.size:
            break
        s = grid[first:first + CHUNK + 1]
        u = evolve_batch(spectra[active], rates[active], slope[active], points, np.broadcast_to(s, (active.size, s.size)))
        for j, limit in enumerate(limits):
            rows = np.flatnonzero(pending[active, j])
            if not rows.size:
                continue
            hit = _reached(limit, u[rows], diameters[active[rows]])
            wheels, k = active[rows][hit.any(axis=1)], np.argmax(hit, axis=1)[hit.any(axis=1)]
            now = k == 0  # only on the first chunk: a later chunk starts at a point not reached
            found[wheels[now], j] = s[0]
            lo[wheels[~now], j], hi[wheels[~now], j] = s[k[~now] - 1], s[k[~now]]
            pending[wheels, j] = False
    w, j = np.nonzero(np.isfinite(lo))
    low, high = lo[w, j], hi[w, j]
    for _ in range(BISECTIONS if w.size else 0):
        mid = 0.5 * (low + high)
        u = evolve_batch(spectra[w], rates[w], slope[w], points, mid[:, None])
        hit = np.zeros(w.size, bool)
        for k, limit in enumerate(limits):
            sel = j == k
            if sel.any():
                hit[sel] = _reached(limit, u[sel], diameters[w[sel]])[:, 0]
        high, low = np.where(hit, mid, high), np.where(hit, low, mid)
    found[w, j] = high
    return found


@dataclass(frozen=True)
class LineForecast:
    """One measured line's state now and its distances (m): ``crossing`` per limit at growth 1,
    ``to_trigger`` (triggers × growth; ``inf`` beyond the horizon), ``to_worn`` (to the
    last-turning diameter by wear), the action at each growth (``action``, ``reason``,
    ``to_action``), and at the recommended growth the ``cut`` (m) and diameters (m) around it."""

    peak_to_peak: float
    dominant_order: int
    dominant_amplitude: float
    levels: np.ndarray
    selected_order: int
    mean_diameter: float
    to_trigger: np.ndarray
    to_worn: float
    action: str
    reason: str
    to_action: np.ndarray
    cut: float
    diameter_before: float
    diameter_after: float


def line_forecast(table, u0, diameter, since, crossing, policy, growth, middle, horizon):
    """The :class:`LineForecast` of one line (SI): ``table`` its :class:`RateTable`, ``u0`` (m on
    the grid), ``diameter`` (m), ``since`` (m since the last turning, NaN if not known),
    ``crossing`` (m) to each limit of the ``policy`` (:class:`~railwear.maintenance.turning.Policy`)
    at growth 1 (:func:`crossings`), ``growth`` the multipliers with ``middle`` the index of the
    recommended one, ``horizon`` (m)."""
    growth = np.asarray(growth, float)
    spectrum = roundness.polygon_spectrum(u0)
    with np.errstate(divide="ignore", invalid="ignore"):
        to_trigger = np.where(crossing[:, None] == 0, 0.0, crossing[:, None] / growth[None, :])
    if policy.triggers.interval is not None:
        left = max(policy.triggers.interval - since, 0.0) if np.isfinite(since) else np.inf
        to_trigger = np.vstack([to_trigger, np.full(growth.size, left)])
    to_trigger = np.where(to_trigger <= horizon, to_trigger, np.inf)
    mean_diameter = diameter + 2 * float(np.mean(u0))
    wear = -table.mean_rate / table.speed  # m of radius per m run
    to_worn = max((mean_diameter - policy.last_diameter) / (2 * wear), 0.0) if wear > 0 else np.inf
    if mean_diameter <= policy.last_diameter:
        to_worn = 0.0
    to_worn = to_worn if to_worn <= horizon else np.inf
    to_action = np.full(growth.size, np.inf)
    actions, reasons = [], []
    names = policy.triggers.names()
    for g in range(growth.size):
        first = int(np.argmin(to_trigger[:, g])) if to_trigger.size else 0
        d = to_trigger[first, g] if to_trigger.size else np.inf
        if np.isfinite(d) and d <= to_worn:
            to_action[g], action, reason = d, TURN, names[first]
        elif np.isfinite(to_worn):
            to_action[g], action, reason = to_worn, REPLACE, WORN
        else:
            action, reason = NONE, ""
        actions.append(action)
        reasons.append(reason)
    cut = before = after = np.nan
    action, reason = actions[middle], reasons[middle]
    if action == TURN:
        u = table.scaled(growth[middle]).evolve(u0, to_action[middle] / table.speed)[0]
        if not np.all(np.isfinite(u)):
            raise OverflowError(f"the polygon overflowed before the action ({to_action[middle] / KM:,.0f} km)")
        cut = policy.turning.cut.depth(u)
        before = diameter + 2 * float(np.mean(u))
        after = before - 2 * cut
        if after < policy.last_diameter:
            action, reason = REPLACE, BELOW
    with np.errstate(divide="ignore"):
        levels = np.asarray(spectrum["roughness_level"], float)
    n = spectrum["dominant_order"]
    return LineForecast(spectrum["peak_to_peak"], int(n), float(spectrum["amplitude"][n - 1]), levels,
                        table.selected_order(), mean_diameter, to_trigger, to_worn, action, reason, to_action,
                        cut, before, after)


def forecast_batch(task):
    """A batch of lines in a worker: ``task`` is ``(tables, u0, diameters, since, policy, growth,
    middle, horizon, resolution)`` with a :class:`RateTable`, a state and a diameter per line;
    returns a :class:`LineForecast` or the text of its failure per line."""
    tables, u0, diameters, since, policy, growth, middle, horizon, resolution = task
    crossing = crossings(u0, tables, diameters, policy.triggers.limits, horizon * max(growth), resolution)
    out = []
    for table, u, d, s, c in zip(tables, u0, diameters, since, crossing):
        try:
            out.append(line_forecast(table, u, d, s, c, policy, growth, middle, horizon))
        except OverflowError as e:
            out.append(str(e))
    return out


def node_table(task):
    """The :class:`RateTable` of a scenario's wheel at a diameter in a worker: ``task`` is
    ``(scenario_toml, diameter, highest)``."""
    from railwear.scenario import parse_scenario

    text, diameter, highest = task
    return WheelRates(parse_scenario(text, source="fleet node"), highest).at(diameter)


def _middle(growth):
    g = np.asarray(growth)
    return int(np.argmin(np.abs(g - 1.0))) if np.any(g == 1.0) else g.size // 2


def _check(name, value, low, high, unit):
    if not (isinstance(value, (int, float, np.floating, np.integer)) and np.isfinite(value) and low <= value <= high):
        raise OptionError(f"{name}: must be in [{low:g}, {high:g}] {unit}, got {value!r}")
    return float(value)


def _run(executor, fn, tasks, progress, done, total):
    """``fn`` over ``tasks`` on ``executor`` (the sweep's: serial, local processes or Dask), results
    in the order of the tasks."""
    futures = [executor.submit(fn, task, f"fleet-{fn.__name__}-{k}") for k, task in enumerate(tasks)]
    index = {id(f): k for k, f in enumerate(futures)}
    out = [None] * len(tasks)
    for future in executor.as_completed(futures):
        out[index[id(future)]] = future.result()
        done[0] += 1
        if progress is not None:
            progress(done[0] / total)
    return out


def fleet(scenario=None, manifest=EXAMPLE, policy="metro-condition", daily_km=DAILY_KM, growth=GROWTH,
          horizon_km=HORIZON_KM, diameter_step_mm=DIAMETER_STEP_MM, resolution_km=RESOLUTION_KM, executor=None,
          progress=None, rates=None, batch=BATCH, load_speeds_kmh=None, detectors=None, load_revolutions=8,
          load_transient_s=1.0, load_tolerance=None):
    """Each wheel of a measured fleet under one maintenance policy: its state now, the distance to
    each trigger with its band over the ``growth`` multipliers, the action and its date at
    ``daily_km``. ``scenario`` a :class:`~railwear.scenario.Scenario`, file or built-in name whose
    body gives a linear model; ``manifest`` the fleet's CSV (or the built-in ``example-fleet``);
    ``policy`` a file or built-in name. ``executor``: one of :mod:`railwear.sweep`'s (serial in
    this process by default; local processes, or Dask). ``rates``: a callable ``diameter (m) ->``
    :class:`RateTable` in place of the scenario's technique (for a wheel of known rates). Returns
    an ``xarray.Dataset`` over ``wheel`` (:func:`dataset`); a fleet of which no wheel can be read
    raises :class:`~railwear.errors.MeasuredFileError` naming the first refusal.

    ``load_speeds_kmh`` (a ``vehicle_track`` body only; costly: time-domain runs per wheel): the
    peak wheel–rail force of each wheel's measured shape at these speeds, and the distance at
    which its grown shape passes each of ``detectors`` (:data:`~railwear.maintenance.impact.DETECTORS`
    by default; :mod:`railwear.maintenance.detectors`), ``load_revolutions`` recorded after
    ``load_transient_s`` at each speed, located to ``load_tolerance`` of the peak to peak; one task
    of the executor per wheel."""
    from railwear.sweep import SerialExecutor

    sc = load_scenario(scenario)
    daily_km = _check("daily_km", daily_km, 1.0, 1e5, "km")
    horizon_km = _check("horizon_km", horizon_km, 1e3, 1e8, "km")
    step = _check("diameter_step_mm", diameter_step_mm, 0.1, 100.0, "mm") * MM
    resolution = _check("resolution_km", resolution_km, 1.0, 1e5, "km") * KM
    if not (isinstance(batch, (int, np.integer)) and 1 <= batch <= 10_000):
        raise OptionError(f"batch: a whole number in [1, 10000], got {batch!r}")
    growth = _checked_growth(growth)
    if min(growth) <= 0:
        raise OptionError("growth: a fleet's band needs multipliers above 0 (0 would be no polygon growth at all)")
    middle = _middle(growth)
    load = None if load_speeds_kmh is None else _load_options(sc, load_speeds_kmh, detectors, load_revolutions,
                                                               load_transient_s, load_tolerance)
    base = re_profiled(sc)
    new = 2 * sc.wheel.radius_m
    files, (built,) = _policies([policy], base, new, sc)  # a flange trigger needs a lateral profile: refused
    lines, failed, path = read_fleet(manifest, interval=built.triggers.interval is not None)
    points = sc.solver.points
    kept, states = [], []
    for line in lines:
        if line.diameter > new * (1 + DIAMETER_MATCH):
            failed.append(f"{path.name} line {line.row}, column diameter_mm: wheel {line.wheel_id} is "
                          f"{line.diameter / MM:g} mm, larger than the scenario's new wheel ({new / MM:g} mm, "
                          "wheel.radius_m): another wheel")
            continue
        kept.append(line)
        states.append(roundness.resample_measured(line.angle, line.deviation, points))
    if not kept:
        raise MeasuredFileError(f"{path.name}: no wheel of the fleet could be read ({len(failed)} refused; the first: "
                                f"{failed[0] if failed else 'no rows'})")
    diameters = np.array([line.diameter for line in kept])
    nodes = diameter_nodes(diameters, step)
    order = np.argsort(diameters, kind="stable")
    chunks = [order[k:k + batch] for k in range(0, order.size, batch)]
    flagged = len({line.wheel_id for line in kept}) if load is not None else 0
    total, done = (0 if rates is not None else nodes.size) + len(chunks) + flagged, [0]
    own = executor is None
    executor = executor or SerialExecutor()
    try:
        if rates is None:
            text = to_toml(sc)
            tables = _run(executor, node_table, [(text, float(d), points // 2) for d in nodes], progress, done, total)
        else:
            tables = [rates(float(d)) for d in nodes]
        since = np.array([line.since for line in kept])
        tasks = [([interpolated(tables, nodes, diameters[i]) for i in c], np.array([states[i] for i in c]),
                  diameters[c], since[c], built, growth, middle, horizon_km * KM, resolution) for c in chunks]
        answers = _run(executor, forecast_batch, tasks, progress, done, total)
        forecasts = [None] * len(kept)
        for c, answer in zip(chunks, answers):
            for i, a in zip(c, answer):
                forecasts[i] = a
        good = []
        for line, f, u in zip(kept, forecasts, states):
            if isinstance(f, str):
                failed.append(f"{line.file}: {f} (wheel {line.wheel_id}, {path.name} line {line.row})")
            else:
                good.append((line, f, u))
        if not good:
            raise MeasuredFileError(f"{path.name}: no wheel of the fleet could be forecast; the first: {failed[0]}")
        ds = dataset(sc, files[0], built, good, failed, growth, middle, nodes, tables,
                     {"manifest": path.name, "daily_km": daily_km, "horizon_km": horizon_km,
                      "diameter_step_mm": step / MM, "resolution_km": resolution / KM})
        if load is not None:
            lines_of = _governing_lines(good, middle)
            wheel_tasks = [[load.task(line.diameter, u, interpolated(tables, nodes, line.diameter), horizon_km * KM)]
                           for line, _, u in lines_of]
            flags = [answer[0] for answer in _run(executor, flag_batch, wheel_tasks, progress, done, total)]
            ds = with_detectors(ds, load, flags, growth)
    finally:
        if own:
            executor.close()
    return ds


@dataclass(frozen=True)
class LoadOptions:
    """The dynamic wheel load of a fleet (SI): the vehicle–track ``case``, ``speeds`` (m/s),
    ``detectors`` (:class:`~railwear.maintenance.impact.Detector`), the ring and the record."""

    case: object
    speeds: tuple
    detectors: tuple
    ring_sleepers: int
    ring_max_frequency_hz: float
    revolutions: int
    transient: float
    tolerance: float

    def task(self, diameter, u, table, horizon):
        """The :class:`~railwear.maintenance.detectors.WheelTask` of a wheel of ``diameter`` (m)."""
        from dataclasses import replace

        from railwear.maintenance.detectors import WheelTask

        return WheelTask(replace(self.case, diameter=float(diameter)), u, table, self.speeds,
                         tuple(d.threshold for d in self.detectors), horizon, self.tolerance, self.ring_sleepers,
                         self.ring_max_frequency_hz, self.revolutions, self.transient)


def detectors_with(own_kn):
    """The published detector thresholds and the planner's own (kN each), one line refusing a bad one."""
    from railwear.maintenance.impact import DETECTORS, Detector

    own = []
    for value in own_kn:
        _check("--load-threshold-kn", value, 1.0, 5000.0, "kN")
        own.append(Detector(f"own-{len(own) + 1}", "own threshold", float(value), "kN", "the planner's own threshold",
                            "given with --load-threshold-kn"))
    if len({d.value for d in own}) != len(own):
        raise OptionError("--load-threshold-kn: a threshold is given twice")
    return tuple(DETECTORS) + tuple(own)


def _load_options(sc, speeds_kmh, detectors, revolutions, transient, tolerance):
    """:class:`LoadOptions` of the scenario, or a one-line refusal naming the option or field."""
    from railwear.maintenance import detectors as flags
    from railwear.maintenance import impact
    from railwear.units import kmh_to_m_s

    impact.check_body(sc, "--load-speeds")
    v = np.atleast_1d(np.asarray(speeds_kmh, float))
    low, high = impact.SPEED_KMH
    if not 1 <= v.size <= 20 or not np.all(np.isfinite(v)) or np.any((v < low) | (v > high)) or np.unique(v).size != v.size:
        raise OptionError(f"--load-speeds: 1 to 20 different speeds in [{low:g}, {high:g}] km/h, got "
                          f"{', '.join(f'{x:g}' for x in v) or 'none'}")
    found = tuple(impact.DETECTORS if detectors is None else detectors)
    if not found or not all(isinstance(d, impact.Detector) for d in found):
        raise OptionError("detectors: give one or more railwear.maintenance.impact.Detector")
    if len({d.name for d in found}) != len(found):
        raise OptionError("detectors: two detectors share a name")
    revolutions = int(_check("load_revolutions", revolutions, 1, 1000, "revolutions"))
    transient = _check("load_transient_s", transient, 0.0, 60.0, "s")
    tolerance = _check("load_tolerance", flags.TOLERANCE if tolerance is None else tolerance, 1e-4, 0.5, "")
    return LoadOptions(sc.body.case(sc), tuple(float(x) for x in np.sort(kmh_to_m_s(v))), found, sc.track.ring_sleepers,
                       sc.track.ring_max_frequency_hz, revolutions, transient, tolerance)


def _governing_lines(good, middle):
    """The governing ``(line, forecast, u)`` of each wheel, in the order of :func:`dataset`'s wheels."""
    wheels = {}
    for entry in good:
        wheels.setdefault(entry[0].wheel_id, []).append(entry)
    return [_governing(entries, middle) for entries in wheels.values()]


def with_detectors(ds, load, flags, growth):
    """``ds`` with the dynamic wheel load of each wheel (:class:`~railwear.maintenance.detectors.WheelFlags`
    in the order of its wheels): the peak force now per speed, what each detector flags now, and
    the distance at which the grown shape passes each threshold, over the growth band."""
    from railwear.api import speed_coordinates
    from railwear.maintenance.detectors import LEAST_STEP_KM

    growth = np.asarray(growth, float)
    thresholds = np.array([d.threshold for d in load.detectors])
    now = np.array([f.peak_now for f in flags])
    at1 = np.array([f.distance for f in flags]) / KM  # km, wheels x detectors
    with np.errstate(divide="ignore", invalid="ignore"):
        band = np.where(at1[..., None] == 0, 0.0, at1[..., None] / growth[None, None, :])
    horizon = ds.attrs["horizon_km"]
    band = np.where(band <= horizon, band, np.inf)
    why = np.array([list(f.why) for f in flags], dtype=object).astype(str)
    wd, dd = ("wheel", "detector"), ("detector",)
    variables = {
        "static_load": ((), load.case.static_load, {"units": "N", "long_name": "static wheel load"}),
        "peak_force_now": (("wheel", "speed"), now, {"units": "N", "long_name": "peak vertical wheel-rail force of the "
                                                     "measured shape (time domain, ring track)"}),
        "flagged_now": (("wheel", "speed", "detector"), (now[..., None] > thresholds).astype(np.int8),
                        {"units": "1", "long_name": "1: the peak force now exceeds the detector's threshold"}),
        "distance_to_detector": (("wheel", "detector", "growth"), band, {
            "units": "km", "long_name": "distance from the measurement at which the grown shape's peak force passes the "
                                        "threshold at one of the speeds", **_undefined(band, NOT_WITHIN)}),
        "detector_speed": (wd, np.array([f.speed for f in flags]), {
            "units": "m s-1", "long_name": "speed whose peak passes the threshold first (growth 1)",
            "undefined_because": "not passed within the search"}),
        "detector_peak_force": (wd, np.array([f.peak for f in flags]), {
            "units": "N", "long_name": "that peak force, at the located distance"}),
        "detector_peak_to_peak": (wd, np.array([f.peak_to_peak for f in flags]), {
            "units": "m", "long_name": "peak-to-peak radius deviation of the grown shape there"}),
        "detector_not_found": (wd, why, {"long_name": "why no distance is given ('' where one is)"}),
        "load_runs": (("wheel",), np.array([f.runs for f in flags], np.int64), {
            "units": "1", "long_name": "time-domain runs the wheel took"}),
        "threshold": (dd, thresholds, {"units": "N", "long_name": "detector threshold on the peak force"}),
        "detector_who": (dd, np.array([d.who for d in load.detectors]), {"long_name": "who acts"}),
        "detector_action": (dd, np.array([d.action for d in load.detectors]), {"long_name": "what they do"}),
        "detector_source": (dd, np.array([d.source for d in load.detectors]), {"long_name": "source"}),
    }
    out = ds.assign(variables).assign_coords(detector=("detector", [d.name for d in load.detectors],
                                                       {"long_name": "wheel-impact-load detector threshold"}))
    out = speed_coordinates(out, np.asarray(load.speeds), "speed")
    out.attrs.update({
        "load_revolutions": load.revolutions, "load_transient_s": load.transient, "load_tolerance": load.tolerance,
        "ring_sleepers": load.ring_sleepers, "ring_max_frequency_hz": load.ring_max_frequency_hz,
        "load_method": (f"peak force of the time-domain wheel on the ring track at each speed, {load.revolutions} "
                        f"revolutions after {load.transient:g} s, the wheel of the vehicle-track case at its own "
                        "diameter; the grown shape is the Fourier evolution of the measured line at growth 1 without "
                        "turnings, the distance located by bisection until the peak to peak across the bracket differs "
                        f"by less than {load.tolerance:.0%} (or {LEAST_STEP_KM:g} km), assuming each speed's peak grows "
                        "with the distance; under growth g the distance is the one at 1 divided by g")})
    return out


def _governing(entries, middle):
    """The line of a wheel whose action comes first at the recommended growth (the larger peak
    to peak on a tie)."""
    return min(entries, key=lambda e: (e[1].to_action[middle], -e[1].peak_to_peak))


def _date(day, distance_m, daily_km):
    """``(days, ISO date)`` the action falls due at ``daily_km`` after ``day``: ``(-1, '')`` for none."""
    if not np.isfinite(distance_m):
        return -1, ""
    days = int(np.floor(distance_m / KM / daily_km))
    return days, (day + datetime.timedelta(days=days)).isoformat()


def _undefined(values, reason):
    return {} if np.all(np.isfinite(values)) else {UNDEFINED: reason}


def dataset(scenario, file, policy, good, failed, growth, middle, nodes, tables, options):
    """The fleet as an ``xarray.Dataset`` over ``wheel`` (× ``trigger`` × ``growth``, × ``order``),
    and the refusals over ``failure``."""
    from railwear import __version__

    wheels = {}
    for entry in good:
        wheels.setdefault(entry[0].wheel_id, []).append(entry)
    rows = [(_governing(entries, middle), len(entries)) for entries in wheels.values()]
    daily = options["daily_km"]
    n_w, n_t, n_g = len(rows), len(policy.triggers.names()), len(growth)
    orders = np.arange(1, rows[0][0][2].size // 2 + 1)
    level = np.full((n_w, orders.size), -np.inf)
    to_trigger = np.full((n_w, n_t, n_g), np.inf)
    to_action = np.full((n_w, n_g), np.inf)
    per = {name: [] for name in ("car", "axle", "side", "lines", "lateral", "file", "row", "diameter", "mileage",
                                 "date", "since", "ptp", "order", "amplitude", "dominant_level", "selected", "worn",
                                 "action", "reason", "days", "when", "days_early", "when_early", "cut", "before",
                                 "after", "at_mileage", "mean_diameter")}
    for w, ((line, f, _), count) in enumerate(rows):
        level[w, :f.levels.size] = f.levels
        to_trigger[w], to_action[w] = f.to_trigger, f.to_action
        days, when = _date(line.date, f.to_action[middle], daily)
        days_early, when_early = _date(line.date, np.min(f.to_action), daily)
        for name, value in (("car", line.car), ("axle", line.axle), ("side", line.side), ("lines", count),
                            ("lateral", line.lateral), ("file", line.file), ("row", line.row),
                            ("diameter", line.diameter), ("mileage", line.mileage / KM), ("date", line.date.isoformat()),
                            ("since", line.since / KM), ("ptp", f.peak_to_peak), ("order", f.dominant_order),
                            ("amplitude", f.dominant_amplitude), ("dominant_level", f.levels[f.dominant_order - 1]),
                            ("selected", f.selected_order), ("worn", f.to_worn / KM), ("action", f.action),
                            ("reason", f.reason), ("days", days), ("when", when), ("days_early", days_early),
                            ("when_early", when_early), ("cut", f.cut), ("before", f.diameter_before),
                            ("after", f.diameter_after), ("at_mileage", (line.mileage + f.to_action[middle]) / KM),
                            ("mean_diameter", f.mean_diameter)):
            per[name].append(value)
    a = {k: np.array(v) for k, v in per.items()}
    to_trigger_km, to_action_km = to_trigger / KM, to_action / KM
    with np.errstate(invalid="ignore"):
        early_km, late_km = np.min(to_action_km, axis=1), np.max(to_action_km, axis=1)
    g = float(growth[middle])
    wheel_dims = ("wheel",)
    variables = {
        "car": (wheel_dims, a["car"].astype(str), {"long_name": "car the wheel is under"}),
        "axle": (wheel_dims, a["axle"].astype(np.int64), {"units": "1", "long_name": "axle position in the car (1: leading)"}),
        "side": (wheel_dims, a["side"].astype(str), {"long_name": "side: L or R"}),
        "lines": (wheel_dims, a["lines"].astype(np.int64), {"units": "1", "long_name": "measured lines read"}),
        "lateral_position": (wheel_dims, a["lateral"], {"units": "m", "long_name": "lateral position of the governing line "
                                                        "(NaN: one line, not given)"}),
        "file": (wheel_dims, a["file"].astype(str), {"long_name": "measured file of the governing line, relative to the manifest"}),
        "manifest_line": (wheel_dims, a["row"].astype(np.int64), {"units": "1", "long_name": "line of the governing row in the manifest"}),
        "diameter": (wheel_dims, a["diameter"], {"units": "m", "long_name": "measured running-circle diameter"}),
        "mileage": (wheel_dims, a["mileage"], {"units": "km", "long_name": "odometer at the measurement"}),
        "measured": (wheel_dims, a["date"].astype(str), {"long_name": "date of the measurement (ISO 8601)"}),
        "since_last_turning": (wheel_dims, a["since"], {"units": "km", "long_name": "distance since the last turning "
                                                        "(NaN: not given)"}),
        "peak_to_peak": (wheel_dims, a["ptp"], {"units": "m", "long_name": "peak-to-peak radius deviation now"}),
        "dominant_order": (wheel_dims, a["order"].astype(np.int64), {"units": "1", "long_name": "order of the largest harmonic now"}),
        "dominant_amplitude": (wheel_dims, a["amplitude"], {"units": "m", "long_name": "amplitude of the dominant order now"}),
        "dominant_level": (wheel_dims, a["dominant_level"], {"units": "dB", "long_name": "level of the dominant order now, re 1 um",
                                                             **_undefined(a["dominant_level"], "a round wheel")}),
        "order_level": (("wheel", "order"), level, {"units": "dB", "long_name": "level of each order now, re 1 um",
                                                    **_undefined(level, "no amplitude in the order")}),
        "selected_order": (wheel_dims, a["selected"].astype(np.int64),
                           {"units": "1", "long_name": "fastest-growing order at the wheel's diameter"}),
        "distance_to_trigger": (("wheel", "trigger", "growth"), to_trigger_km,
                                {"units": "km", "long_name": "distance from the measurement to the trigger",
                                 **_undefined(to_trigger_km, NOT_WITHIN)}),
        "distance_to_last_turning_diameter": (wheel_dims, a["worn"], {
            "units": "km", "long_name": "distance until wear alone takes the mean diameter to the last-turning diameter",
            **_undefined(a["worn"], NOT_WITHIN)}),
        "distance_to_action": (("wheel", "growth"), to_action_km, {"units": "km", "long_name": "distance to the first action",
                                                                   **_undefined(to_action_km, NOT_WITHIN)}),
        "distance_to_action_early": (wheel_dims, early_km, {"units": "km", "long_name": "distance to the action, earliest over the growth band",
                                                            **_undefined(early_km, NOT_WITHIN)}),
        "distance_to_action_late": (wheel_dims, late_km, {"units": "km", "long_name": "distance to the action, latest over the growth band",
                                                          **_undefined(late_km, NOT_WITHIN)}),
        "action": (wheel_dims, a["action"].astype(str), {"long_name": f"recommended action at growth x{g:g}: turn, replace or none"}),
        "action_reason": (wheel_dims, a["reason"].astype(str), {"long_name": "the trigger, or why the wheel is replaced"}),
        "days_to_action": (wheel_dims, a["days"].astype(np.int64), {"units": "d", "long_name": "days from the measurement to the action "
                                                                    "at the daily mileage (-1: none within the horizon)"}),
        "action_date": (wheel_dims, a["when"].astype(str), {"long_name": "date the action is due (ISO 8601; empty: none)"}),
        "days_to_action_early": (wheel_dims, a["days_early"].astype(np.int64), {
            "units": "d", "long_name": "days to the action, earliest over the growth band (-1: none)"}),
        "action_date_early": (wheel_dims, a["when_early"].astype(str), {"long_name": "date the action is due, earliest over the growth band"}),
        "mileage_at_action": (wheel_dims, a["at_mileage"], {"units": "km", "long_name": "odometer at the action",
                                                            **_undefined(a["at_mileage"], "no action within the horizon")}),
        "mean_diameter": (wheel_dims, a["mean_diameter"], {"units": "m", "long_name": "mean diameter now (the measured line's mean)"}),
        "cut_depth": (wheel_dims, a["cut"], {"units": "m", "long_name": "cut depth on the radius the policy's rule takes at the "
                                                                      "action (NaN: no turning)"}),
        "diameter_before": (wheel_dims, a["before"], {"units": "m", "long_name": "mean diameter at the action (NaN: no turning)"}),
        "diameter_after": (wheel_dims, a["after"], {"units": "m", "long_name": "diameter after the turning (NaN: no turning)"}),
        "failed": (("failure",), np.array(failed, dtype=object).astype(str) if failed else np.array([], dtype=str),
                   {"long_name": "refused files and rows, each naming its file and line"}),
        "node_diameter": (("node",), np.asarray(nodes), {"units": "m", "long_name": "diameters the rates were built at"}),
        "node_selected_order": (("node",), np.array([t.selected_order() for t in tables], np.int64),
                                {"units": "1", "long_name": "fastest-growing order at the node"}),
    }
    speed = tables[0].speed
    attrs = {"scenario": to_toml(scenario), "scenario_hash": scenario_hash(scenario), "scenario_name": scenario.name,
             "new_diameter_m": 2 * scenario.wheel.radius_m, "speed_kmh": float(m_s_to_kmh(speed)),
             "policy": file.model_dump_json(), "policy_name": file.name, "policy_source": file.source,
             "last_turning_diameter_m": policy.last_diameter, "recommended_growth": g,
             "growth_band": (f"growth multipliers {', '.join(f'{x:g}' for x in growth)} on the polygon rates of the Fourier "
                             "technique: no field growth rate of a polygon is published"),
             "wheels_read": n_w, "lines_read": len(good), "refused": len(failed), "railwear_version": __version__,
             **options}
    return xr.Dataset(variables, coords={
        "wheel": ("wheel", np.array(list(wheels), dtype=str), {"long_name": "wheel id"}),
        "trigger": ("trigger", np.array(policy.triggers.names(), dtype=str), {"long_name": "trigger of the policy"}),
        "growth": ("growth", np.array(growth), {"units": "1", "long_name": "growth multiplier on the polygon rates"}),
        "order": ("order", orders, {"units": "1", "long_name": "polygon order"})}, attrs=attrs)


# What `railwear fleet` writes besides fleet.nc, read from the Dataset alone (so the files can be
# written again from fleet.nc).
TEXT, TABLE, HTML = "fleet.txt", "wheels.csv", "fleet.html"
FIGURES = ("fleet-actions", "fleet-cars", "fleet-orders")
NEXT = 15  # wheels listed in the summary, soonest first
ORDER_MAP_RANGE_DB = 50.0  # the order map's colour range below the fleet's loudest order


def _km(x):
    return f"{x:,.0f}" if np.isfinite(x) else "-"


def _slug(name):
    """A trigger's name as a column name: ``0.1 mm peak to peak`` -> ``0_1mm_peak_to_peak``,
    ``interval 400,000 km`` -> ``interval_400000`` (the column adds ``_km``)."""
    text = name.lower().replace(",", "").replace(" mm ", "mm ").replace(".", "_").removesuffix(" km")
    return "_".join(part for part in "".join(c if c.isalnum() else "_" for c in text).split("_") if part)


def table_rows(ds):
    """One row per wheel: what a planner sorts and filters (units in the column names)."""
    rows = []
    triggers = [str(t) for t in ds.trigger.values]
    growth = ds.growth.values
    g = int(np.argmin(np.abs(growth - ds.attrs["recommended_growth"])))
    for w, wheel in enumerate(ds.wheel.values):
        d = ds.isel(wheel=w)
        row = {"wheel_id": str(wheel), "car": str(d.car.values), "axle": int(d.axle), "side": str(d.side.values),
               "lines": int(d.lines), "diameter_mm": float(d.diameter) / MM, "mileage_km": float(d.mileage),
               "measured": str(d.measured.values), "peak_to_peak_um": float(d.peak_to_peak) / UM,
               "dominant_order": int(d.dominant_order), "dominant_level_db": float(d.dominant_level),
               "selected_order": int(d.selected_order)}
        for t, name in enumerate(triggers):
            slug = _slug(name)
            values = d.distance_to_trigger.values[t]
            row[f"to_{slug}_km"] = float(values[g])
            row[f"to_{slug}_early_km"], row[f"to_{slug}_late_km"] = float(np.min(values)), float(np.max(values))
        row.update({"to_last_turning_diameter_km": float(d.distance_to_last_turning_diameter),
                    "action": str(d.action.values), "reason": str(d.action_reason.values),
                    "to_action_km": float(d.distance_to_action.values[g]),
                    "to_action_early_km": float(d.distance_to_action_early),
                    "to_action_late_km": float(d.distance_to_action_late),
                    "days_to_action": int(d.days_to_action), "action_date": str(d.action_date.values),
                    "action_date_early": str(d.action_date_early.values),
                    "cut_mm": float(d.cut_depth) / MM, "diameter_after_mm": float(d.diameter_after) / MM})
        if "peak_force_now" in ds:
            row.update(_load_columns(ds, d, g))
        rows.append(row)
    return rows


def _detector_slug(ds, k):
    return f"{_slug(str(ds.detector.values[k]))}_{ds.threshold.values[k] / 1e3:.0f}kN"


def _load_columns(ds, d, g):
    """A wheel's dynamic-load columns: the peak force now per speed (kN), the detectors that
    flag it now, and per detector the distance to its threshold (km) with its band and the speed."""
    row = {f"peak_now_{v:g}kmh_kN": float(p) / 1e3 for v, p in zip(ds.speed_kmh.values, d.peak_force_now.values)}
    now = [str(ds.detector.values[k]) for k in range(ds.sizes["detector"]) if d.flagged_now.values[:, k].any()]
    row["flagged_now_by"] = " ".join(now)
    for k in range(ds.sizes["detector"]):
        slug, values = _detector_slug(ds, k), d.distance_to_detector.values[k]
        row[f"to_{slug}_km"] = float(values[g])
        row[f"to_{slug}_early_km"], row[f"to_{slug}_late_km"] = float(np.min(values)), float(np.max(values))
        row[f"{slug}_speed_kmh"] = float(m_s_to_kmh(float(d.detector_speed.values[k])))
    return row


def _cell(value):
    if isinstance(value, float):
        return "" if np.isnan(value) else ("inf" if np.isinf(value) else f"{value:.10g}")
    text = str(value)
    return '"' + text.replace('"', '""') + '"' if any(c in text for c in ',"\n') else text


def csv_text(ds):
    """The per-wheel table as CSV (empty cell: not defined; ``inf``: beyond the horizon)."""
    rows = table_rows(ds)
    head = list(rows[0])
    return "\n".join([",".join(head)] + [",".join(_cell(r[k]) for k in head) for r in rows]) + "\n"


def _when(ds, w):
    days = int(ds.days_to_action[w])
    return "-" if days < 0 else str(ds.action_date.values[w])


def report(ds):
    """The fleet in words: what was read and refused, the policy and the growth band, how many
    wheels are due when, the wheels due soonest, and every refusal."""
    a = ds.attrs
    n = ds.sizes["wheel"]
    triggers = ", ".join(str(t) for t in ds.trigger.values) or "none"
    g = a["recommended_growth"]
    lines = [f"fleet {a['manifest']}: {n} wheel{'s' if n != 1 else ''} read ({a['lines_read']} measured line"
             f"{'s' if a['lines_read'] != 1 else ''}), {a['refused']} file(s) or row(s) refused",
             f"scenario {a['scenario_name']} ({a['new_diameter_m'] / MM:g} mm new wheel, {a['speed_kmh']:g} km/h, the "
             f"Fourier technique at each wheel's diameter); policy {a['policy_name']}: {triggers}; scrapped at "
             f"{a['last_turning_diameter_m'] / MM:g} mm",
             f"{a['growth_band']}; the action is at x{g:g}, its band from the fastest to the slowest growth",
             f"dates at {a['daily_km']:g} km a day from each wheel's measurement; horizon {a['horizon_km']:,.0f} km", ""]
    action = ds.action.values
    days = ds.days_to_action.values
    edges = list(WINDOWS_DAYS)
    head = f"  {'due':<22}" + "".join(f"{k:>9}" for k in (TURN, REPLACE))
    lines += [f"actions at growth x{g:g}:", head]
    labels = ["now (day 0)"] + [f"within {edges[i]} days" for i in range(1, len(edges))] + [f"after {edges[-1]} days", "none within horizon"]
    for i, label in enumerate(labels):
        if i == 0:
            sel = days == 0
        elif i < len(edges):
            sel = (days > edges[i - 1]) & (days <= edges[i])
        elif i == len(edges):
            sel = days > edges[-1]
        else:
            sel = days < 0
        lines.append(f"  {label:<22}" + "".join(f"{int(np.sum(sel & (action == k))):>9}" for k in (TURN, REPLACE))
                     + (f"{int(np.sum(sel)):>9} wheels" if i == len(labels) - 1 else ""))
    due = np.flatnonzero(days >= 0)
    due = due[np.lexsort((ds.wheel.values[due], days[due]))][:NEXT]
    if due.size:
        lines += ["", f"due soonest ({due.size} of {int(np.sum(days >= 0))}):",
                  f"  {'wheel':<10} {'car':>5} {'axle':>4} {'side':>4} {'p-p (um)':>9} {'order':>5}  {'action':<8} "
                  f"{'km (band)':<28} {'due (earliest)':<25} reason"]
        for w in due:
            band = f"{_km(float(ds.distance_to_action_early[w]))}-{_km(float(ds.distance_to_action_late[w]))}"
            dist = float(ds.distance_to_action.values[w][int(np.argmin(np.abs(ds.growth.values - g)))])
            lines.append(f"  {str(ds.wheel.values[w]):<10} {str(ds.car.values[w]):>5} {int(ds.axle[w]):>4} "
                         f"{str(ds.side.values[w]):>4} {float(ds.peak_to_peak[w]) / UM:>9.1f} {int(ds.dominant_order[w]):>5}  "
                         f"{str(action[w]):<8} {_km(dist) + ' (' + band + ')':<28} "
                         f"{_when(ds, w) + ' (' + (str(ds.action_date_early.values[w]) or '-') + ')':<25} "
                         f"{ds.action_reason.values[w]}")
    if "peak_force_now" in ds:
        lines += [""] + load_lines(ds)
    failed = [str(f) for f in ds.failed.values]
    lines += ["", f"refused ({len(failed)}):" if failed else "refused: none"]
    lines += [f"  {f}" for f in failed]
    return "\n".join(lines) + "\n"


def load_lines(ds):
    """The dynamic wheel load in words: the highest peak now, what each detector flags now, and
    when the grown shapes pass each threshold (the first wheel, how many within the horizon and
    how many before their own action)."""
    kmh = ds.speed_kmh.values
    now = ds.peak_force_now.values
    w, i = np.unravel_index(int(np.nanargmax(now)), now.shape)
    g = float(ds.attrs["recommended_growth"])
    gi = int(np.argmin(np.abs(ds.growth.values - g)))
    action = ds.distance_to_action.values[:, gi]
    lines = [f"dynamic wheel load at {', '.join(f'{v:g}' for v in kmh)} km/h (static {float(ds.static_load) / 1e3:.1f} kN;"
             f" growth x{g:g}, no turning): the highest peak now {now[w, i] / 1e3:.1f} kN ({ds.wheel.values[w]} at "
             f"{kmh[i]:g} km/h)"]
    for k in range(ds.sizes["detector"]):
        flagged = np.flatnonzero(ds.flagged_now.values[:, :, k].any(axis=1))
        d = ds.distance_to_detector.values[:, k, gi]
        head = f"  {ds.detector_who.values[k]} {ds.threshold.values[k] / 1e3:.0f} kN: "
        head += (f"{flagged.size} flagged now ({', '.join(str(x) for x in ds.wheel.values[flagged][:5])}"
                 f"{' ...' if flagged.size > 5 else ''})" if flagged.size else "none flagged now")
        later = np.flatnonzero(np.isfinite(d) & (d > 0))
        if later.size:
            first = later[np.argmin(d[later])]
            head += (f"; {later.size}{' more' if flagged.size else ''} within the horizon, the first "
                     f"{ds.wheel.values[first]} after "
                     f"{_km(d[first])} km (at {m_s_to_kmh(float(ds.detector_speed.values[first, k])):g} km/h), "
                     f"{int(np.sum(d[later] < action[later]))} before their action")
        else:
            head += "; no other within the horizon"
        lines.append(head)
    return lines


def _car_key(car):
    """Cars in their natural order: numbers by value, then names."""
    return (0, float(car), "") if car.replace(".", "", 1).isdigit() else (1, 0.0, car)


def _positions(ds):
    """``(cars, rows, index)``: the cars in order, the ``(axle, side)`` rows, and each wheel's
    ``(row, column)``."""
    cars = sorted({str(c) for c in ds.car.values}, key=_car_key)
    rows = [(a, s) for a in range(1, int(ds.axle.max()) + 1) for s in ("L", "R")]
    index = [(rows.index((int(a), str(s))), cars.index(str(c))) for a, s, c in
             zip(ds.axle.values, ds.side.values, ds.car.values)]
    return cars, rows, index


def _recommended(ds):
    return ds.distance_to_action.sel(growth=ds.attrs["recommended_growth"]).values


def figure_actions(ds):
    """Histogram of the distance to the next action (10³ km) at the recommended growth, split
    into turnings and replacements, with the band's fastest and slowest growth as outlines and
    30 days, 90 days and a year at the daily mileage marked; days on the top axis."""
    from matplotlib.figure import Figure

    a = ds.attrs
    daily = a["daily_km"]
    d = _recommended(ds) / 1e3
    early, late = ds.distance_to_action_early.values / 1e3, ds.distance_to_action_late.values / 1e3
    finite = np.concatenate([v[np.isfinite(v)] for v in (d, early, late)])
    top = max(float(finite.max()) if finite.size else 1.0, 365 * daily / 1e3 * 1.05)
    bins = np.linspace(0, top * 1.02, 31)
    fig = Figure(figsize=(8, 4.8), layout="constrained")
    ax = fig.subplots()
    action = ds.action.values
    groups = [(d[(action == k) & np.isfinite(d)], label, colour) for k, label, colour in
              ((TURN, "turn", "C0"), (REPLACE, "replace", "C3"))]
    ax.hist([x for x, _, _ in groups], bins=bins, stacked=True, color=[c for _, _, c in groups],
            label=[f"{label} ({x.size}), growth x{a['recommended_growth']:g}" for x, label, c in groups])
    g = ds.growth.values
    ax.hist(early[np.isfinite(early)], bins=bins, histtype="step", color="k", ls="--", lw=1,
            label=f"earliest over the band (x{g.max():g})")
    ax.hist(late[np.isfinite(late)], bins=bins, histtype="step", color="0.5", ls=":", lw=1.2,
            label=f"latest over the band (x{g.min():g})")
    for days, text in ((30, "30 d"), (90, "90 d"), (365, "1 year")):
        x = days * daily / 1e3
        if x <= bins[-1]:
            ax.axvline(x, color="C2", lw=0.8, ls="-.")
            ax.annotate(text, (x, 1), xycoords=("data", "axes fraction"), xytext=(2, -12), textcoords="offset points",
                        fontsize="small", color="C2")
    none = int(np.sum(~np.isfinite(d)))
    ax.set(xlabel="distance from the measurement to the next action (10³ km)", ylabel="wheels",
           title=f"{ds.sizes['wheel']} wheels under {a['policy_name']}"
                 + (f"; {none} with no action within {a['horizon_km'] / 1e3:,.0f} 10³ km" if none else ""))
    ax.set_xlim(0, bins[-1])
    ax.set_ylim(0, ax.get_ylim()[1] * 1.25)  # room for the legend
    top_axis = ax.secondary_xaxis("top", functions=(lambda x: x * 1e3 / daily, lambda t: t * daily / 1e3))
    top_axis.set_xlabel(f"days at {daily:g} km a day")
    ax.legend(fontsize="small", loc="upper right")
    return fig


def figure_cars(ds):
    """Heat map of the distance to the next action (10³ km, recommended growth) by car (columns)
    and axle and side (rows); replacements crossed, wheels with no action within the horizon and
    places with no wheel read shown apart."""
    from matplotlib.figure import Figure
    from matplotlib.patches import Patch
    import matplotlib as mpl

    cars, rows, index = _positions(ds)
    d = _recommended(ds) / 1e3
    grid = np.full((len(rows), len(cars)), np.nan)
    for (r, c), value in zip(index, d):
        grid[r, c] = value
    finite = d[np.isfinite(d)]
    vmax = float(finite.max()) if finite.size else 1.0
    shown = np.where(np.isinf(grid), vmax * 10, grid)
    cmap = mpl.colormaps["viridis"].with_extremes(over="#d9d9d9", bad="white")
    width = min(max(6.0, 0.45 * len(cars) + 2.5), 16.0)
    fig = Figure(figsize=(width, 1.2 + 0.38 * len(rows) + 1.2), layout="constrained")
    ax = fig.subplots()
    image = ax.pcolormesh(np.arange(len(cars) + 1), np.arange(len(rows) + 1), np.ma.masked_invalid(shown), cmap=cmap,
                          vmin=0, vmax=vmax, edgecolors="white", linewidth=0.5)
    colourbar = fig.colorbar(image, ax=ax, extend="max" if np.isinf(grid).any() else "neither")
    colourbar.set_label("distance to the next action (10³ km)")
    replace = [(c, r) for (r, c), act in zip(index, ds.action.values) if act == REPLACE]
    if replace:
        ax.plot([c + 0.85 for c, _ in replace], [r + 0.25 for _, r in replace], "x", color="C3", ms=7, mew=1.5,
                ls="none", label="replace")
    if len(cars) <= 16:
        for r in range(len(rows)):
            for c in range(len(cars)):
                if np.isfinite(grid[r, c]):
                    ax.text(c + 0.5, r + 0.5, f"{grid[r, c]:.0f}", ha="center", va="center", fontsize="x-small",
                            color="white" if grid[r, c] < 0.6 * vmax else "black")
    handles = ax.get_legend_handles_labels()[0]
    handles += [Patch(facecolor="#d9d9d9", label=f"no action within {ds.attrs['horizon_km'] / 1e3:,.0f} 10³ km"),
                Patch(facecolor="white", edgecolor="0.6", label="no wheel read")]
    step = max(1, len(cars) // 40)
    ax.set_xticks(np.arange(0, len(cars), step) + 0.5, [cars[k] for k in range(0, len(cars), step)],
                  rotation=90 if len(cars) > 16 else 0)
    ax.set_yticks(np.arange(len(rows)) + 0.5, [f"axle {a} {s}" for a, s in rows])
    ax.invert_yaxis()
    ax.set(xlabel="car", title=f"next action by car and axle ({ds.attrs['policy_name']}, growth "
                                 f"x{ds.attrs['recommended_growth']:g})")
    ax.legend(handles=handles, fontsize="small", loc="upper center", bbox_to_anchor=(0.5, -0.16 if len(cars) <= 16 else -0.3),
              ncol=3, frameon=False)
    return fig


def figure_orders(ds):
    """Order map: the level of each polygon order (dB re 1 µm) of each wheel now, wheels by car,
    axle and side; each wheel's dominant order and the order its rates grow fastest at its
    diameter marked."""
    from matplotlib.figure import Figure

    cars, rows, index = _positions(ds)
    order = np.lexsort(([r for r, _ in index], [c for _, c in index]))
    dominant, selected = ds.dominant_order.values[order], ds.selected_order.values[order]
    top = int(min(ds.sizes["order"], max(24, int(1.5 * max(dominant.max(), selected.max())))))
    level = ds.order_level.values[order][:, :top]
    finite = level[np.isfinite(level)]
    vmax = float(finite.max()) if finite.size else 0.0
    n = level.shape[0]
    fig = Figure(figsize=(8, min(3.0 + 0.12 * n, 11.0)), layout="constrained")
    ax = fig.subplots()
    image = ax.pcolormesh(np.arange(0.5, top + 1), np.arange(n + 1), np.ma.masked_invalid(level), cmap="magma",
                          vmin=vmax - ORDER_MAP_RANGE_DB, vmax=vmax)
    fig.colorbar(image, ax=ax, extend="min").set_label("level now (dB re 1 µm)")
    y = np.arange(n) + 0.5
    ax.plot(dominant, y, "o", mfc="none", mec="cyan", ms=4 if n <= 60 else 2, ls="none", label="dominant order now")
    ax.plot(selected, y, "|", color="lime", ms=6 if n <= 60 else 3, ls="none",
            label="fastest-growing order at the wheel's diameter")
    car_of = [cars[index[w][1]] for w in order]
    starts = [k for k in range(n) if k == 0 or car_of[k] != car_of[k - 1]]
    step = max(1, len(starts) // 30)
    ax.set_yticks([s + 0.5 for s in starts[::step]], [f"car {car_of[s]}" for s in starts[::step]], fontsize="small")
    for s in starts[1:]:
        ax.axhline(s, color="white", lw=0.4)
    ax.set_ylim(n, 0)
    ax.set(xlabel="polygon order (maxima round the wheel)", xlim=(0.5, top + 0.5),
           title=f"order map: {n} wheels, each car's wheels by axle and side")
    ax.legend(fontsize="small", loc="upper center", bbox_to_anchor=(0.5, -0.08 if n > 60 else -0.12), ncol=2,
              frameon=False)
    return fig


LOAD_FIGURE = "fleet-load"
DETECTOR_MARKERS = "osD^vP"


def figure_load(ds):
    """Left: the peak vertical force now (kN) of each wheel (rows, by car, axle and side) at each
    speed, coloured against the static load and the detector thresholds (ticked on the colour
    bar; a cell over the lowest threshold is outlined). Right: the distance at which each wheel's
    grown shape passes each threshold (10³ km, growth band as a line), beside its next action."""
    from matplotlib.colors import Normalize
    from matplotlib.figure import Figure
    from matplotlib.patches import Rectangle

    cars, rows, index = _positions(ds)
    order = np.lexsort(([r for r, _ in index], [c for _, c in index]))
    n, kmh = order.size, ds.speed_kmh.values
    now = ds.peak_force_now.values[order] / 1e3
    thresholds = ds.threshold.values / 1e3
    static = float(ds.static_load) / 1e3
    names = [str(x) for x in ds.wheel.values[order]]
    fig = Figure(figsize=(11, min(3.2 + 0.22 * n, 14.0)), layout="constrained")
    left, right = fig.subplots(1, 2, width_ratios=(1, 1.3))
    top = float(np.nanmax(now))
    # the colours span the fleet's peaks (a scale up to 400 kN would leave every wheel of a metro one colour);
    # a threshold within them is marked on the colour bar, and the title says how far the highest is from the lowest
    image = left.pcolormesh(np.arange(kmh.size + 1), np.arange(n + 1), now, cmap="inferno",
                            norm=Normalize(vmin=static, vmax=max(top, static * 1.01)), edgecolors="white", linewidth=0.3)
    bar = fig.colorbar(image, ax=left, location="bottom", pad=0.02, aspect=30, extend="max")
    bar.set_label(f"peak vertical force now (kN), from the static load {static:.1f} kN")
    for t in thresholds[thresholds <= top]:
        bar.ax.axvline(t, color="cyan", lw=1.5)
    lowest = float(thresholds.min())
    over = now > lowest
    for r, c in zip(*np.nonzero(over)):
        left.add_patch(Rectangle((c, r), 1, 1, fill=False, edgecolor="cyan", lw=1.5))
    if n <= 40 and kmh.size <= 12:
        for r in range(n):
            for c in range(kmh.size):
                left.text(c + 0.5, r + 0.5, f"{now[r, c]:.0f}", ha="center", va="center", fontsize="xx-small",
                          color="white" if now[r, c] < static + 0.6 * (top - static) else "black")
    step = max(1, n // 40)
    left.set_yticks(np.arange(0, n, step) + 0.5, names[::step], fontsize="x-small")
    left.set_xticks(np.arange(kmh.size) + 0.5, [f"{v:g}" for v in kmh])
    left.set_ylim(n, 0)
    left.set(xlabel="speed (km/h)", title=f"peak force now (kN): the highest {top:.0f} kN is {top / lowest:.0%} of the\n"
                                          f"lowest threshold ({lowest:.0f} kN){'; over it: outlined' if over.any() else ''}")
    g = float(ds.attrs["recommended_growth"])
    gi = int(np.argmin(np.abs(ds.growth.values - g)))
    y = np.arange(n) + 0.5
    for k in range(ds.sizes["detector"]):
        d = ds.distance_to_detector.values[order, k] / 1e3
        offset = (k - (ds.sizes["detector"] - 1) / 2) * 0.15
        shown = np.isfinite(d[:, gi])
        colour = f"C{k + 1}"
        reach = np.where(np.isfinite(d), d, ds.attrs["horizon_km"] / 1e3)  # a band beyond the horizon ends there
        right.hlines(y[shown] + offset, reach[shown].min(axis=1), reach[shown].max(axis=1), color=colour, lw=1,
                     alpha=0.6)
        right.plot(d[shown, gi], y[shown] + offset, DETECTOR_MARKERS[k % len(DETECTOR_MARKERS)], color=colour, ms=4,
                   ls="none", label=f"{ds.detector_who.values[k]} {thresholds[k]:.0f} kN")
    action = ds.distance_to_action.values[order, gi] / 1e3
    fin = np.isfinite(action)
    right.plot(action[fin], y[fin], "|", color="k", ms=9, mew=1.5, ls="none", label="next action (policy)")
    right.set_yticks(np.arange(0, n, step) + 0.5, names[::step], fontsize="x-small")
    right.set_ylim(n, 0)
    right.set_xlim(left=0)
    right.set(xlabel=f"distance from the measurement (10³ km), growth x{g:g}; line: band "
                     f"x{ds.growth.values.max():g} to x{ds.growth.values.min():g}",
              title="when the grown shape passes each threshold (no turning)")
    right.grid(axis="x", alpha=0.3)
    right.legend(fontsize="x-small", loc="upper center", bbox_to_anchor=(0.5, -0.06), ncol=3, frameon=False)
    fig.suptitle(f"dynamic wheel load of {n} wheels: {ds.attrs['scenario_name']}, static load {static:.1f} kN")
    return fig


def draw_figures(ds, directory, fmt="png", dpi=120):
    """The fleet's figures in ``directory`` (the load figure where ``ds`` holds the dynamic load);
    returns their paths."""
    from pathlib import Path

    from railwear import plots

    makers = list(zip(FIGURES, (figure_actions, figure_cars, figure_orders)))
    if "peak_force_now" in ds:
        makers.append((LOAD_FIGURE, figure_load))
    return [plots.save(make(ds), Path(directory) / f"{name}.png", fmt, dpi) for name, make in makers]


def html_report(ds, path, figures=()):
    """``fleet.html``: the summary, a row per wheel, the figures embedded, the refusals, the policy
    and its source, and the scenario, in one file a planner can send; returns its path."""
    from railwear import report as pages

    rows = table_rows(ds)
    keys = ["wheel_id", "car", "axle", "side", "diameter_mm", "peak_to_peak_um", "dominant_order", "action",
            "to_action_km", "to_action_early_km", "to_action_late_km", "action_date", "reason"]
    keys += [k for k in rows[0] if k.startswith("peak_now_") or k == "flagged_now_by"
             or (k.startswith("to_") and k.endswith("kN_km"))]
    table = [[_html_cell(r[k]) for k in keys] for r in rows]
    a = ds.attrs
    blocks = [("p", f"policy {a['policy_name']}: {a['policy_source']}"), ("h2", "Summary"), ("pre", report(ds)),
              ("h2", f"Wheels ({len(rows)}; every column in {TABLE})"), ("table", (keys, table))]
    if "load_method" in a:
        blocks += [("h2", "The dynamic wheel load"), ("p", a["load_method"]),
                   ("table", (("detector", "threshold (kN)", "who", "action", "source"),
                              [(str(ds.detector.values[k]), f"{ds.threshold.values[k] / 1e3:.0f}",
                                str(ds.detector_who.values[k]), str(ds.detector_action.values[k]),
                                str(ds.detector_source.values[k])) for k in range(ds.sizes["detector"])]))]
    return pages.write_page(path, f"railwear fleet: {a['manifest']} under {a['policy_name']}", blocks, figures,
                            scenario=a.get("scenario", ""))


def _html_cell(value):
    if isinstance(value, float):
        if np.isnan(value):
            return "-"
        return "beyond the horizon" if np.isinf(value) else f"{value:,.1f}" if abs(value) < 1e4 else f"{value:,.0f}"
    return str(value)


def write(ds, directory, fmt="png", dpi=120, figures=True):
    """``fleet.nc``, ``fleet.txt``, ``wheels.csv``, (with ``figures``) ``fleet-actions``,
    ``fleet-cars``, ``fleet-orders`` (and ``fleet-load`` with the dynamic load), and ``fleet.html``
    (all of it in one file) in ``directory``, each written atomically; returns their paths."""
    from pathlib import Path

    from railwear import results

    directory = Path(directory)
    paths = [results.write_netcdf(ds, directory / "fleet.nc"), results.write_text(report(ds), directory / TEXT),
             results.write_text(csv_text(ds), directory / TABLE)]
    drawn = draw_figures(ds, directory, fmt, dpi) if figures else []
    paths += drawn
    paths.append(html_report(ds, directory / HTML, drawn))
    return paths
