"""The measured-wheel forecast: when does this wheel pass its out-of-roundness limit? (layer 4)

The measured radius deviation is evolved under service conditions drawn from the scenario's
``[service]`` section (speed peaks with weights and scatter, static-load scatter, a friction
range), one batch row per Monte Carlo sample. The limit (:class:`Limit`) is a peak-to-peak
radius deviation, a roughness level per polygon order (dB re 1 µm) or a one-third-octave band
spectrum (EN 15610, :mod:`railwear.geometry.bands`); the forecast is the distance run until the
wheel first reaches it, reported as a median with a 90 % band over the samples, with the
measured wheel's own state (peak to peak, dominant order, band levels) beside it.
"""

import warnings
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import xarray as xr
from pydantic import ValidationError

from railwear.errors import OptionError, ScenarioError
from railwear.geometry import bands, roundness
from railwear.geometry.roundness import ROUGHNESS_REFERENCE
from railwear.longterm.phenomenological import Phenomenological
from railwear.longterm.spectra import UNDEFINED
from railwear.measured import ANGLE_UNITS, BLANK, DEVIATION_UNITS, NUMBER, read_measured, read_table
from railwear.scenario import Scenario, load_scenario, scenario_hash, to_toml
from railwear.scenario.schema import MAX_SAVED_VALUES, Solver
from railwear.scenario import build
from railwear.units import MM, UM, kmh_to_m_s, m_s_to_kmh

QUANTILES = (0.05, 0.5, 0.95)
LENGTH_UNITS = {"mm": MM, "um": UM, "µm": UM, "m": 1.0}
LEVEL_RANGE = (-100.0, 100.0)  # dB re 1 µm: a limit level beyond it is a typing error
ECHO_RANGE = 40.0  # dB: the bands echoed lie within this of the measured wheel's largest band
BAND_UNITS = {"wavelength_m": 1.0, "wavelength_cm": 1e-2, "wavelength_mm": MM}


class NoScatterWarning(UserWarning):
    """The scenario's ``[service]`` gives every sample the same conditions: a band of zero width."""


@dataclass(frozen=True)
class Limit:
    """An out-of-roundness limit. ``kind`` ``"peak_to_peak"`` (``peak_to_peak`` in m),
    ``"order_level"`` (``levels`` in dB re 1 µm per order ``orders``; no orders: the one level
    for every order; the level of order n is ``20 lg(A_n / √2 / 1 µm)``) or ``"band_level"``
    (``spectrum``, a :class:`~railwear.geometry.bands.LimitSpectrum`); ``name`` says which."""

    kind: str
    name: str
    peak_to_peak: float = float("nan")
    orders: tuple = ()
    levels: tuple = ()
    spectrum: bands.LimitSpectrum | None = field(default=None, compare=False)

    def check(self, u, diameter):
        """Refuse (``limit: ...``) a limit the wheel ``u`` (m, on the grid) cannot be compared with."""
        top = u.shape[-1] // 2 - 1
        if self.kind == "order_level" and self.orders and max(self.orders) > top:
            raise OptionError(f"limit: order {max(self.orders)} is above the grid's highest order {top} "
                              "(raise solver.points)")
        if self.kind == "band_level":
            over = bands.exceedance(bands.band_levels(u, diameter), self.spectrum)
            if np.all(np.isnan(over.level)):
                raise OptionError(f"limit: none of the bands of {self.name} ({self.spectrum.wavelength.max() / MM:g} "
                                  f"to {self.spectrum.wavelength.min() / MM:g} mm) holds a wavelength of this wheel "
                                  f"(diameter {diameter / MM:g} mm, {u.shape[-1]} points)")

    def excess(self, u, diameter):
        """``(excess, where)`` along the last axis of ``u`` (m): the largest level above the
        limit (dB; ``-inf`` for a round wheel), and the order (order limits) or band centre
        wavelength in m (band limits) where it lies (``nan`` for a peak-to-peak limit)."""
        u = np.asarray(u, float)
        with np.errstate(divide="ignore"):
            if self.kind == "peak_to_peak":
                excess = 20 * np.log10(np.ptp(u, axis=-1) / self.peak_to_peak)
                return excess, np.full(excess.shape, np.nan)
            if self.kind == "order_level":
                orders, amp = bands.order_amplitudes(u)
                orders, amp = orders[:-1], amp[..., :-1]  # the alternating order N/2 is no polygon
                limit = np.full(orders.size, self.levels[0]) if not self.orders else None
                if limit is None:
                    keep = np.isin(orders, self.orders)
                    orders, amp = orders[keep], amp[..., keep]
                    limit = np.array(self.levels)[np.searchsorted(self.orders, orders)]
                over = 20 * np.log10(amp / np.sqrt(2) / ROUGHNESS_REFERENCE) - limit
                k = np.argmax(over, axis=-1)
                return np.take_along_axis(over, k[..., None], -1)[..., 0], orders[k].astype(float)
            over = bands.exceedance(bands.band_levels(u, diameter), self.spectrum).excess
        over = np.where(np.isnan(over), -np.inf, over)
        k = np.argmax(over, axis=-1)
        return np.take_along_axis(over, k[..., None], -1)[..., 0], self.spectrum.wavelength[k]


def peak_to_peak_limit(value):
    """A :class:`Limit` on the peak-to-peak radius deviation ``value`` (m, in (0, 1])."""
    if not (np.isfinite(value) and 0 < value <= 1.0):
        raise OptionError(f"limit: must be in (0, 1] m, got {value!r}")
    return Limit("peak_to_peak", f"{value / MM:g} mm peak to peak", peak_to_peak=float(value))


def order_limit(levels, orders=None, name=None):
    """A :class:`Limit` on the roughness level per order (dB re 1 µm): one level for every order
    (``orders`` None) or a level per order in ``orders`` (whole numbers of at least 1, each once)."""
    levels = np.atleast_1d(np.asarray(levels, float))
    if not (np.all(np.isfinite(levels)) and np.all((levels >= LEVEL_RANGE[0]) & (levels <= LEVEL_RANGE[1]))):
        raise OptionError(f"limit: levels must be in [{LEVEL_RANGE[0]:g}, {LEVEL_RANGE[1]:g}] dB re 1 um")
    if orders is None:
        if levels.size != 1:
            raise OptionError("limit: one level for every order, or give the orders")
        return Limit("order_level", name or f"{levels[0]:g} dB re 1 um in every order", levels=(float(levels[0]),))
    orders = np.atleast_1d(np.asarray(orders, float))
    if orders.size != levels.size or np.any(orders < 1) or np.any(orders != np.round(orders)):
        raise OptionError("limit: orders must be whole numbers of at least 1, one per level")
    if np.unique(orders).size != orders.size:
        raise OptionError("limit: an order is given twice")
    k = np.argsort(orders)
    return Limit("order_level", name or f"levels per order {int(orders.min())} to {int(orders.max())}",
                 orders=tuple(int(n) for n in orders[k]), levels=tuple(float(v) for v in levels[k]))


def band_limit(spectrum):
    """A :class:`Limit` on the one-third-octave band levels: a ``LimitSpectrum``."""
    return Limit("band_level", spectrum.name, spectrum=spectrum, orders=tuple(int(k) for k in spectrum.index),
                 levels=tuple(float(v) for v in spectrum.level))


def parse_length(text, field, high=1.0):
    """``0.3mm``, ``300um`` or ``3e-4m`` in metres, positive and at most ``high`` m; else an
    :class:`OptionError` naming ``field``."""
    stripped = str(text).strip(BLANK)
    for suffix in ("mm", "um", "µm", "m"):
        number = stripped.removesuffix(suffix).strip(BLANK)
        if number != stripped and NUMBER.fullmatch(number):
            value = float(number) * LENGTH_UNITS[suffix]
            if 0 < value <= high:
                return value
            break
    raise OptionError(f"{field}: expected a positive length of at most {high:g} m with a unit "
                      f"(0.3mm, 300um, 3e-4m), got {text!r}")


def read_limit_table(path, field="limit"):
    """A :class:`Limit` from a CSV table: columns ``order`` and ``level_db`` (per order), or
    ``wavelength_mm`` (``_cm``, ``_m``) and ``level_db`` (one-third-octave bands); the dialects
    of :func:`railwear.measured.read_table`."""
    path = Path(path)
    header, table = read_table(path, field)
    if "level_db" not in header:
        raise OptionError(f"{field}: {path.name}: needs a level_db column beside order or wavelength_mm")
    level = table[:, header.index("level_db")]
    if "order" in header:
        return order_limit(level, table[:, header.index("order")], name=f"{path.name} (levels per order)")
    unit = next((u for u in BAND_UNITS if u in header), None)
    if unit is None:
        raise OptionError(f"{field}: {path.name}: names neither an order nor a wavelength_mm column")
    try:
        spectrum = bands.limit_spectrum(table[:, header.index(unit)] * BAND_UNITS[unit], level,
                                        name=f"{path.name} (band levels)", source=str(path.name))
    except ScenarioError as e:
        raise OptionError(f"{field}: {e}") from None
    return band_limit(spectrum)


def parse_limit(text, field="limit"):
    """A :class:`Limit` from its text: a peak-to-peak length (``0.3mm``), a level for every order
    (``20dB``), ``iso3095`` (the band limit of :func:`~railwear.geometry.bands.iso3095_limit`),
    or a CSV table (:func:`read_limit_table`)."""
    stripped = str(text).strip(BLANK)
    if stripped.lower() == "iso3095":
        return band_limit(bands.iso3095_limit())
    if stripped.lower().endswith("db") and NUMBER.fullmatch(stripped[:-2].strip(BLANK)):
        try:
            return order_limit(float(stripped[:-2]))
        except OptionError as e:
            raise OptionError(f"{field}: {str(e).removeprefix('limit: ')}") from None
    if stripped and not stripped[0].isdigit() and not stripped.startswith((".", "+", "-")) and Path(stripped).is_file():
        return read_limit_table(stripped, field)
    try:
        return peak_to_peak_limit(parse_length(stripped, field))
    except OptionError:
        raise OptionError(f"{field}: expected a peak-to-peak length (0.3mm, 300um), a level per order (20dB), "
                          f"iso3095 or a CSV table of limits, got {text!r}") from None


def as_limit(limit):
    """A :class:`Limit` from a Limit, a peak-to-peak length in m, or a text (:func:`parse_limit`)."""
    if isinstance(limit, Limit):
        return limit
    if isinstance(limit, str):
        return parse_limit(limit)
    return peak_to_peak_limit(float(limit))


def draw_conditions(scenario: Scenario):
    """Speeds (km/h), static loads (kN) and friction coefficients of the samples."""
    service, samples = scenario.service, scenario.service.samples
    rng = np.random.default_rng(service.seed)
    base_speed = scenario.operation.speeds
    peaks = np.array(service.speed_kmh if service.speed_kmh else
                     [m_s_to_kmh(v) for v in np.atleast_1d(base_speed)])
    weights = np.array(service.speed_weights) if service.speed_weights else np.full(peaks.size, 1 / peaks.size)
    speed = rng.choice(peaks, size=samples, p=weights) + service.speed_scatter_kmh * rng.standard_normal(samples)
    load = scenario.wheel.static_load_kN * (1 + service.load_scatter * rng.standard_normal(samples))
    if service.friction_range:
        friction = rng.uniform(*service.friction_range, size=samples)
    else:
        friction = np.full(samples, scenario.contact.friction_coefficient)
    return np.maximum(speed, 1.0), np.maximum(load, 1e-3), friction


NOT_REACHED = "the limit is not reached within the horizon (the distance is beyond it)"
ROUND = ("no out-of-round where the limit applies (a round wheel, or no amplitude in the orders or bands it "
         "names): its level would be -inf dB")
NO_ENERGY = "the measured wheel has no out-of-round in the band: its level would be -inf dB"


def _undefined(values, reason):
    """The attributes of a forecast variable: :data:`UNDEFINED` ``reason`` where ``values`` are
    not finite (written masked; in memory they keep their ``inf``), else none."""
    return {} if np.all(np.isfinite(values)) else {UNDEFINED: reason}


NO_SCATTER = ("the scenario's [service] gives every sample the same speed, load and friction: the "
              "forecast is one distance and its '90 % band' has no width (set speed_scatter_kmh, "
              "load_scatter or friction_range, or more than one speed peak)")


def _speeds(speed_kmh):
    """The samples' drawn speeds (km/h) by the convention of every file railwear writes:
    ``speed`` in m s-1 (the speed each sample ran) and ``speed_kmh`` in km h-1 beside it."""
    from railwear.api import speed_coordinates

    ds = speed_coordinates(xr.Dataset(), kmh_to_m_s(np.asarray(speed_kmh, float)), "sample")
    for name in ("speed", "speed_kmh"):
        ds[name].attrs["long_name"] = "drawn vehicle speed of the sample"
    return {name: ds[name] for name in ("speed", "speed_kmh")}


def crossing(time, peak_to_peak, limit):
    """First time the peak-to-peak reaches ``limit``, interpolated linearly; ``inf`` if never."""
    above = np.flatnonzero(peak_to_peak >= limit)
    if above.size == 0:
        return np.inf
    k = above[0]
    if k == 0:
        return float(time[0])
    t0, t1, p0, p1 = time[k - 1], time[k], peak_to_peak[k - 1], peak_to_peak[k]
    return float(t0 + (limit - p0) / (p1 - p0) * (t1 - t0))


def measured_state(u, diameter):
    """What the measured wheel ``u`` (m, on the grid) is now: a dict of ``peak_to_peak`` (m),
    ``dominant_order`` with its ``dominant_amplitude`` (m) and ``dominant_level`` (dB re 1 µm),
    and its one-third-octave ``band_levels`` (:class:`~railwear.geometry.bands.BandLevels`) on a
    wheel of ``diameter`` (m)."""
    spectrum = roundness.polygon_spectrum(u)
    n = spectrum["dominant_order"]
    return {"peak_to_peak": spectrum["peak_to_peak"], "dominant_order": n,
            "dominant_amplitude": float(spectrum["amplitude"][n - 1]),
            "dominant_level": float(spectrum["roughness_level"][n - 1]),
            "band_levels": bands.band_levels(u, diameter)}


MAX_FORECAST_WORK = 2 * 10**9  # ETDRK4 steps x points over the samples: 2 million steps of 1024 points


def _check_saved(rows, n_save, points):
    """Refuse, before it runs, a forecast whose saved states (``rows`` samples, ``n_save`` times,
    ``points``) are more than ``MAX_SAVED_VALUES``, naming ``service.samples``."""
    if rows * n_save * points > MAX_SAVED_VALUES:
        raise ScenarioError(f"service.samples: {rows} samples of {points} points saved {n_save} times are "
                            f"{rows * n_save * points:.3g} values, more than MAX_SAVED_VALUES = {MAX_SAVED_VALUES:.0e}: "
                            f"at most {MAX_SAVED_VALUES // (n_save * points)} samples at {points} points (--samples)")


def _check_work(strategy, u0, t_end, n_save, life_km, horizon_field):
    """Refuse, before it runs, a batched forecast (``strategy`` a :class:`Phenomenological` over the
    samples, from ``u0`` to normed time ``t_end``) whose work is more than :data:`MAX_FORECAST_WORK`:
    the ETDRK4 steps the step-size control starts with (each sample's largest linear growth rate
    at the measured wheel sets them), over the samples and output intervals, times the points.
    The refusal names ``horizon_field`` (``solver.t_end`` or ``horizon_km``) and the longest
    horizon within the bound."""
    from railwear.pde import as_wear_rate
    from railwear.pde.equation import EvolutionEquation
    from railwear.pde.solver import ETDRK4Solver, _Loop

    rows, points, intervals = len(strategy.speed), u0.size, n_save - 1
    equation = EvolutionEquation.from_input(u0, as_wear_rate(strategy.h), strategy.speed, strategy.epsilon,
                                            strategy.nu, drift=strategy.drift, dispersion=strategy.dispersion,
                                            dealias=strategy.options.get("dealias", True))
    loop = _Loop(ETDRK4Solver(dt=strategy.options.get("dt"), n_save=n_save), equation, t_end)
    steps = float(np.sum(loop.steps)) * intervals
    if steps * points <= MAX_FORECAST_WORK:
        return
    # The steps scale with the horizon; rounding each row's steps per interval up (and to even)
    # adds at most two per row and interval, which the longest horizon leaves room for.
    longest = _round_down(t_end * (MAX_FORECAST_WORK - 2 * rows * intervals * points) / (steps * points))
    growth = float(np.max(equation.growth_bound(loop.v)))
    efold = life_km / growth
    efold = _length(efold) if efold >= 1 else f"{efold * 1e3:.2g} m"
    if horizon_field == "horizon_km":
        asked, most = _length(t_end * life_km), _length(longest * life_km)
    else:
        asked = f"{t_end:.6g} ({_length(t_end * life_km)})"
        most = f"{longest:.4g} ({_length(longest * life_km)}; --horizon-km)"
    raise ScenarioError(
        f"{horizon_field}: {asked} is too far to forecast: {rows} samples of {points} points take about "
        f"{steps:.2g} ETDRK4 steps, as the fastest grows e-fold every {efold} ({growth:.2g} per life), and "
        f"{steps * points:.2g} steps x points is more than MAX_FORECAST_WORK = {MAX_FORECAST_WORK:.0e}: "
        f"at most {most}, or a wheel that grows slower")


def _length(km):
    """A distance in km as the messages write it: whole km from 10 km, else two digits."""
    return f"{km:,.0f} km" if km >= 10 else f"{km:.2g} km"


def _round_down(x, digits=2):
    """``x`` > 0 rounded down to ``digits`` significant digits."""
    unit = 10.0 ** (np.floor(np.log10(x)) - digits + 1)
    return float(np.floor(x / unit) * unit)


def _linear_runs(samples, u0, t_end, progress=None):
    """Each sample's scenario run by its own strategy (the Fourier technique or the multiplier law
    on its body: the disk wheel or the wheel on the track) from ``u0`` to ``t_end``, stacked over a
    ``speed`` dimension as the phenomenological batch gives them."""
    runs, done = [], {}
    for k, sample in enumerate(samples):
        key = (sample.operation.speed_kmh, sample.wheel.static_load_kN, sample.contact.friction_coefficient)
        if key not in done:  # samples without scatter share one run
            done[key] = _states(build.strategy(sample), u0, t_end)
        runs.append(done[key])
        if progress is not None:
            progress((k + 1) / len(samples))
    speeds = [float(sample.operation.speeds) for sample in samples]
    time = runs[0][0]  # every run saves the same normed times; their float values differ in the last bit
    u = np.stack([states for _, states in runs])
    return xr.Dataset({"u": (("speed", "time", "angle"), u)},
                      coords={"speed": speeds, "time": time, "angle": 2 * np.pi * np.arange(u0.size) / u0.size})


def _states(strategy, u0, until):
    """``(time, u)``: the normed times and ``u`` (m, over time and angle) of ``strategy.run(u0,
    until)``, the states alone. For the Fourier technique without a limit (a forecast's samples)
    they are its exact solution (:meth:`~railwear.longterm.fourier.Harmonics.run`) over ``until``
    lives at its speed, without the strategy's result around it (the spectra of
    :func:`railwear.longterm.spectra.describe`, most of a sample's cost); a state that is not
    finite is left to ``run`` to report in normed time."""
    from railwear.errors import NumericalInstabilityError
    from railwear.longterm.base import checked_start
    from railwear.longterm.fourier import Fourier, FourierCycle, FourierStrategy

    if (isinstance(strategy, FourierStrategy) and type(strategy.fourier) in (Fourier, FourierCycle)
            and strategy.peak_to_peak_limit is None):
        speed, life = strategy.fourier.speed, strategy.life_distance
        try:
            ds = strategy.fourier.run(checked_start(u0, until, None), until * life / speed, strategy.n_save)
        except NumericalInstabilityError:
            ds = None  # the strategy's own run below reports it, in normed time
        if ds is not None:
            return ds.time.values * speed / life, ds.u.transpose("time", "angle").values
    u = strategy.run(u0, until=until).u
    return u.time.values, u.transpose("time", "angle").values


def forecast(scenario: Scenario, angle, deviation, limit, horizon=None, n_save=201, progress=None,
             horizon_field="horizon", diameter_checked=False):
    """Distance (km) until the measured wheel reaches ``limit``, per sample: each sample's speed,
    load and friction run by the scenario's Fourier technique or multiplier law on its body, or
    else by the evolution equation of its ``[wear_rate]`` (batched over the samples).

    ``angle`` (rad) and ``deviation`` (m) are the measured wheel; ``limit`` a :class:`Limit`, a
    peak-to-peak deviation in m or a text (:func:`parse_limit`); ``horizon`` is in units of
    normed time (default the scenario's ``solver.t_end``). Returns a Dataset with the samples'
    conditions, peak-to-peak and excess over the limit over distance, crossing distances, the
    measured wheel's state, and the quantiles in attributes. Warns (:class:`NoScatterWarning`)
    when the samples all run the same conditions; ``diameter_checked``: whether the measured
    wheel's nominal diameter was found to be the scenario's (:func:`check_diameter`). A forecast past ``MAX_SAVED_VALUES`` or
    :data:`MAX_FORECAST_WORK` is refused before it runs (:class:`ScenarioError` naming
    ``service.samples``, or ``horizon_field``, the horizon's name, ``solver.t_end`` without one).
    """
    limit = as_limit(limit)
    _check_saved(scenario.service.samples, n_save, scenario.solver.points)
    diameter = 2 * scenario.wheel.radius_m
    u0 = roundness.resample_measured(angle, deviation, scenario.solver.points)
    limit.check(u0, diameter)
    speed, load, friction = draw_conditions(scenario)
    scatter = bool(np.ptp(speed) > 0 or np.ptp(load) > 0 or np.ptp(friction) > 0)
    if not scatter:
        warnings.warn(NO_SCATTER, NoScatterWarning, stacklevel=2)
    solver = scenario.solver
    t_end = solver.t_end if horizon is None else horizon
    samples = [scenario.model_copy(update={
        "wheel": scenario.wheel.model_copy(update={"static_load_kN": float(w)}),
        "contact": scenario.contact.model_copy(update={"friction_coefficient": float(mu)}),
        "operation": scenario.operation.model_copy(update={"speed_kmh": float(v), "speed_m_s": None}),
        "solver": solver.model_copy(update={"n_save": n_save, "peak_to_peak_limit_mm": None})})
        for v, w, mu in zip(speed, load, friction)]
    if scenario.strategy.needs == "linear_model":
        ds = _linear_runs(samples, u0, t_end, progress)
    else:
        strategy = Phenomenological([build.wear_rate(sample) for sample in samples], kmh_to_m_s(speed), solver.epsilon,
                                    solver.nu, options={"n_save": n_save, "dealias": solver.dealias, "dt": solver.dt},
                                    life_distance=build.life_distance(scenario))
        _check_work(strategy, u0, t_end, n_save, scenario.operation.life_distance_km,
                    "solver.t_end" if horizon is None else horizon_field)
        ds = strategy.run(u0, t_end, progress=progress)
    life = scenario.operation.life_distance_km
    skip = not np.all(np.isfinite(ds.u.values))  # NaN-skipping reductions (slow) only where a NaN is
    dev = (ds.u - ds.u.mean("angle", skipna=skip)).transpose("speed", "time", "angle")
    ptp = (dev.max("angle", skipna=skip) - dev.min("angle", skipna=skip)).values
    excess, where = limit.excess(dev.values, diameter)
    times = ds.time.values
    if limit.kind == "peak_to_peak":
        cross = np.array([crossing(times, p, limit.peak_to_peak) for p in ptp]) * life
    else:
        cross = np.array([crossing(times, e, 0.0) for e in excess]) * life
    at = [int(np.searchsorted(times * life, c)) if np.isfinite(c) else times.size - 1 for c in cross]
    at = np.minimum(at, times.size - 1)
    # polygon_spectrum's dominant order (the largest amplitude of orders 1 to N/2), all samples at once
    orders = np.argmax(roundness.harmonic_amplitudes(dev.values[np.arange(len(at)), at])[:, 1:], axis=-1) + 1
    crossed = np.isfinite(cross)
    with np.errstate(invalid="ignore"):  # inf where more than that fraction never crosses
        q = np.quantile(cross, QUANTILES, method="inverted_cdf")
    state = measured_state(u0, diameter)
    levels = state["band_levels"]
    variables = {
        "peak_to_peak": (("sample", "distance"), ptp, {"units": "m", "long_name": "peak-to-peak radius deviation"}),
        "excess": (("sample", "distance"), excess,
                   {"units": "dB", "long_name": f"largest level above the limit ({limit.name})",
                    **_undefined(excess, ROUND)}),
        "crossing_distance": (("sample",), cross,
                              {"units": "km", "long_name": "distance until the limit is reached (inf: not within the horizon)",
                               **_undefined(cross, NOT_REACHED)}),
        "dominant_order": (("sample",), orders,
                           {"units": "1", "long_name": "dominant polygon order at the crossing (at the horizon if none)"}),
        **{name: (("sample",), v.values, dict(v.attrs)) for name, v in _speeds(speed).items()},
        "static_load": (("sample",), load, {"units": "kN", "long_name": "static wheel load"}),
        "friction_coefficient": (("sample",), friction, {"units": "1", "long_name": "friction coefficient"}),
        "u_initial": (("angle",), u0, {"units": "m", "long_name": "measured radius deviation on the grid"}),
        "measured_band_level": (("band",), levels.level,
                                {"units": "dB", "long_name": "one-third-octave band level of the measured wheel, re 1 um",
                                 **_undefined(levels.level, NO_ENERGY)}),
        "band_resolved": (("band",), levels.resolved.astype(np.int8),
                          {"units": "1", "long_name": "1 where the band is at most a quarter of the circumference"}),
    }
    if limit.kind != "peak_to_peak":
        name, units = (("limiting_order", "1") if limit.kind == "order_level" else ("limiting_wavelength", "m"))
        variables[name] = (("sample",), where[np.arange(speed.size), at],
                           {"units": units, "long_name": "order or band furthest above the limit at the crossing "
                                                         "(at the horizon if none)"})
    sample = np.arange(speed.size)
    attrs = {"limit_kind": limit.kind, "limit_name": limit.name,
             "crossing_median_km": q[1], "crossing_p05_km": q[0], "crossing_p95_km": q[2],
             "fraction_crossed": float(np.mean(crossed)),
             "dominant_order": int(np.bincount(orders[crossed] if crossed.any() else orders).argmax()),
             "dominant_order_at": "crossing" if crossed.any() else "horizon",
             "horizon_km": float(times[-1] * life), "scatter": int(scatter),
             "initial_excess_db": float(excess[0, 0]), "above_at_start": int(excess[0, 0] >= 0 or cross.min() == 0),
             "measured_peak_to_peak_m": state["peak_to_peak"], "measured_dominant_order": state["dominant_order"],
             "measured_dominant_amplitude_m": state["dominant_amplitude"],
             "measured_dominant_level_db": state["dominant_level"], "wheel_diameter_m": diameter,
             "diameter_checked": int(bool(diameter_checked)),
             "scenario": to_toml(scenario), "scenario_hash": scenario_hash(scenario)}
    for key in ("initial_excess_db", "measured_dominant_level_db"):  # -inf dB of a round wheel: no level
        if not np.isfinite(attrs[key]):
            del attrs[key]
    if limit.kind == "peak_to_peak":
        attrs["limit_m"] = limit.peak_to_peak
    else:
        attrs.update(limit_orders=np.array(limit.orders, int), limit_levels_db=np.array(limit.levels, float))
    return xr.Dataset(
        variables,
        coords={"sample": sample, "distance": ("distance", times * life, {"units": "km", "long_name": "distance run"}),
                "angle": ("angle", ds.angle.values, dict(ds.angle.attrs)),
                "band": ("band", levels.wavelength, {"units": "m", "long_name": "nominal band centre wavelength"})},
        attrs=attrs)


def forecast_file(measured, scenario=None, limit=0.3 * MM, samples=None, seed=None, horizon_km=None,
                  angle_unit=None, deviation_unit=None, progress=None, nominal_diameter=None):
    """:func:`forecast` for a measured wheel in a CSV file (see :mod:`railwear.measured`; the
    units of plain ``angle`` and ``deviation`` columns are ``angle_unit`` 'deg' or 'rad' and
    ``deviation_unit`` 'um', 'mm' or 'm'; ``nominal_diameter`` in m for a file of absolute
    radius or diameter), a scenario file or built-in name, ``limit`` as :func:`forecast` takes
    it, ``samples`` and ``seed`` in place of the scenario's ``[service]`` ones and
    ``horizon_km`` the distance to look ahead (default the scenario's ``solver.t_end`` lives)."""
    sc = load_scenario(scenario)
    service = {k: v for k, v in (("samples", samples), ("seed", seed)) if v is not None}
    if service:
        try:
            sc = sc.model_validate({**sc.applicable(mode="python", exclude_none=False), "service": {**sc.service.model_dump(), **service}})
        except ValidationError as e:
            first = e.errors()[0]
            raise OptionError(f"{first['loc'][-1]}: {first['msg']}") from None
    limit = as_limit(limit)
    if horizon_km is not None and not (np.isfinite(horizon_km) and horizon_km > 0):
        raise OptionError(f"horizon_km: must be finite and > 0 (km), got {horizon_km!r}")
    for name, unit, units in (("angle_unit", angle_unit, ANGLE_UNITS), ("deviation_unit", deviation_unit, DEVIATION_UNITS)):
        if unit is not None and unit not in units:
            raise OptionError(f"{name}: unknown unit {unit!r}; use one of {', '.join(units)}")
    horizon = None if horizon_km is None else horizon_km / sc.operation.life_distance_km
    if horizon is not None:  # the horizon takes the place of solver.t_end, and its bounds
        try:
            Solver.model_validate({**sc.solver.model_dump(), "t_end": horizon})
        except ValidationError as e:
            raise OptionError(f"horizon_km: {horizon_km:g} km is {horizon:g} lives: "
                              f"{e.errors()[0]['msg'].removeprefix('Value error, ')}") from None
    if nominal_diameter is not None:
        check_diameter(nominal_diameter, sc)
    angle, deviation = read_measured(measured, angle_unit, deviation_unit, field=str(measured),
                                     nominal_diameter=nominal_diameter)
    return forecast(sc, angle, deviation, limit, horizon, progress=progress, horizon_field="horizon_km",
                    diameter_checked=nominal_diameter is not None)


DIAMETER_MATCH = 0.01  # a measured wheel's nominal diameter within 1 % of the scenario's wheel is that wheel


def check_diameter(nominal_diameter, scenario):
    """Refuse a measured wheel whose nominal diameter (m) is not the scenario's wheel's (within
    :data:`DIAMETER_MATCH`): its orders would be read on another circumference and run by another
    wheel's physics (an 840 mm metro wheel under a 920 mm scenario)."""
    wheel = 2 * scenario.wheel.radius_m
    if not abs(nominal_diameter - wheel) <= DIAMETER_MATCH * wheel:
        raise OptionError(
            f"--nominal-diameter: the measured wheel is {nominal_diameter / MM:g} mm, the scenario's {wheel / MM:g} mm "
            f"(wheel.radius_m = {scenario.wheel.radius_m:g}): the forecast would read it as another wheel; give a "
            f"scenario of that wheel (--set wheel.radius_m={nominal_diameter / 2:g}) or check the diameter")


def _km(x, horizon):
    return f"{x:,.0f} km" if np.isfinite(x) else f"beyond {horizon:,.0f} km"


def _wavelength(m):
    return f"{m / MM:.4g} mm"


def _limiting(ds):
    """Where the limit bites at the crossing (or at 0 km): the commonest order or band, or ''."""
    crossed = np.isfinite(ds.crossing_distance.values)
    for name, words in (("limiting_order", "order {:.0f}"), ("limiting_wavelength", "the {} band")):
        if name in ds and crossed.any():
            values, counts = np.unique(ds[name].values[crossed], return_counts=True)
            value = values[counts.argmax()]
            return words.format(_wavelength(value) if name == "limiting_wavelength" else value)
    return ""


def measured_text(ds):
    """Lines on the measured wheel's state: peak to peak, dominant order, band levels."""
    a = ds.attrs
    if "measured_peak_to_peak_m" not in a:
        return ""
    if "measured_dominant_level_db" in a:
        lines = [f"measured wheel: {a['measured_peak_to_peak_m'] / UM:.1f} um peak to peak, dominant order "
                 f"{a['measured_dominant_order']} ({a['measured_dominant_amplitude_m'] / UM:.1f} um amplitude, "
                 f"{a['measured_dominant_level_db']:.1f} dB re 1 um)"]
    else:
        lines = [f"measured wheel: {a['measured_peak_to_peak_m'] / UM:.1f} um peak to peak, round: no polygon order "
                 "has an amplitude"]
    if "wheel_diameter_m" in a:
        size = f"  wheel diameter {a['wheel_diameter_m'] / MM:g} mm, the scenario's (wheel.radius_m)"
        lines.append(size + (": the measured wheel's nominal diameter agrees" if a.get("diameter_checked") else
                             "; the measured wheel's is not given, so a wheel of another size is read as "
                             "this one (--nominal-diameter checks it)"))
    level = ds.measured_band_level.values
    if np.isfinite(level).any():
        keep = level >= np.max(level[np.isfinite(level)]) - ECHO_RANGE
        cells = [(f"{_wavelength(w)} {v:.1f}" if r else f"({_wavelength(w)} {v:.1f})")
                 for w, v, r, k in zip(ds.band.values, level, ds.band_resolved.values, keep) if k]
        lines.append(f"  band levels, dB re 1 um (EN 15610, diameter {a['wheel_diameter_m'] / MM:g} mm; in brackets "
                     f"bands longer than a quarter of the circumference, not resolved): " + ", ".join(cells))
    return "\n".join(lines) + "\n"


def report(ds):
    """Lines for a person: the measured wheel, the limit, and when it is reached, in words (and in
    months of service where the scenario gives ``operation.daily_distance_km``)."""
    from railwear.results import daily_distance_km, months

    a = ds.attrs
    horizon, samples = a["horizon_km"], ds.sizes["sample"]
    name = a.get("limit_name", f"{a.get('limit_m', float('nan')) / MM:g} mm peak to peak")
    lines = [measured_text(ds).rstrip("\n")] if "measured_peak_to_peak_m" in a else []
    lines.append(f"limit: {name}")
    excess = ds.excess.values if "excess" in ds else None
    where = _limiting(ds)
    daily = daily_distance_km(ds)
    if daily:
        lines.append(f"  months of service at {daily:g} km a day (operation.daily_distance_km)")

    def at(x):
        return _km(x, horizon) + (f" ({months(x, daily):.1f} months)" if daily and np.isfinite(x) else "")

    if a.get("above_at_start", 0) or (np.isfinite(a["crossing_p95_km"]) and a["crossing_p95_km"] == 0):
        over = f" by {a['initial_excess_db']:.1f} dB" if "initial_excess_db" in a else ""
        lines.append(f"  already above the limit at 0 km{over}{f' ({where})' if where else ''}: "
                     "the wheel is due for re-profiling now")
    elif a["fraction_crossed"] == 0:
        closest = ""
        if excess is not None:
            closest = (f"; the closest sample ends {-np.max(excess[:, -1]):.1f} dB under it"
                       if np.isfinite(np.max(excess[:, -1])) else "; every sample ends round")
        lines.append(f"  no sample reaches the limit within the horizon of {horizon:,.0f} km "
                     f"({samples} samples){closest}; dominant order at {horizon:,.0f} km: {a['dominant_order']}")
    else:
        if not a.get("scatter", 1):
            when = (f"reached after {at(a['crossing_median_km'])}, the same for every sample: the "
                    "scenario has no service scatter, so there is no band")
        elif np.isfinite(a["crossing_median_km"]):
            share = ("every sample reaches it" if a["fraction_crossed"] == 1 else
                     f"{a['fraction_crossed']:.0%} of {samples} samples reach it within {horizon:,.0f} km")
            when = (f"reached after {at(a['crossing_median_km'])} (median of {samples} samples), "
                    f"90 % band {at(a['crossing_p05_km'])} to {at(a['crossing_p95_km'])}; {share}")
        else:
            first = (f"the first 5 % after {a['crossing_p05_km']:,.0f} km" if np.isfinite(a["crossing_p05_km"]) else
                     f"the first after {np.nanmin(ds.crossing_distance.values):,.0f} km")
            when = (f"{a['fraction_crossed']:.0%} of {samples} samples reach it within {horizon:,.0f} km, {first}; "
                    f"the median lies beyond {horizon:,.0f} km")
        lines.append(f"  {when}; dominant order at the crossing {a['dominant_order']}"
                     + (f", furthest above the limit there: {where}" if where else ""))
    if not a.get("scatter", 1):
        lines.append(f"  warning: {NO_SCATTER}")
    return "\n".join(lines) + "\n"
