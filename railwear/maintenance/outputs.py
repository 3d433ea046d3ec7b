"""What ``railwear plan`` writes besides ``plan.nc``: the text for a person, the comparison and the
turnings as CSV tables, and the figure (layer 4). Everything is read from the plan's Dataset, so
the files can be written again from ``plan.nc``."""

from pathlib import Path

import numpy as np

from railwear import results
from railwear.units import MM

TEXT, TABLE, TURNINGS, FIGURE, HTML = "plan.txt", "plan.csv", "turnings.csv", "plan.png", "plan.html"
def _km(x):
    return f"{x:,.0f}" if np.isfinite(x) else "not scrapped"


def _middle(ds):
    """Index of the growth multiplier the text and the figure detail: 1 if given, else the middle."""
    g = ds.growth.values
    return int(np.argmin(np.abs(g - 1.0))) if np.any(g == 1.0) else g.size // 2


def _band(ds, p, g):
    """``(median, p05, p95)`` of the distance to scrap (km) over the drawn wheels, or None."""
    if "distance_to_scrap_p50" not in ds:
        return None
    return tuple(float(ds[f"distance_to_scrap_{q}"][p, g]) for q in ("p50", "p05", "p95"))


def comparison_rows(ds):
    """One row per policy and growth multiplier: the comparison a planner reads."""
    rows = []
    for p, name in enumerate(ds.policy.values):
        for g, growth in enumerate(ds.growth.values):
            w0 = ds.isel(policy=p, growth=g, wheel=0)
            row = {"policy": str(name), "growth": float(growth), "turnings": int(w0.turnings),
                   "distance_to_scrap_km": float(w0.distance_to_scrap), "km_per_mm_diameter": float(w0.distance_per_mm),
                   "turnings_per_million_km": float(w0.turnings_per_million_km), "end": str(w0.end_reason.values)}
            band = _band(ds, p, g)
            if band is not None:
                drawn = ds.isel(policy=p, growth=g, wheel=slice(1, None))
                row.update({"median_km": band[0], "p05_km": band[1], "p95_km": band[2],
                            "median_turnings": float(np.median(drawn.turnings.values)),
                            "median_km_per_mm": float(np.nanmedian(drawn.distance_per_mm.values))})
            rows.append(row)
    return rows


def _csv(rows):
    head = list(rows[0])
    lines = [",".join(head)]
    for row in rows:
        lines.append(",".join(f"{row[k]:.10g}" if isinstance(row[k], float) else
                              f'"{row[k]}"' if ("," in str(row[k]) or " " in str(row[k])) else str(row[k]) for k in head))
    return "\n".join(lines) + "\n"


def _lateral(ds):
    """Whether the plan ran on a lateral profile (flange triggers, the design profile restored)."""
    return "profile_wear_rate" in ds


FLANGE_COLUMNS = (("flange_height_mm", "flange_height_at_turning"), ("flange_thickness_mm", "flange_thickness_at_turning"),
                  ("flange_gradient_mm", "flange_gradient_at_turning"), ("profile_cut_mm", "profile_cut"))


def turning_rows(ds):
    """One row per turning of every life (with a lateral profile: Sh, Sd, qR before the cut and
    the share of the cut that restores the design profile)."""
    rows = []
    for (p, name) in enumerate(ds.policy.values):
        for g, growth in enumerate(ds.growth.values):
            for w in ds.wheel.values:
                life = ds.isel(policy=p, growth=g, wheel=int(w))
                for k in range(int(life.turnings)):
                    t = life.isel(turning=k)
                    rows.append({"policy": str(name), "growth": float(growth), "wheel": int(w), "turning": k + 1,
                                 "distance_km": float(t.turning_distance), "trigger": str(t.trigger.values),
                                 "peak_to_peak_mm": float(t.peak_to_peak_at_turning) / MM,
                                 "dominant_order": int(t.dominant_order), "cut_mm": float(t.cut_depth) / MM,
                                 "diameter_before_mm": float(t.diameter_before) / MM,
                                 "diameter_after_mm": float(t.diameter_after) / MM, "selected_order": int(t.selected_order)})
                    if _lateral(ds):
                        rows[-1].update({column: float(t[name]) / MM for column, name in FLANGE_COLUMNS})
    return rows


def report(ds):
    """The plan in words: the wheel, the growth band, each policy's life of wheel 0 at growth 1
    (or the middle multiplier) turning by turning, and the comparison."""
    a = ds.attrs
    n = ds.sizes["wheel"] - 1
    w0 = ds.isel(wheel=0)
    lines = [f"plan of {a['scenario_name']}: {a['new_diameter_m'] / MM:g} mm new wheel; wheel 0 at "
             f"{float(w0.speed_kmh):g} km/h, {float(w0.static_load):.4g} kN, friction {float(w0.friction_coefficient):g}"
             + (f"; {n} wheels drawn from [service] (seed {a.get('seed')})" if n else ""),
             a["growth_band"], ""]
    g = _middle(ds)
    growth = float(ds.growth[g])
    for p, name in enumerate(ds.policy.values):
        life = ds.isel(policy=p, growth=g, wheel=0)
        k = int(life.turnings)
        lines.append(f"policy {name}, growth x{growth:g}, wheel 0: {k} turning{'' if k == 1 else 's'}, "
                     + (f"scrapped after {_km(float(life.distance_to_scrap))} km ({life.end_reason.values}"
                        + (f", asked by {life.end_trigger.values}" if "end_trigger" in life and str(life.end_trigger.values)
                           else "")
                        + ") at "
                        f"{float(life.final_diameter) / MM:.1f} mm" if np.isfinite(float(life.distance_to_scrap)) else
                        f"not scrapped within the horizon of {a['horizon_km']:,.0f} km")
                     + (f"; the new wheel selects order {int(life.selected_order_new)}" if not _lateral(ds) else ""))
        if int(life.turnings) and _lateral(ds):
            lines.append("  turning  distance (km)  Sh, Sd, qR before (mm)  cut (mm)  profile's (mm)  diameter (mm)  trigger")
        elif int(life.turnings):
            lines.append("  turning  distance (km)  p-p before (mm)  order  cut (mm)  diameter (mm)    order after  trigger")
        for k in range(int(life.turnings)):
            t = life.isel(turning=k)
            if _lateral(ds):
                flange = ", ".join(f"{float(t[name]) / MM:.2f}" for _, name in FLANGE_COLUMNS[:3])
                lines.append(f"  {k + 1:7d}  {float(t.turning_distance):13,.0f}  {flange:>22}  {float(t.cut_depth) / MM:8.2f}  "
                             f"{float(t.profile_cut) / MM:14.2f}  {float(t.diameter_before) / MM:6.1f} -> "
                             f"{float(t.diameter_after) / MM:5.1f}  {t.trigger.values}")
                continue
            lines.append(f"  {k + 1:7d}  {float(t.turning_distance):13,.0f}  {float(t.peak_to_peak_at_turning) / MM:15.3f}  "
                         f"{int(t.dominant_order):5d}  {float(t.cut_depth) / MM:8.2f}  "
                         f"{float(t.diameter_before) / MM:6.1f} -> {float(t.diameter_after) / MM:5.1f}  "
                         f"{int(t.selected_order):11d}  {t.trigger.values}")
        lines.append("")
    band = "distance to scrap, km: wheel 0" + (f"; median and 5-95 % band over {n} drawn wheels" if n else "")
    lines.append(f"comparison ({band}):")
    head = f"  {'policy':<20} {'growth':>6} {'turnings':>8} {'wheel 0':>12}"
    head += f" {'median':>12} {'5-95 %':>25}" if n else ""
    lines.append(head + f" {'km per mm':>10} {'turnings per 10^6 km':>21}")
    for row in comparison_rows(ds):
        line = f"  {row['policy']:<20} {row['growth']:>6g} {row['turnings']:>8d} {_km(row['distance_to_scrap_km']):>12}"
        if n:
            line += f" {_km(row['median_km']):>12} {_km(row['p05_km']) + ' - ' + _km(row['p95_km']):>25}"
        lines.append(line + f" {row['km_per_mm_diameter']:>10,.0f} {row['turnings_per_million_km']:>21.2f}")
    return "\n".join(lines) + "\n"


def figure(ds):
    """Per policy, wheel 0 at growth 1 (or the middle multiplier): the peak-to-peak deviation (mm)
    over distance with the turnings marked, and the mean diameter (mm) on a second axis; below,
    the distance to scrap of each policy at each growth multiplier (wheel 0, and the median with
    its 5-95 % band over the drawn wheels)."""
    from matplotlib.figure import Figure

    n_p = ds.sizes["policy"]
    fig = Figure(figsize=(8, 2.8 * n_p + 3.2), layout="constrained")
    axes = fig.subplots(n_p + 1, 1, squeeze=False)[:, 0]
    for ax in axes[1:n_p]:
        ax.sharex(axes[0])  # the policies' lives on one distance scale
    g = _middle(ds)
    growth = float(ds.growth[g])
    for p, name in enumerate(ds.policy.values):
        ax = axes[p]
        life = ds.isel(policy=p, growth=g, wheel=0)
        keep = np.isfinite(life.history_distance.values)
        x = life.history_distance.values[keep] / 1e3
        k = int(life.turnings)
        at = life.turning_distance.values[:k] / 1e3
        scrap = float(life.distance_to_scrap)
        ax.set_title(f"{name}: wheel 0 at growth x{growth:g}, "
                     + (f"scrapped after {_km(scrap)} km" if np.isfinite(scrap) else "not scrapped"),
                     pad=50 if _lateral(ds) else 22)  # the flange's legend takes three rows
        if _lateral(ds):
            _flange_panel(ax, ds, life, p, keep, at)
        else:
            ax.plot(x, life.history_peak_to_peak.values[keep] / MM, color="C0", lw=1, label="peak to peak")
            ax.plot(at, life.peak_to_peak_at_turning.values[:k] / MM, "v", color="C3", ms=6,
                    label=f"turning ({k})")
            limit = float(ds.peak_to_peak_limit[p])
            if np.isfinite(limit):
                ax.axhline(limit / MM, color="C3", ls="--", lw=0.8, label=f"trigger {limit / MM:g} mm")
            ax.set_ylabel("peak to peak (mm)")
            top = np.nanmax(life.history_peak_to_peak.values[keep]) / MM
            ax.set_ylim(0, 1.1 * max(top, limit / MM if np.isfinite(limit) else 0))
        right = ax.twinx()
        d = life.history_diameter.values[keep] / MM
        right.plot(x, d, color="C2", lw=1.2, label="mean diameter")
        last = float(ds.last_turning_diameter[p]) / MM
        right.axhline(last, color="C2", ls=":", lw=1, label=f"last-turning diameter {last:g} mm")
        new = float(ds.attrs["new_diameter_m"]) / MM
        right.set_ylim(last - 0.05 * (new - last), new + 0.05 * (new - last))  # the wheel's whole diameter budget
        right.set_ylabel("mean diameter (mm)", color="C2")
        right.tick_params(axis="y", colors="C2")
        handles = ax.get_legend_handles_labels()[0] + right.get_legend_handles_labels()[0]
        ax.legend(handles=handles, fontsize="small", loc="lower left", bbox_to_anchor=(0, 1.0), ncol=len(handles) if len(handles) <= 5 else 4,
                  frameon=False, borderaxespad=0.1, handlelength=1.5, columnspacing=1.0)
        ax.xaxis.set_major_formatter(lambda v, _: f"{v:,.0f}")
        ax.set_xlim(left=0)
    for ax in axes[:n_p - 1]:
        ax.tick_params(labelbottom=False)
    axes[n_p - 1].set_xlabel("distance run (10³ km)")
    ax = axes[-1]
    positions = np.arange(n_p)
    offsets = (np.arange(ds.sizes["growth"]) - (ds.sizes["growth"] - 1) / 2) * 0.12
    for j, growth in enumerate(ds.growth.values):
        x = positions + offsets[j]
        scrap = ds.distance_to_scrap.isel(growth=j, wheel=0).values / 1e6
        ax.plot(x, np.where(np.isfinite(scrap), scrap, np.nan), "o", color=f"C{j}", label=f"growth x{growth:g}, wheel 0")
        if "distance_to_scrap_p50" in ds:
            med, low, high = (ds[f"distance_to_scrap_{q}"].isel(growth=j).values / 1e6 for q in ("p50", "p05", "p95"))
            shown = np.isfinite(med) & np.isfinite(low) & np.isfinite(high)  # a life not scrapped has no distance
            ax.errorbar(x[shown] + 0.04, med[shown], yerr=[med[shown] - low[shown], high[shown] - med[shown]], fmt="s",
                        mfc="none", color=f"C{j}", capsize=3,
                        label=f"growth x{growth:g}, median and 5-95 % of {ds.sizes['wheel'] - 1} wheels")
    ax.set_xticks(positions, [str(n) for n in ds.policy.values])
    ax.set(ylabel="distance to scrap (10⁶ km)", title="distance to scrap by policy and growth multiplier")
    ax.legend(fontsize="small", loc="upper center", bbox_to_anchor=(0.5, -0.12), ncol=2)
    return fig


FLANGE_LINES = (("flange_height", "Sh", "flange_height_max", "C0"), ("flange_thickness", "Sd", "flange_thickness_min", "C1"),
                ("flange_gradient", "qR", "flange_gradient_min", "C4"))


def _flange_panel(ax, ds, life, p, keep, at):
    """Sh, Sd and qR (mm) of wheel 0 over distance, the policy's flange triggers dashed, the turnings
    marked on Sd."""
    for name, label, limit, colour in FLANGE_LINES:
        values = life[f"history_{name}"].values[keep]
        shown = np.isfinite(values)
        ax.plot(life.history_distance.values[keep][shown] / 1e3, values[shown] / MM, color=colour, lw=1, label=label)
        value = float(ds[limit][p])
        if np.isfinite(value):
            ax.axhline(value / MM, color=colour, ls="--", lw=0.8, label=f"{label} trigger {value / MM:g} mm")
    k = at.size
    ax.plot(at, life.flange_thickness_at_turning.values[:k] / MM, "v", color="C3", ms=6, label=f"turning ({k})")
    ax.set_ylabel("flange parameter (mm)")
    top = max(np.nanmax(np.concatenate([life[f"history_{n}"].values[keep] for n, *_ in FLANGE_LINES] + [[0.0]])),
              np.nanmax(np.r_[[float(ds[limit][p]) for _, _, limit, _ in FLANGE_LINES], 0.0]))
    ax.set_ylim(0, 1.12 * top / MM)


def policy_rows(ds):
    """``(policy, description, source)`` of each policy of the plan, from its stored file."""
    import json

    rows = []
    for i, name in enumerate(ds.policy.values):
        stored = json.loads(ds.attrs.get(f"policy_{i}", "{}"))
        rows.append((str(name), stored.get("description", ""), stored.get("source", "")))
    return rows


def _html_value(value):
    if isinstance(value, float):
        return "-" if np.isnan(value) else "not scrapped" if np.isinf(value) else (
            f"{value:,.0f}" if abs(value) >= 1e3 else f"{value:.4g}")
    return str(value)


def draw_figures(ds, directory, fmt="png", dpi=120):
    """``plan.png`` (and its PDF or SVG) in ``directory``; returns the paths."""
    from railwear import plots

    return [plots.save(figure(ds), Path(directory) / FIGURE, fmt, dpi)]


def html_report(ds, path, figures=()):
    """``plan.html``: the plan's text, the comparison, the policies with their sources, wheel 0's
    turnings, the figure embedded and the scenario, in one file; returns its path."""
    from railwear import report as pages

    comparison = comparison_rows(ds)
    keys = list(comparison[0])
    turnings = [r for r in turning_rows(ds) if r["wheel"] == 0]
    blocks = [("p", ds.attrs["growth_band"]), ("h2", "Summary"), ("pre", report(ds)),
              ("h2", f"Comparison (as {TABLE})"), ("table", (keys, [[_html_value(r[k]) for k in keys] for r in comparison])),
              ("h2", "Policies"), ("table", (("policy", "description", "source"), policy_rows(ds)))]
    if turnings:
        head = list(turnings[0])
        blocks += [("h2", f"Turnings of wheel 0 ({len(turnings)}; every life's in {TURNINGS})"),
                   ("table", (head, [[_html_value(r[k]) for k in head] for r in turnings]))]
    title = f"railwear plan: {ds.attrs['scenario_name']} under {', '.join(str(p) for p in ds.policy.values)}"
    return pages.write_page(path, title, blocks, figures, scenario=ds.attrs.get("scenario", ""))


def write(ds, directory, fmt="png", dpi=120, figures=True):
    """``plan.nc``, ``plan.txt``, ``plan.csv``, ``turnings.csv``, ``plan.png`` (with ``figures``)
    and ``plan.html`` (all of it in one file) in ``directory``, each written atomically; returns
    their paths."""
    directory = Path(directory)
    paths = [results.write_netcdf(ds, directory / "plan.nc"), results.write_text(report(ds), directory / TEXT),
             results.write_text(_csv(comparison_rows(ds)), directory / TABLE)]
    rows = turning_rows(ds)
    paths.append(results.write_text(_csv(rows) if rows else "no turning\n", directory / TURNINGS))
    drawn = draw_figures(ds, directory, fmt, dpi) if figures else []
    paths += drawn
    paths.append(html_report(ds, directory / HTML, drawn))
    return paths
