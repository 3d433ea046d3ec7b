"""Figures of a result: the paper's Figs 9-11, the polygon spectrum and the stability map, the
wheelset's worn lateral profile and angular pattern (layer 4)."""

import contextlib
import os
from pathlib import Path

import numpy as np

from railwear.results import _atomic, speed_in
from railwear.units import HOUR, MM, MN, PM, UM, m_s_to_kmh


def _plain_figure(width, height):
    """A constrained-layout Figure without pyplot (headless and notebook-safe)."""
    from matplotlib.figure import Figure

    return Figure(figsize=(width, height), layout="constrained")


def _figure(width, height, rows=1):
    # The object-oriented Figure needs no pyplot backend: headless and notebook-safe.
    from matplotlib.figure import Figure

    fig = Figure(figsize=(width, height), layout="constrained")
    return fig, fig.subplots(rows, 1, squeeze=False)[:, 0]


def _fixed_figure(width, height):
    """A Figure without a layout engine: its axes are placed by :func:`_grid` from margins in inches.
    Used for the figures of every ``railwear run``, where constrained layout (which measures every
    text of the figure twice a draw) was a quarter of the drawing time."""
    from matplotlib.figure import Figure

    return Figure(figsize=(width, height))


def _margins(fig, rows, cols, left, right, top, bottom, hgap=0.0, wgap=0.0):
    """``subplots_adjust`` keywords for a ``rows`` x ``cols`` grid on ``fig`` with margins and gaps
    between cells given in inches (the room the labels, titles and ticks beside them need)."""
    width, height = fig.get_size_inches()
    cell_h = (height - top - bottom - (rows - 1) * hgap) / rows
    cell_w = (width - left - right - (cols - 1) * wgap) / cols
    return dict(left=left / width, right=1 - right / width, top=1 - top / height, bottom=bottom / height,
                hspace=hgap / cell_h, wspace=wgap / cell_w)


def _grid(fig, rows, cols, left, right, top, bottom, hgap=0.0, wgap=0.0, **ratios):
    """A GridSpec on ``fig`` placed by :func:`_margins`; ``ratios``: ``height_ratios``, ``width_ratios``."""
    return fig.add_gridspec(rows, cols, **_margins(fig, rows, cols, left, right, top, bottom, hgap, wgap), **ratios)


def _rows(ds):
    """``(label, dataset)`` per batch row."""
    batch = [d for d in ds.u.dims if d not in ("time", "angle")]
    if not batch:
        return [(f"{m_s_to_kmh(float(ds.speed)):g} km/h", ds)]
    dim = batch[0]
    names = {"speed": lambda i: f"{m_s_to_kmh(float(ds.speed[i])):g} km/h",
             "wheel": lambda i: f"wheel at {float(ds.wheel[i]):g} m"}  # several wheels on one rail
    return [(names.get(dim, lambda i: f"member {i}")(i), ds.isel({dim: i})) for i in range(ds.sizes[dim])]


def tick_number(value, span):
    """``value`` as a tick or caption number: ``:g``, with a value under a millionth of ``span``
    (the axis's extent, in the same unit) read as zero, so round-off never shows as "-0" or "-3e-15"."""
    value = 0.0 if abs(value) < 1e-6 * abs(span) else float(value)
    return f"{value + 0.0:g}"


def _title(ds, what):
    return f"{ds.attrs.get('scenario_name', 'railwear')}: {what}"


BREAK = 3.0  # the radius panel is broken in two when the mean radius falls by more than this many shape spans


def profiles(ds):
    """Initial and final radius deviation over the angle (paper Figs 9 and 10): ``u`` itself
    (the mean radius falls) and the shape ``u - mean(u)`` on common axes (the pattern). Where the
    mean radius falls by more than :data:`BREAK` times the shape's extent, the ``u`` panel's axis is
    broken into a band round the start and one round the end, of equal height in µm, so the shape
    is seen in both and the fall is written across the break."""
    from matplotlib.lines import Line2D

    deg = np.degrees(ds.angle.values)
    rows = _rows(ds)
    curves = [[d.u.isel(time=k).values / UM for k in (0, -1)] for _, d in rows]
    drops = [float(np.mean(end) - np.mean(start)) for start, end in curves]
    starts = np.concatenate([c[0] for c in curves])
    ends = np.concatenate([c[1] for c in curves])
    shape_span = max(max(np.ptp(c - c.mean()) for c in pair) for pair in curves) or 1.0
    broken = max(abs(x) for x in drops) > BREAK * shape_span
    fig = _fixed_figure(7, 7 if broken else 6.5)
    margins = dict(left=0.85, right=0.2, top=0.35, bottom=0.5)
    if broken:  # the bands 0.1 in apart; a spacer row for the lower band's label and the shape's title
        band = (7 - 0.85 - 3 * 0.1 - 0.75) / 4.1
        grid = _grid(fig, 4, 1, hgap=0.1, height_ratios=[band, band, 0.75, 2.1 * band], **margins)
        top_start, top_end, shape = (fig.add_subplot(grid[k]) for k in (0, 1, 3))
        bands = [top_start, top_end]
        span = max(np.ptp(starts), np.ptp(ends), shape_span)
        height = 1.7 * span  # one µm scale in both bands; the curves in the lower part, the legend above
        for ax, values in zip(bands, (starts, ends)):
            ax.set_ylim(values.min() - 0.08 * span, values.min() - 0.08 * span + height)
        top_start.spines["bottom"].set_visible(False)
        top_end.spines["top"].set_visible(False)
        top_start.tick_params(axis="x", bottom=False, labelbottom=False)
        cut = dict(marker=[(-1, -0.6), (1, 0.6)], markersize=10, linestyle="none", color="k", mec="k", mew=1,
                   clip_on=False)
        top_start.plot([0, 1], [0, 0], transform=top_start.transAxes, **cut)
        top_end.plot([0, 1], [1, 1], transform=top_end.transAxes, **cut)
    else:
        grid = _grid(fig, 2, 1, hgap=0.85, **margins)
        top, shape = fig.add_subplot(grid[0]), fig.add_subplot(grid[1])
        bands = [top]
    for i, ((label, _), (start, end)) in enumerate(zip(rows, curves)):
        colour = f"C{i % 10}"
        for u, style, width, when in ((start, "--", 1.0, "start"), (end, "-", 1.5, "end")):
            name = f"{label}, {when}" if when == "end" or i == 0 or len(rows) < 5 else None
            for ax in bands:
                ax.plot(deg, u, color=colour, ls=style, lw=width, label=name if ax is bands[-1] else None)
            shape.plot(deg, u - u.mean(), color=colour, ls=style, lw=width)
    drop = f"{drops[0]:+.0f} µm" if len(drops) == 1 else f"{min(drops):+.0f} to {max(drops):+.0f} µm"
    for ax in bands:
        ax.set(xlim=(0, 360))
    bands[-1].set_xlabel("angle (deg)")
    if broken:
        top_start.set_ylabel("u, start (µm)")
        top_end.set_ylabel("u, end (µm)")
    else:
        bands[0].set_ylabel("radius deviation u (µm)")
    bands[0].set_title(_title(ds, f"radius at the start and the end (mean radius {drop})"), fontsize="medium")
    shape.set(xlabel="angle (deg)", ylabel="u - mean(u) (µm)", xlim=(0, 360),
              title="the shape: the same less its mean, on one axis")
    if broken:
        bands[0].legend(fontsize="small", loc="upper center", ncol=min(2 * len(rows), 4), title_fontsize="small",
                        title=f"axis broken: two bands {height:.3g} µm high", handles=[line for line in bands[-1].get_lines() if not line.get_label().startswith("_")])
    else:
        bands[0].legend(fontsize="small", loc="best")
    shape.legend(handles=[Line2D([], [], color="0.3", ls="--", lw=1.0, label="start"),
                          Line2D([], [], color="0.3", ls="-", lw=1.5, label="end")], fontsize="small", loc="best")
    return fig


EVOLUTION_RANGE = 1000.0  # the order amplitudes are drawn down to the largest / 1000 (60 dB)


def evolution(ds, orders=6):
    """The out-of-round deviation ``u - mean(u)`` over angle and distance (paper Figs 6 and 11),
    and beside it the amplitude of the ``orders`` polygon orders largest at the end (the dominant
    order among them) over distance on a log axis (down to 60 dB under the largest): growing
    orders solid, decaying ones dashed."""
    from railwear.geometry import bands

    rows = _rows(ds)
    fig = _fixed_figure(11, min(2.6 + 2.6 * len(rows), 14))
    axes = fig.subplots(len(rows), 2, squeeze=False, gridspec_kw={"width_ratios": [1.15, 1]})
    fig.subplots_adjust(**_margins(fig, len(rows), 2, left=1.0, right=0.35, top=0.75, bottom=0.55, hgap=0.85,
                                   wgap=1.25))
    along = ds.distance.values if "distance" in ds.coords else ds.time.values
    along_label = "distance (km)" if "distance" in ds.coords else "normed time"
    for (ax, amp_ax), (label, d) in zip(axes, rows):
        dev = (d.u - d.u.mean("angle")).values / UM
        limit = float(np.max(np.abs(dev))) or 1.0
        mesh = ax.pcolormesh(np.degrees(ds.angle.values), along, dev, shading="nearest", edgecolors="none",
                             cmap="RdBu_r", vmin=-limit, vmax=limit)
        fig.colorbar(mesh, ax=ax, label="u - mean(u) (µm)")
        ax.set(xlabel="angle (deg)", ylabel=along_label, xlim=(0, 360), title=f"{label}: shape over the run")
        n, amp = bands.order_amplitudes(d.u.values)
        amp = amp / UM
        # the largest at the end first (the dominant order always among them), ties by the largest
        # over the run: ranked by the maximum alone, equal starts let decaying orders push it out
        leading = np.lexsort((-amp.max(0), -amp[-1]))[:orders]
        peak = float(amp.max()) or 1.0
        floor = peak / EVOLUTION_RANGE
        for j, k in enumerate(sorted(leading, key=lambda k: -amp[-1, k])):
            ratio = amp[-1, k] / amp[0, k] if amp[0, k] > 0 else np.inf
            said = f"x{ratio:.3g}" if amp[0, k] >= floor else f"from under {floor:.2g} µm"
            amp_ax.plot(along, np.maximum(amp[:, k], floor), color=f"C{j % 10}", lw=1.4,
                        ls="-" if ratio >= 1 else "--", label=f"order {n[k]}: {said}")
        amp_ax.set_yscale("log")
        lowest = max(floor, float(np.min(amp[:, leading])))  # the floor only where a drawn order reaches it
        amp_ax.set_ylim(lowest / 1.3, peak * 1.6)
        amp_ax.yaxis.set_major_formatter(lambda v, _: f"{v:g}")
        amp_ax.yaxis.set_minor_formatter(lambda v, _: f"{v:g}" if f"{v:.0e}"[0] in "25" else "")
        amp_ax.set(xlabel=along_label, ylabel="amplitude per order (µm)",
                   title=f"the {len(leading)} orders largest at the end")
        amp_ax.legend(fontsize="x-small", ncol=2, title="end / start (solid grow, dashed decay)",
                      title_fontsize="x-small")
        if "distance" in ds.coords:  # long distances: a few ticks with thousands separated
            from matplotlib.ticker import MaxNLocator

            amp_ax.xaxis.set_major_locator(MaxNLocator(5))
            for axis in (ax.yaxis, amp_ax.xaxis):
                axis.set_major_formatter(lambda v, _: f"{v:,.0f}" if abs(v) >= 100 else f"{v:g}")
    fig.suptitle(_title(ds, "evolution of the out-of-round deviation"))
    return fig


SPECTRUM_RANGE = 100.0  # amplitudes below the largest / 100 (40 dB under the peak) sit on the floor
LEAST_AMPLITUDE = PM / UM  # 1 pm in µm: the lowest floor; a wheel with every order under it is round


def _wheel_diameter(ds, diameter=None):
    """``(D in m, where it came from)``: the argument, the result's ``nominal_radius``, or the
    ``[wheel] radius_m`` of the scenario stored with the result; ``(None, reason)`` if none."""
    if diameter is not None:
        return float(diameter), "given"
    for name in ("nominal_radius", "wheel_radius"):
        if name in ds.variables:
            return 2 * float(ds[name]), "from the result"
        if name in ds.attrs:
            return 2 * float(ds.attrs[name]), "from the result"
    try:
        import tomllib

        return 2 * float(tomllib.loads(ds.attrs["scenario"])["wheel"]["radius_m"]), "from the scenario"
    except (KeyError, TypeError, ValueError, tomllib.TOMLDecodeError):
        return None, "wheel diameter unknown: pass diameter= for wavelengths"


def _limit(limit):
    from railwear.geometry import bands

    return bands.iso3095_limit() if isinstance(limit, str) and limit.lower() == "iso3095" else limit


def _band_levels(ds, d, k, diameter):
    """The band levels of batch row ``d`` of ``ds`` at the start (``k`` 0) or the end (-1) on a
    wheel of ``diameter`` (m): those the result stores (``band_level_initial``, ``band_level``)
    where it stores them for this wheel, else from ``u``."""
    from railwear.geometry import bands

    if "band_level" in ds and "nominal_radius" in ds and 2 * float(ds.nominal_radius) == diameter:
        name = "band_level_initial" if k == 0 else "band_level"
        return bands.BandLevels.from_levels(d.band.values, d[name].values, np.pi * diameter)
    return bands.band_levels(d.u.isel(time=k).values, diameter)


def spectrum(ds, diameter=None, limit=None):
    """Amplitude per polygon order at the start (dashed) and the end (solid), with the wavelength
    ``π D / n`` on the top axis, over the one-third-octave band levels in wavelength (EN 15610,
    dB re 1 µm, those the result stores; bands longer than a quarter of the circumference drawn
    open: not resolved).

    ``diameter`` (m) defaults to the result's wheel; ``limit`` a ``bands.LimitSpectrum`` or
    ``"iso3095"`` (the rail roughness limit of ISO 3095) drawn over the bands. Amplitudes more
    than 40 dB under the largest are drawn on that floor with open markers. Several wheels on one
    rail (a ``wheel`` dimension) each have their own floor, 40 dB under their own largest, drawn
    in their colour and stated in the legend; a wheel round at a time (every order under 1 pm) is
    said so in the legend, not drawn."""
    from matplotlib.ticker import NullFormatter

    from railwear.geometry import bands

    d_wheel, origin = _wheel_diameter(ds, diameter)
    limit = _limit(limit)
    fig = _fixed_figure(7.5, 8)
    ax, band_ax = fig.subplots(2, 1)
    margins = dict(left=0.9, right=0.3, top=0.85, hgap=0.95)  # the title over the wavelength axis on top
    fig.subplots_adjust(**_margins(fig, 2, 1, bottom=0.6, **margins))
    rows = _rows(ds)
    amp = {(i, k): bands.order_amplitudes(d.u.isel(time=k).values) for i, (_, d) in enumerate(rows) for k in (0, -1)}
    orders = amp[(0, 0)][0]
    amp = {key: a / UM for key, (_, a) in amp.items()}
    # 40 dB under the peak, never under 1 pm (-120 dB re 1 µm): round-off is not drawn as a spectrum;
    # several wheels: each wheel's own (one wheel's polygon does not bury the others' spectra)
    per_wheel = "wheel" in ds.u.dims
    largest = {i: max(float(np.max(amp[(i, k)])) for k in (0, -1)) for i in range(len(rows))}
    floors = ({i: max(a / SPECTRUM_RANGE, LEAST_AMPLITUDE) for i, a in largest.items()} if per_wheel else
              dict.fromkeys(largest, max(max(largest.values()) / SPECTRUM_RANGE, LEAST_AMPLITUDE)))
    rounds = {key: per_wheel and float(np.max(a)) < LEAST_AMPLITUDE for key, a in amp.items()}  # not drawn
    shaped = [i for i in floors if not (rounds[(i, 0)] and rounds[(i, -1)])]
    floor = min((floors[i] for i in shaped), default=LEAST_AMPLITUDE)
    peak = max(max(largest.values()), floor * SPECTRUM_RANGE)
    above = np.nonzero(np.any([a > floors[i] for (i, _), a in amp.items()], axis=0))[0]
    top = int(np.clip((above[-1] + 3) if above.size else 20, 20, orders.size))
    n = orders[:top]
    levels = {}
    for i, (label, d) in enumerate(rows):
        colour = f"C{i % 10}"
        for k, style, marker, when in ((0, "--", ".", "start"), (-1, "-", "o", "end")):
            if d_wheel is not None:
                levels[(i, k)] = _band_levels(ds, d, k, d_wheel)
            if rounds[(i, k)]:
                ax.plot([], [], color=colour, ls=style, label=f"{label}, {when}: round (< 1 pm)")
                continue
            a = amp[(i, k)][:top]
            shown = np.maximum(a, floors[i])
            ax.plot(n, shown, color=colour, ls=style, marker=marker, ms=4, label=f"{label}, {when}")
            below = a < floors[i]
            ax.plot(n[below], shown[below], ls="none", marker="o", ms=4, mfc="white", color=colour)
        if per_wheel and i in shaped:
            ax.axhline(floors[i], color=colour, lw=0.8, ls=":", label=f"{label}: floor {floors[i]:.2g} µm")
    ax.set_yscale("log")
    # 10, 1, 0.1 rather than powers of ten, without mathtext (its parser took a quarter of this
    # figure's drawing); the axis spans at least 2.6 decades, so only the decades are labelled
    ax.yaxis.set_major_formatter(lambda v, _: f"{v:g}")
    ax.yaxis.set_minor_formatter(NullFormatter())
    columns = 2 if per_wheel or len(rows) > 2 else 1
    if per_wheel:  # headroom above the curves for the legend's rows (each 6.5 % of the axis)
        entries = 3 * len(shaped) + 2 * (len(rows) - len(shaped)) + 1
        room = min(0.065 * -(-entries // columns) + 0.03, 0.5)
        ax.set_ylim(floor / 1.6, floor / 1.6 * (peak * 2.5 / (floor / 1.6)) ** (1 / (1 - room)))
    else:
        ax.set_ylim(floor / 1.6, peak * 2.5)
    if not per_wheel:
        ax.axhline(floor, color="0.6", lw=0.8, ls=":")
    ax.plot([], [], ls="none", marker="o", mfc="white", color="0.4",
            label=("under its wheel's floor: its peak - 40 dB, at least 1 pm" if per_wheel else
                   "under the floor: peak - 40 dB, at least 1 pm"))
    ax.xaxis.get_major_locator().set_params(integer=True)
    ax.set(xlabel="polygon order n", ylabel="amplitude per order (µm)", xlim=(0.5, top + 0.5),
           title=_title(ds, "polygon spectrum at the start and the end"))
    ax.legend(fontsize="small", ncol=columns, loc="upper right" if per_wheel else "best")
    if d_wheel is None:
        band_ax.text(0.5, 0.5, f"no band levels: {origin}", ha="center", va="center", transform=band_ax.transAxes)
        band_ax.set_axis_off()
        return fig
    circumference = np.pi * d_wheel

    def to_wl(x):  # order <-> wavelength, its own inverse
        x = np.asarray(x, float)
        return circumference / np.where(x > 0, x, np.nan)

    wl_ax = ax.secondary_xaxis("top", functions=(to_wl, to_wl))
    picks = []  # R10 wavelengths at least a twelfth of the axis apart in order
    for t in bands.nominal_wavelength(np.arange(-6, 30)):
        at = circumference / t
        if 1 <= at <= top + 0.5 and all(abs(at - circumference / p) >= top / 12 for p in picks):
            picks.append(t)
    wl_ax.set_xticks(picks, [f"{t:g}" for t in picks])
    wl_ax.set_xlabel(f"wavelength π D / n (m), wheel diameter D = {d_wheel:g} m ({origin})", fontsize="small")
    # 40 dB under the largest band (several wheels: the wheel's own), never under 1 pm rms (-120 dB
    # re 1 µm); an empty band has no level
    def top_level(keys):
        return max((float(np.nanmax(levels[key].level)) for key in keys if np.any(np.isfinite(levels[key].level))),
                   default=-np.inf)

    lowest = 20 * np.log10(LEAST_AMPLITUDE)
    everything = top_level(levels)
    band_floors = {i: max((top_level([(i, 0), (i, -1)]) if per_wheel else everything) - 20 * np.log10(SPECTRUM_RANGE),
                          lowest) for i in range(len(rows))}
    band_floor = min((band_floors[i] for i in shaped), default=lowest)
    for i, (label, _) in enumerate(rows):
        for k, style, marker, when in ((0, "--", ".", "start"), (-1, "-", "o", "end")):
            lv = levels[(i, k)]
            shown = np.where(lv.level >= band_floors[i], lv.level, np.nan)
            colour = f"C{i % 10}"
            band_ax.plot(lv.wavelength, shown, color=colour, ls=style, lw=1.0,
                         label=f"{label}, {when}" + (": round" if rounds[(i, k)] else ""))
            band_ax.plot(lv.wavelength[lv.resolved], shown[lv.resolved], ls="none", marker=marker, ms=4, color=colour)
            band_ax.plot(lv.wavelength[~lv.resolved], shown[~lv.resolved], ls="none", marker="o", ms=4, mfc="white",
                         color=colour)
    if limit is not None:
        over = [int(bands.exceedance(levels[(i, -1)], limit).count) for i in range(len(rows))]
        said = (f"{over[0]} band{'s' if over[0] != 1 else ''} above at the end" if len(rows) == 1 else
                "bands above at the end:\n" + ", ".join(f"{c} at {label}" for c, (label, _) in zip(over, rows)))
        band_ax.plot(limit.wavelength, limit.level, color="k", lw=1.5, marker="s", ms=3,
                     label=f"{limit.name}: {said}" if len(rows) == 1 else f"{limit.name},\n{said}")
        band_floor = min(band_floor, float(np.min(limit.level)))
    band_ax.plot([], [], ls="none", marker="o", mfc="white", color="0.4",
                 label=f"band longer than L/4 = {circumference / 4:.2f} m (not resolved)")
    band_ax.set_ylim(bottom=band_floor - 3)
    # the axis spans the bands drawn (a level within 40 dB of the largest) and the limit: never the
    # empty bands past the last line of the spectrum
    drawn = [lv.wavelength[np.isfinite(lv.level) & (lv.level >= band_floors[i])] for (i, _), lv in levels.items()]
    span = np.concatenate(drawn + ([limit.wavelength] if limit is not None else []))
    if span.size == 0:
        span = np.concatenate([lv.wavelength for lv in levels.values()])
    if span.max() < 4 * span.min():  # one or two bands: an octave either side, so that two ticks show
        middle = np.sqrt(span.max() * span.min())
        span = np.array([middle / 2, middle * 2])
    band_ticks = bands.nominal_wavelength(np.arange(-9, 40, 3))
    band_ticks = band_ticks[(band_ticks <= span.max() * 1.05) & (band_ticks >= span.min() / 1.05)]
    band_ax.set_xscale("log")
    band_ax.set_xlim(span.max() * 1.12, span.min() / 1.12)  # long waves on the left, as EN 15610 draws them
    if not any(np.any(np.isfinite(lv.level)) for lv in levels.values()):
        band_ax.text(0.5, 0.5, "a round wheel: no band holds any energy", ha="center", va="center",
                     transform=band_ax.transAxes)
    band_ax.set_xticks(band_ticks, [f"{t:g}" for t in band_ticks])
    band_ax.xaxis.set_minor_formatter(NullFormatter())  # the band centres are the labels
    band_ax.set(xlabel="wavelength, one-third-octave band centre (m)", ylabel="band level (dB re 1 µm)",
                title="one-third-octave band levels (EN 15610), 40 dB under each wheel's peak" if per_wheel else
                "one-third-octave band levels in wavelength (EN 15610), 40 dB under the peak")
    band_ax.grid(True, which="major", color="0.9", lw=0.6)
    # under the axis at the foot of the figure, the axis raised by the legend's height
    labels = band_ax.get_legend_handles_labels()[1]
    per_column = -(-len(labels) // 2)
    lines = max(sum(label.count("\n") + 1 for label in labels[c * per_column:(c + 1) * per_column]) for c in (0, 1))
    legend_height = (1.4 * lines + 1.2) * 10 / 1.2 / 72  # in: lines of 'small' text (10 pt / 1.2), padding
    band_ax.legend(fontsize="small", ncol=2, loc="lower center", bbox_to_anchor=(0.5, 0.08 / 8),
                   bbox_transform=fig.transFigure)
    fig.subplots_adjust(**_margins(fig, 2, 1, bottom=0.7 + legend_height, **margins))
    return fig


def polar(ds, diameter=None):
    """The wheel round its circumference at the start (dashed) and the end (solid): the shape
    ``u - mean(u)`` (µm on the radial axis) about a circle that stands for the nominal radius,
    the deviation exaggerated by the factor stated in the figure."""
    import textwrap

    from matplotlib.figure import Figure
    from matplotlib.ticker import MaxNLocator

    d_wheel, origin = _wheel_diameter(ds, diameter)
    every = _rows(ds)
    rows = every[:6]
    cols = min(len(rows), 3)
    lines = (len(rows) + cols - 1) // cols
    fig = _fixed_figure(4.2 * cols, 4.6 * lines + 0.4)
    axes = fig.subplots(lines, cols, squeeze=False, subplot_kw={"projection": "polar"})
    theta = np.append(ds.angle.values, ds.angle.values[0] + 2 * np.pi)
    notes = []
    for ax, (i, (label, d)) in zip(axes.flat, enumerate(rows)):
        shapes = [d.u.isel(time=k).values for k in (0, -1)]
        shapes = [np.append(u - u.mean(), u[0] - u.mean()) / UM for u in shapes]
        span = max(float(np.max(np.abs(s))) for s in shapes) or 1.0
        hub = 2.5 * span  # the circle u = 0 is drawn at this radius, in µm of deviation
        ax.set_rorigin(-hub)
        ax.set_ylim(-1.15 * span, 1.15 * span)
        for s, style, width, when in ((shapes[0], "--", 1.0, "start"), (shapes[1], "-", 1.6, "end")):
            ax.plot(theta, s, color=f"C{i % 10}", ls=style, lw=width, label=when)
        ax.plot(theta, np.zeros_like(theta), color="0.5", lw=0.8, ls=":", label="mean radius")
        ticks = [v for v in MaxNLocator(5).tick_values(-1.15 * span, 1.15 * span) if abs(v) <= 1.15 * span]
        ax.set_yticks(ticks, [""] * len(ticks))
        for v in ticks:  # the radial labels on a white ground, readable over the circles and curves behind
            ax.text(np.radians(100), v, f"{tick_number(v, span)} µm", fontsize="x-small", ha="center", va="center",
                    bbox={"facecolor": "white", "edgecolor": "none", "alpha": 0.85, "pad": 0.8}, zorder=5)
        ax.tick_params(axis="x", labelsize="small")
        drop = float(d.u.isel(time=-1).mean() - d.u.isel(time=0).mean()) / UM
        ax.set_title(f"{label}: mean radius {tick_number(round(drop), 1.0)} µm (not drawn)", fontsize="small", pad=14)
        if d_wheel is not None:
            factor = d_wheel / 2 / (hub * UM)
            notes.append(factor)
        if i == 0:  # in the hub, which the plot leaves empty
            ax.legend(loc="center", fontsize="x-small", frameon=False, handlelength=1.6)
    for ax in list(axes.flat)[len(rows):]:
        ax.set_axis_off()
    scale = (f"radial axis: u - mean(u) in µm, exaggerated about {min(notes):,.0f}x"
             + (f" to {max(notes):,.0f}x" if max(notes) > 1.01 * min(notes) else "")
             + f" against R0 = {d_wheel / 2 * 1e3:g} mm ({origin})") if notes else \
        f"radial axis: u - mean(u) in µm, not to scale ({origin})"
    shown = "" if len(every) == len(rows) else f" (the first {len(rows)} of {len(every)} rows)"
    fig.suptitle(_title(ds, "the wheel at the start and the end" + shown), fontsize="medium")
    scale = textwrap.fill(scale, 28 * 2 * cols)
    fig.supxlabel(scale, fontsize="small")  # under the wheels: one title line
    # room for the titles over the angle labels on top, and under them for the scale's lines (10 / 1.2 pt)
    fig.subplots_adjust(**_margins(fig, lines, cols, left=0.45, right=0.45, top=0.95, hgap=0.9, wgap=0.8,
                                   bottom=0.4 + (scale.count("\n") + 1) * 1.25 * 10 / 1.2 / 72))
    return fig


def stability(map_ds):
    """Growth rate over speed and polygon order, with its zero contour; a map per km is drawn
    per 10 000 km (the field's distance), and growth and decay each take the full half of the
    colour scale, so a weak growth band is not pale beside a strong decay."""
    import textwrap

    from matplotlib.colors import TwoSlopeNorm

    fig, (ax,) = _figure(7, 4)
    rate = map_ds.growth_rate.values.T
    units = map_ds.growth_rate.attrs.get("units", "1")
    label = map_ds.growth_rate.attrs.get("long_name", "growth rate") + ("" if units == "1" else f" ({units})")
    if units == "km-1":
        rate, label = rate * 1e4, "growth per 10 000 km (ln of amplitude ratio)"
    elif units == "1" and map_ds.attrs.get("life_distance_km", 0) > 0:  # per unit normed time: one life
        rate, label = rate * 1e4 / map_ds.attrs["life_distance_km"], "growth per 10 000 km (ln of amplitude ratio)"
    low, high = float(np.min(rate)), float(np.max(rate))
    if low < 0 < high:
        norm = TwoSlopeNorm(0.0, low, high)
    else:
        limit = max(abs(low), abs(high), 1e-30)
        norm = TwoSlopeNorm(0.0, -limit, limit)
    speed = m_s_to_kmh(map_ds.speed.values)
    mesh = ax.pcolormesh(speed, map_ds.order.values, rate, shading="auto", cmap="RdBu_r", norm=norm)
    if low < 0 < high and speed.size > 1:
        ax.contour(speed, map_ds.order.values, rate, levels=[0.0], colors="k", linewidths=1)
    fig.colorbar(mesh, ax=ax, label=label)
    _stability_lines(ax, map_ds, speed)
    source = map_ds.attrs.get("source") or (f"crest amplitude {map_ds.attrs['amplitude'] / UM:g} µm"
                                            if "amplitude" in map_ds.attrs else "")
    ax.set(xlabel="speed (km/h)", ylabel="polygon order")
    fig.suptitle(textwrap.fill("stability map" + (f": {source}" if source else ""), 90), fontsize="medium")
    return fig


def _stability_lines(ax, map_ds, speed):
    """On a stability map, where its attributes give them: the run's speed (``run_speed_kmh``) and
    the orders the P2 resonance ``p2_frequency_hz`` and the wheelset modes
    ``wheel_mode_frequencies_hz`` excite at each speed on a wheel of ``wheel_diameter_m``,
    ``n = f π D / V``."""
    a, lines = map_ds.attrs, False
    if "run_speed_kmh" in a and speed.min() <= a["run_speed_kmh"] <= speed.max():
        ax.axvline(a["run_speed_kmh"], color="k", ls="--", lw=1, label=f"the run: {a['run_speed_kmh']:.4g} km/h")
        lines = True
    if "p2_frequency_hz" in a and "wheel_diameter_m" in a:
        v = np.linspace(speed.min(), speed.max(), 200)
        n = a["p2_frequency_hz"] * np.pi * a["wheel_diameter_m"] / (v / 3.6)
        top = float(map_ds.order.max()) + 0.5
        ax.plot(v[n <= top], n[n <= top], color="0.25", ls="-.", lw=1.2,
                label=f"n = f π D / V, P2 {a['p2_frequency_hz']:.1f} Hz")
        for f in np.atleast_1d(a.get("wheel_mode_frequencies_hz", [])):
            n = f * np.pi * a["wheel_diameter_m"] / (v / 3.6)
            ax.plot(v[n <= top], n[n <= top], color="0.25", ls=":", lw=1.2, label=f"wheelset mode {f:.0f} Hz")
        ax.set_ylim(float(map_ds.order.min()) - 0.5, top)
        lines = True
    if lines:
        ax.legend(fontsize="x-small", loc="upper right", framealpha=0.9)


def worn_profile(ds):
    """Wheelset wear: depth removed (angle mean) over the lateral position on the wheel profile at a
    few distances, one panel per wheel."""
    fig, axes = _figure(7, 5.5, ds.sizes["wheel"])
    picks = np.unique(np.round(np.linspace(0, ds.sizes["time"] - 1, min(5, ds.sizes["time"]))).astype(int))
    for ax, wheel in zip(axes, ds.wheel.values):
        for i, k in enumerate(picks):
            ax.plot(ds.lateral.values / MM, ds.worn_depth.sel(wheel=wheel).values[k] / UM, color=f"C{i % 10}",
                    label=f"{float(ds.distance[k]):.0f} km")
        ax.set(ylabel="worn depth (µm)", title=f"{wheel} wheel")
        ax.legend(fontsize="small")
    axes[-1].set_xlabel("lateral position on the wheel profile (mm, + field side)")
    fig.suptitle(_title(ds, f"worn lateral profile at {m_s_to_kmh(float(ds.speed)):g} km/h"))
    return fig


def angular_pattern(ds):
    """Wheelset wear: depth removed at the end over angle round the wheel and lateral position."""
    fig, axes = _figure(7, 5.5, ds.sizes["wheel"])
    n = ds.sizes["angle"]
    edges = np.degrees(np.linspace(0, 2 * np.pi, n + 1))
    lateral = ds.lateral.values
    step = lateral[1] - lateral[0]
    lateral_edges = np.concatenate([lateral - step / 2, [lateral[-1] + step / 2]]) / MM
    for ax, wheel in zip(axes, ds.wheel.values):
        mesh = ax.pcolormesh(edges, lateral_edges, ds.surface_depth.sel(wheel=wheel).values.T / UM, cmap="viridis")
        fig.colorbar(mesh, ax=ax, label="worn depth (µm)")
        ax.set(ylabel="lateral (mm)", title=f"{wheel} wheel")
    axes[-1].set_xlabel("angle round the wheel (deg)")
    fig.suptitle(_title(ds, "worn depth over angle and lateral position at the end"))
    return fig


FIGURES = {"profiles": profiles, "evolution": evolution, "spectrum": spectrum, "polar": polar}
BODY_FIGURES = {"wheelset": {"worn-profile": worn_profile, "angular-pattern": angular_pattern}}


FORMATS = ("png", "pdf", "svg")  # what save writes; the PNG always, a vector format on request
DPI = 120  # dots per inch of the PNG (and of the raster parts of a PDF or SVG)


def save(fig, path, format="png", dpi=DPI):
    """Save a figure atomically as ``PATH`` with the suffix ``.png``, and also as ``.pdf`` or
    ``.svg`` when ``format`` asks for it; ``dpi`` in dots per inch (30 to 1200). Returns the path
    of the requested format."""
    if format not in FORMATS:
        raise ValueError(f"format: expected one of {', '.join(FORMATS)}, got {format!r}")
    if not 30 <= dpi <= 1200:
        raise ValueError(f"dpi: expected 30 to 1200 dots per inch, got {dpi!r}")
    path = Path(path)
    written = path.with_suffix(".png")
    _atomic(written, lambda tmp: fig.savefig(tmp, dpi=dpi, format="png"))
    if format != "png":
        written = path.with_suffix(f".{format}")
        _atomic(written, lambda tmp: fig.savefig(tmp, dpi=dpi, format=format))
    return written


def write_figures(ds, directory, format="png", dpi=DPI):
    """Every figure of a result as ``DIRECTORY/NAME.png`` (and ``.pdf`` or ``.svg`` with
    ``format``), in turn; returns the paths of the requested format. The command line has them
    drawn by forked processes instead (:func:`fork_drawers`)."""
    return [_draw_one(ds, i, directory, format, dpi) for i in range(len(_figures(ds)))]


def _figures(ds):
    return list(BODY_FIGURES.get(ds.attrs.get("body"), FIGURES).items())


def _draw_one(ds, i, directory, format, dpi):
    name, make = _figures(ds)[i]
    return save(make(ds), Path(directory) / f"{name}.png", format, dpi)


DRAWERS = 2  # forked drawing processes, each drawing a run of consecutive figures (:func:`_share`)


def fork_drawers():
    """Fork :data:`DRAWERS` processes that import matplotlib now, while this one goes on (the
    command line calls it before its run: importing matplotlib and drawing were most of a warm
    ``railwear run``), and then wait for one result to draw (:class:`Drawers`). None where forking
    is not safe or useful: no fork, one processor, or other threads running."""
    import threading

    if not hasattr(os, "fork") or len(os.sched_getaffinity(0)) < 2 or threading.active_count() > 1:
        return None
    pipes = [os.pipe() for _ in range(DRAWERS)]
    pid = os.fork()
    if pid:
        for read, _ in pipes:
            os.close(read)
        return Drawers(pid, [write for _, write in pipes])
    status = 1
    try:  # the first drawer; it forks the others once matplotlib is imported, and waits for them
        for _, write in pipes:
            os.close(write)
        import matplotlib.backends.backend_agg  # noqa: F401
        import matplotlib.figure  # noqa: F401
        import matplotlib.ticker  # noqa: F401

        share, others = 0, []
        for k in range(1, DRAWERS):
            child = os.fork()
            if not child:
                share, others = k, []
                break
            others.append(child)
        for k, (read, _) in enumerate(pipes):
            if k != share:
                os.close(read)
        status = _draw_share(pipes[share][0], share)
        for child in others:
            status |= os.waitpid(child, 0)[1] != 0
    except BaseException:  # noqa: BLE001  (the parent draws the figures again and sees the error)
        status = 1
    os._exit(status)


def _draw_share(read, share):
    """In a drawer: read one pickled ``(ds, directory, format, dpi)`` from the pipe ``read`` and draw
    its ``share`` of the figures; nothing when the pipe closes empty. Exit status."""
    import pickle

    with os.fdopen(read, "rb") as pipe:
        message = pipe.read()
    if not message:  # the run failed or drew no figures
        return 0
    ds, directory, format, dpi = pickle.loads(message)
    for i in _share(len(_figures(ds)), share):
        _draw_one(ds, i, directory, format, dpi)
    return 0


def _share(count, k):
    """The figures drawer ``k`` draws of ``count``: the ``k``-th of :data:`DRAWERS` consecutive runs
    (the run's four: profiles and evolution, spectrum and polar, about 0.3 s of CPU each)."""
    return range(k * count // DRAWERS, (k + 1) * count // DRAWERS)


class Drawers:
    """The forked drawers of :func:`fork_drawers`, seen from the process that forked them."""

    def __init__(self, pid, pipes):
        self.pid, self.pipes, self.job, self.sent = pid, pipes, None, False

    def send(self, ds, directory, format="png", dpi=DPI):
        """Hand ``ds`` to the drawers; they draw while this process goes on (writing result.nc)."""
        import pickle

        self.job = (ds, Path(directory), format, dpi)
        try:
            message = pickle.dumps((ds, str(directory), format, dpi), protocol=pickle.HIGHEST_PROTOCOL)
            for write in self.pipes:
                with os.fdopen(write, "wb", closefd=False) as pipe:
                    pipe.write(message)
            self.sent = True
        except (OSError, pickle.PicklingError, TypeError, AttributeError):  # a drawer is gone: drawn here
            self.sent = False
        finally:
            self.close()

    def close(self):
        """Close the pipes: drawers still waiting exit without drawing."""
        for write in self.pipes:
            with contextlib.suppress(OSError):  # already closed by a failed send
                os.close(write)
        self.pipes = []

    def wait(self):
        """Wait for the drawers; the paths of the figures (all drawn here again if a drawer failed)."""
        self.close()
        _, status = os.waitpid(self.pid, 0)
        ds, directory, format, dpi = self.job
        figures = _figures(ds)
        if self.sent and status == 0:
            return [(directory / f"{name}.png").with_suffix(f".{format}") for name, _ in figures]
        return [_draw_one(ds, i, directory, format, dpi) for i in range(len(figures))]


REGIME_COLOURS = {"stable": "#4daf4a", "smoothing": "#377eb8", "onset": "#ff7f00",
                  "polygonalising": "#e41a1c", "driven by the other wheels": "#984ea3", "failed": "#999999"}


FLAT = 1e-9  # a relative spread below this is round-off: the quantity is drawn flat, with ticks
UNIT_SUFFIXES = {"_kmh": "km/h", "_m_s": "m/s", "_kN": "kN", "_MN_m": "MN/m", "_N_m": "N/m", "_kN_s_m": "kN s/m",
                 "_N_s_m": "N s/m", "_kg_m2": "kg m²", "_kg": "kg", "_mm": "mm", "_um": "µm", "_m": "m",
                 "_GPa": "GPa", "_km": "km", "_deg": "deg"}


def field_label(field):
    """A scenario field as an axis label in words, with the unit its name carries:
    ``operation.speed_kmh`` is ``speed (km/h)``, ``wheel.static_load_kN`` ``static load (kN)``
    (the figure's title names the fields themselves)."""
    name = field.rsplit(".", 1)[-1]
    suffix = next((s for s in UNIT_SUFFIXES if name.endswith(s) and len(name) > len(s)), None)
    words = (name[: -len(suffix)] if suffix else name).replace("_", " ")
    return f"{words} ({UNIT_SUFFIXES[suffix]})" if suffix else words


def flat_if_round_off(ax, values, axis="y"):
    """Draw a quantity whose finite ``values`` spread by less than :data:`FLAT` of their size as
    constant: a linear axis a few per cent either side, with plain ticks, never the round-off
    autoscaled into a cliff. Returns whether it did."""
    from matplotlib.ticker import ScalarFormatter

    v = np.asarray(values, float)
    v = v[np.isfinite(v)]
    if v.size == 0:
        return False
    middle = float(np.mean(v))
    if np.ptp(v) > FLAT * max(abs(middle), np.finfo(float).tiny):
        return False
    half = 0.05 * abs(middle) if middle else 1.0
    getattr(ax, f"set_{axis}scale")("linear")
    getattr(ax, f"set_{axis}lim")(middle - half, middle + half)
    formatter = ScalarFormatter(useOffset=False)
    getattr(ax, f"{axis}axis").set_major_formatter(formatter)
    return True


def sweep(ds):
    """What a sweep answers, over the varied fields: for one field the distance to the
    out-of-roundness limit (km) per point, coloured by regime and labelled with the dominant
    order (the peak-to-peak over the run where the scenario has no limit); a map of the regime for
    two fields, points for samples. A quantity constant to round-off is drawn flat."""
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    fields = [c for c in ds.coords if c != "angle"]
    regimes = ds.regime.values
    colours = np.vectorize(lambda r: REGIME_COLOURS.get(str(r), "#999999"))(regimes)
    ran = regimes != "failed"
    order = np.where(ran, ds.dominant_order.values, 0) if "dominant_order" in ds else np.zeros(regimes.shape, int)
    if "limit_distance" in ds:
        limit = (f"{float(ds.peak_to_peak_limit) / MM:g} mm peak-to-peak " if "peak_to_peak_limit" in ds else "")
        reached = np.isfinite(ds.limit_distance.values)
        y = np.where(reached, ds.limit_distance.values, ds.distance_run.values if "distance_run" in ds else np.nan)
        ylabel, log = f"distance to the {limit}limit (km)", False
    else:
        reached = np.ones(regimes.shape, bool)
        with np.errstate(divide="ignore", invalid="ignore"):
            y = (ds.peak_to_peak / ds.peak_to_peak_initial).values
        ylabel, log = "peak-to-peak end / start", True
    fig, (ax,) = _figure(7, 4.5)
    handles = []
    if "sample" in ds.dims or len(fields) > 2:
        x = ds[fields[0]].values.ravel()
        other = ds[fields[1]].values.ravel() if len(fields) > 1 else y.ravel()
        ax.scatter(x, other, c=colours.ravel(), s=30)
        ax.set(xlabel=field_label(fields[0]), ylabel=field_label(fields[1]) if len(fields) > 1 else ylabel)
        if len(fields) == 1 and not flat_if_round_off(ax, other) and log:
            ax.set_yscale("log")
        title = "regime of each sample"
    elif len(fields) == 1:
        x = ds[fields[0]].values
        ax.plot(x[ran], y[ran], color="k", lw=1)
        ax.scatter(x[ran & reached], y[ran & reached], c=colours[ran & reached], s=40, zorder=3)
        if np.any(ran & ~reached):
            ax.scatter(x[ran & ~reached], y[ran & ~reached], facecolors="none", edgecolors=colours[ran & ~reached],
                       marker="^", s=50, zorder=3)
            handles.append(Line2D([], [], color="0.3", marker="^", ls="", mfc="none",
                                  label="limit not reached: drawn at the distance run"))
        for xi, yi, n, ok in zip(x, y, order, ran):
            if ok and np.isfinite(yi):
                ax.annotate(f"{int(n)}", (xi, yi), textcoords="offset points", xytext=(0, 7), ha="center",
                            fontsize="small")
        handles.append(Line2D([], [], ls="", marker="$8$", ms=8, color="0.2",
                              label="number over a point: dominant order at the end"))
        ax.set(xlabel=field_label(fields[0]), ylabel=ylabel)
        if not flat_if_round_off(ax, y[ran]):
            if log:
                ax.set_yscale("log")
            else:
                top = float(np.nanmax(y[ran])) if np.any(ran) else 1.0
                ax.set_ylim(0, 1.12 * top)
        title = "distance to the limit and dominant order" if "limit_distance" in ds else "growth and dominant order"
    else:
        from matplotlib.colors import to_rgb

        x, yy = ds[fields[0]].values, ds[fields[1]].values
        X, Y = np.meshgrid(x, yy, indexing="ij")
        # one cell per point, filling the grid, coloured by regime
        ax.pcolormesh(_cell_edges(x), _cell_edges(yy), np.array([[to_rgb(c) for c in row] for row in colours.T]),
                      edgecolors="w", linewidth=1.5)
        said = "dominant order at the end"
        distance = ds.limit_distance.values if "limit_distance" in ds else np.full(regimes.shape, np.nan)
        if np.any(np.isfinite(distance)):
            said += "; under it the distance to the limit\n(thousand km; none where the run ends before it)"
        for xi, yi, n, km, ok in zip(X.ravel(), Y.ravel(), order.ravel(), distance.ravel(), ran.ravel()):
            if ok:
                text = f"{int(n)}" + (f"\n{km / 1e3:,.0f}" if np.isfinite(km) else "")
                ax.annotate(text, (xi, yi), ha="center", va="center", fontsize="small", color="w",
                            fontweight="bold")
        handles.append(Line2D([], [], ls="", marker="$8$", ms=8, color="0.2", label=f"number in a cell: {said}"))
        ax.set(xlabel=field_label(fields[0]), ylabel=field_label(fields[1]))
        ax.set_xticks(x)
        ax.set_yticks(yy)
        title = "regime and dominant order"
    if ax.get_yscale() == "log" or "limit_distance" in ds:  # plain ticks: 2.5, 150,000; never 2x10^0
        plain = lambda v, _: f"{v:,.0f}" if abs(v) >= 1000 else f"{v:g}"  # noqa: E731
        ax.yaxis.set_major_formatter(plain)
        ax.yaxis.set_minor_formatter(lambda v, _: plain(v, _) if f"{v:.0e}"[0] in "25" else "")
    present = [r for r in REGIME_COLOURS if r in set(map(str, regimes.ravel()))]
    legend = [Patch(color=REGIME_COLOURS[r], label=f"regime: {r}") for r in present] + handles
    if len(fields) == 2 and "sample" not in ds.dims:  # the cells fill the axes: the legend beside them
        ax.legend(handles=legend, fontsize="small", loc="upper center", bbox_to_anchor=(0.5, -0.14), ncol=2)
    else:
        ax.legend(handles=legend, fontsize="small")
    import textwrap

    name = ds.attrs.get("base_scenario_name", "") or "sweep"
    ax.set_title(textwrap.fill(f"{name}: {title}, over {' × '.join(fields)}", 70), fontsize="medium")
    return fig


def _cell_edges(values):
    """Edges of cells centred on sorted grid ``values`` (halfway between neighbours)."""
    v = np.asarray(values, float)
    if v.size == 1:
        half = 0.5 * abs(v[0]) if v[0] else 0.5
        return np.array([v[0] - half, v[0] + half])
    middle = 0.5 * (v[1:] + v[:-1])
    return np.concatenate([[v[0] - (middle[0] - v[0])], middle, [v[-1] + (v[-1] - middle[-1])]])


def forecast(ds):
    """For every sample over distance, the peak-to-peak deviation (µm) against a peak-to-peak
    limit, or the largest level above a limit per order or band (dB) against 0 dB; the median
    and 90 % band of the crossings, and their histogram when a sample reaches the limit after
    0 km (a wheel already above it, or no crossing at all, is said in the title, no empty panel)."""
    cross = ds.crossing_distance.values
    crossed = cross[np.isfinite(cross)]
    above = bool(ds.attrs.get("above_at_start", crossed.size == cross.size and np.all(crossed == 0)))
    fig, axes = _figure(7, 6.5 if crossed.size and not above else 4, 2 if crossed.size and not above else 1)
    ax = axes[0]
    distance = ds.distance.values
    if "limit_m" in ds.attrs:
        values, limit, ylabel = ds.peak_to_peak.values / UM, ds.attrs["limit_m"] / UM, "peak-to-peak (µm)"
        label = f"limit {limit:g} µm"
    else:
        values, limit, ylabel = ds.excess.values, 0.0, "largest level above the limit (dB)"
        label = f"limit: {ds.attrs.get('limit_name', '')}"
    for i, p in enumerate(values):
        ax.plot(distance, p, color="C0", lw=0.6, alpha=0.4, label="samples" if i == 0 else None)
    ax.axhline(limit, color="C3", lw=1.5, label=label)
    for key, style, name in (("crossing_p05_km", ":", "5 % / 95 % of the crossings"), ("crossing_median_km", "-", "median"),
                             ("crossing_p95_km", ":", None)):
        if np.isfinite(ds.attrs[key]) and not above:
            ax.axvline(ds.attrs[key], color="k", ls=style, lw=1, label=name)
    n = ds.sizes["sample"]
    title = ("out-of-roundness per sample: already above the limit at 0 km" if above else
             "out-of-roundness per sample, median and 90 % band of the crossing" if crossed.size else
             f"out-of-roundness per sample: none of {n} reaches the limit within {distance[-1]:.0f} km")
    ax.set(xlabel="distance (km)", ylabel=ylabel, title=title)
    cuts = []
    # the distance axis ends a fifth past the last crossing: past it the samples that crossed run on
    # in a model no longer meant for them, and the samples that did not are said in words
    end = float(distance[-1])
    if crossed.size and not above and FORECAST_REACH * float(np.max(crossed)) < end:
        last = float(np.max(crossed))
        step = 10.0 ** np.floor(np.log10(1.1 * last) - 1)  # a round end: 390,000 km, not 421,304
        end = min(np.ceil(1.1 * last / step) * step, FORECAST_REACH * last)
        under = int(np.sum(~np.isfinite(cross)))
        cuts.append(f"distance cut at {end:,.0f} km"
                    + (f"; {under} sample{'s' if under != 1 else ''} stay under the limit to {distance[-1]:,.0f} km"
                       if under else ""))
    ax.set_xlim(distance[0] - 0.02 * (end - distance[0]), end)
    seen = values[:, distance <= end]
    if "limit_m" in ds.attrs:  # a log axis from the start to a few times the limit: the limit stays in view
        ax.set_yscale("log")
        top = FORECAST_SPAN * limit
        low = max(float(np.nanmin(seen)), limit / 1e3)
        ax.set_ylim(low / 1.5, max(top, low * 2))
        if np.nanmax(seen) > top:
            cuts.append(f"axis cut at {FORECAST_SPAN:g}x the limit")
        ax.yaxis.set_major_formatter(lambda v, _: f"{v:g}")
        ax.yaxis.set_minor_formatter(lambda v, _: f"{v:g}" if f"{v:.0e}"[0] in "25" else "")
    else:  # the same span in dB: 20 dB above the limit, 60 dB under it at most
        span = 20 * np.log10(FORECAST_SPAN)
        finite = seen[np.isfinite(seen)]
        high = float(np.max(finite)) if finite.size else span
        low = float(np.min(finite)) if finite.size else -span
        ax.set_ylim(max(low, -3 * span) - 2, min(max(high, 0.0), span) + 2)
        if high > span or low < -3 * span:
            cuts.append(f"axis cut at +{span:g} dB" + (f" and -{3 * span:g} dB" if low < -3 * span else ""))
    if cuts:
        ax.text(0.01, 0.98, "; ".join(cuts), transform=ax.transAxes, fontsize="x-small", va="top",
                bbox={"facecolor": "white", "edgecolor": "none", "alpha": 0.8, "pad": 1})
    ax.xaxis.set_major_formatter(lambda v, _: f"{v:,.0f}")
    ax.legend(fontsize="small", loc="lower right")
    if crossed.size and not above:
        hist = axes[1]
        hist.hist(crossed, bins=min(30, max(5, crossed.size // 3)), color="C0")
        hist.set(xlabel="distance at the limit (km)", ylabel="samples", title=f"{crossed.size} of {n} samples reach the limit")
        hist.xaxis.set_major_formatter(lambda v, _: f"{v:,.0f}")
    return fig


FORECAST_SPAN = 10.0  # the forecast's peak-to-peak axis ends at this many times the limit (+20 dB)
FORECAST_REACH = 1.2  # its distance axis ends at this many times the last crossing


def hunting_map(map_ds):
    """Linear critical speed over conicity and yaw stiffness, as a filled contour map in km/h
    (the file's ``critical_speed`` is read by its ``units``: m s-1, or km h-1 in earlier files)."""
    speed = speed_in(map_ds.critical_speed.transpose("yaw_stiffness", "conicity"), "km h-1")
    fig, (ax,) = _figure(7, 4.5)
    from matplotlib.ticker import MaxNLocator

    finite = np.where(np.isfinite(speed), speed, np.nan)
    if np.isfinite(finite).any():  # round levels (100, 150, ... km/h), never 96.3, 195.2
        low, high = float(np.nanmin(finite)), min(float(np.nanmax(finite)), 3 * float(np.nanmin(finite)) + 500)
        levels = MaxNLocator(14, steps=[1, 2, 2.5, 5, 10]).tick_values(low, max(high, low + 1))
        levels = levels[(levels < high) | (np.arange(levels.size) == 0)]
        levels = np.append(levels, levels[-1] + (levels[1] - levels[0]) if levels.size > 1 else levels[0] + 10)
        extend = "both" if levels[0] > low else "max"
    else:
        levels, extend = 10, "max"
    mesh = ax.contourf(map_ds.conicity.values, map_ds.yaw_stiffness.values / MN, finite, levels=levels,
                       cmap="viridis", extend=extend)
    bar = fig.colorbar(mesh, ax=ax, label="critical speed (km/h)")
    bar.ax.yaxis.set_major_formatter(lambda v, _: f"{v:,.0f}" if abs(v) >= 100 else f"{v:g}")
    ax.set(xlabel="equivalent conicity", ylabel="yaw stiffness (MN m/rad)",
           title="linear critical speed of hunting (blank: stable at every speed)")
    return fig


def lateral_motion(ds):
    """Lateral displacement of the wheelset against distance, one panel per speed (paper Fig. 1)."""
    speeds = np.atleast_1d(ds.speed.values)
    fig, axes = _figure(7, min(1.6 + 1.8 * speeds.size, 12), speeds.size)
    for ax, v in zip(axes, speeds):
        d = ds.sel(speed=v) if ds.speed.ndim else ds
        ax.plot(d.time.values * v, d.lateral_displacement.values / MM, lw=0.8)
        # each panel its own distance (the same time at another speed): each its own label
        ax.set(xlabel="distance run (m)", ylabel="lateral displacement y (mm)", title=f"{m_s_to_kmh(v):g} km/h")
    vc = ds.attrs.get("linear_critical_speed_kmh")
    fig.suptitle("hunting of a wheelset" + (f" (linear critical speed {vc:.0f} km/h)" if vc else ""))
    return fig


def _revolutions(contact_angle):
    """Revolution index (0, 1, ...) and angle on the wheel (rad, [0, 2π)) of each sample of a
    contact angle that runs round the wheel."""
    total = np.unwrap(np.asarray(contact_angle, float))
    total = total - 2 * np.pi * np.floor(total[0] / (2 * np.pi))
    return np.floor(total / (2 * np.pi)).astype(int), np.mod(total, 2 * np.pi)


def _per_revolution(ax, angle, values, revolution, **style):
    """One line per revolution over the angle (deg), coloured from early to late; returns the lines."""
    from matplotlib import colormaps

    turns = np.unique(revolution)
    colours = colormaps["viridis"](np.linspace(0, 0.85, turns.size))
    lines = []
    for colour, k in zip(colours, turns):
        pick = revolution == k
        label = f"revolution {k + 1}" if turns.size <= 8 or k in (turns[0], turns[-1]) else None
        lines += ax.plot(np.degrees(angle[pick]), values[pick], color=colour, label=label, **style)
    return lines


def contact_path(ds, bins=180):
    """The contact point (paper Fig. 2) and the frictional power (Fig. 3) over the angle on the
    wheel, revolution by revolution: the contact point's deviation from rigid rotation ``R0 (φ -
    V t / R0)`` (mm of tread), the same less its mean creep drift (µm: the short-time dynamics),
    and the frictional power (W) over angle × revolution in ``bins`` angle cells."""
    from matplotlib.figure import Figure

    d = ds.isel(speed=0) if ds.speed.ndim else ds
    speed = float(np.atleast_1d(ds.speed.values)[0])
    radius = float(ds.attrs.get("model_radius", 1.0))
    revolution, angle = _revolutions(d.contact_angle.values)
    t = d.time.values
    if "rotation_deviation" in d:
        rotation = d.rotation_deviation.values
    else:  # a file without it: the contact angle less rigid rotation (its mean rate when R0 is unknown)
        total = np.unwrap(d.contact_angle.values)
        rigid = speed * t / radius if "model_radius" in ds.attrs else np.polyval(np.polyfit(t, total, 1), t)
        rotation = total - total[0] - rigid
    deviation = radius * rotation  # m of tread
    drift = np.polyval(np.polyfit(t, deviation, 1), t)  # the mean creep: a steady slip of the wheel
    slip = np.polyfit(t, deviation, 1)[0] / speed
    fig = Figure(figsize=(7.5, 9.5), layout="constrained")
    path, dynamic, power = fig.subplots(3, 1)
    _per_revolution(path, angle, deviation / MM, revolution, lw=1.2)
    path.set(xlabel="contact angle on the wheel (deg)", ylabel="R0 (φ - V t / R0) (mm of tread)", xlim=(0, 360),
             title="contact point: deviation from rigid rotation (paper Fig. 2)")
    path.legend(fontsize="small", ncol=2, title=f"mean creepage {slip:.2e}", title_fontsize="small",
                loc="lower right")
    _per_revolution(dynamic, angle, (deviation - drift) / UM, revolution, lw=1.2)
    dynamic.axhline(0.0, color="0.5", lw=0.8, ls=":", label="rigid rotation with the mean creep")
    dynamic.set(xlabel="contact angle on the wheel (deg)", ylabel="deviation less the mean creep (µm of tread)",
                xlim=(0, 360), title="the same less the mean creep drift: oscillations of the short-time dynamics")
    low, high = dynamic.get_ylim()
    dynamic.set_ylim(low, high + 0.45 * (high - low))  # room for the legend above the lines
    dynamic.legend(fontsize="small", ncol=3, loc="upper center")
    turns = np.unique(revolution)
    cell = np.minimum((angle / (2 * np.pi) * bins).astype(int), bins - 1)
    grid = np.full((turns.size, bins), np.nan)
    for row, k in enumerate(turns):
        pick = revolution == k
        total = np.bincount(cell[pick], d.frictional_power.values[pick], bins)
        count = np.bincount(cell[pick], minlength=bins)
        grid[row] = np.where(count > 0, total / np.maximum(count, 1), np.nan)
    mesh = power.pcolormesh(np.linspace(0, 360, bins + 1), np.arange(turns.size + 1) + turns[0] + 0.5, grid,
                            shading="flat", edgecolors="none", cmap="inferno")
    fig.colorbar(mesh, ax=power, label="frictional power (W)")
    power.set(xlabel="contact angle on the wheel (deg)", ylabel="revolution", xlim=(0, 360),
              title=f"frictional power over angle × revolution (paper Fig. 3), {360 / bins:g} deg cells")
    power.yaxis.get_major_locator().set_params(integer=True)
    fig.suptitle(f"{ds.attrs.get('scenario_name', 'disk wheel')}: contact point and frictional power at "
                 f"{m_s_to_kmh(speed):g} km/h, R0 = {radius * 1e3:g} mm")
    return fig


def bifurcation(ds):
    """Limit-cycle amplitude against speed from the ramp down, with the Hopf point."""
    fig, (ax,) = _figure(7, 4)
    ax.plot(m_s_to_kmh(ds.speed.values), ds.amplitude.values / MM, "o-")
    hopf = ds.attrs.get("hopf_speed")
    if hopf:
        ax.axvline(m_s_to_kmh(hopf), color="C3", ls="--", label=f"Hopf point {m_s_to_kmh(hopf):.1f} km/h")
    nonlinear = ds.attrs.get("nonlinear_critical_speed")
    if nonlinear and np.isfinite(nonlinear):
        ax.axvline(m_s_to_kmh(nonlinear), color="k", ls=":", label=f"nonlinear critical {m_s_to_kmh(nonlinear):.1f} km/h")
    ax.set(xlabel="speed (km/h)", ylabel="limit-cycle amplitude (mm)", title="bifurcation diagram (ramp down)")
    ax.legend(fontsize="small")
    return fig


def _complete_teeth(ds):
    """Indices of the passes of a wear-intensity Dataset that are whole (not the first or last)."""
    return np.arange(1, ds.sizes["tooth"] - 1) if ds.sizes["tooth"] > 2 else np.arange(ds.sizes["tooth"])


def wear_intensity(ds):
    """Wear intensity at a fixed position on the wheel (paper Fig. 7): the depth rate over the
    turns (µm/h), one tooth zoomed (ms), and the integrals of the teeth (pm): the distribution
    over the Monte Carlo draws of speed and phase (``sample_tooth_depth``, ``sample_speed``) that
    the stepwise strategy samples, against the identical teeth of one speed."""
    fig = _plain_figure(7.5, 9.0)
    mosaic = fig.subplot_mosaic([["turns", "turns"], ["tooth", "tooth"], ["histogram", "speed"]])
    t, rate = ds.time.values, ds.wear_intensity.values / UM * HOUR
    teeth = ds.tooth_depth.values / PM
    speed = m_s_to_kmh(float(ds.attrs["speed"]))
    where = f"{np.degrees(ds.attrs['position_rad']):g} deg"
    ax = mosaic["turns"]
    ax.plot(t, rate, lw=0.8, color="C0", label=f"depth rate at {where}, {speed:g} km/h")
    ax.set(xlabel="time (s)", ylabel="depth rate (µm/h)",
           title=f"{teeth.size} passes of the patch over the position in {t[-1]:.2f} s: one tooth each")
    ax.legend(fontsize="small", loc="upper right")
    whole = _complete_teeth(ds)
    k = int(whole[np.argmin(np.abs(teeth[whole] - np.median(teeth[whole])))])
    covered = ds.wear_intensity.values > 0
    passes = np.cumsum(np.diff(covered.astype(int), prepend=0) == 1) * covered
    pick = np.nonzero(passes == k + 1)[0]
    pick = np.arange(max(pick[0] - pick.size // 2, 0), min(pick[-1] + pick.size // 2 + 1, t.size))
    zoom = mosaic["tooth"]
    ms = (t[pick] - t[pick[0]]) * 1e3
    zoom.plot(ms, rate[pick], color="C0", lw=1.2, label="depth rate")
    zoom.fill_between(ms, rate[pick], color="C0", alpha=0.25, label=f"its integral: {teeth[k]:.4g} pm")
    zoom.set(xlabel=f"time from {t[pick[0]]:.4f} s (ms)", ylabel="depth rate (µm/h)",
             title=f"tooth {k + 1} zoomed: the patch ({2e3 * float(ds.attrs.get('patch_half_length', np.nan)):.3g} mm) "
                   "passing the position" if "patch_half_length" in ds.attrs else f"tooth {k + 1} zoomed")
    zoom.legend(fontsize="small", loc="lower center")
    hist, by_speed = mosaic["histogram"], mosaic["speed"]
    if "sample_tooth_depth" in ds:
        drawn = ds.sample_tooth_depth.values / PM
        spread = float(np.std(drawn, ddof=1))
        hist.hist(drawn, bins=max(5, min(20, drawn.size // 3)), color="C1", alpha=0.8,
                  label=f"{drawn.size} draws: mean {drawn.mean():.4g} pm,\nstandard deviation {spread:.2g} pm")
        hist.axvline(float(np.mean(teeth[whole])), color="C0", lw=1.5, ls="--",
                     label=f"the {whole.size} whole teeth above\n(spread {np.ptp(teeth[whole]):.1g} pm)")
        hist.set(xlabel="tooth integral (pm of depth)", ylabel="draws",
                 title="the teeth's integrals over service")
        hist.legend(fontsize="x-small", loc="upper left")
        by_speed.plot(m_s_to_kmh(ds.sample_speed.values), drawn, "o", ms=3, color="C1", label="draw")
        by_speed.plot([speed], [np.mean(teeth[whole])], "s", ms=6, color="C0", label=f"the run above, {speed:g} km/h")
        by_speed.set(xlabel="drawn speed (km/h)", ylabel="tooth integral (pm)", title="against the drawn speed")
        by_speed.legend(fontsize="x-small")
    else:
        for ax in (hist, by_speed):
            ax.text(0.5, 0.5, "no Monte Carlo draws in this Dataset", ha="center", va="center", transform=ax.transAxes)
            ax.set_axis_off()
    fig.suptitle(f"wear intensity at a fixed position on the wheel ({where}), paper Fig. 7")
    return fig


RISING, FALLING = "-", "--"  # line styles of the branches of h: ∂h/∂u_xx > 0 (smoothing) and < 0 (ill-posed)


def _branches(ax, s, h, colour, width=1.5):
    """Draw ``h`` (mm per life) over the curvature ``s`` (mm/rad²) solid where it rises and
    dashed where it falls; returns the curvatures (mm/rad²) where it turns."""
    rising = np.gradient(h, s) >= 0
    cuts = np.nonzero(np.diff(rising.astype(int)))[0] + 1
    for piece in np.split(np.arange(s.size), cuts):
        piece = np.arange(max(piece[0] - 1, 0), piece[-1] + 1)  # join the pieces
        ax.plot(s[piece], h[piece], color=colour, lw=width, ls=RISING if rising[piece[-1]] else FALLING)
    ax.plot(s[cuts], h[cuts], "x", ms=8, mew=2, color=colour)
    return s[cuts]


def _shape(turns, rises):
    """How a curve over the sampled curvature runs, in words."""
    if turns.size:
        return "non-monotone, turns at u_xx = " + ", ".join(f"{t:.1f}" for t in turns) + " mm/rad²"
    return "monotone: rising (smoothing)" if rises else "monotone: falling (ill-posed)"


def fitted_relation(stats, fit, reference=None, reference_speeds=None):
    """Mean wear rate against the local curvature with the fitted ``h`` (paper Fig. 8), its
    rising branches solid and its falling ones dashed, each speed said monotone or not. With
    ``reference`` (an ``h(s, speed=v)`` in m per unit normed time, such as the disk_contact form)
    a second panel draws it at ``reference_speeds`` (m/s, default the statistics') over the
    curvature range down past each speed's ``crest_curvature`` where the form has one."""
    from matplotlib.lines import Line2D

    fig, axes = _figure(7.5, 9 if reference is not None else 5.2, rows=2 if reference is not None else 1)
    ax = axes[0]
    life = 1 / MM  # m per normed life -> mm
    speeds = np.atleast_1d(stats.speed.values)
    handles = []
    for i, v in enumerate(speeds):
        colour = f"C{i % 10}"
        s = stats.curvature.values[i].ravel()
        ax.scatter(s / MM, stats.rate.values[i].ravel() * life, s=3, alpha=0.2, color=colour)
        ax.errorbar(fit.bin_curvature[i] / MM, fit.bin_rate[i] * life, yerr=fit.bin_error[i] * life, fmt="o",
                    ms=4, color=colour)
        grid = np.linspace(fit.bin_curvature[i].min(), fit.bin_curvature[i].max(), 400)  # where the bins are
        values = fit(grid, i)
        turns = _branches(ax, grid / MM, values * life, colour)
        handles.append(Line2D([], [], color=colour, marker="o", ms=4,
                              label=f"{m_s_to_kmh(v):g} km/h: fit {_shape(turns, values[-1] > values[0])}; "
                                    f"bin means, reduced χ² {fit.chi2[i]:.2f}"))
    style = [Line2D([], [], color="0.3", ls=RISING, label="∂h/∂u_xx > 0: smoothing"),
             Line2D([], [], color="0.3", ls=FALLING, label="∂h/∂u_xx < 0: ill-posed"),
             Line2D([], [], color="0.3", ls="none", marker="x", mew=2, label="turning point"),
             Line2D([], [], color="0.3", ls="none", marker=".", alpha=0.4, label="cells (one frozen geometry each)")]
    ax.set(xlabel="curvature u_xx (mm/rad²)", ylabel="u_T (mm per life)",
           title="frozen-geometry statistics against the local curvature, with the fitted h")
    ax.legend(handles=handles + style, fontsize="x-small", loc="upper center", bbox_to_anchor=(0.5, -0.14), ncol=1)
    if reference is None:
        return fig
    ref = axes[1]
    speeds = speeds if reference_speeds is None else np.atleast_1d(np.asarray(reference_speeds, float))
    low = float(np.min(stats.curvature.values))
    crest = getattr(reference, "crest_curvature", None)
    handles = []
    for i, v in enumerate(speeds):
        colour = f"C{i % 10}"
        u_c = float(crest(v)) if crest is not None else -np.inf
        bottom = min(low, 1.6 * u_c) if np.isfinite(u_c) else low
        grid = np.linspace(bottom, float(np.max(stats.curvature.values)), 600)
        values = reference(grid, speed=v)
        turns = _branches(ref, grid / MM, values * life, colour)
        said = f"{m_s_to_kmh(v):g} km/h: {_shape(turns, values[-1] > values[0])}"
        if np.isfinite(u_c):
            ref.axvline(u_c / MM, color=colour, lw=0.8, ls=":")
            said += f"; crest unloads to F/μ at u_c = {u_c / MM:.1f} mm/rad² (dotted)"
        handles.append(Line2D([], [], color=colour, label=said))
    ref.axvspan(low / MM, float(np.max(stats.curvature.values)) / MM, color="0.92", zorder=0,
                label="curvatures the statistics sample")
    ref.set(xlabel="curvature u_xx (mm/rad²)", ylabel="h (mm per life)",
            title=f"the derived h of a rigid disk wheel ({type(reference).__name__}), same wheel and load")
    ref.legend(handles=handles + style[:3] + [ref.patches[-1]], fontsize="x-small", loc="upper center",
               bbox_to_anchor=(0.5, -0.14))
    return fig


def _depth_unit(depth):
    """``(metres per unit, unit)`` that shows a depth (m) with a few digits: nm, µm or mm."""
    top = float(np.max(np.abs(depth), initial=0.0))
    return (1e-9, "nm") if top < 1e-6 else (UM, "µm") if top < 1e-3 else (MM, "mm")


def wear_surface(surface, title="wear surface", patch=None, coarse=None, window_cells=1.5):
    """Removed depth over the angle × lateral grid of a :class:`~railwear.geometry.WearSurface`
    (paper Fig. 4): the whole surface, and at true scale (mm of tread) round its deepest cell the
    cell edges and, given ``patch = (a, b)`` (m, the semi-axes along and across), the Hertz contact
    patch against them; a ``coarse`` surface of the same run is drawn so as well, over
    ``± window_cells`` of its cells."""
    from matplotlib.patches import Ellipse

    grids = [g for g in (coarse, surface) if g is not None]
    fig = _plain_figure(7.5, 2.9 + 1.9 * len(grids))
    axes = fig.subplots(1 + len(grids), 1, height_ratios=[2.2] + [1.0] * len(grids))
    whole, zooms = axes[0], axes[1:]
    scale, unit = _depth_unit(surface.depth)
    top = max(float(np.max(g.depth)) for g in grids) / scale or 1.0
    lateral = surface.lateral_edges / MM
    image = whole.imshow(surface.depth.T / scale, origin="lower", extent=(0, 360, lateral[0], lateral[-1]),
                         aspect="auto", interpolation="nearest", cmap="viridis", vmin=0, vmax=top)
    whole.set(xlabel="angle round the wheel (deg)", ylabel="lateral position (mm)",
              title=f"{surface.n_angle} × {surface.lateral_edges.size - 1} cells, at most "
                    f"{surface.depth.max() / scale:.3g} {unit}")
    span = window_cells * grids[0].circumference / grids[0].n_angle / MM  # mm either side
    deepest = float(surface.angle[int(np.argmax(surface.depth.sum(1)))])
    handles = []
    for ax, grid in zip(zooms, grids):
        cell = grid.circumference / grid.n_angle / MM  # mm of tread per angle cell
        edges = grid.circumference / (2 * np.pi) * (np.arange(grid.n_angle + 1) * 2 * np.pi / grid.n_angle) / MM
        centre = grid.radius * deepest / MM
        keep = np.nonzero((edges[1:] > centre - span) & (edges[:-1] < centre + span))[0]
        x = edges[np.append(keep, keep[-1] + 1)] - centre
        ax.pcolormesh(x, grid.lateral_edges / MM, grid.depth[keep].T / scale, shading="flat", edgecolors="none",
                      cmap="viridis", vmin=0, vmax=top)
        handles = [ax.vlines(x, lateral[0], lateral[-1], color="w", lw=1.0, label="cell edges (the panels)")]
        ax.hlines(grid.lateral_edges / MM, x[0], x[-1], color="w", lw=0.4)
        said = f"{grid.n_angle} cells round the wheel, {cell:.1f} mm each"
        if patch is not None:
            a, b = (float(v) for v in patch)
            handles.append(ax.add_patch(Ellipse((0.0, 0.0), 2 * a / MM, 2 * b / MM, fill=False, color="C3", lw=2,
                                                label=f"Hertz contact patch, {2 * a / MM:.1f} × {2 * b / MM:.1f} mm")))
            said += f": the patch is {2 * a / MM / cell:.2g} cells long"
        ax.set_xlim(-span, span)
        ax.set_aspect("equal")
        ax.set(ylabel="lateral (mm)", title=said,
               xlabel=f"along the tread from the deepest cell at {np.degrees(deepest):.0f} deg (mm), to scale")
    fig.colorbar(image, ax=list(axes), label=f"removed depth ({unit})", shrink=0.6)
    fig.legend(handles=handles, loc="outside lower center", ncol=2, fontsize="small", facecolor="0.85")
    fig.suptitle(title)
    return fig


def track_receptance(ds):
    """The rail receptance over frequency (magnitude and phase) with the wheel's normal-force
    transfer, the P2 and pinned-pinned frequencies marked (:func:`railwear.analysis.track_receptance`)."""
    fig, (top, middle, bottom) = _figure(7.5, 8.0, rows=3)
    f = ds.frequency.values
    for style, position in zip(("-", "--", ":"), ds.position.values):
        label = {"sleeper": "above a sleeper"}.get(str(position), str(position))
        top.loglog(f, ds.receptance_magnitude.sel(position=position), style, label=label)
        middle.semilogx(f, ds.receptance_phase.sel(position=position), style, label=label)
    bottom.loglog(f, ds.contact_force_transfer, "k-", label="wheel on the track, bay averaged")
    marks = [("p2_frequency", "P2", "tab:red")] + [("pinned_pinned_frequency", "pinned-pinned", "0.3")] * (
        "pinned_pinned_frequency" in ds)
    for name, label, colour in marks:
        value = float(ds[name])
        for ax in (top, middle, bottom):
            ax.axvline(value, color=colour, lw=0.8, label=f"{label} {value:.0f} Hz" if ax is top else None)
    top.set_ylabel("receptance (m/N)")
    middle.set_ylabel("phase (deg)")
    middle.set_ylim(-180, 0)
    bottom.set_ylabel("|N / u| (N/m)")
    bottom.set_xlabel("frequency (Hz)")
    top.legend(fontsize=8, loc="lower left")
    bottom.legend(fontsize=8, loc="lower right")
    top.set_title(_title(ds, f"rail receptance, {ds.attrs.get('track', '')}"), fontsize=10)
    for ax in (top, middle, bottom):
        ax.grid(True, which="both", alpha=0.3)
    return fig
