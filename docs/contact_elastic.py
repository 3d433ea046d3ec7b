"""The elastic half-space reference on S1002 / UIC60 (1:40) against railwear's contact models.

Run: python docs/contact_elastic.py [--quick] [--output PATH]
(default figure docs/figures/contact-elastic-y0.png; ``--quick``: coarser grid, fewer shifts, no
sensitivity study).

For each lateral shift the rigid solver of ``contact_table`` gives the wheelset's roll and the
axle drop; from them the vertical gap ``g(y_w)`` across the right wheel's profile (the gap the
semi-Hertzian model samples) is turned into the undeformed separation of a tangent plane:

    h(x, s) = (g(y_w) - g_k + x² / (2 r(y_w))) cos γ_k,    y_w = y_k + s cos γ_k

(``y_k`` the deepest minimum of the region, ``γ_k`` its contact angle, ``r`` the wheel radius at
``y_w``; the rail is straight along ``x``). Minima of the gap whose contact angles differ by less
than ``SAME_PLANE`` share one tangent plane, so the elastic solution there includes the
interaction of their patches (the tread at y = 0). Regions further apart in angle (tread and
flange root) are solved each in its own plane and share the wheel's load through one vertical
approach ``δ_v`` (``Σ N_k cos γ_k = Q``, ``N_k`` at the normal approach ``(δ_v - g_k) cos γ_k``), as
the multi-point models do: that neglects the interaction between those patches. The normal
problem of each plane is solved by :func:`railwear.contact.halfspace_contact`.
"""

import argparse
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from railwear.contact import halfspace_contact
from railwear.contact.halfspace import _patch
from railwear.contact.semi_hertz import hertz_matched_factors
from railwear.geometry import contact_table, gauge_point, load_profile
from railwear.geometry.contact_geometry import _gap

SETUP = dict(gauge=1.435, cant=1.0 / 40.0, back_to_back=1.360, axle_load=133.4e3, rolling_radius=0.46,
             taping_line_offset=0.070, gauge_depth=0.014, youngs_modulus=2.1e11, poisson=0.28)
TREAD_SHIFTS = (-3.0, -1.0, 0.0, 1.0, 3.0)  # mm
FLANGE_SHIFTS = (4.4, 4.6, 4.8, 4.9, 5.0, 5.1, 5.3)  # mm, tread and flange sharing
QUICK_SHIFTS = (0.0, 4.9)
MODELS = ("hertz", "multi-hertz", "semi-hertzian")
SAME_PLANE = 0.07  # rad: minima closer than this in contact angle share one tangent plane
LIMIT = 0.2e-3  # m: a region's window ends where the gap exceeds its minimum by this
HALF_LENGTH = 9.6e-3  # m: half the window along rolling
STEP, QUICK_STEP = 0.1e-3, 0.3e-3  # element size (both directions)
PUBLISHED = (5.95e-3, 6.65e-3)  # the published single patch at y = 0, 66.7 kN (a, b)
SENSITIVITY = {"gauge 1.434 m": dict(gauge=1.434), "gauge 1.436 m": dict(gauge=1.436),
               "rail 1:30": dict(cant=1.0 / 30.0), "rail 1:20": dict(cant=1.0 / 20.0),
               "wheel radius 0.43 m": dict(rolling_radius=0.43), "wheel radius 0.50 m": dict(rolling_radius=0.50)}


@dataclass
class Region:
    """One tangent plane: reference minimum (wheel y [m], gap [m], contact angle [rad]), its grid
    and separation, and after solving the half-space result."""

    y_ref: float
    gap: float
    angle: float
    x: np.ndarray
    s: np.ndarray
    h: np.ndarray
    result: object = None
    watersheds: list = None

    def wheel_y(self, s):
        return self.y_ref + np.asarray(s) * np.cos(self.angle)


class Wheel:
    """The right wheel over its rail at one shift of one set-up (``SETUP`` with changes)."""

    def __init__(self, setup, y, table):
        self.setup, self.y = setup, y
        self.wheel, rail = load_profile("S1002"), load_profile("UIC60")
        self.rail = rail.canted(setup["cant"])
        self.yr0 = 0.5 * setup["gauge"] - gauge_point(self.rail, setup["gauge_depth"])
        self.yw0 = 0.5 * setup["back_to_back"] + setup["taping_line_offset"]
        self.wx, self.wc = (np.ascontiguousarray(a, dtype=float) for a in self.wheel.spline_coefficients())
        self.rx, self.rc = (np.ascontiguousarray(a, dtype=float) for a in self.rail.spline_coefficients())
        d = table.sel(y=y, method="nearest").sel(side="right")
        self.theta, self.drop = float(d.roll_angle), float(d.axle_z)
        self.load = 0.5 * setup["axle_load"]

    def gap(self, yw):
        """Vertical gap [m] under the wheel profile points ``yw`` [m] (0 at the rigid contact)."""
        c, s, r0 = np.cos(self.theta), np.sin(self.theta), self.setup["rolling_radius"]
        return np.array([_gap(v, 1.0, self.y, c, s, 1.0, 0.0, self.wx, self.wc, self.rx, self.rc, self.yw0,
                              self.yr0, r0) for v in np.atleast_1d(yw)]) - self.drop

    def angle(self, yw):
        """Contact angle [rad] of the rail under the wheel profile points ``yw`` [m]."""
        r0 = self.setup["rolling_radius"]
        yr = self.y + (self.yw0 + yw) * np.cos(self.theta) - (r0 + self.wheel(yw)) * np.sin(self.theta) - self.yr0
        return -np.arctan(self.rail.slope(yr))

    def regions(self, step, single=False):
        """The tangent-plane regions of this wheel (module docstring), deepest first; ``single``:
        one plane for all minima, at the mean of their contact angles. Each region keeps the
        watersheds (wheel y [m]) between the minima inside it, where its load is split."""
        lo, hi = self.wheel.span
        yw = np.arange(lo + 1e-4, hi - 1e-4, 0.05e-3)
        g = self.gap(yw)
        inner = np.flatnonzero((g[1:-1] <= g[:-2]) & (g[1:-1] < g[2:])) + 1
        inner = inner[(g[inner] < LIMIT) & (g[inner] > -1e-6)]
        gamma = self.angle(yw[inner])
        sheds = [inner[k] + int(np.argmax(g[inner[k]:inner[k + 1] + 1])) for k in range(inner.size - 1)]
        groups = [[0]]  # minima ordered along the profile, grouped by contact angle
        for k in range(1, inner.size):
            if single or abs(gamma[k] - gamma[k - 1]) < SAME_PLANE:
                groups[-1].append(k)
            else:
                groups.append([k])
        cuts = [0] + [sheds[grp[-1]] for grp in groups[:-1]] + [yw.size - 1]
        out = []
        for k, members in enumerate(groups):
            ref = inner[members[int(np.argmin(g[inner[members]]))]]
            window = np.arange(cuts[k], cuts[k + 1] + 1)
            window = window[g[window] < g[ref] + LIMIT]
            if window.size < 5:  # a sliver between two watersheds: nothing to solve
                continue
            y0 = yw[ref]
            gam = float(np.mean(gamma[members])) if single else float(self.angle(yw[ref]))
            c = np.cos(gam)
            s = np.arange(np.floor((yw[window[0]] - y0) / c / step), np.ceil((yw[window[-1]] - y0) / c / step) + 1) * step
            n = int(round(HALF_LENGTH / step))
            x = (np.arange(2 * n) - n + 0.5) * step
            ys = y0 + s * c
            radius = self.setup["rolling_radius"] + self.wheel(ys)
            gs = self.gap(ys)
            gs = np.where(np.isfinite(gs), gs, 1.0)  # no rail under these points: far apart
            h = ((gs - g[ref])[None, :] + x[:, None] ** 2 / (2.0 * radius[None, :])) * c
            region = Region(y0, float(g[ref]), gam, x, s, h)
            region.watersheds = [float(yw[sheds[m]]) for m in members[:-1]]
            out.append(region)
        return sorted(out, key=lambda r: r.gap)

    def solve(self, step, single=False):
        """Solve the elastic reference; returns (regions with results, vertical approach [m])."""
        regions = self.regions(step, single)
        E, nu = self.setup["youngs_modulus"], self.setup["poisson"]
        if len(regions) == 1:
            r = regions[0]
            r.result = halfspace_contact(r.x, r.s, r.h, self.load / np.cos(r.angle), E, nu)
            return regions, r.gap + r.result.approach / np.cos(r.angle)
        warm = {}

        def vertical(dv):
            total = 0.0
            for k, r in enumerate(regions):
                d = (dv - r.gap) * np.cos(r.angle)
                start = warm.get(k)
                r.result = halfspace_contact(r.x, r.s, r.h, approach=d, youngs_modulus=E, poisson=nu,
                                             initial_pressure=start if start is not None and start.any() else None)
                warm[k] = r.result.pressure
                total += r.result.normal_force * np.cos(r.angle)
            return total

        # secant on the 2/3 power of the vertical force (nearly linear in the approach)
        target = self.load ** (2.0 / 3.0)
        d0 = regions[0].gap + 1e-5
        f0 = vertical(d0) ** (2.0 / 3.0) - target
        d1 = regions[0].gap + 1e-4
        f1 = vertical(d1) ** (2.0 / 3.0) - target
        for _ in range(30):
            d2 = d1 - f1 * (d1 - d0) / (f1 - f0)
            d0, f0 = d1, f1
            d1 = max(d2, regions[0].gap + 1e-7)
            f1 = vertical(d1) ** (2.0 / 3.0) - target
            if abs(f1) < 1e-9 * target:
                break
        return regions, d1


def elastic_patches(regions, load):
    """The loaded parts of the regions' patches: each connected patch, split at the watersheds
    between the gap's minima inside its region (the models' split), as dicts with the wheel y of
    the load centroid and edges [m], vertical load share, half-length a and half-width b [m] in
    its plane, peak pressure p0 [Pa], ``patch`` the connected patch it belongs to (numbered over
    the wheel) and ``border`` whether it reaches its window's border (a cut between regions)."""
    out, count = [], 0
    for r in regions:
        res = r.result
        if res.normal_force <= 0.0:
            continue
        border = bool(res.contact[0].any() or res.contact[-1].any() or res.contact[:, 0].any()
                      or res.contact[:, -1].any())
        yw = r.wheel_y(res.s)
        edges = [-np.inf] + sorted(r.watersheds) + [np.inf]
        for whole in res.patches():
            inside = (res.s >= whole.s_min) & (res.s <= whole.s_max)
            for lo, hi in zip(edges[:-1], edges[1:]):
                keep = res.contact & (inside & (yw > lo) & (yw <= hi))[None, :]
                if not np.any(res.pressure[keep] > 0.0):
                    continue
                p = _patch(res, keep)
                out.append(dict(y=float(r.wheel_y(p.centroid_s)), lo=float(r.wheel_y(p.s_min)),
                                hi=float(r.wheel_y(p.s_max)), share=p.normal_force * np.cos(r.angle) / load,
                                a=p.half_length, b=p.half_width, p0=p.p0, angle=r.angle, border=border, patch=count))
            count += 1
    return sorted(out, key=lambda p: -p["share"])


def whole_patches(regions):
    """The connected patches of the regions: (wheel y of the edges [m], half-length, half-width [m])."""
    out = []
    for r in regions:
        if r.result.normal_force > 0.0:
            out += [(float(r.wheel_y(p.s_min)), float(r.wheel_y(p.s_max)), p.half_length, p.half_width)
                    for p in r.result.patches()]
    return out


def model_points(tables, y, load):
    """The loaded contacts of each railwear model at shift ``y`` (right wheel), same keys as
    :func:`elastic_patches` (a: half-length along rolling, b: half-width)."""
    out = {}
    for model, t in tables.items():
        d = t.sel(y=y, method="nearest").sel(side="right")
        if model == "hertz":
            N, a, b = float(d.normal_force), float(d.a), float(d.b)
            out[model] = [dict(y=float(d.wheel_contact_y), share=N * np.cos(float(d.contact_angle)) / load, a=a, b=b,
                               p0=1.5 * N / (np.pi * a * b))]
            continue
        pts = []
        for k in np.flatnonzero(d.point_normal_force.values > 0):
            N, gam = float(d.point_normal_force[k]), float(d.point_contact_angle[k])
            a = float(d.point_half_length[k]) if model == "semi-hertzian" else float(d.point_a[k])
            pts.append(dict(y=float(d.point_wheel_y[k]), share=N * np.cos(gam) / load, a=a, b=float(d.point_b[k]),
                            p0=float(d.point_p0[k])))
        out[model] = sorted(pts, key=lambda p: -p["share"])
    return out


def tables_for(setup, shifts):
    """contact_table of each model at the shifts [m] for the set-up."""
    wheel, rail = load_profile("S1002"), load_profile("UIC60")
    return {m: contact_table(wheel, rail, y=np.asarray(shifts), contact_model=m, **setup) for m in MODELS}


def _match(elastic, points):
    """The model point nearest each elastic patch (by load centroid), or None."""
    out = []
    for e in elastic:
        near = min(points, key=lambda p: abs(p["y"] - e["y"])) if points else None
        out.append(near if near is not None and abs(near["y"] - e["y"]) < 6e-3 else None)
    return out


def compare(quick=False):
    """Solve the reference at the shifts and compare; returns a dict of results and timings."""
    step = QUICK_STEP if quick else STEP
    shifts = np.round(np.array(QUICK_SHIFTS if quick else TREAD_SHIFTS + FLANGE_SHIFTS) * 1e-3, 12)
    tables = tables_for(SETUP, shifts)
    rows = []
    for y in shifts:
        wheel = Wheel(SETUP, y, tables["hertz"])
        models = model_points(tables, y, wheel.load)
        for single in (False, True):
            start = time.perf_counter()
            regions, dv = wheel.solve(step, single)
            seconds = time.perf_counter() - start
            if single and len(regions) == 1 and len(rows[-1]["regions"]) == 1:
                break  # one plane already
            rows.append(dict(y=float(y), planes="one" if len(regions) == 1 else "own", regions=regions, approach=dv,
                             seconds=seconds, elastic=elastic_patches(regions, wheel.load), models=models,
                             whole=whole_patches(regions), iterations=sum(r.result.iterations for r in regions),
                             wheel=wheel))
    return dict(rows=rows, tables=tables, step=step)


def _fmt_patch(p):
    return f"{p['y'] * 1e3:.1f} mm: {100 * p['share']:.0f} %, {p['a'] * 1e3:.2f} x {p['b'] * 1e3:.2f} mm, {p['p0'] / 1e6:.0f} MPa"


def reference_table(res):
    lines = ["| y [mm] | planes | connected patches (wheel y of the edges, a x b) | their parts either side of the "
             "gap's watersheds (load centroid: vertical load share, a x b, p0) | vertical approach [um] | time [s] |",
             "|---|---|---|---|---|---|"]
    for r in res["rows"]:
        whole = "; ".join(f"{lo * 1e3:.1f} .. {hi * 1e3:.1f} mm, {a * 1e3:.2f} x {b * 1e3:.2f} mm"
                          for lo, hi, a, b in r["whole"])
        patches = "; ".join(_fmt_patch(p) for p in r["elastic"])
        flag = " (reaches the cut between the planes)" if any(p["border"] for p in r["elastic"]) else ""
        lines.append(f"| {r['y'] * 1e3:+.1f} | {r['planes']} | {whole}{flag} | {patches} | {r['approach'] * 1e6:.1f} | "
                     f"{r['seconds']:.2f} |")
    return "\n".join(lines)


def error_table(res):
    """Per shift and model: patches carrying load (model / elastic), and for the main elastic
    patch and the second one the model's share difference and a, b, p0 errors."""
    lines = ["| y [mm] | planes | model | parts | main: share | a | b | p0 | second: share | a | b | p0 |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in res["rows"]:
        el = r["elastic"][:2]
        for model in MODELS:
            pts = r["models"][model]
            cells = []
            for e, m in zip(el, _match(el, pts)):
                if m is None:
                    cells += [f"{-100 * e['share']:+.0f} pp (none)", "-", "-", "-"]
                else:
                    cells += [f"{100 * (m['share'] - e['share']):+.1f} pp", f"{100 * (m['a'] / e['a'] - 1):+.0f} %",
                              f"{100 * (m['b'] / e['b'] - 1):+.0f} %", f"{100 * (m['p0'] / e['p0'] - 1):+.0f} %"]
            cells += ["", "", "", ""][: 8 - len(cells)]
            lines.append(f"| {r['y'] * 1e3:+.1f} | {r['planes']} | {model} | {len(pts)} / {len(r['elastic'])} | "
                         + " | ".join(cells) + " |")
    return "\n".join(lines)


def sensitivity(step):
    """The elastic reference at y = 0 for changed set-ups (``SENSITIVITY``): lines of text."""
    lines = ["| set-up at y = 0 | connected patches (wheel y of the edges, a x b) | their parts (load centroid: share, "
             "a x b, p0) | gaps of the rigid minima [um] |", "|---|---|---|---|"]
    for label, change in {"as the table (1.435 m, 1:40, 0.46 m)": {}, **SENSITIVITY}.items():
        setup = {**SETUP, **change}
        t = tables_for(setup, [0.0])
        wheel = Wheel(setup, 0.0, t["hertz"])
        regions, _ = wheel.solve(step)
        patches = "; ".join(_fmt_patch(p) for p in elastic_patches(regions, wheel.load))
        whole = "; ".join(f"{lo * 1e3:.1f} .. {hi * 1e3:.1f} mm, {a * 1e3:.2f} x {b * 1e3:.2f} mm"
                          for lo, hi, a, b in whole_patches(regions))
        pts = t["semi-hertzian"].sel(y=0.0, side="right")
        gaps = pts.point_gap.values[np.isfinite(pts.point_gap.values) & (pts.point_gap.values < LIMIT)]
        lines.append(f"| {label} | {whole} | {patches} | {', '.join(f'{g * 1e6:.1f}' for g in gaps)} |")
    return "\n".join(lines)


def semi_outline(row, tables, step=0.05e-3):
    """Outline of each semi-Hertzian patch of the table at the row's shift, rebuilt from its
    virtual penetration ratio and patch curvature on this script's gap: list of (wheel y [m],
    half-length L(y) [m]) and the table's lateral edges and largest half-length."""
    wheel = row["wheel"]
    d = tables["semi-hertzian"].sel(y=row["y"], method="nearest").sel(side="right")
    out = []
    for k in np.flatnonzero(d.point_normal_force.values > 0):
        gam = float(d.point_contact_angle[k])
        c = np.cos(gam)
        eps, curvature = float(d.point_virtual_penetration_ratio[k]), float(d.point_patch_curvature[k])
        lo, hi = float(d.point_lateral_min[k]), float(d.point_lateral_max[k])
        yw = np.arange(lo - 1e-3, hi + 1e-3, step)
        g = wheel.gap(yw)
        ref = float(np.min(g[(yw >= lo) & (yw <= hi)]))
        approach = (float(d.vertical_approach) - float(d.point_gap[k])) * c
        radius = wheel.setup["rolling_radius"] + wheel.wheel(yw)
        _, a_corr = hertz_matched_factors(c / (2.0 * radius.mean()), curvature)
        L = np.sqrt(np.clip((eps * approach - (g - ref) * c) / float(a_corr), 0.0, None))
        L[(yw < lo) | (yw > hi)] = 0.0
        out.append(dict(y=yw, L=L, lo=lo, hi=hi, half_length=float(d.point_half_length[k]), p0=float(d.point_p0[k])))
    return out


def figure(res, output):
    """Pressure map of the elastic reference at y = 0 with the semi-Hertzian patch outlines, and
    the pressure along the line x = 0."""
    import matplotlib

    matplotlib.use("agg")
    import matplotlib.pyplot as plt

    row = next(r for r in res["rows"] if r["y"] == 0.0 and r["planes"] == "one")
    (region,) = row["regions"]
    rr = region.result
    yw = region.wheel_y(rr.s) * 1e3
    fig, (ax, bx) = plt.subplots(2, 1, figsize=(7.6, 7.4), height_ratios=(2.2, 1.0), sharex=True,
                                 constrained_layout=True)
    p = np.ma.masked_equal(rr.pressure, 0.0) / 1e6
    mesh = ax.pcolormesh(yw, rr.x * 1e3, p, cmap="viridis", shading="nearest")
    fig.colorbar(mesh, ax=ax, label="elastic contact pressure [MPa]")
    ax.contour(yw, rr.x * 1e3, rr.contact.astype(float), levels=[0.5], colors="k", linewidths=1.0)
    ax.plot([], [], "k-", lw=1.0, label="elastic patch edge (half-space)")
    outlines = semi_outline(row, res["tables"])
    for k, o in enumerate(outlines):
        m = o["L"] > 0
        yy = np.concatenate((o["y"][m], o["y"][m][::-1], o["y"][m][:1])) * 1e3
        xx = np.concatenate((o["L"][m], -o["L"][m][::-1], o["L"][m][:1])) * 1e3
        ax.plot(yy, xx, "r--", lw=1.4, label="semi-hertzian patch outline" if k == 0 else None)
    a, b = PUBLISHED
    centre = row["elastic"][0]["y"] * 1e3
    t = np.linspace(0, 2 * np.pi, 200)
    ax.plot(centre + b * 1e3 * np.cos(t), a * 1e3 * np.sin(t), ":", color="orange", lw=1.6,
            label="published 5.95 x 6.65 mm ellipse (at the elastic centroid)")
    (lo_, hi_, a_, b_), = row["whole"][:1]
    semi = res["tables"]["semi-hertzian"].sel(y=0.0, side="right")
    shares = semi.point_normal_force.values * np.cos(np.nan_to_num(semi.point_contact_angle.values)) / (0.5 * SETUP["axle_load"])
    ax.text(0.98, 0.97, f"elastic: {len(row['whole'])} connected patch, {a_ * 1e3:.2f} x {b_ * 1e3:.2f} mm\n"
            f"semi-hertzian: {int((shares > 0).sum())} patches, "
            + " / ".join(f"{100 * v:.0f}" for v in shares[shares > 0]) + " % of the load",
            transform=ax.transAxes, ha="right", va="top", fontsize=8,
            bbox=dict(facecolor="white", edgecolor="0.7", alpha=0.9))
    ax.set_ylabel("x along rolling [mm]")
    ax.set_title("S1002 / UIC60 1:40, y = 0, 66.7 kN per wheel: elastic half-space reference")
    ax.legend(loc="lower left", fontsize=8, framealpha=0.9)
    lo, hi = min(w[0] for w in row["whole"]) * 1e3, max(w[1] for w in row["whole"]) * 1e3
    ax.set_xlim(lo - 3.0, hi + 3.0)
    ax.set_ylim(-8.5, 8.5)
    i0 = int(np.argmin(np.abs(rr.x)))
    bx.plot(yw, rr.pressure[i0] / 1e6, "k-", lw=1.4, label="elastic half-space, x = 0")
    for k, o in enumerate(outlines):
        m = o["L"] > 0
        L0 = np.interp(o["y"][m][np.argmax(o["L"][m])], o["y"], o["L"])
        bx.plot(o["y"][m] * 1e3, o["p0"] * o["L"][m] / L0 / 1e6, "r--", lw=1.4,
                label="semi-hertzian, x = 0" if k == 0 else None)
    d = res["tables"]["multi-hertz"].sel(y=0.0, side="right")
    for k in np.flatnonzero(d.point_normal_force.values > 0):
        c, bb, p0 = float(d.point_wheel_y[k]) * 1e3, float(d.point_b[k]) * 1e3, float(d.point_p0[k]) / 1e6
        yy = np.linspace(c - bb, c + bb, 200)
        bx.plot(yy, p0 * np.sqrt(np.clip(1 - ((yy - c) / bb) ** 2, 0, None)), ":", color="tab:blue", lw=1.4,
                label="multi-hertz, x = 0" if k == 0 else None)
    bx.set_xlabel("lateral position on the wheel profile [mm] (towards the field side)")
    bx.set_ylabel("pressure [MPa]")
    bx.legend(loc="upper right", fontsize=8)
    bx.grid(alpha=0.3)
    fig.savefig(output, dpi=120)
    plt.close(fig)
    return outlines


def main(quick=False, output=None, out=sys.stdout):
    res = compare(quick)
    print(f"element {res['step'] * 1e3:.2f} mm x {res['step'] * 1e3:.2f} mm", file=out)
    print(reference_table(res), file=out)
    print(file=out)
    print(error_table(res), file=out)
    if not quick:
        print(file=out)
        print(sensitivity(res["step"]), file=out)
    if output is not None:
        res["outlines"] = figure(res, output)
    return res


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--output", type=Path, default=Path(__file__).parent / "figures" / "contact-elastic-y0.png")
    args = parser.parse_args()
    main(args.quick, args.output)
