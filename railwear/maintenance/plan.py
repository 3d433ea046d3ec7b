"""``railwear plan``: a wheel's life under maintenance policies, one wheel or a Monte Carlo over the
service scatter, at a band of growth multipliers (layer 4).

Wheel 0 runs the scenario's own conditions; wheels 1..N draw speed, load and friction from its
``[service]`` as the forecast does (:func:`railwear.forecast.draw_conditions`, seeded). Each wheel
runs each policy at each growth multiplier ``g`` from new (the scenario's diameter and
``[initial]`` wheel) to scrap (:meth:`~railwear.maintenance.turning.Policy.life`). No published
field growth rate of a polygon exists, so the plan states its answer over the band of ``g``.
Per life: the turnings (distance, trigger, peak to peak and dominant order before the cut, cut
depth, diameters, the order selected after), the distance to scrap ``S`` (km), the distance per
millimetre of diameter ``S / (D_0 - D_end)`` and the turnings per 10⁶ km ``10⁶ k / S``; over
the drawn wheels the median of ``S`` with its 5-95 % band.

On a body that simulates the lateral profile (the wheelset) the plan runs one wheel on the
profile's wear (:mod:`railwear.maintenance.lateral`): flange triggers, a turning that restores the
design profile, the diameter worn at the tape circle; the polygon is not grown there (that body has
no linear model), and ``g`` multiplies the profile's wear rate.
"""

import hashlib
from dataclasses import dataclass

import numpy as np
import xarray as xr

from railwear.checkpoints import wanted
from railwear.results import _atomic, _readable
from railwear.errors import OptionError, ScenarioError
from railwear.longterm.spectra import UNDEFINED
from railwear.maintenance import lateral
from railwear.maintenance.policy import load_policy
from railwear.maintenance.turning import Life, RateTable, TurnRecord, WheelState
from railwear.scenario import build, load_scenario, scenario_hash, to_toml
from railwear.units import KM, MM, m_s_to_kmh

GROWTH = (0.5, 1.0, 2.0)  # the default band of growth multipliers on the polygon rates
GROWTH_RANGE = (0.0, 100.0)  # a multiplier outside it is a typing error (0 allowed: no growth)
HORIZON_KM = 1e7  # a life not scrapped by then is reported as not scrapped
RESOLUTION_KM = 500.0  # scan step for the triggers (located by bisection within it)
QUANTILES = (0.05, 0.5, 0.95)
MAX_SAMPLES = 1000
NOT_SCRAPPED = "the wheel is not scrapped within the horizon"


class WheelRates:
    """The Fourier technique of one wheel's conditions (``scenario``) at any diameter, built once
    per diameter (:meth:`at`, a :class:`~railwear.maintenance.turning.RateTable` of orders
    1 .. ``highest``)."""

    def __init__(self, scenario, highest):
        self.scenario, self.highest, self.built = scenario, highest, {}

    def at(self, diameter, growth=1.0):
        if diameter not in self.built:
            wheel = self.scenario.wheel.model_copy(update={"radius_m": diameter / 2})
            self.built[diameter] = RateTable.of(build.fourier_technique(self.scenario.model_copy(update={"wheel": wheel})),
                                                self.highest)
        table = self.built[diameter]
        return table if growth == 1.0 else table.scaled(growth)


class ProfileRates:
    """The rates of a wheel on a body without a polygon model but with a lateral profile
    (``wear``, a :class:`~railwear.maintenance.lateral.ProfileWear`): no growth of any order
    1 .. ``highest``, the mean radius worn at the tape circle, ``ṙ = -g w'(0) V``."""

    def __init__(self, scenario, highest, wear):
        self.scenario, self.highest, self.wear = scenario, highest, wear
        self.speed = float(build.one_speed(scenario, "; plan one speed"))

    def at(self, diameter, growth=1.0):
        return RateTable(np.zeros(self.highest, complex), -growth * self.wear.tape_rate * self.speed, self.speed,
                         diameter / 2)


def re_profiled(scenario):
    """The scenario's ``[initial]`` wheel about its mean (m on the grid): a new or re-profiled
    wheel's roughness, where a life starts and what a turning adds with ``add_initial``."""
    base = build.initial_state(scenario, "a wheel's life plan")
    return base - np.mean(base)


def wheel_conditions(scenario, samples, seed):
    """``(scenarios, speed_kmh, load_kN, friction)``: wheel 0 the scenario's own, then ``samples``
    drawn from its ``[service]`` with ``seed``."""
    from railwear.forecast import draw_conditions

    op = scenario.operation
    speed = [m_s_to_kmh(float(op.speeds if op.duty() is not None else build.one_speed(scenario, "; plan one speed")))]
    load, friction = [scenario.wheel.static_load_kN], [scenario.contact.friction_coefficient]
    scenarios = [scenario]
    if samples:
        if op.duty() is not None:
            raise ScenarioError("operation.cycle: a Monte Carlo over the service scatter draws one speed per wheel; "
                                "plan a duty cycle as one wheel (--samples 0)")
        service = scenario.service.model_copy(update={"samples": samples, "seed": scenario.service.seed if seed is None else seed})
        v, w, mu = draw_conditions(scenario.model_copy(update={"service": service}))
        for vi, wi, mi in zip(v, w, mu):
            scenarios.append(scenario.model_copy(update={
                "wheel": scenario.wheel.model_copy(update={"static_load_kN": float(wi)}),
                "contact": scenario.contact.model_copy(update={"friction_coefficient": float(mi)}),
                "operation": op.model_copy(update={"speed_kmh": float(vi), "speed_m_s": None})}))
        speed, load, friction = speed + list(v), load + list(w), friction + list(mu)
    return scenarios, np.array(speed), np.array(load), np.array(friction)


def _checked_growth(growth):
    values = np.atleast_1d(np.asarray(growth, float))
    if values.size == 0 or values.size > 20 or not np.all(np.isfinite(values)) or np.any(values < GROWTH_RANGE[0]) or (
            np.any(values > GROWTH_RANGE[1])):
        raise OptionError(f"growth: 1 to 20 multipliers in [{GROWTH_RANGE[0]:g}, {GROWTH_RANGE[1]:g}], got "
                          f"{', '.join(f'{g:g}' for g in values) or 'none'}")
    if np.unique(values).size != values.size:
        raise OptionError("growth: a multiplier is given twice")
    return tuple(float(g) for g in np.sort(values))


POLYGON_TRIGGERS = ("peak_to_peak_mm", "order_level_db", "band_limit", "band_wavelength_mm", "peak_force_kN")


def _policies(policies, base, diameter, scenario=None):
    """The policy files and their SI policies, checked against the wheel and against what the
    scenario's body simulates (names the field)."""
    files = [load_policy(p) for p in ([policies] if isinstance(policies, str) else policies)]
    if not files:
        raise OptionError("policy: give at least one policy")
    names = [f.name for f in files]
    if len(set(names)) != len(names):
        raise OptionError(f"policy: two policies are named {next(n for n in names if names.count(n) > 1)!r}")
    built = []
    for f in files:
        if f.wheel.last_turning_diameter_mm * MM >= diameter:
            raise ScenarioError(f"{f.name}: wheel.last_turning_diameter_mm: {f.wheel.last_turning_diameter_mm:g} mm is not "
                                f"below the scenario's new wheel ({diameter / MM:g} mm, wheel.radius_m)")
        if scenario is not None:
            kind = scenario.body.kind
            if kind in lateral.BODIES:
                polygon = f.trigger.given(POLYGON_TRIGGERS)
                if polygon:
                    raise ScenarioError(f"{f.name}: trigger.{polygon[0]}: body.kind {kind!r} has no model of the "
                                        "polygon's growth; its triggers are the flange's and interval_km")
            else:
                flange = f.trigger.given(lateral.LIMITS)
                if flange:
                    raise ScenarioError(f"{f.name}: trigger.{flange[0]}: body.kind {kind!r} does not simulate the "
                                        f"lateral profile; flange triggers need body.kind "
                                        f"{' or '.join(repr(b) for b in lateral.BODIES)}")
        policy = f.build(base)
        policy.turning.residual.check(base.size)
        for limit in policy.triggers.limits:
            try:
                limit.check(base, diameter)
            except ScenarioError as e:
                raise ScenarioError(f"{f.name}: trigger: {str(e).removeprefix('limit: ')}") from None
        built.append(policy)
    return files, built


def plan(scenario=None, policies=("metro-interval",), samples=0, seed=None, growth=GROWTH, horizon_km=HORIZON_KM,
         resolution_km=RESOLUTION_KM, progress=None, checkpoint=None, resume=None):
    """Each policy's life of the scenario's wheel at each growth multiplier: wheel 0 at the
    scenario's conditions, and ``samples`` wheels drawn from its ``[service]`` (``seed``, default
    ``service.seed``). ``scenario`` a :class:`~railwear.scenario.Scenario`, file or built-in name
    whose body gives a linear model (the Fourier technique); ``policies`` files or built-in names
    (:func:`~railwear.maintenance.policy.load_policy`). Returns an ``xarray.Dataset``
    (:func:`dataset`). ``checkpoint(PlanCheckpoint)`` is offered the finished lives after each
    (:func:`railwear.checkpoints.wanted`); ``resume`` (a :class:`PlanCheckpoint` of the same plan)
    keeps its lives, which are deterministic, so the result is the uninterrupted one bit for bit."""
    sc = load_scenario(scenario)
    if not (isinstance(samples, (int, np.integer)) and 0 <= samples <= MAX_SAMPLES):
        raise OptionError(f"samples: a whole number in [0, {MAX_SAMPLES}], got {samples!r}")
    for name, value, low, high in (("horizon_km", horizon_km, 1e3, 1e8), ("resolution_km", resolution_km, 1.0, 1e5)):
        if not (np.isfinite(value) and low <= value <= high):
            raise OptionError(f"{name}: must be in [{low:g}, {high:g}] km, got {value!r}")
    growth = _checked_growth(growth)
    base = re_profiled(sc)
    diameter = 2 * sc.wheel.radius_m
    files, built = _policies(policies, base, diameter, sc)
    key = _fingerprint(sc, files, growth, samples, seed, horizon_km, resolution_km)
    if resume is not None and resume.fingerprint != key:
        raise ScenarioError("resume: the plan checkpoint was written for another plan (scenario, policies, samples, "
                            "seed, growth, horizon or resolution differ); run without --resume")
    wear, start = None, 0.0
    if sc.body.kind in lateral.BODIES:
        if samples:
            raise OptionError(f"samples: a plan on body.kind {sc.body.kind!r} runs one wheel (each drawn wheel would "
                              "need its own wheelset-wear run); use --samples 0")
        start = 0.5
        wear = lateral.profile_wear(sc, None if progress is None else (lambda f: progress(start * f)))
    scenarios, speed, load, friction = wheel_conditions(sc, samples, seed)
    if wear is None:
        wheels = [WheelRates(s, base.size // 2) for s in scenarios]
        wheels[0].at(diameter)  # a scenario without a linear model is refused here, before any life
    else:
        wheels = [ProfileRates(sc, base.size // 2, wear)]
    lives = {} if resume is None else dict(resume.lives)
    total, done = len(wheels) * len(built) * len(growth), 0
    for w, wheel in enumerate(wheels):
        for p, policy in enumerate(built):
            force = None if policy.triggers.peak_force is None else peak_force_search(wheel.scenario, policy.triggers)
            for g, multiplier in enumerate(growth):
                if (p, g, w) not in lives:
                    lives[p, g, w] = policy.life(WheelState(base, diameter), lambda d, m=multiplier, r=wheel: r.at(d, m),
                                                 horizon_km * KM, resolution_km * KM, force,
                                                 None if wear is None else wear.scaled(multiplier))
                    if wanted(checkpoint):
                        checkpoint(PlanCheckpoint(key, dict(lives)))
                done += 1
                if progress is not None:
                    progress(start + (1 - start) * done / total)
    return dataset(sc, files, built, growth, lives, speed, load, friction,
                   {"profile_wear": wear, "samples": samples, "seed": sc.service.seed if seed is None else seed, "horizon_km": horizon_km,
                    "resolution_km": resolution_km})


def peak_force_search(scenario, triggers):
    """The peak-force trigger of ``triggers`` on ``scenario``'s wheel (its body must run on the
    time-domain track): ``(state, table, within) -> distance`` (m), where the wheel grown from
    ``state`` on ``table`` first puts a peak wheel–rail force above ``triggers.peak_force`` at one
    of its speeds (the scenario's if none), on the vehicle–track case at the state's diameter;
    ``inf`` if not within ``within`` m (:func:`~railwear.maintenance.detectors.wheel_flags`)."""
    from dataclasses import replace

    from railwear.maintenance.detectors import WheelTask, wheel_flags
    from railwear.maintenance.impact import check_body

    check_body(scenario, "the peak-force trigger (trigger.peak_force_kN)")
    case, track = scenario.body.case(scenario), scenario.track
    speeds = triggers.force_speeds or (build.one_speed(scenario, "; the peak-force trigger takes one speed"),)

    def search(state, table, within):
        if within <= 0:
            return np.inf
        task = WheelTask(replace(case, diameter=float(state.diameter)), state.u, table, tuple(speeds),
                         (triggers.peak_force,), float(within), ring_sleepers=track.ring_sleepers,
                         ring_max_frequency_hz=track.ring_max_frequency_hz)
        return float(wheel_flags(task).distance[0])

    return search


def _fingerprint(scenario, files, growth, samples, seed, horizon_km, resolution_km):
    """What makes a plan's lives what they are: the scenario, the policies and the options."""
    text = "\n".join([scenario_hash(scenario), *(f.model_dump_json() for f in files), repr(tuple(growth)),
                      repr((samples, seed, float(horizon_km), float(resolution_km)))])
    return hashlib.sha256(text.encode()).hexdigest()


_RECORD_FLOATS = ("distance", "peak_to_peak", "cut", "before", "after")
_FLANGE_FLOATS = ("flange_height", "flange_thickness", "flange_gradient", "profile_cut")


def _flange_values(record):
    """Sh, Sd, qR (m, NaN without a lateral profile) and the profile's cut (m) of a turning."""
    return (*(record.flange or (np.nan,) * 3), record.profile_cut)
_STATE_FLOATS = ("diameter", "distance", "since")


@dataclass(frozen=True)
class PlanCheckpoint:
    """The finished lives of a plan, ``{(policy, growth, wheel): Life}``, with the plan's ``fingerprint``."""

    fingerprint: str
    lives: dict

    def plain(self) -> dict:
        """Arrays only (``.npz`` without pickles); :meth:`from_plain` reads them back exactly."""
        out = {"fingerprint": np.array(self.fingerprint), "keys": np.array(sorted(self.lives), np.int64).reshape(-1, 3)}
        for i, k in enumerate(sorted(self.lives)):
            life = self.lives[k]
            states = (*life.starts, life.end)
            out.update({
                f"{i}_records": np.array([[getattr(r, f) for f in _RECORD_FLOATS] for r in life.turnings], float).reshape(-1, 5),
                f"{i}_flange": np.array([_flange_values(r) for r in life.turnings], float).reshape(-1, 4),
                f"{i}_orders": np.array([[r.dominant_order, r.selected_order] for r in life.turnings], np.int64).reshape(-1, 2),
                f"{i}_triggers": np.array([r.trigger for r in life.turnings], str),
                f"{i}_u": np.stack([s.u for s in states]),
                f"{i}_states": np.array([[getattr(s, f) for f in _STATE_FLOATS] for s in states], float),
                f"{i}_turned": np.array([s.turnings for s in states], np.int64),
                f"{i}_end": np.array([life.reason]), f"{i}_asked": np.array([life.asked]), f"{i}_selected": np.array(life.selected_order, np.int64),
                **{f"{i}_history{j}": np.asarray(h) for j, h in enumerate(life.history)}})
        return out

    @classmethod
    def from_plain(cls, data):
        lives = {}
        for i, k in enumerate(map(tuple, np.asarray(data["keys"]).tolist())):
            flange = data.get(f"{i}_flange", np.full((len(data[f"{i}_records"]), 4), np.nan))  # none before flange triggers
            records = tuple(TurnRecord(**dict(zip(_RECORD_FLOATS, map(float, row))), trigger=str(t),
                                       dominant_order=int(o[0]), selected_order=int(o[1]),
                                       flange=() if np.all(np.isnan(fl[:3])) and fl[3] == 0 else tuple(map(float, fl[:3])),
                                       profile_cut=float(fl[3]))
                            for row, o, t, fl in zip(data[f"{i}_records"], data[f"{i}_orders"], data[f"{i}_triggers"],
                                                     flange))
            states = tuple(WheelState(u, *map(float, f), int(n))
                           for u, f, n in zip(data[f"{i}_u"], data[f"{i}_states"], data[f"{i}_turned"]))
            lives[k] = Life(records, states[:-1], states[-1], str(data[f"{i}_end"][0]), int(data[f"{i}_selected"]),
                            tuple(np.asarray(data[f"{i}_history{j}"]) for j in range(3)),
                            str(data[f"{i}_asked"][0]) if f"{i}_asked" in data else "")
        return cls(str(data["fingerprint"]), lives)


def _life_values(life, diameter):
    """Per life: distance to scrap (km, inf if not scrapped), distance reached (km), turnings,
    final mean diameter (m), km per mm of diameter, turnings per 10⁶ km."""
    reached = life.end.distance / KM
    final = life.end.mean_diameter
    used = (diameter - final) / MM
    k = len(life.turnings)
    return (reached if life.scrapped else np.inf, reached, k, final, reached / used if used > 0 else np.nan,
            k / reached * 1e6 if reached > 0 else np.nan)


FLANGE_HISTORY = 33  # points per segment at which wheel 0's flange parameters are measured for the history


def _flange_history(life, wear):
    """Sh, Sd, qR (m) of wheel 0 along ``life.history``: measured at :data:`FLANGE_HISTORY` points
    of each segment (its ends included) on ``wear`` aged since the segment's start, NaN between."""
    distance = life.history[0]
    out = np.full((3, distance.size), np.nan)
    starts = np.concatenate([[0], np.flatnonzero(np.diff(distance) == 0) + 1, [distance.size]])
    for a, b in zip(starts[:-1], starts[1:]):
        for i in np.unique(np.linspace(a, b - 1, FLANGE_HISTORY).round().astype(int)):
            try:
                f = wear.flange(distance[i] - distance[a])
            except ScenarioError:  # worn past measuring
                continue
            out[:, i] = f.height, f.thickness, f.gradient
    return out


def dataset(scenario, files, policies, growth, lives, speed, load, friction, options):
    """The plan as an ``xarray.Dataset`` over ``policy`` × ``growth`` × ``wheel`` (× ``turning``;
    the history of wheel 0 over ``point``)."""
    from railwear import __version__
    from railwear.forecast import _speeds

    diameter = 2 * scenario.wheel.radius_m
    options = dict(options)
    wear = options.pop("profile_wear", None)
    n_p, n_g, n_w = len(policies), len(growth), len(speed)
    shape = (n_p, n_g, n_w)
    k_max = max([len(life.turnings) for life in lives.values()] + [1])
    per_life = {name: np.full(shape, np.nan) for name in ("scrap", "reached", "turnings", "final", "per_mm", "rate")}
    reasons, selected_new, asked = np.empty(shape, object), np.zeros(shape, int), np.full(shape, "", object)
    turn = {name: np.full(shape + (k_max,), np.nan) for name in ("distance", "cut", "before", "after", "ptp",
                                                                 *_FLANGE_FLOATS)}
    turn_int = {name: np.zeros(shape + (k_max,), int) for name in ("dominant", "selected")}
    triggers = np.full(shape + (k_max,), "", object)
    points = max(life.history[0].size for (p, g, w), life in lives.items() if w == 0)
    history = {name: np.full((n_p, n_g, points), np.nan) for name in ("distance", "ptp", "diameter", *_FLANGE_FLOATS[:3])}
    for (p, g, w), life in lives.items():
        for name, value in zip(per_life, _life_values(life, diameter)):
            per_life[name][p, g, w] = value
        reasons[p, g, w], selected_new[p, g, w], asked[p, g, w] = life.reason, life.selected_order, life.asked
        for k, r in enumerate(life.turnings):
            for name, value in (("distance", r.distance / KM), ("cut", r.cut), ("before", r.before), ("after", r.after),
                                ("ptp", r.peak_to_peak), *zip(_FLANGE_FLOATS, _flange_values(r))):
                turn[name][p, g, w, k] = value
            turn_int["dominant"][p, g, w, k], turn_int["selected"][p, g, w, k] = r.dominant_order, r.selected_order
            triggers[p, g, w, k] = r.trigger
        if w == 0:
            n = life.history[0].size
            history["distance"][p, g, :n] = life.history[0] / KM
            history["ptp"][p, g, :n], history["diameter"][p, g, :n] = life.history[1], life.history[2]
            if wear is not None:
                for name, values in zip(_FLANGE_FLOATS, _flange_history(life, wear.scaled(growth[g]))):
                    history[name][p, g, :n] = values
    if wear is not None:  # no polygon model: no order is selected
        selected_new[:], turn_int["selected"][:] = 0, 0
    scrap = per_life["scrap"]
    dims, tdims = ("policy", "growth", "wheel"), ("policy", "growth", "wheel", "turning")
    variables = {
        "distance_to_scrap": (dims, scrap, {"units": "km", "long_name": "distance run from new to scrap",
                                            **({UNDEFINED: NOT_SCRAPPED} if np.isinf(scrap).any() else {})}),
        "life_distance": (dims, per_life["reached"], {"units": "km", "long_name": "distance run from new to the end of the life"}),
        "turnings": (dims, per_life["turnings"].astype(int), {"units": "1", "long_name": "turnings in the life"}),
        "final_diameter": (dims, per_life["final"], {"units": "m", "long_name": "mean diameter at the end of the life"}),
        "distance_per_mm": (dims, per_life["per_mm"], {"units": "km mm-1", "long_name": "distance run per mm of diameter used"}),
        "turnings_per_million_km": (dims, per_life["rate"], {"units": "1", "long_name": "turnings per 10^6 km"}),
        "end_reason": (dims, reasons.astype(str), {"long_name": "why the life ended"}),
        "end_trigger": (dims, asked.astype(str), {"long_name": "the trigger that asked for the cut the wheel could not "
                                                  "take (empty: another end)"}),
        "selected_order_new": (dims, selected_new, {"units": "1", "long_name": "fastest-growing order of the new wheel (0: no polygon model)"}),
        "turning_distance": (tdims, turn["distance"], {"units": "km", "long_name": "distance at the turning (NaN: none)"}),
        "cut_depth": (tdims, turn["cut"], {"units": "m", "long_name": "cut depth on the radius"}),
        "diameter_before": (tdims, turn["before"], {"units": "m", "long_name": "mean diameter before the turning"}),
        "diameter_after": (tdims, turn["after"], {"units": "m", "long_name": "diameter after the turning"}),
        "peak_to_peak_at_turning": (tdims, turn["ptp"], {"units": "m", "long_name": "peak-to-peak radius deviation before the cut"}),
        "dominant_order": (tdims, turn_int["dominant"], {"units": "1", "long_name": "dominant order before the cut (0: no turning)"}),
        "selected_order": (tdims, turn_int["selected"], {"units": "1", "long_name": "fastest-growing order at the new diameter (0: no turning, or no polygon model)"}),
        "trigger": (tdims, triggers.astype(str), {"long_name": "what asked for the turning"}),
        **{f"{name}_at_turning": (tdims, turn[name], {"units": "m", "long_name": f"{label} before the cut, EN 15313 "
                                                       "(NaN: no lateral profile)"})
           for name, label in (("flange_height", "flange height Sh"), ("flange_thickness", "flange thickness Sd"),
                               ("flange_gradient", "flange gradient qR"))},
        "profile_cut": (tdims, turn["profile_cut"], {"units": "m", "long_name": "share of the cut that restores the "
                                                     "design profile below the tape circle"}),
        **{name: (("wheel",), v.values, dict(v.attrs)) for name, v in _speeds(speed).items()},
        "static_load": (("wheel",), load, {"units": "kN", "long_name": "static wheel load"}),
        "friction_coefficient": (("wheel",), friction, {"units": "1", "long_name": "friction coefficient"}),
        "peak_to_peak_limit": (("policy",), np.array([next((x.peak_to_peak for x in q.triggers.limits if x.kind == "peak_to_peak"),
                                                          np.nan) for q in policies]),
                               {"units": "m", "long_name": "peak-to-peak trigger of the policy (NaN: none)"}),
        "interval": (("policy",), np.array([np.nan if q.triggers.interval is None else q.triggers.interval / KM for q in policies]),
                     {"units": "km", "long_name": "turning interval of the policy (NaN: none)"}),
        "peak_force_limit": (("policy",), np.array([np.nan if q.triggers.peak_force is None else q.triggers.peak_force
                                                    for q in policies]),
                             {"units": "N", "long_name": "peak wheel-rail force trigger of the policy (NaN: none)"}),
        **{f"{key[:-3]}": (("policy",), np.array([next((x.value for x in q.triggers.flange if x.key == key), np.nan)
                                                   for q in policies]),
                             {"units": "m", "long_name": f"{lateral.LIMITS[key][2]} trigger of the policy (NaN: none)"})
           for key in lateral.LIMITS},
        "last_turning_diameter": (("policy",), np.array([q.last_diameter for q in policies]),
                                  {"units": "m", "long_name": "last-turning diameter: scrapped there"}),
        "history_distance": (("policy", "growth", "point"), history["distance"], {"units": "km", "long_name": "distance run, wheel 0"}),
        "history_peak_to_peak": (("policy", "growth", "point"), history["ptp"], {"units": "m", "long_name": "peak-to-peak radius deviation, wheel 0"}),
        "history_diameter": (("policy", "growth", "point"), history["diameter"], {"units": "m", "long_name": "mean diameter, wheel 0"}),
    }
    coords = {}
    if wear is not None:
        for name, label in (("flange_height", "flange height Sh"), ("flange_thickness", "flange thickness Sd"),
                            ("flange_gradient", "flange gradient qR")):
            variables[f"history_{name}"] = (("policy", "growth", "point"), history[name], {
                "units": "m", "long_name": f"{label}, wheel 0 (EN 15313; measured at {FLANGE_HISTORY} points a segment, "
                                           "NaN between)"})
        variables["profile_wear_rate"] = (("lateral",), wear.rate * KM, {
            "units": "m km-1", "long_name": "depth of the lateral profile worn per km run", "source": wear.source})
        coords["lateral"] = ("lateral", wear.lateral, {"units": "m", "long_name": "lateral position on the wheel profile"})
    if n_w > 1:
        with np.errstate(invalid="ignore"):
            q = np.quantile(scrap[:, :, 1:], QUANTILES, axis=-1, method="inverted_cdf")
        for name, values in zip(("p05", "p50", "p95"), q):
            variables[f"distance_to_scrap_{name}"] = (("policy", "growth"), values, {
                "units": "km", "long_name": f"{name[1:]} % quantile of the distance to scrap over the drawn wheels",
                **({UNDEFINED: NOT_SCRAPPED} if np.isinf(values).any() else {})})
    attrs = {"scenario": to_toml(scenario), "scenario_hash": scenario_hash(scenario), "scenario_name": scenario.name,
             "new_diameter_m": diameter, "railwear_version": __version__,
             "growth_band": (f"growth multipliers {', '.join(f'{g:g}' for g in growth)} on the polygon rates of the Fourier "
                             "technique: no field growth rate of a polygon is published") if wear is None else (
                 f"growth multipliers {', '.join(f'{g:g}' for g in growth)} on the lateral profile's wear rate: "
                 "no field wear rate of this profile is calibrated"),
             **{f"policy_{i}": f.model_dump_json() for i, f in enumerate(files)},
             **{k: v for k, v in options.items() if v is not None}}
    return xr.Dataset(variables, coords={
        "policy": ("policy", [p.name for p in policies], {"long_name": "maintenance policy"}),
        "growth": ("growth", np.array(growth), {"units": "1", "long_name": "growth multiplier on the polygon rates"}),
        "wheel": ("wheel", np.arange(n_w), {"long_name": "wheel 0: the scenario's conditions; 1..N drawn from [service]"}),
        "turning": ("turning", np.arange(1, k_max + 1), {"long_name": "turning number"}), **coords}, attrs=attrs)


CHECKPOINT = "plan-checkpoint.npz"


def write_checkpoint(checkpoint, path):
    """Save a :class:`~railwear.maintenance.plan.PlanCheckpoint` (``.npz``, no pickles), atomically."""
    def write(tmp):
        with open(tmp, "wb") as f:
            np.savez(f, **checkpoint.plain())

    return _atomic(path, write)


def read_checkpoint(path):
    """The :class:`~railwear.maintenance.plan.PlanCheckpoint` in ``path``; a file cut short or of
    another kind is refused in one line."""
    import zipfile

    from railwear.errors import CheckpointError

    try:
        with np.load(_readable(path, "plan checkpoint"), allow_pickle=False) as data:
            return PlanCheckpoint.from_plain({k: data[k] for k in data.files})
    except (OSError, ValueError, KeyError, EOFError, TypeError, zipfile.BadZipFile) as e:
        raise CheckpointError(f"plan checkpoint {path}: cannot be read ({type(e).__name__}); run without --resume") from None
