"""The measured-wheel forecast: when does this wheel pass its out-of-roundness limit? (layer 4)

The measured radius deviation is evolved under service conditions drawn from the scenario's
``[service]`` section (speed peaks with weights and scatter, static-load scatter, a friction
range), one batch row per Monte Carlo sample. The out-of-roundness is the peak-to-peak radius
deviation round the wheel; the forecast is the distance run until it first reaches the limit,
reported as a median with a 90 % band over the samples.
"""

import numpy as np
import xarray as xr
from pydantic import ValidationError

from railwear.errors import OptionError
from railwear.geometry import roundness
from railwear.longterm.phenomenological import Phenomenological
from railwear.measured import ANGLE_UNITS, DEVIATION_UNITS, read_measured
from railwear.scenario import Scenario, load_scenario, scenario_hash, to_toml
from railwear.scenario.schema import Solver
from railwear.scenario import build
from railwear.units import MM, kmh_to_m_s, m_s_to_kmh

QUANTILES = (0.05, 0.5, 0.95)


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


def forecast(scenario: Scenario, angle, deviation, limit, horizon=None, n_save=201, progress=None):
    """Distance (km) until the peak-to-peak deviation reaches ``limit`` (m), per sample.

    ``angle`` (rad) and ``deviation`` (m) are the measured wheel; ``horizon`` is in units of
    normed time (default the scenario's ``solver.t_end``). Returns a Dataset with the samples'
    conditions, peak-to-peak over distance and crossing distances, and the quantiles in attributes.
    """
    speed, load, friction = draw_conditions(scenario)
    forms = []
    for v, w, mu in zip(speed, load, friction):
        sample = scenario.model_copy(update={
            "wheel": scenario.wheel.model_copy(update={"static_load_kN": float(w)}),
            "contact": scenario.contact.model_copy(update={"friction_coefficient": float(mu)})})
        forms.append(build.wear_rate(sample))
    u0 = roundness.resample_measured(angle, deviation, scenario.solver.points)
    solver = scenario.solver
    t_end = solver.t_end if horizon is None else horizon
    strategy = Phenomenological(forms, kmh_to_m_s(speed), solver.epsilon, solver.nu,
                                options={"n_save": n_save, "dealias": solver.dealias, "dt": solver.dt},
                                life_distance=build.life_distance(scenario))
    ds = strategy.run(u0, t_end, progress=progress)
    life = scenario.operation.life_distance_km
    dev = ds.u - ds.u.mean("angle")
    ptp = (dev.max("angle") - dev.min("angle")).transpose("speed", "time").values
    times = ds.time.values
    cross = np.array([crossing(times, p, limit) for p in ptp]) * life
    orders = []
    for i, c in enumerate(cross):
        k = int(np.searchsorted(times * life, c)) if np.isfinite(c) else times.size - 1
        orders.append(roundness.polygon_spectrum(dev.isel(speed=i, time=min(k, times.size - 1)).values)["dominant_order"])
    with np.errstate(invalid="ignore"):  # inf where more than that fraction never crosses
        q = np.quantile(cross, QUANTILES, method="inverted_cdf")
    sample = np.arange(speed.size)
    out = xr.Dataset(
        {
            "peak_to_peak": (("sample", "distance"), ptp,
                             {"units": "m", "long_name": "peak-to-peak radius deviation"}),
            "crossing_distance": (("sample",), cross,
                                  {"units": "km", "long_name": "distance until the limit is reached (inf: not within the horizon)"}),
            "dominant_order": (("sample",), np.array(orders),
                               {"units": "1", "long_name": "dominant polygon order at the crossing"}),
            "speed": (("sample",), speed, {"units": "km h-1", "long_name": "vehicle speed"}),
            "static_load": (("sample",), load, {"units": "kN", "long_name": "static wheel load"}),
            "friction_coefficient": (("sample",), friction, {"units": "1", "long_name": "friction coefficient"}),
            "u_initial": (("angle",), u0, {"units": "m", "long_name": "measured radius deviation on the grid"}),
        },
        coords={"sample": sample, "distance": ("distance", times * life, {"units": "km", "long_name": "distance run"}),
                "angle": ("angle", ds.angle.values, dict(ds.angle.attrs))},
        attrs={"limit_m": limit, "crossing_median_km": q[1], "crossing_p05_km": q[0], "crossing_p95_km": q[2],
               "fraction_crossed": float(np.mean(np.isfinite(cross))),
               "dominant_order": int(np.bincount(np.array(orders)[np.isfinite(cross)]).argmax()) if np.isfinite(cross).any() else 0,
               "horizon_km": float(times[-1] * life), "scenario": to_toml(scenario),
               "scenario_hash": scenario_hash(scenario)},
    )
    return out


def forecast_file(measured, scenario=None, limit=0.3 * MM, samples=None, seed=None, horizon_km=None,
                  angle_unit=None, deviation_unit=None, progress=None):
    """:func:`forecast` for a measured wheel in a CSV file (see :mod:`railwear.measured`; the
    units of plain ``angle`` and ``deviation`` columns are ``angle_unit`` 'deg' or 'rad' and
    ``deviation_unit`` 'um', 'mm' or 'm'), a scenario file or built-in name, ``limit`` in m,
    ``samples`` and ``seed`` in place of the scenario's ``[service]`` ones and ``horizon_km``
    the distance to look ahead (default the scenario's ``solver.t_end`` lives)."""
    sc = load_scenario(scenario)
    service = {k: v for k, v in (("samples", samples), ("seed", seed)) if v is not None}
    if service:
        try:
            sc = sc.model_validate({**sc.applicable(mode="python", exclude_none=False), "service": {**sc.service.model_dump(), **service}})
        except ValidationError as e:
            first = e.errors()[0]
            raise OptionError(f"{first['loc'][-1]}: {first['msg']}") from None
    if not (np.isfinite(limit) and 0 < limit <= 1.0):
        raise OptionError(f"limit: must be in (0, 1] m, got {limit!r}")
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
    angle, deviation = read_measured(measured, angle_unit, deviation_unit, field=str(measured))
    return forecast(sc, angle, deviation, limit, horizon, progress=progress)


def report(ds):
    """Lines for a person."""
    def km(x):
        return f"{x:,.0f} km" if np.isfinite(x) else f"beyond {ds.attrs['horizon_km']:,.0f} km"

    a = ds.attrs
    return (f"limit {a['limit_m'] / MM:g} mm peak-to-peak: median {km(a['crossing_median_km'])}, "
            f"90 % band {km(a['crossing_p05_km'])} to {km(a['crossing_p95_km'])} "
            f"({a['fraction_crossed']:.0%} of {ds.sizes['sample']} samples cross); "
            f"dominant order {a['dominant_order']}\n")
