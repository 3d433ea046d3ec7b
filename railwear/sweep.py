"""Parameter sweeps: many scenarios as one study, on local worker processes or a Dask cluster (layer 4).

A sweep varies numeric scenario fields (dotted paths such as ``operation.speed_kmh``) over a grid,
a list or a Latin hypercube. Every point is a full scenario, validated like a file. Each finished
point is written to ``STORE/points/KEY.nc`` (``KEY`` from the point's scenario hash) as it
completes, so a sweep that is stopped and run again computes only what is missing; a point that
fails is recorded with its error and the others go on.
"""

import os
from concurrent.futures import ProcessPoolExecutor, as_completed
from dataclasses import dataclass
from itertools import product
from pathlib import Path

import numpy as np
import xarray as xr

from railwear.errors import OptionError, RailwearError, ScenarioError
from railwear.measured import BLANK, NUMBER
from railwear.scenario import SPEED_FIELDS, Scenario, field_table, scenario_hash, set_field, to_toml, validated
from railwear.api import SPEED_KMH_DECIMALS
from railwear.units import GPA, KN, m_s_to_kmh

POINT_SCALARS = {
    "dominant_order": ("1", "order of the largest harmonic at the end"),
    "maxima": ("1", "radius maxima round the wheel at the end"),
    "limit_distance": ("km", "distance to the out-of-roundness limit (peak to peak)"),
    "limit_months": ("months", "time to the out-of-roundness limit at the scenario's daily mileage"),
    "distance_run": ("km", "distance the run went"),
    "dominant_growth_per_10000_km": ("percent", "growth of the dominant order per 10 000 km"),
    "max_removed_depth": ("m", "largest radius lost (most worn spot)"),
    "peak_to_peak": ("m", "peak-to-peak deviation at the end"),
    "peak_to_peak_initial": ("m", "peak-to-peak deviation at the start"),
    "stop_time": ("1", "normed time at which the run stopped"),
    "spectral_tail": ("1", "top quarter of the kept orders over the largest amplitude (resolution)"),
}
INTEGERS = ("dominant_order", "maxima")  # stored as integers; FAILED where the point did not run
OPTIONAL = ("limit_distance", "limit_months", "distance_run", "dominant_growth_per_10000_km")  # where the runs give them
FAILED = -1
NOT_REACHED = "the out-of-roundness limit was not reached within the run (see distance_run)"
FAILED_POINT = "the point failed (see error)"


@dataclass(frozen=True)
class Vary:
    """A varied field: explicit ``values``, or a ``[low, high]`` range for random designs."""

    field: str
    values: tuple
    low: float
    high: float


MAX_VALUES = 10000  # values of one range: more is a typo in STEP, not a study


def _number(text):
    """The finite number ``text`` spells (blanks round it allowed); else ValueError."""
    text = text.strip(BLANK)
    if not NUMBER.fullmatch(text) or not np.isfinite(float(text)):
        raise ValueError
    return float(text)


def parse_values(spec, what):
    """``A:B:STEP`` (B included) or ``v1,v2,...`` as an array of finite numbers; anything else
    (a STEP of zero, NaN, more than :data:`MAX_VALUES` values) is an :class:`OptionError` naming ``what``."""
    try:
        if ":" in spec:
            a, b, step = (_number(p) for p in spec.split(":"))
            if not (step > 0 and b >= a) or (b - a) / step >= MAX_VALUES:
                raise ValueError
            values = np.arange(a, b + step / 2, step)
        else:
            values = np.array([_number(p) for p in spec.split(",")])
        if not (0 < values.size <= MAX_VALUES and np.all(np.isfinite(values))):
            raise ValueError
    except ValueError:
        raise OptionError(f"{what}: expected A:B:STEP with STEP > 0, B >= A and at most {MAX_VALUES} "
                          f"values, or a list v1,v2,... of numbers; got {spec!r}") from None
    return values


def parse_vary(text):
    """``NAME=A:B:STEP`` (B included), ``NAME=v1,v2,...`` or ``NAME=A:B``, a range with no values
    that only a random design (:func:`design` with ``samples``) can use."""
    name, sep, spec = text.partition("=")
    name = name.strip()
    if not sep or not name or not spec:
        raise OptionError(f"--vary {text!r}: expected NAME=A:B:STEP, NAME=v1,v2,... or NAME=A:B (with --samples)")
    if spec.count(":") == 1:
        try:
            low, high = (_number(p) for p in spec.split(":"))
            if not high >= low:
                raise ValueError
        except ValueError:
            raise OptionError(f"--vary {name}: expected A:B with B >= A (with --samples), A:B:STEP or "
                              f"v1,v2,...; got {spec!r}") from None
        return Vary(name, (), low, high)
    values = parse_values(spec, f"--vary {name}")
    return Vary(name, tuple(float(v) for v in values), float(values.min()), float(values.max()))


def _assign(base: Scenario, assignment: dict):
    """The plain data of ``base`` with dotted fields set; a name that is no numeric scenario
    field is an :class:`OptionError` (the sweep's specification, not one point, is wrong)."""
    data = base.applicable(mode="python", exclude_none=False)
    for path, value in assignment.items():
        node, key = field_table(data, path, "--vary")
        if key not in node and not (path in SPEED_FIELDS):
            raise OptionError(f"--vary {path}: no such scenario field")
        current = node.get(key)
        if current is not None and (isinstance(current, bool) or not isinstance(current, (int, float))):
            raise OptionError(f"--vary {path}: not a numeric field")
        set_field(data, path, int(round(value)) if isinstance(current, int) else float(value), "--vary")
    return data


def with_values(base: Scenario, assignment: dict):
    """The scenario ``base`` with dotted fields set, validated again (errors name the field)."""
    return validated(Scenario, _assign(base, assignment), "sweep point")


def design(varies, samples=None, seed=0):
    """Points of the sweep: ``(coords, assignments)``.

    Without ``samples`` the grid of all combinations, ``coords`` a dict ``field -> values``; with
    ``samples`` a Latin hypercube of that many points over each field's ``[low, high]``
    (scipy.stats.qmc), ``coords`` a dict ``field -> array over 'sample'``.
    """
    fields = [v.field for v in varies]
    if len(set(fields)) != len(fields):
        raise OptionError("--vary names a field twice")
    if samples is None:
        for v in varies:
            if not v.values:
                raise OptionError(f"--vary {v.field}: a range A:B has no values for a grid; give A:B:STEP or "
                                  f"v1,v2,..., or --samples N for a Latin hypercube over it")
        coords = {v.field: np.array(v.values) for v in varies}
        points = [dict(zip(fields, combo)) for combo in product(*(v.values for v in varies))]
        return coords, points
    if isinstance(samples, bool) or not isinstance(samples, (int, np.integer)) or not 1 <= samples <= MAX_VALUES:
        raise OptionError(f"--samples must be a whole number from 1 to {MAX_VALUES}, got {samples!r}")
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or not 0 <= seed < 2**63:
        raise OptionError(f"--seed must be a whole number >= 0, got {seed!r}")
    from scipy.stats import qmc

    unit = qmc.LatinHypercube(d=len(varies), seed=seed).random(samples)
    lows = np.array([v.low for v in varies])
    highs = np.array([v.high for v in varies])
    values = lows + unit * (highs - lows)
    coords = {f: values[:, i] for i, f in enumerate(fields)}
    return coords, [dict(zip(fields, row)) for row in values]


def point_key(scenario):
    return scenario_hash(scenario)[:16]


def _bad_key(assignment):
    """The key of a point whose scenario is invalid (it has no scenario hash)."""
    import hashlib
    import json

    return "invalid-" + hashlib.sha256(json.dumps(assignment, sort_keys=True).encode()).hexdigest()[:8]


def run_point(task):
    """Run one point in a worker: ``task`` is ``(scenario_toml, path or None)``.

    Returns the reduced result; with a path (a store the worker shares) the worker writes it there
    too, so that the process collecting the points does not do all the writing.
    """
    from railwear import api, results
    from railwear.scenario import parse_scenario

    scenario_toml, path = task
    ds = reduce_result(api.run(parse_scenario(scenario_toml, source="sweep point")))
    if path is not None:
        results.write_netcdf(ds, path)
    return ds


def reduce_result(ds):
    """The part of a run a sweep keeps: final deviation, spectrum, regime and scalars, with the
    answers in the planner's units: the distance run and to the out-of-roundness limit (km; NaN
    where the run did not reach it) and the dominant order's growth per 10 000 km (percent; NaN
    where it has none worth stating, :func:`railwear.results.growth_note`)."""
    from railwear import results
    from railwear.longterm.spectra import UNDEFINED

    keep = ["amplitude", "regime", "peak_to_peak_limit", *POINT_SCALARS]
    derived = ("max_removed_depth", "limit_distance", "limit_months", "distance_run", "dominant_growth_per_10000_km")
    out = ds[[k for k in keep if k in ds and k not in derived]]
    out["max_removed_depth"] = ds.removed_depth.isel(time=-1, drop=True).assign_attrs(
        units="m", long_name=POINT_SCALARS["max_removed_depth"][1])
    life = float(ds.attrs.get("life_distance_km", 0.0))
    if life > 0 and "stop_time" in ds:
        run = (ds.stop_time * life).assign_attrs(units="km", long_name=POINT_SCALARS["distance_run"][1])
        out["distance_run"] = run
        if "peak_to_peak_limit" in ds:
            reached = ds.peak_to_peak >= ds.peak_to_peak_limit * (1 - 1e-9)
            out["limit_distance"] = run.where(reached).assign_attrs(
                units="km", long_name=POINT_SCALARS["limit_distance"][1],
                **({} if bool(reached.all()) else {UNDEFINED: NOT_REACHED}))
            daily = results.daily_distance_km(ds)
            if daily:  # [operation] daily_distance_km: the same in months of service
                out["limit_months"] = (out["limit_distance"] / (daily * results.DAYS_PER_MONTH)).assign_attrs(
                    units="months", long_name=POINT_SCALARS["limit_months"][1],
                    **({} if bool(reached.all()) else {UNDEFINED: NOT_REACHED}))
        growth, notes = [], []
        for _, d in results._runs(ds):
            value, note = (float("nan"), results.ROUND_WHEEL) if results.is_round(float(d.peak_to_peak)) else \
                results.order_growth(d, int(d.dominant_order), life)
            growth.append(100.0 * value)
            notes.append(note)
        dims = ds.dominant_order.dims
        out["dominant_growth_per_10000_km"] = (dims, np.reshape(growth, ds.dominant_order.shape), {
            "units": "percent", "long_name": POINT_SCALARS["dominant_growth_per_10000_km"][1],
            **({UNDEFINED: "; ".join(dict.fromkeys(n for n in notes if n))} if any(notes) else {})})
    out["u_final"] = (ds.u.isel(time=-1, drop=True) - ds.u.isel(time=-1, drop=True).mean("angle")).assign_attrs(
        units="m", long_name="radius deviation less its mean at the end")
    out = out.drop_vars([c for c in ("distance", "time") if c in out.coords])
    out.attrs = {k: ds.attrs[k] for k in ("scenario", "scenario_hash", "railwear_version") if k in ds.attrs}
    return out


def warm_up(seconds):
    """Import railwear and load its compiled solver in a worker; hold it ``seconds`` so that every
    worker of a pool gets one."""
    import time

    from railwear.pde import Cubic, solve_evolution

    solve_evolution(np.cos(np.arange(16) * np.pi / 8), 0.01, Cubic(c1=0.1), n_save=2)
    time.sleep(seconds)
    return os.getpid()


def _exit_with_parent(parent):
    """In a worker: exit as soon as the process that started it is gone (a sweep killed with
    ``kill -9`` cannot stop its workers, which would go on writing points)."""
    import threading
    import time

    def watch():
        while os.getppid() == parent:
            time.sleep(0.5)
        os._exit(1)

    threading.Thread(target=watch, daemon=True).start()


class LocalExecutor:
    """Worker processes on this machine (``workers`` defaults to the number of cores).

    The workers are started, and railwear imported and its compiled loop loaded in each, when the
    executor is made, so that the first points do not pay for it.
    """

    shares_disk = True

    def __init__(self, workers=None):
        import multiprocessing

        self.workers = workers or os.cpu_count() or 1
        self.pool = ProcessPoolExecutor(self.workers, mp_context=multiprocessing.get_context("spawn"),
                                        initializer=_exit_with_parent, initargs=(os.getpid(),))
        for f in [self.pool.submit(warm_up, 0.5) for _ in range(self.workers)]:
            f.result()

    def submit(self, fn, arg, key):
        return self.pool.submit(fn, arg)

    def as_completed(self, futures):
        return as_completed(futures)

    def close(self):
        self.pool.shutdown(cancel_futures=True)


class SerialExecutor:
    """In this process, one point after the other, each run as the sweep asks for its result."""

    shares_disk = True

    class _Deferred:
        def __init__(self, fn, arg):
            self.fn, self.arg = fn, arg

        def result(self):
            return self.fn(self.arg)

    def submit(self, fn, arg, key):
        return self._Deferred(fn, arg)

    def as_completed(self, futures):
        return iter(futures)

    def close(self):
        """Nothing to release: the points ran in this process."""


class DaskExecutor:
    """A Dask distributed cluster at ``address`` (``tcp://HOST:PORT``) or from a scheduler file.

    Tasks of a lost worker are retried ``retries`` times by Dask. The workers may be on other
    machines, so the points come back to be written here.
    """

    shares_disk = False

    def __init__(self, address=None, scheduler_file=None, retries=2):
        from distributed import Client

        self.client = Client(address, scheduler_file=scheduler_file, set_as_default=False)
        self.retries = retries

    def submit(self, fn, arg, key):
        return self.client.submit(fn, arg, key=f"railwear-{key}", retries=self.retries, pure=False)

    def as_completed(self, futures):
        from distributed import as_completed as dask_completed

        return dask_completed(futures, loop=self.client.loop)

    def close(self):
        self.client.close()


def _point_path(store, key):
    return store / "points" / f"{key}.nc"


def _write_point(store, key, ds):
    from railwear import results

    results.write_netcdf(ds, _point_path(store, key))


def _batched_speeds(base, varies, samples):
    """Whether the sweep is a grid over the speed alone, which one batched solve does best."""
    return samples is None and len(varies) == 1 and varies[0].field in SPEED_FIELDS and \
        isinstance(base.operation.speeds, float) and base.strategy.batches_speeds


def run_sweep(base: Scenario, varies, store, samples=None, seed=0, executor=None, progress=None,
              batch="auto"):
    """Run every point of the design; returns the combined Dataset (also ``STORE/sweep.nc``).

    ``batch`` ('auto', True, False): a grid over the speed alone runs as one batched solve.
    """
    from railwear import api, results

    store = Path(store)
    coords, assignments = design(varies, samples, seed)
    scenarios, errors = [], {}
    for a in assignments:  # a bad specification fails here, before anything is written
        data = _assign(base, a)
        try:
            scenarios.append(validated(Scenario, data, "sweep point"))
        except ScenarioError as e:  # this point is outside a field's bounds: recorded, the rest run
            scenarios.append(str(e))
    keys = [point_key(s) if isinstance(s, Scenario) else _bad_key(a) for s, a in zip(scenarios, assignments)]
    (store / "points").mkdir(parents=True, exist_ok=True)
    results.clean_partial(store / "points")
    results.clean_partial(store)
    done = {}
    for k in set(keys):
        path = _point_path(store, k)
        if path.exists():
            try:
                done[k] = results.read_netcdf(path)
            except (OSError, ValueError):  # a point file cut short: computed again
                path.unlink(missing_ok=True)
    todo = [(k, s) for k, s in dict(zip(keys, scenarios)).items() if k not in done and isinstance(s, Scenario)]
    count = [len(keys) - len(todo)]
    errors.update({k: s for k, s in zip(keys, scenarios) if isinstance(s, str)})

    def finished(key, ds=None, error=None, written=False):
        count[0] += 1
        if error is None:
            if not written:
                _write_point(store, key, ds)
            done[key] = ds
            (store / "points" / f"{key}.error").unlink(missing_ok=True)
        else:
            errors[key] = error
            results.write_text(error + "\n", store / "points" / f"{key}.error")
        if progress is not None:
            progress(count[0] / len(keys))

    use_batch = bool(todo) and (batch is True or (batch == "auto" and _batched_speeds(base, varies, samples)))
    if use_batch:
        field = varies[0].field
        values = np.array([assignments[keys.index(k)][field] for k, _ in todo])
        order = np.argsort(values)
        data = base.applicable(mode="python", exclude_none=False)
        section = field.split(".")[-1]
        data["operation"][section] = [float(values[j]) for j in order]
        data["operation"][SPEED_FIELDS[1 - SPEED_FIELDS.index(field)].split(".")[-1]] = None
        try:
            reduced = reduce_result(api.run(validated(Scenario, data, "sweep batch")))
            for i, j in enumerate(order):
                key, sc = todo[j]
                point = reduced.isel(speed=i)
                point.attrs.update(scenario=to_toml(sc), scenario_hash=scenario_hash(sc))
                finished(key, point)
            todo = []
        except RailwearError:
            pass  # one row failed the whole batch: fall back to points, which record it alone
    if todo:
        own = executor is None
        executor = executor or LocalExecutor()
        try:
            shared = executor.shares_disk
            futures = {executor.submit(run_point, (to_toml(s), _point_path(store, k) if shared else None), k): k
                       for k, s in todo}
            for future in executor.as_completed(list(futures)):
                key = futures[future]
                try:
                    finished(key, future.result(), written=shared)
                except Exception as e:  # noqa: BLE001  (a failing point must not stop the sweep)
                    finished(key, error=f"{type(e).__name__}: {e}")
        finally:
            if own:
                executor.close()
    combined = with_speeds(combine(coords, keys, done, errors, samples is not None), base, coords, samples is not None)
    combined.attrs.update(base_scenario=to_toml(base), base_scenario_hash=scenario_hash(base), base_scenario_name=base.name,
                          design="latin hypercube" if samples else "grid", seed=seed)
    results.write_netcdf(combined, store / "sweep.nc")
    return combined


def with_speeds(ds, base, coords, random_design):
    """The sweep's speed by the convention of every result file, ``speed`` in m s-1 with
    ``speed_kmh`` in km h-1 beside it: over the varied speed field's dimension (``sample`` in a
    random design), else the base scenario's one speed. Variables, not coordinates: the
    coordinates of ``sweep.nc`` are the varied fields."""
    from railwear.api import speed_coordinates
    from railwear.units import kmh_to_m_s

    varied = [f for f in SPEED_FIELDS if f in coords]
    if varied:
        values = np.asarray(coords[varied[0]], float)
        dim = "sample" if random_design else varied[0]
        speeds = speed_coordinates(xr.Dataset(), kmh_to_m_s(values) if varied[0].endswith("_kmh") else values, dim)
    elif isinstance(base.operation.speeds, float):
        speeds = speed_coordinates(xr.Dataset(), base.operation.speeds)
    else:  # a batch of speeds in every point: each point's result has them
        return ds
    return ds.assign({name: speeds[name].variable for name in ("speed", "speed_kmh")})


def combine(coords, keys, done, errors, random_design):
    """One Dataset over the sweep dimensions (grid) or ``sample`` (random design)."""
    from railwear.longterm.spectra import UNDEFINED

    fields = list(coords)
    shape = (len(keys),) if random_design else tuple(len(v) for v in coords.values())
    dims = ("sample",) if random_design else tuple(fields)
    some = next(iter(done.values()), None)
    data = {}
    for name, (units, long_name) in POINT_SCALARS.items():
        attrs = {"units": units, "long_name": long_name}
        if name in INTEGERS:  # counts: integers, FAILED where the point did not run
            attrs["long_name"] += f" ({FAILED}: the point failed)"
            values = np.array([int(done[k][name]) if k in done and name in done[k] else FAILED for k in keys])
            data[name] = (dims, values.reshape(shape).astype(np.int64), attrs)
            continue
        values = np.array([float(done[k][name]) if k in done and name in done[k] else np.nan for k in keys])
        if name in OPTIONAL and not any(k in done and name in done[k] for k in keys):
            continue  # no point has it (a run without an out-of-roundness limit has no limit_distance)
        reasons = [done[k][name].attrs.get(UNDEFINED, "") if k in done and name in done[k] else
                   (FAILED_POINT if k in errors else "") for k, v in zip(keys, values) if not np.isfinite(v)]
        reasons = [r for r in dict.fromkeys("; ".join(reasons).split("; ")) if r]
        data[name] = (dims, values.reshape(shape), {**attrs, **({UNDEFINED: "; ".join(reasons)} if reasons else {})})
    if some is not None and "peak_to_peak_limit" in some:
        data["peak_to_peak_limit"] = ((), float(some.peak_to_peak_limit), dict(some.peak_to_peak_limit.attrs))
    data["regime"] = (dims, np.array([str(done[k].regime.values) if k in done else "failed" for k in keys],
                                     dtype=object).reshape(shape).astype(str),
                      {"long_name": "wear regime"})
    data["error"] = (dims, np.array([errors.get(k, "") for k in keys], dtype=object).reshape(shape).astype(str),
                     {"long_name": "error of a failed point (empty when it ran)"})
    coord_vars = {}
    if some is not None:
        n_angle = some.sizes["angle"]
        blank = np.full(n_angle, np.nan)
        finals = [done[k].u_final.values if k in done and done[k].sizes["angle"] == n_angle else blank
                  for k in keys]
        data["u_final"] = (dims + ("angle",), np.array(finals).reshape(shape + (n_angle,)),
                           dict(some.u_final.attrs))
        coord_vars["angle"] = ("angle", some.angle.values, dict(some.angle.attrs))
    for f, values in coords.items():
        coord_vars[f] = (("sample",) if random_design else (f,), np.asarray(values),
                         {"long_name": f"scenario field {f}"})
    return xr.Dataset(data, coords=coord_vars)


def hunting_map(scenario: Scenario, conicity, yaw_stiffness, lateral_stiffness=None):
    """Linear critical speed ``critical_speed`` (m s-1, ``inf`` where stable at every speed; and
    ``critical_speed_kmh`` in km h-1 beside it) of the scenario's wheelset over conicity × yaw
    stiffness (N m/rad) [× lateral stiffness (N/m)].

    The closed form of :func:`railwear.dynamics.linear_critical_speed` (Kalker creep without spin,
    conical wheels), with ``f11`` and ``f22`` per wheel from the Hertz patch at the wheel load.
    """
    from railwear.dynamics import contact_constants, linear_critical_speed

    w, c, ws = scenario.wheel, scenario.contact, scenario.wheelset
    constants = contact_constants(w.static_load_kN * KN, 1 / (2 * w.radius_m), 1 / (2 * c.rail_head_radius_m),
                                  c.youngs_modulus_GPa * GPA, c.poisson)
    conicity = np.atleast_1d(np.asarray(conicity, float))
    yaw = np.atleast_1d(np.asarray(yaw_stiffness, float))
    lateral = np.atleast_1d(np.asarray(ws.lateral_stiffness_N_m if lateral_stiffness is None else lateral_stiffness, float))
    if np.any(conicity <= 0) or np.any(yaw < 0) or np.any(lateral < 0):
        raise OptionError("conicity must be > 0 and the stiffnesses >= 0")
    speed = np.array([[[linear_critical_speed(ws.mass_kg, ws.yaw_inertia_kg_m2, ky, kpsi, constants["f11"],
                                              constants["f22"], ws.half_gauge_m, w.radius_m, lam)
                        for ky in lateral] for kpsi in yaw] for lam in conicity])
    dims, long_name = ("conicity", "yaw_stiffness", "lateral_stiffness"), "linear critical speed of hunting (inf: stable at every speed)"
    ds = xr.Dataset(
        {"critical_speed": (dims, speed, {"units": "m s-1", "long_name": long_name}),
         "critical_speed_kmh": (dims, np.round(m_s_to_kmh(speed), SPEED_KMH_DECIMALS),
                                {"units": "km h-1", "long_name": long_name})},
        coords={"conicity": ("conicity", conicity, {"units": "1", "long_name": "equivalent conicity"}),
                "yaw_stiffness": ("yaw_stiffness", yaw, {"units": "N m rad-1", "long_name": "yaw stiffness of the suspension"}),
                "lateral_stiffness": ("lateral_stiffness", lateral, {"units": "N m-1", "long_name": "lateral stiffness of the suspension"})},
        attrs={"f11": constants["f11"], "f22": constants["f22"], "method": "closed form (Routh-Hurwitz)"},
    )
    return ds.squeeze("lateral_stiffness") if lateral.size == 1 else ds
