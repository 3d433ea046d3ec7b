"""Long-term wear of the wheelset on real profiles: the worn lateral profile and the angular pattern.

The wheelset is :class:`railwear.dynamics.TableWheelsetModel` on a contact table of the wheel
profile (S1002) on the rail (UIC60), :func:`railwear.geometry.contact_table`. Each wheel has a
wear surface (:class:`railwear.geometry.wear_surface.WearSurface`) over angle × lateral position
``s`` on the wheel profile (m, the profile coordinate, positive towards the field side). Between
two output times of the dynamics the frictional energy ``E = ∫ P dt`` of a wheel (trapezoidal) is
removed as the volume ``β E`` (energy law, ``railwear.wear.EnergyLaw.beta``, m³/J) under the Hertz
ellipse of the contact table (semi-axes ``a`` along rolling, ``b`` across, interpolated at the
wheelset's shift), centred at the contact position the table gives and swept along the
circumference over the angle the wheel turned in that interval (at the axle's quasi-static spin
``2 V / (r_L + r_R)``). The removed volume equals ``β ∫ P dt`` to round-off.

Feedback ("the contact geometry sees u"): after each long-term step the wheel profile is worn by
the angle-averaged depth over ``s``, averaged over the two wheels (the contact table is built for
a symmetric wheelset; under hunting and random starts the two wheels wear alike), the contact
table is recomputed from the worn profile and the dynamics continue on it. The angle-dependent
part of the depth is an output only: the table model has no angle round the wheel.

- :class:`WheelsetStepwise` (strategy 3): frozen profile; ``samples`` runs from random initial
  lateral offsets and phases, each ``transient`` seconds thrown away and ``seconds`` gathered;
  the mean depth rate is extrapolated over a long-term step in which the fed lateral profile
  changes by at most ``step_limit`` (m); repeat.
- :class:`WheelsetDirect` (strategy 1): one run, the wear coefficient multiplied by
  ``acceleration``; the surface takes the wear of every interval, the profile and the table are
  updated every ``update_seconds`` of simulated time.

Normed time: ``life_distance`` metres of running are one unit. Both strategies' ``run`` return an
``xarray.Dataset`` with ``worn_depth(distance, wheel, lateral)`` (m, angle-averaged),
``surface_depth(wheel, angle, lateral)`` at the end, the removed and the law's volume, the contact
positions and the largest lateral displacement seen per step, the tables' rolling-radius
difference per step, and the cost (simulated seconds, right-hand sides, tables, wall seconds);
stepwise adds the Monte Carlo standard error of the final worn depth.

Both ``run`` s take ``checkpoint`` (called with a :class:`WheelsetCheckpoint` after every step or
update) and ``resume`` (one such checkpoint of the same problem): the resumed run gives the same
result, bit for bit, as the uninterrupted one.
"""

import time as _time
from dataclasses import dataclass, field, fields, replace

import numpy as np

from railwear.errors import ScenarioError
from railwear.geometry import contact_table, worn_profile
from railwear.geometry.wear_surface import WearSurface, deposit_rectangles, ellipse_footprint
from railwear.longterm.wheel_runs import fingerprint, fraction_done, rng_from_text, rng_state_text, stop_fraction

WHEELS = ("left", "right")


def _default_shifts():
    return tuple(np.round(np.linspace(-0.010, 0.010, 201), 12))


def _default_edges():
    return tuple(np.round(np.linspace(-0.050, 0.040, 181), 12))


def band_width(depth, lateral, fraction=0.9):
    """Width (m) of the central lateral band holding ``fraction`` of the removed volume: the
    distance between the ``(1 - fraction)/2`` and ``(1 + fraction)/2`` quantiles of ``depth``
    (m, on cell centres ``lateral``, equally spaced), the depth constant on each cell."""
    depth = np.clip(np.asarray(depth, float), 0.0, None)
    lateral = np.asarray(lateral, float)
    ds = lateral[1] - lateral[0]
    edges = np.concatenate([lateral - ds / 2, [lateral[-1] + ds / 2]])
    cumulative = np.concatenate([[0.0], np.cumsum(depth)])
    if not cumulative[-1] > 0:
        return 0.0
    cumulative /= cumulative[-1]
    lo, hi = np.interp([(1 - fraction) / 2, (1 + fraction) / 2], cumulative, edges)
    return float(hi - lo)


def sweep_deposit(surface, volume, angle0, angle1, lateral, a, b, footprint="hertz", n=8):
    """Remove ``volume`` (m³, one per interval) under the patch ellipse (semi-axes ``a``, ``b``, m)
    centred at ``lateral`` (m) and swept from ``angle0`` to ``angle1`` (rad): each piece of the
    footprint (:func:`~railwear.geometry.wear_surface.ellipse_footprint`) is stretched along the
    circumference by the distance turned. Returns the volume added (m³)."""
    volume, angle0, angle1, lateral, a, b = (np.asarray(v, float) for v in
                                             np.broadcast_arrays(volume, angle0, angle1, lateral, a, b))
    if np.any(volume < 0) or not np.all(np.isfinite(volume)):
        raise ScenarioError("wear volumes must be finite and >= 0")
    x_lo, x_hi, s_lo, s_hi, share = ellipse_footprint(1.0, 1.0, n, footprint)
    start = np.mod(angle0, 2 * np.pi) * surface.radius
    travel = (angle1 - angle0) * surface.radius
    if np.any(travel < 0) or np.any(travel + 2 * a >= 0.5 * surface.circumference):
        raise ScenarioError("the wheel must turn forwards by less than half a revolution per interval")
    col = (slice(None), None)
    return deposit_rectangles(
        surface.depth, surface.circumference, surface.lateral_edges[0],
        surface.lateral_edges[1] - surface.lateral_edges[0],
        (x_lo * a[col] + start[col]).ravel(), (x_hi * a[col] + (start + travel)[col]).ravel(),
        (s_lo * b[col] + lateral[col]).ravel(), (s_hi * b[col] + lateral[col]).ravel(),
        (share * volume[col]).ravel())


@dataclass(frozen=True)
class WheelsetWear:
    """What both wheelset strategies wear.

    ``model`` a :class:`~railwear.dynamics.TableWheelsetModel` (its speed, suspension and friction
    are used; its table, start and phase are replaced), ``wheel`` and ``rail`` the
    :class:`~railwear.geometry.Profile` s, ``beta`` (m³/J) the energy law's volume per frictional
    energy, ``life_distance`` (m) one unit of normed time, ``shifts`` (m) the lateral shifts of the
    contact tables, ``lateral_edges`` (m) the lateral cells of the wear surface on the wheel
    profile, ``n_angle`` its cells round the wheel, ``transient`` (s) run before wear is gathered,
    ``offsets`` (m) the range of the magnitude of the random initial lateral displacement (its
    sign random too), ``output_rate`` (1/s) output times of the dynamics per simulated second.
    """

    model: object
    wheel: object
    rail: object
    beta: float
    life_distance: float
    shifts: tuple = field(default_factory=_default_shifts)
    lateral_edges: tuple = field(default_factory=_default_edges)
    n_angle: int = 64
    transient: float = 3.0
    offsets: tuple = (1e-3, 3e-3)
    output_rate: float = 2000.0
    footprint: str = "hertz"

    def __post_init__(self):
        for name in ("beta", "life_distance", "output_rate"):
            value = getattr(self, name)
            if not (np.isfinite(value) and value > 0):
                raise ScenarioError(f"{name} must be finite and > 0, got {value}")
        if not (np.isfinite(self.transient) and self.transient >= 0):
            raise ScenarioError(f"transient must be finite and >= 0 (s), got {self.transient}")
        lo, hi = (float(v) for v in self.offsets)
        if not 0 <= lo <= hi:
            raise ScenarioError(f"offsets must be (low, high) with 0 <= low <= high (m), got {self.offsets}")
        if self.footprint not in ("hertz", "uniform"):
            raise ScenarioError(f"footprint must be 'hertz' or 'uniform', not {self.footprint!r}")
        object.__setattr__(self, "shifts", tuple(float(v) for v in self.shifts))
        object.__setattr__(self, "lateral_edges", tuple(float(v) for v in self.lateral_edges))
        self.new_surface()  # validates the grid

    @property
    def lateral(self):
        """Lateral cell centres (m)."""
        edges = np.asarray(self.lateral_edges)
        return 0.5 * (edges[1:] + edges[:-1])

    def new_surface(self):
        """An unworn :class:`WearSurface` of one wheel at the model's nominal radius."""
        return WearSurface(self.radius, self.n_angle, self.lateral_edges)

    @property
    def radius(self):
        """Nominal rolling radius (m) the surface is laid on: the model's contact table's."""
        return float(self.model.table.attrs["nominal_rolling_radius"])

    def profile(self, depth):
        """The wheel profile worn by ``depth`` (m, removed, on the lateral cell centres; zero
        outside the grid)."""
        removed = np.interp(self.wheel.y, self.lateral, np.asarray(depth, float), left=0.0, right=0.0)
        return worn_profile(self.wheel, -removed)

    def table(self, depth):
        """Contact table of the wheel worn by the lateral ``depth`` (m) on the rail, over ``shifts``."""
        return contact_table(self.profile(depth), self.rail, y=np.asarray(self.shifts))

    def start(self, rng):
        """Random initial lateral displacement (m) and phase (rad)."""
        lo, hi = self.offsets
        offset = rng.uniform(lo, hi) * rng.choice((-1.0, 1.0))
        return float(offset), float(rng.uniform(0.0, 2 * np.pi))

    def run(self, table, seconds, state=None, offset=0.0, cost=None):
        """Run the wheelset on ``table`` for ``seconds`` (s) from ``state`` (or at rest displaced by
        ``offset``, m): ``(dataset, final state)``; the seconds and right-hand sides are added to
        ``cost``."""
        from railwear.dynamics import simulate

        model = replace(self.model, table=table, initial_lateral_displacement=offset, initial_yaw_angle=0.0,
                        initial_lateral_velocity=0.0, initial_yaw_rate=0.0)
        ds = simulate(model, seconds, n_output=max(int(np.ceil(seconds * self.output_rate)), 2) + 1,
                      initial_state=state)
        end = np.array([ds[v].values[-1] for v in ("lateral_displacement", "yaw_angle", "lateral_velocity",
                                                    "yaw_rate")])
        if cost is not None:
            cost["seconds"] += seconds
            cost["rhs"] += ds.attrs["rhs_evaluations"]
        return ds, end

    def settle(self, table, offset, cost):
        """State (or ``None``) after the transient from rest at ``offset`` (m)."""
        return self.run(table, self.transient, offset=offset, cost=cost)[1] if self.transient > 0 else None

    def deposit(self, surfaces, ds, table, phase, factor=1.0):
        """Wear the two ``surfaces`` (left, right) by ``factor β`` times the frictional energy of the
        run ``ds`` on ``table``, the wheel angle starting at ``phase`` (rad) and turning at
        ``2 V / (r_L + r_R)`` (the axle's quasi-static spin, radii from the table). Returns the volume
        added (m³), the law's volume ``factor β ∫ P dt`` (m³) and the end angle (rad)."""
        t = ds.time.values
        shift = -0.5 * (ds.lateral_displacement.values[1:] + ds.lateral_displacement.values[:-1])  # table y: right
        at = {(wheel, v): np.interp(shift, table.y.values, table[v].sel(side=wheel).values)
              for wheel in WHEELS for v in ("a", "b", "rolling_radius")}
        turned = 2 * self.model.speed * np.diff(t) / (at["left", "rolling_radius"] + at["right", "rolling_radius"])
        angle = phase + np.concatenate([[0.0], np.cumsum(turned)])
        added = law = 0.0
        for surface, wheel in zip(surfaces, WHEELS):
            power = ds.frictional_power.sel(wheel=wheel).values
            volume = factor * self.beta * 0.5 * (power[1:] + power[:-1]) * np.diff(t)
            position = ds.contact_lateral_position.sel(wheel=wheel).values
            a, b = at[wheel, "a"], at[wheel, "b"]
            added += sweep_deposit(surface, volume, angle[:-1], angle[1:], 0.5 * (position[1:] + position[:-1]),
                                   a, b, self.footprint)
            law += float(volume.sum())
        return added, law, float(angle[-1])


def _seconds_check(name, value, seed):
    if not (np.isfinite(value) and value > 0):
        raise ScenarioError(f"{name} must be finite and > 0 (s), got {value}")
    if int(seed) != seed or seed < 0:
        raise ScenarioError(f"seed must be a whole number >= 0, got {seed}")


SAVED = ("time", "depth", "volume", "law", "cmin", "cmax", "amplitude", "rrd")


@dataclass(frozen=True)
class WheelsetCheckpoint:
    """State of a wheelset run after ``steps`` steps (stepwise) or updates (direct), in plain
    values and arrays for ``.npz``: normed time, the law's volume (m³), both wheels' depth (m,
    wheel × angle × lateral), the Monte Carlo variance (m², stepwise; empty for direct), the
    generator state as JSON text, the dynamics' state, start offset (m) and wheel angle (rad)
    (direct; empty and 0 for stepwise), the cost so far and the outputs saved so far."""

    fingerprint: str
    steps: int
    normed_time: float
    law_volume: float
    surface_depth: np.ndarray
    variance: np.ndarray
    rng_state: str
    dynamics_state: np.ndarray
    offset: float
    phase: float
    cost_seconds: float
    cost_rhs: int
    cost_tables: int
    saved_time: np.ndarray
    saved_depth: np.ndarray
    saved_volume: np.ndarray
    saved_law: np.ndarray
    saved_cmin: np.ndarray
    saved_cmax: np.ndarray
    saved_amplitude: np.ndarray
    saved_rrd: np.ndarray


def _key(kind, problem, u0, until, depth_limit, *settings):
    """Fingerprint of a wheelset run: the strategy, its ``settings``, the start, the end and the
    problem (the model's fields but its table, which the run replaces; the profiles' points)."""
    p = problem
    model = {f.name: getattr(p.model, f.name) for f in fields(p.model) if f.name != "table"}
    return fingerprint(kind, *settings, np.zeros(0) if u0 is None else np.asarray(u0, float), until, depth_limit,
                       repr(model), p.wheel.y, p.wheel.z, p.rail.y, p.rail.z, (p.wheel.cant, p.rail.cant),
                       p.beta, p.life_distance, np.asarray(p.shifts), np.asarray(p.lateral_edges), p.n_angle,
                       p.transient, p.offsets, p.output_rate, p.footprint, p.radius)


def _snapshot(key, j, T, law, surfaces, variance, rng, cost, saved, state=None, offset=0.0, phase=0.0):
    """The :class:`WheelsetCheckpoint` of a run's variables."""
    return WheelsetCheckpoint(
        key, j, T, law, np.stack([s.depth for s in surfaces]), np.array(variance), rng_state_text(rng),
        np.zeros(0) if state is None else np.array(state, float), float(offset), float(phase),
        float(cost["seconds"]), int(cost["rhs"]), int(cost["tables"]),
        *(np.array(saved[k]) for k in SAVED))


def _restore(problem, resume, key):
    """Generator, surfaces, table, cost, outputs, step, normed time and law's volume of ``resume``."""
    if resume.fingerprint != key:
        raise ScenarioError("resume: the checkpoint belongs to another wheelset problem or run")
    surfaces = (problem.new_surface(), problem.new_surface())
    for s, depth in zip(surfaces, resume.surface_depth):
        s.depth[...] = depth
    saved = _Saved()
    for k in SAVED:
        saved[k] = list(getattr(resume, f"saved_{k}"))
    cost = {"seconds": float(resume.cost_seconds), "rhs": int(resume.cost_rhs), "tables": int(resume.cost_tables)}
    return (rng_from_text(resume.rng_state), surfaces, problem.table(_fed(surfaces)), cost, saved,
            int(resume.steps), float(resume.normed_time), float(resume.law_volume))


def _begin(problem, u0, seed):
    """Generator, the two surfaces worn by the lateral depth ``u0`` (m), the fed start depth, its
    table, the cost counters and the outputs with the start saved."""
    surfaces = (problem.new_surface(), problem.new_surface())
    if u0 is not None:
        u0 = np.asarray(u0, float)
        if u0.shape != problem.lateral.shape or not np.all(np.isfinite(u0)):
            raise ScenarioError(f"u0 must be {problem.lateral.size} finite lateral depths (m)")
        for surface in surfaces:
            surface.depth += u0[None, :]
    start_depth = _fed(surfaces)
    table = problem.table(start_depth)
    saved = _Saved()
    saved.add(0.0, surfaces, 0.0, (np.nan,) * 3, table)
    return (np.random.default_rng(seed), surfaces, start_depth, table, {"seconds": 0.0, "rhs": 0, "tables": 1},
            saved)


def _result(problem, saved, surfaces, cost, attrs, extra=None):
    """The Dataset of a wheelset run: ``worn_depth(distance, wheel, lateral)`` and the others."""
    import xarray as xr

    times = np.array(saved["time"])
    lateral = problem.lateral
    tables = saved["rrd"]
    data = {
        "worn_depth": (("distance", "wheel", "lateral"), np.array(saved["depth"]),
                       {"units": "m", "long_name": "depth removed, mean round the wheel"}),
        "surface_depth": (("wheel", "angle", "lateral"), np.stack([s.depth for s in surfaces]),
                          {"units": "m", "long_name": "depth removed at the end over angle and lateral position"}),
        "removed_volume": ("distance", np.array(saved["volume"]),
                           {"units": "m3", "long_name": "volume removed from both wheels"}),
        "law_volume": ("distance", np.array(saved["law"]),
                       {"units": "m3", "long_name": "volume of the wear law, beta times the frictional energy"}),
        "contact_min": ("distance", np.array(saved["cmin"]),
                        {"units": "m", "long_name": "smallest contact lateral position seen in the step"}),
        "contact_max": ("distance", np.array(saved["cmax"]),
                        {"units": "m", "long_name": "largest contact lateral position seen in the step"}),
        "lateral_amplitude": ("distance", np.array(saved["amplitude"]),
                              {"units": "m", "long_name": "largest lateral displacement after the transient in the step"}),
        "rolling_radius_difference": (("distance", "shift"), np.array(tables),
                                      {"units": "m", "long_name": "rolling radius difference right - left of the table"}),
        "cost_seconds": ((), float(cost["seconds"]), {"units": "s", "long_name": "seconds of dynamics simulated"}),
        "cost_rhs_evaluations": ((), int(cost["rhs"]), {"units": "1", "long_name": "right-hand sides evaluated"}),
        "cost_tables": ((), int(cost["tables"]), {"units": "1", "long_name": "contact tables computed"}),
    }
    data.update(extra or {})
    coords = {
        "distance": ("distance", times * problem.life_distance, {"units": "m", "long_name": "distance run"}),
        "time": ("distance", times, {"units": "1", "long_name": "normed life time"}),
        "wheel": ("wheel", list(WHEELS), {"long_name": "wheel of the wheelset"}),
        "lateral": ("lateral", lateral, {"units": "m", "long_name": "lateral position on the wheel profile"}),
        "angle": ("angle", surfaces[0].angle, {"units": "rad", "long_name": "angle round the wheel"}),
        "shift": ("shift", np.asarray(problem.shifts), {"units": "m", "long_name": "lateral shift of the wheelset"}),
    }
    attrs = dict(attrs, speed=float(problem.model.speed), beta=problem.beta, life_distance=problem.life_distance)
    return xr.Dataset(data, coords=coords, attrs=attrs)


class _Saved(dict):
    """Outputs gathered step by step."""

    def __init__(self):
        super().__init__(time=[], depth=[], volume=[], law=[], cmin=[], cmax=[], amplitude=[], rrd=[])

    def add(self, T, surfaces, law, seen, table):
        """Outputs after a step: ``seen`` the contact range and the largest |y| (m) of its runs."""
        cmin, cmax, amplitude = seen
        self["time"].append(T)
        self["depth"].append([s.depth.mean(0) for s in surfaces])
        self["volume"].append(sum(s.removed_volume() for s in surfaces))
        self["law"].append(law)
        self["cmin"].append(cmin)
        self["cmax"].append(cmax)
        self["amplitude"].append(amplitude)
        self["rrd"].append(table.rolling_radius_difference.values.copy())


def _seen(ds):
    """Smallest and largest contact lateral position and largest |y| (m) of a run."""
    position = ds.contact_lateral_position.values
    return float(position.min()), float(position.max()), float(np.abs(ds.lateral_displacement.values).max())


def _checked(until, depth_limit):
    if not (np.isfinite(until) and until > 0):
        raise ScenarioError(f"until must be finite and > 0 (normed time), got {until}")
    if depth_limit is not None and not depth_limit > 0:
        raise ScenarioError(f"depth_limit must be > 0 (m), got {depth_limit}")


def _fed(surfaces):
    """Lateral depth (m) the profile is worn by: round the wheel and over both wheels."""
    return np.mean([s.depth.mean(0) for s in surfaces], axis=0)


@dataclass(frozen=True)
class WheelsetStepwise:
    """Strategy 3 on the wheelset: frozen-profile statistics over ``samples`` random starts of
    ``seconds`` (s) each after the transient, extrapolated over steps of at most ``step_limit``
    (m) change of the fed lateral profile; ``seed`` seeds the run's generator."""

    problem: WheelsetWear
    step_limit: float
    seconds: float = 2.0
    samples: int = 4
    seed: int = 0
    max_steps: int = 10_000

    def __post_init__(self):
        if not (np.isfinite(self.step_limit) and self.step_limit > 0):
            raise ScenarioError(f"step_limit must be > 0 (m), got {self.step_limit}")
        _seconds_check("seconds", self.seconds, self.seed)
        if int(self.samples) != self.samples or self.samples < 2:
            raise ScenarioError(f"samples must be a whole number >= 2 (for a variance), got {self.samples}")

    def statistics(self, table, rng, cost=None):
        """Depth rate (m per unit normed time) per draw over (wheel, angle, lateral), the law's
        volume rate (m³ per unit normed time) per draw, the contact range and largest |y| (m)
        seen, and the cost (added to ``cost`` when given)."""
        p = self.problem
        rates, law, seen = [], [], (np.inf, -np.inf, 0.0)
        cost = {"seconds": 0.0, "rhs": 0} if cost is None else cost
        for _ in range(self.samples):
            offset, phase = p.start(rng)
            ds, _ = p.run(table, self.seconds, state=p.settle(table, offset, cost), offset=offset, cost=cost)
            surfaces = (p.new_surface(), p.new_surface())
            _, volume, _ = p.deposit(surfaces, ds, table, phase)
            per_life = p.life_distance / (p.model.speed * self.seconds)
            rates.append(np.stack([s.depth for s in surfaces]) * per_life)
            law.append(volume * per_life)
            lo, hi, amplitude = _seen(ds)
            seen = (min(seen[0], lo), max(seen[1], hi), max(seen[2], amplitude))
        return np.array(rates), np.array(law), seen, cost

    def run(self, u0=None, until=1.0, depth_limit=None, progress=None, checkpoint=None, resume=None):
        """Worn lateral profile over normed time from the lateral depth ``u0`` (m removed, on the
        lateral cells; default unworn) until ``until`` or ``depth_limit`` (m) at the most worn
        spot of the fed profile. ``checkpoint(WheelsetCheckpoint)`` is called after every step;
        ``resume`` continues from one to the same result, bit for bit."""
        _checked(until, depth_limit)
        p = self.problem
        started = _time.perf_counter()
        key = _key("stepwise", p, u0, until, depth_limit, self.step_limit, self.seconds, self.samples, self.seed)
        rng, surfaces, start_depth, table, cost, saved = _begin(p, u0, self.seed)
        T, law, j = 0.0, 0.0, 0
        variance = np.zeros((2, p.lateral.size))
        if resume is not None:
            rng, surfaces, table, cost, saved, j, T, law = _restore(p, resume, key)
            variance = np.array(resume.variance, float)
        while T < until and (depth_limit is None or np.max(_fed(surfaces) - start_depth) < depth_limit * (1 - 1e-12)):
            if j >= self.max_steps:
                raise ScenarioError(f"step_limit: {self.max_steps} steps did not reach the end; raise step_limit")
            rates, laws, seen, _ = self.statistics(table, rng, cost)
            rate = rates.mean(0)
            lateral_rate = rate.mean(1)  # (wheel, lateral)
            top = np.max(lateral_rate.mean(0))
            dT = min(self.step_limit / top if top > 0 else np.inf, until - T)
            frac = stop_fraction(_fed(surfaces) - start_depth, lateral_rate.mean(0) * dT, depth_limit)
            at_end = frac == 1.0 and dT == until - T
            dT *= frac
            for s, r in zip(surfaces, rate):
                s.depth += r * dT
            variance += (rates.mean(2).std(0, ddof=1) / np.sqrt(self.samples) * dT) ** 2
            law += laws.mean() * dT
            T = until if at_end else T + dT
            j += 1
            table = p.table(_fed(surfaces))
            cost["tables"] += 1
            saved.add(T, surfaces, law, seen, table)
            if progress is not None:
                progress(fraction_done(T, until, _fed(surfaces) - start_depth, depth_limit))
            if checkpoint is not None:
                checkpoint(_snapshot(key, j, T, law, surfaces, variance, rng, cost, saved))
        error = {"worn_depth_final_standard_error": (("wheel", "lateral"), np.sqrt(variance),
                                                     {"units": "m", "long_name": "Monte Carlo standard error of the final worn depth"})}
        attrs = {"strategy": "wheelset stepwise frozen geometry", "steps": j, "step_limit_m": self.step_limit,
                 "samples": self.samples, "seconds_per_sample": self.seconds,
                 "wall_seconds": _time.perf_counter() - started}
        return _result(p, saved, surfaces, cost, attrs, error)


@dataclass(frozen=True)
class WheelsetDirect:
    """Strategy 1 on the wheelset: one run with ``acceleration`` ``A >= 1`` times the wear
    coefficient; the profile and the table follow the surface every ``update_seconds`` (s) of
    simulated time. Each simulated second stands for ``A`` seconds of service."""

    problem: WheelsetWear
    acceleration: float
    update_seconds: float = 0.5
    seed: int = 0
    max_updates: int = 100_000

    def __post_init__(self):
        if not (np.isfinite(self.acceleration) and self.acceleration >= 1):
            raise ScenarioError(f"acceleration factor must be >= 1, got {self.acceleration}")
        _seconds_check("update_seconds", self.update_seconds, self.seed)

    def run(self, u0=None, until=1.0, depth_limit=None, progress=None, checkpoint=None, resume=None):
        """As :meth:`WheelsetStepwise.run`; checkpoints after every update."""
        _checked(until, depth_limit)
        p = self.problem
        started = _time.perf_counter()
        key = _key("direct", p, u0, until, depth_limit, self.acceleration, self.update_seconds, self.seed)
        rng, surfaces, start_depth, table, cost, saved = _begin(p, u0, self.seed)
        if resume is None:
            offset, phase = p.start(rng)
            state = p.settle(table, offset, cost)
            T, law, j = 0.0, 0.0, 0
        else:
            rng, surfaces, table, cost, saved, j, T, law = _restore(p, resume, key)
            offset, phase = float(resume.offset), float(resume.phase)
            state = np.array(resume.dynamics_state, float) if np.size(resume.dynamics_state) else None
        per_second = self.acceleration * p.model.speed / p.life_distance  # normed time per simulated second
        while T < until and (depth_limit is None or np.max(_fed(surfaces) - start_depth) < depth_limit * (1 - 1e-12)):
            if j >= self.max_updates:
                raise ScenarioError(f"direct: {self.max_updates} updates did not reach the end; raise the acceleration factor")
            last = (until - T) / per_second <= self.update_seconds
            seconds = (until - T) / per_second if last else self.update_seconds
            ds, state = p.run(table, seconds, state=state, offset=offset, cost=cost)
            segment = (p.new_surface(), p.new_surface())
            _, volume, phase = p.deposit(segment, ds, table, phase, self.acceleration)
            frac = stop_fraction(_fed(surfaces) - start_depth, _fed(segment), depth_limit)
            for s, new in zip(surfaces, segment):
                s.depth += frac * new.depth
            law += frac * volume
            T = until if (frac == 1.0 and last) else T + frac * seconds * per_second
            j += 1
            table = p.table(_fed(surfaces))
            cost["tables"] += 1
            saved.add(T, surfaces, law, _seen(ds), table)
            if progress is not None:
                progress(fraction_done(T, until, _fed(surfaces) - start_depth, depth_limit))
            if checkpoint is not None:
                checkpoint(_snapshot(key, j, T, law, surfaces, np.zeros(0), rng, cost, saved, state, offset, phase))
        attrs = {"strategy": "wheelset direct coupled integration", "updates": j,
                 "acceleration": self.acceleration, "update_seconds": self.update_seconds,
                 "wall_seconds": _time.perf_counter() - started}
        return _result(p, saved, surfaces, cost, attrs)
