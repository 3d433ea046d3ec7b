"""Kalker's exact rolling contact on S1002 / UIC60 (1:40) against railwear's FASTSIM paths.

Run: python docs/contact_rolling.py [--quick] [--output PATH]
(default figure docs/figures/contact-rolling-y0.png; ``--quick``: y = 0 only, one creepage,
0.4 mm elements, no convergence study).

The normal pressure is the elastic half-space reference of ``docs/contact_elastic.py`` (its
geometry, tangent planes and load sharing, imported from it). On each plane
:func:`railwear.contact.rolling_contact` solves the tangential problem with the rigid slip of the
wheel (:func:`kinematics`, the same for every path): the axle turns at ``Ω = (1 - ξ0) V / r0``
(ξ0 at the deepest minimum of the main region, radius r0), so a strip of rolling radius ``r(s)``
has the longitudinal creepage ``ξ(s) = 1 - Ω r(s) / V``, and the plane of contact angle γ the
spin ``φ = -Ω sin γ / V``. The solvers' rigid slip is ``(ξ_s - φ s, η + φ x)``, and the spin's
longitudinal term ``-φ s`` is already the first-order part of the radius change (on a cone all of
it), so every strip is given ``ξ_s = ξ(s) + φ s``: the longitudinal rigid slip is then the exact
``ξ(s)``, counted once. railwear's ellipse paths get FASTSIM's kinematics at their own points
(``ξ_i = 1 - Ω r_i / V`` uniform on the ellipse, ``φ_i = -Ω sin γ_i / V``):

- (a) hertz: the single Hertz point of ``contact_table`` with FASTSIM on its ellipse;
- (b) multi-hertz and semi-hertzian: every contact of ``contact_table(..., contact_model=...)``
  with FASTSIM on its (equivalent) ellipse;
- (c) FASTSIM strip by strip on the elastic patch itself (Kik and Piotrowski's way: the traction
  bound is μ times the elastic pressure of the strip, the flexibilities those of the patch's
  equivalent ellipse, same area and width), with the exact solution's ``ξ_s`` and φ (the
  dynamics' ``creep_law = "strip-fastsim"`` rule: on a cone exactly FASTSIM's uniform ξ and spin);
- (d) the same on the semi-hertzian patches (each rebuilt from the table's virtual penetration
  and patch curvature, pressure semi-elliptic along every strip and carrying the point's load).

Compared per tangent plane: the resultant tangential force |F|, Fx, Fy, the spin moment Mz
about each solution's own normal-load centroid (so a lever arm between two models' centres does
not enter), and the frictional power per unit rolling speed (W per m/s): FASTSIM's local sum,
and for the exact solution the rigid slip work ``-Σ p · w dA``, which the local sum
``Σ |p| |s| dA`` equals in the limit (the nearer of the two on these grids).
"""

import argparse
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from contact_elastic import SETUP, Wheel, semi_outline, tables_for  # noqa: E402  (the geometry)

from railwear.contact import fastsim, rolling_contact  # noqa: E402
from railwear.contact.strip_fastsim import strip_fastsim, strip_fastsim_grid  # noqa: E402

MU = 0.3
E, NU = SETUP["youngs_modulus"], SETUP["poisson"]
G = E / (2.0 * (1.0 + NU))
CASES = {"xi = eta = 1e-3 + spin": (1e-3, 1e-3, False), "xi = eta = 4e-3 + spin": (4e-3, 4e-3, False)}
# Kalker's planar kinematics (xi uniform, the radius change across the plane only through the
# spin of its angle, i.e. linearised), at y = 0 only: how much of the difference is the wide
# patch's profile curvature (the radius change beyond first order)
PLANAR = {"xi = eta = 1e-3, planar": (1e-3, 1e-3, True)}
SHIFTS, QUICK_SHIFTS = (-3.0, 0.0, 3.0, 5.0), (0.0,)  # mm
STEP, QUICK_STEP = 0.2e-3, 0.4e-3
CONVERGENCE = (0.4e-3, 0.2e-3, 0.1e-3)
PATHS = ("exact", "hertz", "multi-hertz", "semi-hertzian", "strip elastic", "strip semi-hertzian")


def kinematics(xi0, r0, radius, s, angle):
    """The rigid slip of the wheel on a plane of contact angle ``angle`` [rad], for every path:
    ``(ξ_s, φ)`` for the solvers' ``(ξ_s - φ s, η + φ x)``, ``radius`` [m] the rolling radius of the
    strips at ``s`` [m] (arrays, or one point at ``s = 0``), ``xi0`` the creepage at radius ``r0``.

    The axle's one angular speed ``Ω / V = (1 - ξ0) / r0`` gives each strip ``ξ(s) = 1 - Ω r(s) / V``
    and the plane the spin ``φ = -Ω sin γ / V``. The spin's longitudinal term ``-φ s`` is the axle's
    rotation seen in the plane, i.e. the first-order part of that same radius change (on a cone,
    ``r(s) = r(0) - s sin γ``, all of it), so it is taken out of the strip's creepage,
    ``ξ_s = ξ(s) + φ s``, and left to the spin term, as the dynamics' ``creep_law = "strip-fastsim"``
    does (``railwear.dynamics.kernels._strip_point``). Of the two consistent forms this is the one
    every solver can take: the exact solver then sees the longitudinal slip ``ξ(s)`` itself (the
    other form, exact ``ξ(s)`` with only the lateral spin term ``φ x``, is the same rigid slip to
    round-off), and FASTSIM, which applies the spin with its own flexibility ``L3`` along and
    across, gets on a cone exactly its uniform ξ and full spin, so that strip-wise and ellipse
    FASTSIM differ only by the patch and the profile's curvature, not by kinematics."""
    omega = (1.0 - xi0) / r0
    phi = -omega * np.sin(angle)
    return 1.0 - omega * np.asarray(radius, dtype=float) + phi * np.asarray(s, dtype=float), phi


def _totals(x, s, pressure, px, py, power):
    """Fx, Fy, |F|, Mz about the normal-load centroid, normal force, power of a grid solution."""
    cell = (x[1] - x[0]) * (s[1] - s[0])
    N = pressure.sum() * cell
    xc, sc = (pressure.sum(1) @ x) * cell / N, (pressure.sum(0) @ s) * cell / N
    Fx, Fy = px.sum() * cell, py.sum() * cell
    Mz = np.sum((x[:, None] - xc) * py - (s[None, :] - sc) * px) * cell
    return dict(Fx=Fx, Fy=Fy, F=np.hypot(Fx, Fy), Mz=Mz, N=N, P=power)


def _points(tables, model, y):
    """Loaded contacts of a model at shift y: dicts of wheel y, N, a, b, angle, radius."""
    d = tables[model].sel(y=y, method="nearest").sel(side="right")
    if model == "hertz":
        return [dict(y=float(d.wheel_contact_y), N=float(d.normal_force), a=float(d.a), b=float(d.b),
                     angle=float(d.contact_angle), radius=float(d.rolling_radius), k=0)]
    return [dict(y=float(d.point_wheel_y[k]), N=float(d.point_normal_force[k]), a=float(d.point_a[k]),
                 b=float(d.point_b[k]), angle=float(d.point_contact_angle[k]),
                 radius=float(d.point_rolling_radius[k]), k=int(k))
            for k in np.flatnonzero(d.point_normal_force.values > 0)]


def _region_of(regions, yw):
    """Index of the region whose window on the wheel holds yw (else the nearest)."""
    spans = [(r.wheel_y(r.s[0]), r.wheel_y(r.s[-1])) for r in regions]
    inside = [k for k, (lo, hi) in enumerate(spans) if min(lo, hi) <= yw <= max(lo, hi)]
    return inside[0] if inside else int(np.argmin([abs(r.y_ref - yw) for r in regions]))


def _ellipse_paths(points, region, xi0, r0, eta, planar=None):
    """FASTSIM on each point's ellipse with its own creepages (:func:`kinematics` at the point's
    radius and angle: uniform ξ_i and the spin φ_i), summed in the region's plane (``planar``:
    ``(ξ_ref, φ)`` of the plane, Kalker's planar kinematics, ξ_ref - φ s at the point and the
    plane's φ)."""
    if not points:
        return None
    out = []
    for p in points:
        s = (p["y"] - region.y_ref) / np.cos(region.angle)
        if planar is None:
            xi, phi = kinematics(xi0, r0, p["radius"], 0.0, p["angle"])
        else:
            xi, phi = planar[0] - planar[1] * s, planar[1]
        f = fastsim(p["a"], p["b"], p["N"], xi, eta, phi, MU, G, NU)
        out.append((p, f, s))
    N = sum(p["N"] for p, _, _ in out)
    sc = sum(p["N"] * s for p, _, s in out) / N
    Fx, Fy = sum(f.Fx for _, f, _ in out), sum(f.Fy for _, f, _ in out)
    Mz = sum(f.Mz - (s - sc) * f.Fx for _, f, s in out)
    return dict(Fx=Fx, Fy=Fy, F=np.hypot(Fx, Fy), Mz=Mz, N=N, P=sum(f.power_local for _, f, _ in out),
                slip=sum(f.slip_fraction * np.pi * p["a"] * p["b"] for p, f, _ in out)
                / sum(np.pi * p["a"] * p["b"] for p, _, _ in out))


def _semi_strips(region, wheel, tables, y, members):
    """The semi-hertzian patches of the region as strips on its grid's columns: list of
    (columns, half-lengths, point)."""
    outlines = semi_outline(dict(wheel=wheel, y=y), tables)
    out = []
    yw = region.wheel_y(region.s)
    for o, p in zip(outlines, _points(tables, "semi-hertzian", y)):
        if p["k"] not in members:
            continue
        L = np.interp(yw, o["y"], o["L"], left=0.0, right=0.0)
        cols = np.flatnonzero(L > 0)
        if cols.size:
            out.append((cols, L[cols], p))
    return out


def _strip_paths(region, semi, xi, eta, phi):
    """Strip-wise FASTSIM (``railwear.contact.strip_fastsim``) on every semi-hertzian patch of the
    region, summed: totals as ``_totals`` (Mz about the patches' joint load centroid)."""
    ds = region.s[1] - region.s[0]
    res = [(strip_fastsim(region.s[cols], ds, L, p["N"], xi[cols], eta, phi, MU, G, NU, p["a"], p["b"]), cols, L, p)
           for cols, L, p in semi]
    N = sum(p["N"] for _, _, _, p in res)
    sc = sum(np.sum(0.5 * np.pi * L**2 * ds * r.pressure_scale * region.s[cols]) for r, cols, L, _ in res) / N
    Fx, Fy = sum(r.Fx for r, *_ in res), sum(r.Fy for r, *_ in res)
    Mz = sum(r.Mz for r, *_ in res) + sc * Fx
    area = [2.0 * np.sum(L) * ds for _, _, L, _ in res]
    slip = sum(r.slip_fraction * A for (r, *_), A in zip(res, area)) / sum(area)
    return dict(Fx=Fx, Fy=Fy, F=np.hypot(Fx, Fy), Mz=Mz, N=N, P=sum(r.power_local for r, *_ in res), slip=slip)


def solve_shift(y, tables, step, cases):
    """Exact and model paths at shift y [m] for the creepage cases: list of row dicts."""
    wheel = Wheel(SETUP, y, tables["hertz"])
    regions, _ = wheel.solve(step)
    r_nom = SETUP["rolling_radius"]
    r0 = r_nom + float(wheel.wheel(regions[0].y_ref))
    rows = []
    for k, region in enumerate(regions):
        res = region.result
        if res.normal_force <= 0.0:
            continue
        yw = region.wheel_y(res.s)
        radius = r_nom + wheel.wheel(yw)
        on = res.contact
        jj = np.flatnonzero(on.any(0))
        b = 0.5 * (res.s[jj[-1]] - res.s[jj[0]] + (res.s[1] - res.s[0]))
        a = res.area / (np.pi * b)
        members = {m: [p for p in _points(tables, m, y) if _region_of(regions, p["y"]) == k] for m in tables}
        semi = _semi_strips(region, wheel, tables, y, [p["k"] for p in members["semi-hertzian"]])
        for label, (xi0, eta, planar) in cases.items():
            xi, phi = kinematics(xi0, r0, radius, res.s, region.angle)
            if planar:  # ξ uniform in the plane (the plane's own ξ at s = 0), the spin as above
                xi = np.full_like(xi, float(kinematics(xi0, r0, r_nom + float(wheel.wheel(region.y_ref)), 0.0,
                                                       region.angle)[0]))
            start = time.perf_counter()
            ex = rolling_contact(res.x, res.s, res.pressure, xi, eta, phi, MU, G, NU)
            seconds = time.perf_counter() - start
            # the exact power: the rigid slip work (the local sum converges to it from below, the
            # work from above, both at first order; at 0.2 mm the work is the nearer, +1.3 %
            # against -4.5 % at y = 0, see the convergence table)
            paths = {"exact": dict(_totals(res.x, res.s, res.pressure, ex.px, ex.py, ex.power_global),
                                   slip=ex.slip_fraction, P_local=ex.power_local)}
            for m in ("hertz", "multi-hertz", "semi-hertzian"):
                paths[m] = _ellipse_paths(members[m], region, xi0, r0, eta, (xi[0], phi) if planar else None)
            g = strip_fastsim_grid(res.x, res.s, res.pressure, xi, eta, phi, MU, G, NU, a, b)
            paths["strip elastic"] = dict(_totals(res.x, res.s, res.pressure, g.px, g.py, g.power_local),
                                          slip=float((g.slip & on).sum() / on.sum()))
            paths["strip semi-hertzian"] = _strip_paths(region, semi, xi, eta, phi) if semi else None
            rows.append(dict(y=y, region=k, angle=region.angle, case=label, paths=paths, exact=ex, seconds=seconds,
                             elements=int(on.sum()), region_obj=region, wheel_y=yw, xi=xi, phi=phi, radius=radius,
                             xi0=xi0, r0=r0, planar=planar,
                             share=res.normal_force * np.cos(region.angle) / wheel.load))
    return rows


def table(rows):
    lines = ["| y [mm] | plane (angle, load share) | creepage | path | \\|F\\| [kN] | Fx / Fy [kN] | Mz [N m] | "
             "power [W per m/s] | slip area |", "|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        ref = r["paths"]["exact"]
        for name in PATHS:
            p = r["paths"][name]
            head = (f"| {r['y'] * 1e3:+.1f} | {np.degrees(r['angle']):.1f} deg, {100 * r['share']:.0f} % | {r['case']} | "
                    f"{name} |")
            if p is None:
                lines.append(head + " none | | | | |")
                continue
            d = (lambda k: "" if name == "exact" else f" ({100 * (p[k] / ref[k] - 1):+.0f} %)")  # noqa: E731
            slip = f"{100 * p['slip']:.0f} %" if "slip" in p else ""
            lines.append(head + f" {p['F'] / 1e3:.2f}{d('F')} | {p['Fx'] / 1e3:.2f} / {p['Fy'] / 1e3:.2f} | "
                         f"{p['Mz']:.2f}{d('Mz')} | {p['P']:.2f}{d('P')} | {slip} |")
    return "\n".join(lines)


def convergence(tables, case):
    """The exact solution at y = 0 on the grids of CONVERGENCE: lines of a table."""
    lines = ["| element [mm] | elements | \\|F\\| [kN] | Mz [N m] | power local / global [W per m/s] | slip area | "
             "Newton / GMRES steps | time [s] |", "|---|---|---|---|---|---|---|---|"]
    out = []
    for step in CONVERGENCE:
        (r,) = solve_shift(0.0, tables, step, {case: CASES[case]})
        ex, p = r["exact"], r["paths"]["exact"]
        out.append((step, p, ex))
        lines.append(f"| {step * 1e3:.1f} | {r['elements']} | {p['F'] / 1e3:.3f} | {p['Mz']:.3f} | "
                     f"{ex.power_local:.2f} / {ex.power_global:.2f} | {100 * ex.slip_fraction:.1f} % | "
                     f"{ex.iterations} / {ex.krylov_iterations} | {r['seconds']:.1f} |")
    return "\n".join(lines), out


def figure(row, output):
    """Traction and slip at y = 0: |p| with arrows and the adhesion area; frictional power density."""
    import matplotlib

    matplotlib.use("agg")
    import matplotlib.pyplot as plt

    ex, region = row["exact"], row["region_obj"]
    yw = row["wheel_y"] * 1e3
    xx = ex.x * 1e3
    on = ex.pressure > 0
    fig, (ax, bx) = plt.subplots(2, 1, figsize=(7.8, 8.0), sharex=True, constrained_layout=True)
    t = np.ma.masked_where(~on, ex.traction / 1e6)
    mesh = ax.pcolormesh(yw, xx, t, cmap="viridis", shading="nearest")
    fig.colorbar(mesh, ax=ax, label="tangential traction |p| [MPa]")
    ax.contour(yw, xx, on.astype(float), levels=[0.5], colors="k", linewidths=1.0)
    ax.contourf(yw, xx, ex.adhesion.astype(float), levels=[0.5, 1.5], colors="none", hatches=["///"])
    ax.contour(yw, xx, ex.adhesion.astype(float), levels=[0.5], colors="w", linewidths=1.2)
    k = max(1, int(round(0.8e-3 / (ex.x[1] - ex.x[0]))))
    sub = (slice(k // 2, None, k), slice(k // 2, None, 2 * k))
    Y, X = np.meshgrid(yw, xx)
    m = on[sub]
    # arrows in the plot's axes: lateral traction (py) horizontal, longitudinal (px) vertical
    q = ax.quiver(Y[sub][m], X[sub][m], ex.py[sub][m] / 1e6, ex.px[sub][m] / 1e6, color="w", scale=2500,
                  width=0.003, edgecolor="k", linewidth=0.3)
    ax.quiverkey(q, 0.80, 0.055, 200, "traction 200 MPa (py across, px along)", labelpos="W", coordinates="axes",
                 color="k", fontproperties=dict(size=7.5))
    from matplotlib.patches import Patch

    ax.plot([], [], "k-", lw=1.0, label="contact edge (elastic pressure > 0)")
    ax.add_artist(ax.legend(handles=[ax.lines[-1], Patch(facecolor="none", edgecolor="k", hatch="///",
                                                          label="adhesion area (hatched, white edge)")],
                            loc="upper right", fontsize=7.5, framealpha=0.9))
    ax.annotate("", xy=(0.04, 0.70), xytext=(0.04, 0.92), xycoords="axes fraction",
                arrowprops=dict(arrowstyle="->", color="k"))
    ax.text(0.055, 0.95, "material flow: enters at +x", transform=ax.transAxes, fontsize=8, va="center")
    ax.set_ylabel("x along rolling [mm]")
    ax.set_title(f"S1002 / UIC60 1:40, y = 0, 66.7 kN, mu = {MU}: exact rolling contact, "
                 f"{(ex.x[1] - ex.x[0]) * 1e3:.1f} mm elements\n"
                 f"{row['case']} (phi = {row['phi']:.3f} 1/m), |F| = {np.hypot(ex.Fx, ex.Fy) / 1e3:.1f} kN, "
                 f"slip area {100 * ex.slip_fraction:.0f} %", fontsize=10)
    pd = np.ma.masked_where(~on, ex.power_density / 1e3)
    mesh = bx.pcolormesh(yw, xx, pd, cmap="magma", shading="nearest")
    fig.colorbar(mesh, ax=bx, label="frictional power density [kW/m² per m/s]")
    bx.contour(yw, xx, on.astype(float), levels=[0.5], colors="k", linewidths=1.0)
    bx.contour(yw, xx, ex.adhesion.astype(float), levels=[0.5], colors="c", linewidths=1.2)
    bx.plot([], [], "c-", label="adhesion / slip boundary")
    bx.legend(loc="lower right", fontsize=7.5, framealpha=0.9)
    bx.set_ylabel("x along rolling [mm]")
    bx.set_xlabel("lateral position on the wheel profile [mm] (towards the field side)")
    cols = np.flatnonzero(on.any(0))
    for a in (ax, bx):
        a.set_xlim(yw[cols[0]] - 2.0, yw[cols[-1]] + 2.0)
        a.set_ylim(-6.5, 7.0)
    fig.savefig(output, dpi=120)
    plt.close(fig)


def main(quick=False, output=None, out=sys.stdout):
    step = QUICK_STEP if quick else STEP
    shifts = np.round(np.array(QUICK_SHIFTS if quick else SHIFTS) * 1e-3, 12)
    cases = dict(list(CASES.items())[:1]) if quick else CASES
    tables = tables_for(SETUP, shifts)
    rows = []
    for y in shifts:
        rows += solve_shift(float(y), tables, step, {**cases, **(PLANAR if y == 0.0 and not quick else {})})
    print(f"mu = {MU}, G = {G / 1e9:.1f} GPa, nu = {NU}, elements {step * 1e3:.1f} mm; power per unit rolling speed",
          file=out)
    print(table(rows), file=out)
    res = dict(rows=rows, step=step)
    if not quick:
        text, res["convergence"] = convergence(tables, next(iter(CASES)))
        print(file=out)
        print(text, file=out)
    if output is not None:
        figure(next(r for r in rows if r["y"] == 0.0 and r["case"] == next(iter(CASES))), output)
    return res


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--output", type=Path, default=Path(__file__).parent / "figures" / "contact-rolling-y0.png")
    args = parser.parse_args()
    main(args.quick, args.output)
