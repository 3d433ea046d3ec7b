"""The regime of a wheel, one rule for every result (docs/outputs.md, "The summary and the regime").

Read from growth rates per distance and from the state the wheel reached, never from the growth
over the run (a run that stops sooner at its limit grows less): the same wheel at the same speed
gets the same label whatever its start amplitude, its limit or the strategy that ran it, as far as
their growth rates agree. Light to import (numpy only): the summaries read it too.
"""

import numpy as np

PER_10000_KM = 1e4  # km: the field's distance for wear and growth rates
ROUND_PEAK_TO_PEAK = 1e-12  # m: a wheel with less peak to peak than 1 pm is round (no out-of-round to read)

# Growth g per 10 000 km: g = exp(rate x 10 000 km / life) - 1, rate the fitted ln-rate per unit normed time.
POLYGON_ORDER_GROWTH = 0.10  # the largest order at the end grows at least 10 % per 10 000 km: a polygon forms
POLYGON_RMS_GROWTH = 0.50  # or the out-of-round rms grows at least 50 % per 10 000 km
SMOOTHING_RMS_GROWTH = -0.20  # the out-of-round rms falls by at least 20 % per 10 000 km: smoothing
ONSET_GROWTH = 0.01  # an order the wheel has, or the rms, grows at least 1 % per 10 000 km: onset
SEEDED_SHARE = 0.01  # an order the wheel has: at least 1 % of its largest amplitude at the start
SIGNIFICANT = 2.0  # a rate counts when it exceeds this many standard errors

REGIME_RULE = (
    "from growth per 10 000 km (exp(fitted ln-rate x 10 000 km) - 1) and the state reached, not from the "
    "growth over the run: polygonalising when the largest order at the end, one the wheel had at the start "
    "(at least 1 % of its largest amplitude then), grows at least 10 % per 10 000 km, or the out-of-round "
    "rms grows at least 50 % per 10 000 km; smoothing when the rms falls at least 20 % per 10 000 km; "
    "onset when an order the wheel had at the start, or the rms, grows at least 1 % per 10 000 km; else "
    "stable (a round wheel too). A rate counts only beyond 2 standard errors. With several wheels on one rail, "
    "a wheel round at the start (under 1 pm peak to peak) and not at the end, while another wheel started out of "
    "round, is driven by the other wheels: its out-of-round came to it through the rail")
DRIVEN = "driven by the other wheels"  # the label of such a wheel: no order of its own to read a growth from
LONG_NAME = f"wear regime of the wheel (stable, smoothing, onset, polygonalising; {DRIVEN})"


def is_round(peak_to_peak):
    """Whether a wheel of ``peak_to_peak`` (m) is round: under :data:`ROUND_PEAK_TO_PEAK`."""
    return bool(peak_to_peak < ROUND_PEAK_TO_PEAK)


def wheel_regime(d, life, others_shaped=False):
    """The regime of the run ``d`` (one row of a long-term result, described by
    ``longterm.spectra.describe``) by :data:`REGIME_RULE`, the normed life being ``life`` km;
    ``others_shaped``: another wheel on the same rail started out of round (several wheels)."""
    per = PER_10000_KM / life
    rate = np.asarray(d.growth_rate.values, float) * per
    error = np.asarray(d.growth_rate_error.values, float) * per
    start = np.asarray(d.amplitude_initial.values, float)
    with np.errstate(invalid="ignore"):
        counts = np.isfinite(rate) & (np.abs(rate) > SIGNIFICANT * np.where(np.isfinite(error), error, 0.0))
        seeded = start >= SEEDED_SHARE * start.max() if start.max() > 0 else np.zeros(start.size, bool)
    rms = float(d.out_of_round_growth_rate) * per
    rms_error = float(d.out_of_round_growth_rate_error) * per
    rms_counts = np.isfinite(rms) and abs(rms) > SIGNIFICANT * (rms_error if np.isfinite(rms_error) else 0.0)
    if is_round(float(d.peak_to_peak_initial)):
        if is_round(float(d.peak_to_peak)):
            return "stable"
        if others_shaped:
            return DRIVEN
    k = int(d.dominant_order) - 1
    if not is_round(float(d.peak_to_peak)) and seeded[k] and counts[k] and rate[k] >= np.log1p(POLYGON_ORDER_GROWTH):
        return "polygonalising"
    if rms_counts and rms >= np.log1p(POLYGON_RMS_GROWTH):
        return "polygonalising"
    if rms_counts and rms <= np.log1p(SMOOTHING_RMS_GROWTH):
        return "smoothing"
    if (rms_counts and rms >= np.log1p(ONSET_GROWTH)) or np.any(seeded & counts & (rate >= np.log1p(ONSET_GROWTH))):
        return "onset"
    return "stable"


def life_km(ds):
    """The distance of one unit of normed time of the result ``ds`` (km): its ``life_distance_km``
    attribute, else its ``distance`` coordinate over its ``time``; None when it has neither."""
    life = float(ds.attrs.get("life_distance_km", 0.0))
    if life > 0:
        return life
    if "distance" in ds.coords and "time" in ds.coords and ds.time.size > 1:
        t, km = ds.time.values, np.asarray(ds.distance.values, float)
        if float(t[-1] - t[0]) > 0:
            return float((km[-1] - km[0]) / (t[-1] - t[0]))
    return None


def others_shaped(ds):
    """Per row of ``ds`` (over its batch): whether another wheel on its rail (along ``wheel``)
    started out of round (``peak_to_peak_initial`` not :func:`is_round`); False without several wheels."""
    shaped = ds.peak_to_peak_initial >= ROUND_PEAK_TO_PEAK
    if ds.sizes.get("wheel", 1) < 2 or "wheel" not in shaped.dims:
        return shaped & False
    return shaped.sum("wheel") - shaped > 0


def with_wheel_regime(ds, life=None):
    """``ds`` with ``regime`` (over its batch) by :func:`wheel_regime` and its ``rule`` attribute,
    where it has the growth rates and a normed life (``life`` km, else :func:`life_km`);
    otherwise ``ds`` as it is."""
    life = life if life is not None else life_km(ds)
    if not (life and life > 0 and "growth_rate" in ds and "amplitude_initial" in ds):
        return ds
    batch = [d for d in ds.dominant_order.dims]
    shape = [ds.sizes[d] for d in batch]
    others = others_shaped(ds).transpose(*batch).values
    labels = np.array([wheel_regime(ds.isel(dict(zip(batch, index))), life, bool(others[index]))
                       for index in np.ndindex(*shape)], dtype=str).reshape(shape)
    ds["regime"] = (tuple(batch), labels, {"long_name": LONG_NAME, "rule": REGIME_RULE})
    return ds
