"""What users read off a worn wheel's ``u`` over the angle: removed depth and polygon spectra."""

import numpy as np
import xarray as xr

from railwear.errors import ModelRangeError
from railwear.geometry import bands, roundness
from railwear.longterm import regime

ROUND_OFF = 1e4 * np.finfo(float).eps  # of the largest |u|: a mean below -this is a gain, not round-off
UNDEFINED = "undefined_because"  # attribute of a statistic: why its masked (NaN) entries have no value
TOO_SHORT = "the run is too short to fit a rate: its saved times do not differ, so the order did not change over the run"
FEW_TIMES = "fewer than 3 saved times: no scatter about the fit to estimate its error from"
ALTERNATING = "order N/2 alternates from point to point round the wheel and is not fitted"
NO_AMPLITUDE = "the amplitude of the order is zero at a saved time: no out-of-round in it to grow"
NO_LEVEL = "the amplitude of the order is zero at the end: its level would be -inf dB"
ROUND = "no out-of-round left: the wheel is round at a saved time"
NO_BAND_LEVEL = "no line of the wheel's spectrum in the band has any amplitude: its level would be -inf dB"


def masked(values, causes):
    """``(values, attrs)``: ``values`` with NaN wherever not finite, and ``attrs`` naming why in
    :data:`UNDEFINED` (empty when all are finite). ``causes`` are ``(reason, where)`` in order of
    precedence, ``where`` a boolean broadcastable to ``values``; a masked entry takes the first
    reason that holds there (the last cause should hold everywhere)."""
    values = np.asarray(values, float)
    values = np.where(np.isfinite(values), values, np.nan)
    left = np.isnan(values)
    reasons = []
    for reason, where in causes:
        hit = left & np.broadcast_to(where, values.shape)
        if hit.any():
            reasons.append(reason)
            left &= ~hit
    return values, ({UNDEFINED: "; ".join(reasons)} if reasons else {})


def _label(da, dim, i):
    """Entry ``i`` of ``dim``: its coordinate value with units, else the index."""
    if dim not in da.coords or da[dim].dtype.kind not in "fiu":
        return str(i)
    return f"{float(da[dim].values[i]):g} {da[dim].attrs.get('units', '')}".strip()


def check_no_gain(u, mean_removed):
    """Refuse a wheel that gains radius as a whole: the mean removed depth below minus round-off
    (:data:`ROUND_OFF` of the largest ``|u|``) at some time means the wear model gave material
    back, outside the range where it holds. Raises :class:`ModelRangeError` naming when (and for
    which batch entry), with the last state before it as the last good one."""
    scale = float(np.nanmax(np.abs(u.values))) if u.size else 0.0
    gain = (mean_removed < -ROUND_OFF * scale).transpose("time", ...)
    if not bool(gain.any()):
        return
    flat = gain.values.reshape(gain.sizes["time"], -1)
    first = int(np.argmax(flat.any(axis=1)))
    row = int(np.argmax(flat[first]))
    batch = [d for d in gain.dims if d != "time"]
    index = np.unravel_index(row, [gain.sizes[d] for d in batch])
    parts = [f"{d} {_label(gain, d, i)}" for d, i in zip(batch, index)]
    where = f" ({', '.join(parts)})" if parts else ""
    depth = float(mean_removed.transpose("time", ...).values.reshape(flat.shape)[first, row])
    time = float(u.time.values[first])
    last = max(first - 1, 0)
    raise ModelRangeError(
        f"removed_depth: the wheel gained radius as a whole{where}: mean removed depth {depth * 1e6:.3g} um "
        f"at T = {time:.4g}; the wear model left its range (a negative wear rate) and its result is not written",
        last_good=u.isel(time=last).values, last_time=float(u.time.values[last]))


def with_band_levels(ds: xr.Dataset, radius):
    """``ds`` with the one-third-octave band levels in wavelength (EN 15610, :mod:`railwear.geometry.bands`)
    of ``u`` at the start and the end on a wheel of nominal ``radius`` (m), as the spectrum figure
    draws them: ``band_level_initial`` and ``band_level`` (dB re 1 µm rms, ``L = 10 lg(r_rms² /
    (1 µm)²)`` per band, over the batch and ``wavelength``), the coordinate ``wavelength`` (m, the
    nominal band centre, longest first as the bands fall in wavenumber), ``band`` (``k``: centre
    wavenumber ``10^(k/10)`` per m) and ``band_resolved`` (centre at most a quarter of the
    circumference ``L = 2π R0``, EN 15610 7.5), and ``nominal_radius``. A band with no amplitude in
    it is NaN, its :data:`UNDEFINED` attribute saying why. The bands are every band a line of ``u``
    reaches, so the band mean squares add up to the variance of ``u``."""
    batch = [d for d in ds.u.dims if d not in ("time", "angle")]
    diameter = 2.0 * float(radius)
    start, end = (bands.band_levels(ds.u.isel(time=k).transpose(*batch, "angle").values, diameter) for k in (0, -1))
    dims = tuple(batch) + ("wavelength",)
    centre = {"units": "m", "long_name": "one-third-octave band centre wavelength, nominal (EN 15610)"}
    number = {"units": "1", "long_name": "band number k: centre wavenumber 10^(k/10) per m"}
    resolved = {"long_name": "band centre at most a quarter of the circumference: resolved by one revolution "
                             "(EN 15610 7.5)"}
    ds = ds.assign_coords(wavelength=("wavelength", end.wavelength, centre), band=("wavelength", end.index, number),
                          band_resolved=("wavelength", end.resolved, resolved))
    for name, levels, when in (("band_level_initial", start, "start"), ("band_level", end, "end")):
        level, undefined = masked(levels.level, [(NO_BAND_LEVEL, True)])
        ds[name] = (dims, level, {"units": "dB", "long_name": f"one-third-octave band level of u at the {when}, "
                                                               "re 1 um rms (EN 15610)", **undefined})
    if "nominal_radius" not in ds:
        ds["nominal_radius"] = ((), float(radius), {"units": "m", "long_name": "nominal rolling radius"})
    return ds


def describe(ds: xr.Dataset, radius=None):
    """Add removed depth over time, the initial and final polygon spectra and the fitted growth
    to a solution, its ``regime`` by the rule of :mod:`railwear.longterm.regime` where its
    ``distance`` coordinate (or ``life_distance_km``) gives the distance of a unit of normed time,
    and with the wheel's nominal ``radius`` (m; or the solution's ``nominal_radius``) the band
    levels in wavelength (:func:`with_band_levels`). A statistic
    without a value somewhere (a rate of an order that is absent, the level of a zero amplitude)
    is NaN there, and its :data:`UNDEFINED` attribute says why."""
    u = ds.u
    batch = [d for d in u.dims if d not in ("time", "angle")]
    u0, u_end = u.isel(time=0), u.isel(time=-1)
    mean_removed = (u0 - u).mean("angle")
    check_no_gain(u, mean_removed)
    removed = (u0 - u).max("angle").clip(min=0.0)  # >= the mean, so only round-off is clipped
    ds["removed_depth"] = removed.assign_attrs(
        units="m", long_name="largest radius lost since the start (most worn spot)")
    ds["mean_removed_depth"] = mean_removed.assign_attrs(
        units="m", long_name="mean radius lost since the start")
    deviation = u - u.mean("angle")
    rows = deviation.transpose(*batch, "time", "angle").values.reshape(-1, u.sizes["time"], u.sizes["angle"])
    spectra = [(roundness.polygon_spectrum(r[0]), roundness.polygon_spectrum(r[-1])) for r in rows]
    shape = [u.sizes[d] for d in batch]
    order = spectra[0][1]["order"]

    def per_row(key, which):
        return np.array([s[which][key] for s in spectra]).reshape(shape + list(np.shape(spectra[0][which][key])))

    dims_order = tuple(batch) + ("order",)
    ds = ds.assign_coords(order=("order", order, {"units": "1", "long_name": "polygon order"}))
    ds["amplitude"] = (dims_order, per_row("amplitude", 1),
                       {"units": "m", "long_name": "harmonic amplitude at the end"})
    ds["amplitude_initial"] = (dims_order, per_row("amplitude", 0),
                               {"units": "m", "long_name": "harmonic amplitude at the start"})
    level, undefined = masked(per_row("roughness_level", 1), [(NO_LEVEL, True)])
    ds["roughness_level"] = (dims_order, level, {"units": "dB", "long_name": "roughness level per order at the end, "
                                                                          "re 1 um rms", **undefined})
    ds["dominant_order"] = (tuple(batch), per_row("dominant_order", 1),
                            {"units": "1", "long_name": "order of the largest harmonic at the end"})
    ds["maxima"] = (tuple(batch), per_row("maxima", 1),
                    {"units": "1", "long_name": "radius maxima round the wheel at the end"})
    pp0, pp1 = per_row("peak_to_peak", 0), per_row("peak_to_peak", 1)
    ds["peak_to_peak_initial"] = (tuple(batch), pp0, {"units": "m", "long_name": "peak-to-peak deviation at the start"})
    ds["peak_to_peak"] = (tuple(batch), pp1, {"units": "m", "long_name": "peak-to-peak deviation at the end"})
    times = ds.time.values
    stops = np.broadcast_to(np.asarray(ds.stop_time.values, float), shape).ravel() if "stop_time" in ds else \
        np.full(len(rows), times[-1])
    windows = [times <= stop for stop in stops]
    fitted_times = [times[w] for w in windows]
    fits = [roundness.growth(times[w], r[w]) for r, w in zip(rows, windows)]
    short = np.reshape([t.size < 2 or np.sum((t - t.mean()) ** 2) == 0 for t in fitted_times], shape)
    few = np.reshape([t.size < 3 for t in fitted_times], shape)

    def fitted(key):
        return np.array([f[key] for f in fits]).reshape(shape + list(np.shape(fits[0][key])))

    top = fits[0]["order_rate"].size
    rate = np.full(shape + [order.size], np.nan)
    rate[..., :top] = fitted("order_rate")
    error = np.full(shape + [order.size], np.nan)
    error[..., :top] = fitted("order_rate_error")
    per_time = "per unit normed time"
    alternating = np.arange(order.size) >= top
    rate, undefined = masked(rate, [(TOO_SHORT, short[..., None]), (ALTERNATING, alternating), (NO_AMPLITUDE, True)])
    ds["growth_rate"] = (dims_order, rate, {"units": "1", "long_name": f"fitted growth rate of ln amplitude, {per_time}",
                                            **undefined})
    error, undefined = masked(error, [(TOO_SHORT, short[..., None]), (ALTERNATING, alternating),
                                      (NO_AMPLITUDE, np.isnan(rate)), (FEW_TIMES, True)])
    ds["growth_rate_error"] = (dims_order, error, {"units": "1", "long_name": "standard error of the growth rate",
                                                   **undefined})
    scalars = {"out_of_round_growth_rate": ("rms_rate", f"fitted growth rate of the out-of-round rms, {per_time}"),
               "out_of_round_growth_rate_error": ("rms_rate_error", "standard error of that rate"),
               "out_of_round_growth_factor": ("rms_factor", "exp(rate x run): growth of the out-of-round rms"),
               "leading_order": ("leading_order", "fastest-growing order of those present at the start"),
               "leading_growth_factor": ("leading_factor", "exp(rate x run) of the leading order")}
    rms_rate = fitted("rms_rate")
    for name, (key, long_name) in scalars.items():
        values, undefined = fitted(key), {}
        if name.startswith("out_of_round_"):
            values, undefined = masked(values, [(TOO_SHORT, short), (ROUND, ~np.isfinite(rms_rate)), (FEW_TIMES, True)])
        ds[name] = (tuple(batch), values, {"units": "1", "long_name": long_name, **undefined})
    ds = regime.with_wheel_regime(ds)  # the one rule: from growth per distance (its distance coordinate)
    if radius is None and "nominal_radius" in ds:
        radius = float(ds.nominal_radius)
    return ds if radius is None else with_band_levels(ds, radius)
