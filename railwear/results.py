"""Result files: netCDF through h5netcdf written atomically, and the run summary (layer 4)."""

import json
import os
import secrets
import zipfile
import zlib
from pathlib import Path

import numpy as np
import xarray as xr
from numpy.lib.npyio import NpzFile

from railwear.errors import CheckpointError, ScenarioError
from railwear.longterm import regime
from railwear.longterm.regime import PER_10000_KM, REGIME_RULE, ROUND_PEAK_TO_PEAK, is_round, wheel_regime  # noqa: F401
from railwear.units import MM, MM3, UM, kmh_to_m_s, m_s_to_kmh


PART = ".part"  # the suffix of a file being written; never read as a result


def _part_name(path):
    """``.NAME.PID.RANDOM.part`` beside ``path``: the writer's process id tells a later run
    whether the writer is still alive (:func:`clean_partial`)."""
    return path.parent / f".{path.name}.{os.getpid()}.{secrets.token_hex(4)}{PART}"


def _atomic(path, write):
    """Call ``write(tmp_path)`` on a new temporary file beside ``path``, then rename it over
    ``path``. The rename replaces a symbolic link of that name rather than writing through it,
    and the file gets the permissions of a new file (group-readable under the usual umask)."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = _part_name(path)
    os.close(os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_NOFOLLOW", 0), 0o666))
    try:
        write(str(tmp))
        os.replace(tmp, path)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise
    return path


def _alive(pid):
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except OSError:  # another user's process, or no signals here: keep its file
        return True
    return True


def clean_partial(directory):
    """Remove the temporary files killed writers left in ``directory`` (those of a live process
    are kept); returns their names."""
    directory = Path(directory)
    if not directory.is_dir():
        return []
    removed = []
    for entry in directory.iterdir():
        name = entry.name
        if not (name.startswith(".") and name.endswith(PART)):
            continue
        parts = name[: -len(PART)].rsplit(".", 2)
        pid = int(parts[1]) if len(parts) == 3 and parts[1].isdigit() else None
        if pid is not None and _alive(pid):
            continue
        if entry.is_symlink() or entry.is_file():
            entry.unlink(missing_ok=True)
            removed.append(name)
    return removed


def _readable(path, what):
    path = Path(path)
    if path.name.endswith(PART):
        raise ScenarioError(f"{path}: a temporary file of a killed writer, not a {what}")
    return path


FILL_VALUE = 9.969209968386869e36  # netCDF's default fill of a double: where a statistic is undefined


def masked_for_writing(ds: xr.Dataset):
    """``ds`` with each float variable that says why it has no value somewhere (its
    :data:`~railwear.longterm.spectra.UNDEFINED` attribute) encoded with ``_FillValue``
    :data:`FILL_VALUE`: its NaN and ±inf are written as the fill, and read back as NaN."""
    from railwear.longterm.spectra import UNDEFINED

    out = ds.copy()
    for name, var in ds.data_vars.items():
        if UNDEFINED in var.attrs and var.dtype.kind == "f":
            values = np.asarray(var.values)
            out[name] = var.copy(data=np.where(np.isfinite(values), values, np.nan))
            out[name].encoding = {**var.encoding, "_FillValue": FILL_VALUE}
    return out


def write_netcdf(ds: xr.Dataset, path):
    """Write ``ds`` as netCDF 4 (h5netcdf) to ``path`` without ever leaving a half-written file;
    undefined statistics are masked (:func:`masked_for_writing`)."""
    ds = masked_for_writing(ds)
    return _atomic(path, lambda tmp: ds.to_netcdf(tmp, engine="h5netcdf", invalid_netcdf=False))


def write_text(text, path):
    """Write text atomically (UTF-8)."""
    return _atomic(path, lambda tmp: Path(tmp).write_text(text, encoding="utf-8"))


def write_array(array, path):
    """Write a NumPy array as ``.npy`` atomically."""
    def write(tmp):
        with open(tmp, "wb") as f:
            np.save(f, np.asarray(array), allow_pickle=False)

    return _atomic(path, write)


SPEED_UNITS = ("m s-1", "km h-1")  # the units attributes of the speeds railwear writes


def speed_in(var, units):
    """The values of the speed variable ``var`` in ``units`` ('m s-1' or 'km h-1'), read by its
    own ``units`` attribute (files of earlier versions kept some speeds in km h-1); a speed in no
    unit railwear writes is refused naming the variable (:class:`ScenarioError`)."""
    given = var.attrs.get("units")
    if given not in SPEED_UNITS:
        raise ScenarioError(f"{var.name}: a speed in units {given!r}, expected "
                            f"{' or '.join(repr(u) for u in SPEED_UNITS)}")
    values = np.asarray(var.values, float)
    if given == units:
        return values
    return kmh_to_m_s(values) if units == "m s-1" else m_s_to_kmh(values)


def read_netcdf(path):
    """Open a result file fully into memory (the file is closed again)."""
    with xr.open_dataset(_readable(path, "result"), engine="h5netcdf") as ds:
        return ds.load()


def wheelset_summary(ds: xr.Dataset):
    """A wheelset wear result's run: distance, worn depth (mm) per wheel at its most worn spot
    and the 90 % band it lies in, the contact range and hunting amplitude of the last step, cost."""
    from railwear.longterm.wheelset_wear import band_width

    last = ds.isel(time=-1)
    entry = {"speed_kmh": round(m_s_to_kmh(float(ds.speed)), 6), "strategy": str(ds.attrs.get("strategy", "")),
             "distance_km": float(last.distance), "steps": int(ds.sizes["time"] - 1)}
    for wheel in ds.wheel.values:
        depth = last.worn_depth.sel(wheel=wheel).values
        entry[f"{wheel}_max_worn_depth_mm"] = float(depth.max()) / MM
        entry[f"{wheel}_max_worn_at_mm"] = float(ds.lateral.values[depth.argmax()]) / MM
        if "flange_height" in ds:  # Sh, Sd, qR (EN 15313) at the end
            entry[f"{wheel}_flange_mm"] = [float(last[v].sel(wheel=wheel)) / MM
                                           for v in ("flange_height", "flange_thickness", "flange_gradient")]
    entry.update({
        "band_90_mm": band_width(last.worn_depth.mean("wheel").values, ds.lateral.values) / MM,
        "contact_range_mm": [float(last.contact_min) / MM, float(last.contact_max) / MM],
        "lateral_amplitude_mm": float(last.lateral_amplitude) / MM,
        "removed_volume_mm3": float(last.removed_volume) / MM3,
        "cost_seconds_simulated": float(ds.cost_seconds), "cost_rhs_evaluations": int(ds.cost_rhs_evaluations),
        "cost_tables": int(ds.cost_tables)})
    return entry


def summary(ds: xr.Dataset):
    """Dominant order, maxima, removed depth (mm) and regime, per speed when batched; for a
    body with its own summary (:data:`BODY_SUMMARIES`, by the result's ``body``), that one.

    A number without a value is left out and named under ``undefined`` (strict JSON has no NaN),
    and where railwear knows why, ``undefined_because`` says it: a wheel round at the end has no
    dominant order or maxima, an order that grew from round-off or whose rate is within its
    standard error has no growth per 10 000 km (:func:`growth_note`)."""
    if ds.attrs.get("body") in BODY_SUMMARIES:
        return {"scenario": ds.attrs.get("scenario_name", ""), "scenario_hash": ds.attrs.get("scenario_hash", ""),
                "railwear_version": ds.attrs.get("railwear_version", ""),
                "runs": [_defined(BODY_SUMMARIES[ds.attrs["body"]](ds))]}
    out = []
    life = float(ds.attrs.get("life_distance_km", 0.0))
    for key, d in _runs(ds):
        entry = dict(key)
        entry.pop("speed", None)
        entry["speed_kmh"] = round(m_s_to_kmh(float(d.speed)), 6)
        why = {}
        entry.update({
            "regime": str(d.regime.values),
            "round": is_round(float(d.peak_to_peak)),
            "round_at_start": is_round(float(d.peak_to_peak_initial)),
            "dominant_order": int(d.dominant_order),
            "maxima": int(d.maxima),
            "max_removed_depth_mm": float(d.removed_depth.isel(time=-1)) / MM,
            "mean_removed_depth_mm": float(d.mean_removed_depth.isel(time=-1)) / MM,
            "peak_to_peak_initial_um": float(d.peak_to_peak_initial) / UM,
            "peak_to_peak_um": float(d.peak_to_peak) / UM,
            "stop_time": float(d.stop_time),
            "distance_km": float(d.stop_time) * life,
            "out_of_round_growth_factor": float(d.out_of_round_growth_factor),
            "leading_order": int(d.leading_order),
            "leading_growth_factor": float(d.leading_growth_factor),
        })
        if entry["round"]:
            for name in ("dominant_order", "maxima"):
                entry[name] = None
                why[name] = ROUND_WHEEL
        if entry["round_at_start"]:
            why["out_of_round_growth_factor"] = ROUND_START
        if life > 0 and entry["leading_order"] > 0:
            entry["leading_growth_per_10000_km"], note = order_growth(d, entry["leading_order"], life)
            if note:
                why["leading_growth_per_10000_km"] = note
        polygon, notes = _polygon(d, entry, life)
        entry.update(polygon)
        why.update(notes)
        # a surface per wheel: the wheels' combination is the whole result's, not this row's
        entry.update(_wheels(ds if "wheel" in ds.dims and "wheel" not in d.dims else d, entry["dominant_order"]))
        entry.update(_wheel_on_rail(d, entry["dominant_order"], life))
        out.append(_defined(entry, why))
    return {"scenario": ds.attrs.get("scenario_name", ""), "scenario_hash": ds.attrs.get("scenario_hash", ""),
            "railwear_version": ds.attrs.get("railwear_version", ""), **_demand(ds), **_scope(ds), "runs": out}


def _wheels(d, n):
    """Several wheels on one rail: their positions (m) and the combination in which order ``n``
    grows on them, amplitudes relative to the largest and phases (degrees) against the first."""
    if ("combination_phase" not in d and "wheel_growth_per_km" not in d) or not n:
        return {}
    at = d.sel(order=n)
    modes = {}
    if "rail_mode_held" in d:
        modes = {"rail_modes_hz": {k: [None if np.isnan(v) else round(float(v), 1) for v in d[f"rail_mode_{k}"].values]
                                   for k in ("pinned", "clamped", "held")}}
    if "wheel_growth_per_km" in d:  # phases drifting: each wheel on its own
        return {**modes, "wheel_positions_m": [float(x) for x in d.wheel_position.values],
                "wheel_growth": {"order": int(n), "per_10000_km": [float(np.expm1(g * PER_10000_KM))
                                                                   for g in at.wheel_growth_per_km.values]}}
    return {**modes, "wheel_positions_m": [float(x) for x in d.wheel_position.values],
            "combination": {"order": int(n), "amplitudes": [round(float(a), 4) for a in at.combination_amplitude.values],
                            "phases_deg": [180 - (180 - round(float(np.degrees(p)), 2)) % 360  # in (-180, 180]
                                           for p in at.combination_phase.values]}}


def _wheel_on_rail(d, n, life):
    """One wheel of several on the time-domain track (``d.linear_growth_rate``): its dominant
    order's amplitude (um) at the end and, beside its share and phase (deg, against the first
    wheel) among the wheels' harmonics, the linear model's fastest combination of that order:
    its growth per 10 000 km, this wheel's share and phase in it."""
    if "linear_growth_rate" not in d or not n:
        return {}
    degrees = {k: round(float(np.degrees(d[k])), 1) + 0.0 for k in ("linear_phase", "measured_phase")}  # never -0
    return {"dominant_amplitude_um": float(d.amplitude.sel(order=n)) / UM,
            "linear_growth_per_10000_km": growth_per_10000_km(float(d.linear_growth_rate), life) if life > 0 else
            float("nan"), "linear_share": float(d.linear_share), "linear_phase_deg": degrees["linear_phase"],
            "measured_share": float(d.measured_share), "measured_phase_deg": degrees["measured_phase"]}


def _scope(ds):
    """What the model was validated against and why the run lies outside it, where it does
    (``api.run``'s ``validated_against`` and ``outside_validation``)."""
    keys = ("validated_against", "outside_validation")
    return {k: ds.attrs[k] for k in keys} if "outside_validation" in ds.attrs else {}


def _runs(ds):
    """``(key, run)`` per row of a long-term result: ``{}`` and the result itself, or per entry of
    its batch dimension ``{dim: value}`` and that row."""
    batch = list(ds.regime.dims) if "regime" in ds else [d for d in ds.u.dims if d not in ("time", "angle")]
    if not batch:
        yield {}, ds
        return
    for i in range(ds.sizes[batch[0]]):
        yield {batch[0]: float(ds[batch[0]][i])}, ds.isel({batch[0]: i})


ROUND_OFF_SHARE = 1e-9  # an order starting below this share of the largest amplitude starts at round-off
ROUND_WHEEL = "the wheel is round at the end (peak to peak under 1 pm): no order is the largest"
ROUND_START = "the wheel is round at the start (peak to peak under 1 pm): no out-of-round to grow"


def growth_note(d, n):
    """Why order ``n`` of the run ``d`` has no growth rate worth printing, or None when it has one:
    it started at round-off (under :data:`ROUND_OFF_SHARE` of the largest amplitude at the start,
    so its fitted rate is that of numerical noise, not of the wheel), its rate is undefined, or
    its standard error is as large as the rate itself."""
    start = d.amplitude_initial.values
    a0 = float(d.amplitude_initial.sel(order=n))
    if a0 == 0 and "regime" in d and str(d.regime.values) == regime.DRIVEN:
        return f"not meaningful: order {n} started at 0 m on this wheel, {regime.DRIVEN} through the rail"
    if not a0 >= ROUND_OFF_SHARE * float(start.max()) or a0 == 0:
        return (f"not meaningful: order {n} grew from round-off ({a0:.2g} m at the start, under "
                f"{_short(ROUND_OFF_SHARE)} of the largest amplitude then), so its fitted rate is not the wheel's")
    rate, error = float(d.growth_rate.sel(order=n)), float(d.growth_rate_error.sel(order=n))
    if not np.isfinite(rate):
        return f"undefined: {d.growth_rate.attrs.get('undefined_because', 'no fitted rate')}"
    if np.isfinite(error) and error >= abs(rate):
        return f"undefined: the standard error of its rate ({error:.2g}) is as large as the rate ({rate:.2g})"
    return None


def _short(x):
    """``1e-9`` for 1e-09: a number as people write it."""
    return f"{x:g}".replace("e-0", "e-").replace("e+0", "e")


def order_growth(d, n, life):
    """``(growth per 10 000 km of order n, note)``; the growth is NaN where :func:`growth_note`
    gives a reason, which is the note."""
    note = growth_note(d, n)
    return (float("nan") if note else growth_per_10000_km(float(d.growth_rate.sel(order=n)), life)), note


DEMAND = ("mean_traction_coefficient", "braking_share", "duty_cycle")  # api.demand_attributes


def _demand(ds):
    """The run's longitudinal demand (signed mean creep force over load, braking share, the cycle
    in words) as the summary's ``demand``, where the result states it."""
    return {"demand": {k: ds.attrs[k] for k in DEMAND}} if all(k in ds.attrs for k in DEMAND) else {}


def _polygon(d, entry, life):
    """The dominant polygon in the field's terms: wavelength on the tread ``2π R0 / n`` (mm), the
    frequency it excites ``n V / (2π R0)`` (Hz), its growth per 10 000 km, and where the run met
    the out-of-roundness limit (km; None if it did not). Returns ``(fields, why undefined)``."""
    out, why, n = {}, {}, entry["dominant_order"]
    if "nominal_radius" in d and n:
        circumference = 2 * np.pi * float(d.nominal_radius)
        out.update(wavelength_mm=circumference / n / MM, passing_frequency_hz=n * float(d.speed) / circumference)
        if life > 0:
            out["dominant_growth_per_10000_km"], note = order_growth(d, n, life)
            if note:
                why["dominant_growth_per_10000_km"] = note
    if "peak_to_peak_limit" in d:
        limit = float(d.peak_to_peak_limit)
        out["peak_to_peak_limit_mm"] = limit / MM
        out["limit_distance_km"] = entry["distance_km"] if float(d.peak_to_peak) >= limit * (1 - 1e-9) else None
        daily = daily_distance_km(d)
        if daily and out["limit_distance_km"] is not None:
            out["daily_distance_km"] = daily
            out["limit_months"] = months(out["limit_distance_km"], daily)
    return out, why


DAYS_PER_MONTH = 365.25 / 12


def daily_distance_km(ds):
    """The daily mileage (km) of the scenario stored with the result or sweep ``ds`` (``[operation]
    daily_distance_km``), or None where it gives none."""
    import tomllib

    try:
        text = ds.attrs.get("scenario", ds.attrs.get("base_scenario", ""))
        value = tomllib.loads(text).get("operation", {}).get("daily_distance_km")
    except tomllib.TOMLDecodeError:
        return None
    return float(value) if isinstance(value, (int, float)) and value > 0 else None


def months(km, daily_km):
    """A distance (km) in months of service at ``daily_km`` km a day (a month: 365.25 / 12 days)."""
    return km / daily_km / DAYS_PER_MONTH


def with_wheel_regime(ds):
    """``ds`` with ``regime`` by :func:`~railwear.longterm.regime.wheel_regime` (its ``rule``
    attribute :data:`REGIME_RULE`), where it has the growth rates and a normed life in km (its
    ``life_distance_km``, else its ``distance`` coordinate); otherwise ``ds`` as it is. A
    strategy's result carries this label already (``longterm.spectra.describe``)."""
    return regime.with_wheel_regime(ds)


def growth_per_10000_km(rate, life):
    """Growth (fraction) over 10 000 km of ln-rate ``rate`` per unit normed time of ``life`` km;
    ``inf`` past the float range (undefined in the summary)."""
    with np.errstate(over="ignore"):
        return float(np.expm1(rate * PER_10000_KM / life))


def defined(value):
    """Whether ``value`` (a number, or a list of them) is defined: no float in it is NaN or
    infinite. An undefined statistic is written masked and printed as 'undefined'."""
    items = value if isinstance(value, list) else [value]
    return all(np.isfinite(x) for x in items if isinstance(x, (float, np.floating)))


def _defined(entry, why=None):
    """``entry`` without its numbers that are not finite (an undefined statistic) or None for
    a reason in ``why``; ``undefined`` lists them by name and ``undefined_because`` gives the
    reasons railwear knows. Strict JSON has no NaN."""
    why = why or {}
    undefined = [k for k, v in entry.items() if not defined(v) or (v is None and k in why)]
    out = {k: v for k, v in entry.items() if k not in undefined}
    if undefined:
        out["undefined"] = undefined
    because = {k: why[k] for k in undefined if k in why}
    if because:
        out["undefined_because"] = because
    return out


BODY_SUMMARIES = {"wheelset": wheelset_summary}


def summary_text(s):
    """A few lines for a person (:func:`run_lines` per run)."""
    lines = [f"scenario {s['scenario']} (railwear {s['railwear_version']})"]
    if "demand" in s:
        lines.append(f"  service: {s['demand']['duty_cycle']}")
    for r in s["runs"]:
        lines.extend("  " + line for line in run_lines(r))
    if "outside_validation" in s:
        lines.append(f"  validated against: {s['validated_against']}")
        lines.extend(f"  outside it: {note}" for note in s["outside_validation"].split("; "))
    return "\n".join(lines) + "\n"


def run_lines(r):
    """The summary lines of one run ``r`` (an entry of :func:`summary`'s ``runs``), worded for
    the edges: a wheel round at the end or the start says so (no dominant order, no maxima, no
    growth), order 1 is the eccentricity, '1 maximum', a growth per 10 000 km in two significant
    digits (never '-0%'), and a growth that is undefined or not meaningful says which and why."""
    if "band_90_mm" in r:
        return [f"{r['speed_kmh']:g} km/h, wheelset {r['strategy']}: after {r['distance_km']:.0f} km worn "
                f"{r['left_max_worn_depth_mm'] * MM / UM:.2f} / {r['right_max_worn_depth_mm'] * MM / UM:.2f} um at most "
                f"(left / right), 90 % of the volume in a band {r['band_90_mm']:.1f} mm wide; last step: "
                f"lateral amplitude {r['lateral_amplitude_mm']:.2f} mm, contact from {r['contact_range_mm'][0]:.1f} "
                f"to {r['contact_range_mm'][1]:.1f} mm; {r['steps']} steps, {r['cost_seconds_simulated']:g} s "
                f"simulated, {r['cost_tables']} contact tables"] + [
            f"flange of the {wheel} wheel (EN 15313): Sh {sh:.2f} mm, Sd {sd:.2f} mm, qR {qr:.2f} mm"
            for wheel in ("left", "right") if f"{wheel}_flange_mm" in r for sh, sd, qr in [r[f"{wheel}_flange_mm"]]]
    if r.get("round"):
        shape = "round at the end (peak to peak under 1 pm: no dominant order, no maxima)"
    else:
        n = r["dominant_order"]
        shape = f"{plural(r['maxima'], 'maximum', 'maxima')}, dominant order {n}" + (" (eccentricity)" if n == 1 else "")
    if r.get("round_at_start") and r["regime"] == regime.DRIVEN:
        growth = "round at the start: its out-of-round came through the rail from the other wheels"
    elif r.get("round_at_start"):
        growth = "round at the start: out-of-round growth undefined, nothing to grow"
    else:
        rms = (f"x{r['out_of_round_growth_factor']:.2f}" if "out_of_round_growth_factor" in r else "growth undefined")
        leading = (f"fastest order present at the start {r['leading_order']} (x{r['leading_growth_factor']:.2f}"
                   + _growth_text(r, "leading_growth_per_10000_km") + ")" if r["leading_order"] > 0 else
                   "no order present at the start has a defined growth rate")
        growth = f"out-of-round rms {rms} over the run, {leading}"
    wheel = f"wheel at {r['wheel']:g} m, " if "wheel" in r else ""  # one of several wheels on the rail
    lines = [f"{wheel}{r['speed_kmh']:g} km/h: {r['regime']}, {shape}, removed {r['max_removed_depth_mm']:.3f} mm "
             f"at the most worn spot ({r['mean_removed_depth_mm']:.3f} mm mean) after {r['distance_km']:.0f} km; "
             f"peak-to-peak {r['peak_to_peak_initial_um']:.1f} -> {r['peak_to_peak_um']:.1f} um; {growth}"]
    if "wavelength_mm" in r:
        growth = _growth_text(r, "dominant_growth_per_10000_km")
        if r["dominant_order"] == 1:
            lines.append(f"eccentricity (order 1): once per revolution, {r['passing_frequency_hz']:.1f} Hz{growth}")
        else:
            lines.append(f"order-{r['dominant_order']} polygon: wavelength {r['wavelength_mm']:.0f} mm on the tread, "
                         f"passing at {r['passing_frequency_hz']:.1f} Hz{growth}")
    if "dominant_amplitude_um" in r:
        linear = (f"the linear model's fastest combination of order {r['dominant_order']} grows "
                  f"{percent(r['linear_growth_per_10000_km'])} per 10 000 km with this wheel at {r['linear_share']:.2f} "
                  f"of the largest, {r['linear_phase_deg']:+.0f} deg from the first" if "linear_share" in r else
                  "no linear model to compare (it takes one speed and no duty cycle)")
        lines.append(f"wheel at {r['wheel']:g} m: order {r['dominant_order']}, {r['dominant_amplitude_um']:.2f} um at the "
                     f"end{_growth_text(r, 'dominant_growth_per_10000_km')}, at {r['measured_share']:.2f} of the "
                     f"wheels' largest, {r['measured_phase_deg']:+.0f} deg from the first; {linear}")
    if "wheel_growth" in r:
        g = r["wheel_growth"]
        lines.append(f"wheels at {', '.join(f'{x:g}' for x in r['wheel_positions_m'])} m on one rail, their polygons' "
                     f"phases drifting: each grows on its own, order {g['order']} at "
                     f"{', '.join(f'{p:+.0%}' for p in g['per_10000_km'])} per 10 000 km")
    if "combination" in r:
        c = r["combination"]
        lines.append(f"wheels at {', '.join(f'{x:g}' for x in r['wheel_positions_m'])} m on one rail: order {c['order']} "
                     f"grows with their polygons at phases {', '.join(str(round(p)) for p in c['phases_deg'])} deg, "
                     f"amplitudes {', '.join(f'{a:.2f}' for a in c['amplitudes'])}")
    if "rail_modes_hz" in r:
        m, x = r["rail_modes_hz"], r["wheel_positions_m"]
        bounds = ", ".join(f"{lo:.0f}-{hi:.0f}" for lo, hi in zip(m["pinned"], m["clamped"]))
        peaks = [f"{h:.0f} Hz (mode {i + 1})" for i, h in enumerate(m["held"]) if h is not None]
        held = ", ".join(peaks) if peaks else "none (the track's damping takes them)"
        lines.append(f"rail between the wheels at {x[0]:g} and {x[1]:g} m: bending modes at {bounds} Hz (pinned-clamped "
                     f"span); the rail they hold peaks at {held}")
    if "peak_to_peak_limit_mm" in r:
        reached = (f"reached after {r['limit_distance_km']:,.0f} km" if r["limit_distance_km"] is not None
                   else f"not reached in {r['distance_km']:,.0f} km")
        if "limit_months" in r:
            reached += f", {r['limit_months']:.1f} months at {r['daily_distance_km']:g} km a day"
        lines.append(f"out-of-roundness limit {r['peak_to_peak_limit_mm']:g} mm peak to peak: {reached}")
    return lines


def plural(count, one, many):
    """``1 maximum``, ``0 maxima``, ``8 maxima``."""
    return f"{count} {one if count == 1 else many}"


def percent(fraction):
    """A growth ``fraction`` as a signed percentage of two significant digits and no more decimals
    than that needs: ``+20%``, ``+132%``, ``+4.7%``, ``-0.24%``; ``0%`` only for no change."""
    p = 100.0 * fraction
    if p == 0:
        return "0%"
    rounded = float(f"{p:.2g}")  # two significant digits first: 9.96 is 10, not 10.0
    decimals = max(0, 1 - int(np.floor(np.log10(abs(rounded)))))
    return f"{p:+.{decimals}f}%"


def _growth_text(r, key):
    """``, +20% per 10 000 km`` for the growth ``r[key]``; where the summary lists it as undefined,
    'undefined' or 'not meaningful' with the reason it gives; nothing where it has none."""
    if key in r:
        return f", {percent(r[key])} per 10 000 km"
    if key not in r.get("undefined", ()):
        return ""
    why = r.get("undefined_because", {}).get(key)
    return f", growth per 10 000 km {why}" if why else ", growth per 10 000 km undefined"


def write_summary(ds, directory):
    """``summary.json`` (strict JSON) and ``summary.txt`` in ``directory``; returns the summary."""
    s = summary(ds)
    write_text(json.dumps(s, indent=2, allow_nan=False,
                          default=lambda o: o.item() if isinstance(o, np.generic) else str(o)),
               Path(directory) / "summary.json")
    write_text(summary_text(s), Path(directory) / "summary.txt")
    return s


def write_checkpoint(path, checkpoint, scenario_toml, scenario_hash):
    """Save a :class:`~railwear.longterm.base.Checkpoint` with its scenario (``.npz``)."""
    fields = checkpoint.plain()
    fields.update(scenario=np.array(scenario_toml), scenario_hash=np.array(scenario_hash))

    def write(tmp):
        with open(tmp, "wb") as f:
            np.savez(f, **fields)

    return _atomic(path, write)


def read_checkpoint(path):
    """``(checkpoint, scenario_toml, scenario_hash)`` from :func:`write_checkpoint`'s file; a
    file cut short, edited or of another kind is refused in one line."""
    from railwear.longterm.base import Checkpoint

    source = f"checkpoint {path}"
    try:
        data = np.load(_readable(path, "checkpoint"), allow_pickle=False)
        if not isinstance(data, NpzFile):
            raise ValueError("not an .npz archive")
        with data:
            fields = {k: data[k] for k in data.files}
    except (OSError, ValueError, EOFError, zipfile.BadZipFile, zlib.error) as e:
        message = " ".join(str(e).split())[:200]
        raise CheckpointError(f"{source}: cannot be read ({type(e).__name__}: {message}); start the run again") from None
    texts = [fields.pop(k, None) for k in ("scenario", "scenario_hash")]
    if any(t is None or t.dtype.kind != "U" or t.ndim for t in texts):
        raise CheckpointError(f"{source}: no scenario text and hash; start the run again")
    return Checkpoint.from_plain(fields, source=source), str(texts[0]), str(texts[1])
