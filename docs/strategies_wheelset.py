"""The wheelset on real profiles: worn lateral profile and angular pattern, stepwise against direct.

``wheelset_section(quick)`` runs the comparison and returns a Markdown section; run alone
(``python docs/strategies_wheelset.py [--quick]``) it prints the section.

S1002 wheels on UIC60 rails through contact tables, the suspended wheelset of
``docs/dynamics.md`` (``TableWheelsetModel``), the energy wear law, a wear surface per wheel over
angle × lateral position, the worn profile fed back into the contact table after every long-term
step (``railwear.longterm.wheelset_wear``). Two speeds: one at which centred running is the only
motion, one at which the wheelset hunts. Each runs to the same distance with the stepwise
strategy at falling step limits and the direct strategy at falling acceleration factors; the
direct run at the smallest factor is the reference. All of it on each contact model of the tables
(``contact_model`` "hertz", "multi-hertz", "semi-hertzian", ``docs/contact.md``).
"""

import sys
import time
from dataclasses import replace

import numpy as np

from railwear.dynamics import TableWheelsetModel, critical_speed
from railwear.geometry import contact_table, load_profile
from railwear.longterm.direct import Direct
from railwear.longterm.stepwise import Stepwise
from railwear.longterm.wheelset_wear import Wheelset, WheelsetWear, band_width
from railwear.wear import EnergyLaw

SUSPENSION = dict(mass=1022.0, yaw_inertia=678.0, lateral_stiffness=1.823e6, yaw_stiffness=2.0e6)
FRICTION = 0.3
SPEEDS = {"centred running": 30.0, "hunting": 60.0}  # m/s
LIFE = 1e6  # m of running per unit normed time
SAMPLES, SECONDS = 4, 2.0  # stepwise: draws per step and seconds gathered per draw
QUICK_SAMPLES, QUICK_SECONDS = 2, 1.0  # --quick: a quarter of the gathered dynamics per step
UPDATE_SECONDS = 0.25  # direct: profile and table updated every this many simulated seconds
CONTACTS = ("hertz", "multi-hertz", "semi-hertzian")  # the tables' contact models, hertz first
QUICK_CONTACTS = ("hertz",)  # --quick: the single point (the load-sharing tables cost 75 of the 85 s)


def settings(quick):
    """Distance (m), stepwise step limits (m) and direct factors (the last the reference)."""
    if quick:
        return 0.5e6, (4e-6, 2e-6), (1e4, 5e3)
    return 1e6, (8e-6, 4e-6, 2e-6, 1e-6), (2e4, 1e4, 5e3, 2.5e3)


def problem(speed, contact="hertz"):
    """The wheelset wear problem at ``speed`` (m/s) on the unworn profiles, tables of ``contact``."""
    wheel, rail = load_profile("S1002"), load_profile("UIC60")
    model = TableWheelsetModel(speed=speed, **SUSPENSION, table=contact_table(wheel, rail, contact_model=contact),
                               friction_coefficient=FRICTION)
    return WheelsetWear(model, wheel, rail, EnergyLaw(), LIFE, contact_model=contact)


def worn_critical_speed(p, ds):
    """Linear critical speed (m/s) of the wheelset on the table of the run's final fed profile."""
    return critical_speed(replace(p.model, table=p.table(ds.worn_depth.values[-1].mean(0))))


def speed_text(v):
    """A critical speed for the tables: 0 is a wheelset unstable about y = 0 at every speed."""
    return "0 (unstable at every speed)" if v == 0.0 else f"{v:.1f}"


def centre_jump(p, ds):
    """Rolling-radius difference (m) at the table's first shift off y = 0 on the run's final profile."""
    table = p.table(ds.worn_depth.values[-1].mean(0))
    y = table.y.values
    at = y[np.argmin(np.abs(y)) + 1]
    row = table.sel(y=at)
    return abs(float(row.rolling_radius.sel(side="left") - row.rolling_radius.sel(side="right"))), at


def centre(p):
    """Hertz curvatures A, B (1/m) and lateral semi-axis b (m) of the new profiles at y = 0."""
    at = p.model.table.sel(y=0.0, side="right")
    return float(at.A), float(at.B), float(at.b)


def warm_up(contacts=CONTACTS):
    """Compile and load the kernels once, so that the wall times below are those of the runs."""
    for contact in contacts:
        p = problem(SPEEDS["hunting"], contact)
        Direct(Wheelset(p, update_seconds=UPDATE_SECONDS), 1e5, n_save=None).run(until=0.01)
        Stepwise(Wheelset(p, seconds=0.1, samples=2), 1e-6).run(until=0.001)


def worn(ds):
    """Final worn depth over both wheels (m), flattened (wheel, lateral)."""
    return ds.worn_depth.values[-1].ravel()


def relative_l2(ds, ref):
    return float(np.linalg.norm(worn(ds) - worn(ref)) / np.linalg.norm(worn(ref)))


def band(ds, step=-1):
    """90 % band width (m) of the lateral depth of both wheels after save ``step`` (the increment
    of the first step for ``step=1``)."""
    depth = ds.worn_depth.values[step].mean(0)
    return band_width(depth, ds.lateral.values, 0.9)


def contact_range(ds, first_only=False):
    """(smallest, largest) contact lateral position (m) seen in the run or in its first step."""
    lo, hi = ds.contact_min.values[1:], ds.contact_max.values[1:]
    return (float(lo[0]), float(hi[0])) if first_only else (float(np.min(lo)), float(np.max(hi)))


def centroid(ds, step=-1):
    """Lateral position (m) of the volume's centre of the lateral depth of both wheels after save ``step``."""
    depth = np.clip(ds.worn_depth.values[step].mean(0), 0.0, None)
    return float(np.sum(depth * ds.lateral.values) / np.sum(depth))


def deepest_at(ds):
    """Lateral position (m) of the deepest point of the final lateral depth of both wheels."""
    return float(ds.lateral.values[np.argmax(ds.worn_depth.values[-1].mean(0))])


def runs(speed, quick, contact="hertz"):
    """Stepwise and direct runs at ``speed`` (m/s) on tables of ``contact``: ``{label: (dataset, wall seconds)}``."""
    distance, limits, factors = settings(quick)
    p = problem(speed, contact)
    out = {}
    for factor in factors:
        t = time.perf_counter()
        ds = Direct(Wheelset(p, update_seconds=UPDATE_SECONDS), factor, n_save=None).run(until=distance / LIFE)
        out[f"direct, A = {factor:g}"] = (ds, time.perf_counter() - t)
    for limit in limits:
        t = time.perf_counter()
        samples, seconds = (QUICK_SAMPLES, QUICK_SECONDS) if quick else (SAMPLES, SECONDS)
        ds = Stepwise(Wheelset(p, seconds=seconds, samples=samples), limit).run(until=distance / LIFE)
        out[f"stepwise, {limit * 1e6:g} um"] = (ds, time.perf_counter() - t)
    return p, out


def mm(x):
    return f"{1e3 * x:.2f}"


def wheelset_section(quick: bool) -> str:
    """The Markdown section on the wheelset: bands, contact ranges, stepwise against direct, cost,
    on each contact model."""
    distance, limits, factors = settings(quick)
    lines = ["## The wheelset on real profiles: the worn lateral profile", ""]
    contacts = QUICK_CONTACTS if quick else CONTACTS
    warm_up(contacts)
    every = {}  # (contact, regime): (speed, runs, problem)
    for contact in contacts:
        for regime, speed in SPEEDS.items():
            p, out = runs(speed, quick, contact)
            every[contact, regime] = (speed, out, p)
    results = {regime: every["hertz", regime] for regime in SPEEDS}
    vc = critical_speed(results["hunting"][2].model)
    reference = f"direct, A = {factors[-1]:g}"
    finest = f"stepwise, {limits[-1] * 1e6:g} um"
    lines += [
        f"S1002 wheels on UIC60 rails (1/40 cant, gauge 1435 mm), contact tables over 201 shifts of "
        f"±10 mm; the wheelset of `docs/dynamics.md` (1022 kg, k_y 1.823 MN/m, k_psi 2 MN m/rad, "
        f"friction {FRICTION}), linear critical speed {vc:.1f} m/s on the Hertz table; the hunting limit "
        f"cycle exists well below it (down to about 40 m/s, `docs/dynamics.md`). Energy law k_e = 5.3e-9 kg/J "
        f"(beta = {EnergyLaw().beta:.3g} m³/J, no scaling of the wear), a wear surface per wheel of "
        f"64 angles × 180 lateral cells of 0.5 mm on the wheel profile, Hertz footprint from the "
        f"table's semi-axes. Every run goes {distance / 1e3:g} km from new profiles; after every "
        f"long-term step the wheel profile is worn by the angle-averaged depth of both wheels and "
        f"the contact table is recomputed from it. "
        f"Stepwise: {QUICK_SAMPLES if quick else SAMPLES} random starts (lateral offset 1-3 mm of either "
        f"sign, random phase) of 3 s transient + {QUICK_SECONDS if quick else SECONDS:g} s gathered per step, step limit = the largest change of the "
        f"fed lateral profile per step. Direct: one run from one such start, the wear coefficient "
        f"times A, profile and table updated every {UPDATE_SECONDS:g} s of simulated time. "
        f"Reference: {reference}. Everything is run on each contact model of the tables "
        f"(`[body] contact_model`, `docs/contact.md`): **hertz** one rigid point per wheel "
        f"carrying the load; **multi-hertz** and **semi-hertzian** every local minimum of the gap a "
        f"contact, the load shared, the dynamics evaluating each contact on its own (its creepages, "
        f"Kalker coefficients and saturation), and each contact worn at its own position under its own "
        f"patch by its own frictional power.",
        "",
        "Hertz contact. Regime, contact positions and worn band: on the new profiles (the first stepwise step, "
        f"{finest}) and over the whole reference run. Largest lateral displacement: after the "
        "transients, in the first step and over the run.",
        "",
        "| speed | regime (new profiles) | largest lateral displacement, new / over the run [mm] | "
        "contact positions, new profiles [mm] | contact positions over the run [mm] | 90 % band, new profiles [mm] "
        "| 90 % band at the end [mm] | deepest [um] | linear critical speed on the worn profile [m/s] |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for regime, (speed, out, p) in results.items():
        ref, first = out[reference][0], out[finest][0]
        lo0, hi0 = contact_range(first, first_only=True)
        lo, hi = contact_range(ref)
        lines.append(
            f"| {speed:g} m/s ({speed * 3.6:g} km/h) | {regime} | {mm(float(first.lateral_amplitude[1]))} / "
            f"{mm(float(np.max(ref.lateral_amplitude[1:])))} | "
            f"{mm(lo0)} to {mm(hi0)} (range {mm(hi0 - lo0)}) | {mm(lo)} to {mm(hi)} (range {mm(hi - lo)}) | "
            f"{mm(band(first, 1))} | {mm(band(ref))} | {1e6 * float(ref.worn_depth.values[-1].max()):.1f} | "
            f"{speed_text(worn_critical_speed(p, ref))} |")
    lines += ["", "The three contact models, same quantities (contact positions: every loaded contact of the "
              "tables at the shifts the runs visit), the linear critical speed on the new and on the worn "
              "profile, where the final depth lands (deepest point and centre of the removed volume on the "
              "wheel profile, positive towards the field side), its relative L2 difference from the Hertz "
              "reference's, and the reference run's cost.", "",
              "| contact | speed | largest lateral displacement, new / over the run [mm] | linear critical speed, "
              "new / worn [m/s] | contact positions, new profiles [mm] | contact positions over the run [mm] | "
              "90 % band, new / end [mm] | deepest [um] | deepest at / volume centre [mm] | rel. L2 from hertz | "
              "reference: tables, wall [s] |", "|---|---|---|---|---|---|---|---|---|---|---|"]
    for (contact, regime), (speed, out, q) in every.items():
        ref, first = out[reference][0], out[finest][0]
        hertz = every["hertz", regime][1][reference][0]
        lo0, hi0 = contact_range(first, first_only=True)
        lo, hi = contact_range(ref)
        difference = "-" if contact == "hertz" else f"{relative_l2(ref, hertz):.2f}"
        lines.append(
            f"| {contact} | {speed:g} m/s | {mm(float(first.lateral_amplitude[1]))} / "
            f"{mm(float(np.max(ref.lateral_amplitude[1:])))} | {critical_speed(q.model):.1f} / "
            f"{speed_text(worn_critical_speed(q, ref))} | {mm(lo0)} to {mm(hi0)} | {mm(lo)} to {mm(hi)} | "
            f"{mm(band(first, 1))} / {mm(band(ref))} | {1e6 * float(ref.worn_depth.values[-1].max()):.1f} | "
            f"{mm(deepest_at(ref))} / {mm(centroid(ref))} | {difference} | {int(ref.cost_tables)}, "
            f"{out[reference][1]:.1f} |")
    lines += ["", "The worn lateral profile: relative L2 difference of the final angle-averaged depth of both "
              f"wheels from the reference of the same contact model, and the cost (dynamics seconds simulated, "
              f"right-hand sides, contact tables, wall time on a shared 2-core machine).", "",
              "| speed | contact | strategy | rel. L2 difference | steps / updates | simulated [s] | right-hand sides "
              "| tables | wall [s] | volume removed / law |", "|---|---|---|---|---|---|---|---|---|---|"]
    for (contact, regime), (speed, out, _) in every.items():
        ref = out[reference][0]
        for label, (ds, wall) in out.items():
            steps = ds.attrs["steps"]
            difference = "reference" if label == reference else f"{relative_l2(ds, ref):.3f}"
            closure = float(ds.removed_volume[-1] / ds.law_volume[-1]) - 1
            lines.append(f"| {speed:g} m/s | {contact} | {label} | {difference} | {steps} | "
                         f"{float(ds.cost_seconds):.1f} | {int(ds.cost_rhs_evaluations)} | {int(ds.cost_tables)} | "
                         f"{wall:.1f} | 1 {closure:+.0e} |")
    lines += ["", "Angular pattern at the end (reference run): peak-to-peak over angle of the depth at the most "
              "worn lateral cell, against its mean.", "",
              "| speed | contact | mean depth [um] | peak-to-peak over angle [um] |", "|---|---|---|---|"]
    for (contact, regime), (speed, out, _) in every.items():
        surface = out[reference][0].surface_depth.values.mean(0)
        k = int(np.argmax(surface.mean(0)))
        lines.append(f"| {speed:g} m/s | {contact} | {1e6 * surface[:, k].mean():.2f} | "
                     f"{1e6 * np.ptp(surface[:, k]):.2f} |")
    samples = QUICK_SAMPLES if quick else SAMPLES
    lines += ["", "### Why", "", _why(results, p, reference, finest, limits, factors, samples),
              _why_contacts(every, reference, finest), ""]
    return "\n".join(lines)


def _differences(out, reference, labels):
    return ", ".join(f"{relative_l2(out[label][0], out[reference][0]):.3f}" for label in labels)


def _why(results, p, reference, finest, limits, factors, samples=SAMPLES):
    slow, fast = (results[r][1] for r in SPEEDS)
    first_slow, first_fast = slow[finest][0], fast[finest][0]
    low = SPEEDS["centred running"]
    ref_slow = slow[reference][0]
    amplitude = float(np.max(ref_slow.lateral_amplitude[1:]))
    vc_worn = worn_critical_speed(results["centred running"][2], ref_slow)
    if amplitude > 5e-5:
        onset = (f"the wheelset at {low:g} m/s starts a small hunting cycle ({mm(amplitude)} mm) whose "
                 f"contact jumps between the groove's edges")
    else:
        onset = (f"by the end of this distance the centred wheelset at {low:g} m/s is "
                 f"{'linearly unstable' if vc_worn < low else 'still stable'}, the cycle not yet grown")
    A, B, b = centre(p)
    x = min(r.real for r in np.roots([1, 0, -3, 1.8]) if 0 < r.real < 1 and abs(r.imag) < 1e-12)
    steps = [f"stepwise, {limit * 1e6:g} um" for limit in limits]
    directs = [f"direct, A = {factor:g}" for factor in factors[:-1]]
    lo, hi = contact_range(first_fast, True)
    return "\n".join([
        f"- **Band against contact range.** In centred running the contact sits at one point of the "
        f"tread, so on the new profiles the band is the Hertz footprint alone: the lateral depth of an "
        f"elliptic pressure rolled over is proportional to 1 - (s/b)², whose central 90 % is {2 * x:.3f} b "
        f"wide: {mm(2 * x * b)} mm with the table's b = {mm(b)} mm, measured {mm(band(first_slow, 1))} mm "
        f"(cells of 0.5 mm). Hunting carries the contact over the range the table gives for the cycle's "
        f"shifts, and the band is that range widened by the footprint: {mm(band(first_fast, 1))} mm "
        f"against a range of {mm(hi - lo)} mm.",
        f"- **Feedback.** S1002 on UIC60 is nearly conformal at the nominal contact (lateral Hertz "
        f"curvature B = {B:.2f} 1/m against A = {A:.2f} 1/m in the rolling direction): a groove of some "
        f"5-10 um worn by centred running is already more concave than the rail head, and the contact "
        f"of the centred wheelset moves to the groove's edges, where the rolling radius changes fast "
        f"with the shift. The conicity rises and the linear critical speed of the worn wheelset falls "
        f"to {vc_worn:.1f} m/s (last column); {onset}. The 90 % band at the end is "
        f"{mm(band(ref_slow))} mm against the footprint's {mm(band(first_slow, 1))} mm. The onset is a "
        f"threshold in the "
        f"worn depth, and near it the random starts of the stepwise strategy fall on either side "
        f"(centred or on the small cycle), so this case converges slowly and not monotonically in the "
        f"step limit and in the factor. (Tables of several contacts per wheel share the "
        f"load over the conformal groove; what that changes: last bullets.) At "
        f"{SPEEDS['hunting']:g} m/s the depth is spread thin over the hunting band and the contact "
        f"positions hardly change.",
        f"- **Stepwise against direct.** Both integrate the same frozen-geometry wear; stepwise is "
        f"forward Euler in the long-term time plus the Monte Carlo error of the cycle's phase within "
        f"the gathered seconds, direct lags the profile by one update and averages one trajectory. "
        f"Under hunting both converge to about first order: differences from the reference "
        f"{_differences(fast, reference, steps)} for step limits "
        f"{', '.join(f'{limit * 1e6:g}' for limit in limits)} um, and "
        f"{_differences(fast, reference, directs)} for A = {', '.join(f'{f:g}' for f in factors[:-1])}; "
        f"the reference's own error is about its difference from the run at twice its factor "
        f"({_differences(fast, reference, directs[-1:])}), which is the floor the finest steps reach. "
        f"The costs are of the same order here, stepwise the dearer: the wheelset on a table is cheap "
        f"to integrate, each stepwise step pays {samples} transients of 3 s, and the contact tables, one "
        f"per step or update, are a large part of the wall time.",
        "- **Angular pattern (output only).** The table model has no angle round the wheel, so the "
        "angle-dependent depth does not feed back; it records where the hunting cycle met the "
        "wheel's revolutions. Without feedback it stays a small ripple on the mean depth.",
        "- **Fourier and phenomenological strategies.** Both are formulated for the angular pattern "
        "of a disk wheel: the Fourier technique needs dynamics linear in u (the transfer function "
        "from a harmonic of u round the wheel to the wear rate), the phenomenological one a local "
        "law h(u_xx) over the angle. For the wheelset they would need the lateral direction: a "
        "linearisation of the table model about the worn profile (the wear rate's response to a "
        "lateral profile change, e.g. through the rolling-radius difference) and a fit of h over "
        "the lateral curvature and position on the tread; neither is built.",
    ])


def _points_at_centre(p):
    """(positions on the wheel profile (m), shares of the load) of the loaded contacts of the right
    wheel at y = 0 on the new profiles."""
    at = p.model.table.sel(y=0.0, side="right")
    if "point_normal_force" not in at:
        return np.array([float(at.wheel_contact_y)]), np.array([1.0])
    force = at.point_normal_force.values
    loaded = force > 0
    return at.point_wheel_y.values[loaded], force[loaded] / force.sum()


def _why_contacts(every, reference, finest):
    """The bullets on what the contact models change, from the runs ``every[(contact, regime)]``
    (none for one contact model)."""
    contacts = list(dict.fromkeys(c for c, _ in every))
    if len(contacts) < 2:
        return ""
    def ref(contact, regime):
        return every[contact, regime][1][reference][0]

    def each(values, unit="", fmt=mm):
        return ", ".join(f"{c} {fmt(values[c])}{unit}" for c in contacts)

    def worn(contact, regime):
        ds = ref(contact, regime)
        return (f"{contact} {1e6 * float(ds.worn_depth.values[-1].max()):.1f} um deep, band {mm(band(ds))} mm, "
                f"deepest at {mm(deepest_at(ds))} mm, volume centre {mm(centroid(ds))} mm")

    def motion(amplitude):
        return "stays centred" if amplitude < 5e-5 else f"runs a cycle of up to {mm(amplitude)} mm"

    slow, fast = SPEEDS
    new = [c for c in contacts if c != "hertz"]
    points = {c: _points_at_centre(every[c, slow][2]) for c in contacts}
    where = "; ".join(f"{c} " + " and ".join(f"{mm(y)} mm ({100 * w:.0f} %)" for y, w in zip(*points[c]))
                      for c in contacts)
    apart = [float(np.ptp(points[c][0])) for c in new]
    first = {c: every[c, slow][1][finest][0] for c in contacts}
    first_deepest = {c: float(first[c].lateral.values[np.argmax(first[c].worn_depth.values[1].mean(0))])
                     for c in contacts}
    vc = {c: critical_speed(every[c, slow][2].model) for c in contacts}
    vc_worn = {(c, r): worn_critical_speed(every[c, r][2], ref(c, r)) for c in contacts for r in SPEEDS}
    amplitude = {(c, r): float(np.max(ref(c, r).lateral_amplitude[1:])) for c in contacts for r in SPEEDS}
    start = {c: float(every[c, fast][1][finest][0].lateral_amplitude[1]) for c in contacts}
    calm = [c for c in contacts if start[c] < 1e-3]
    later = {c: ref(c, fast).lateral_amplitude.values[2:] for c in calm}
    cost = {c: sum(every[c, r][1][reference][1] for r in SPEEDS) for c in contacts}
    total = {c: sum(w for r in SPEEDS for _, w in every[c, r][1].values()) for c in contacts}
    tables = {c: sum(int(ds.cost_tables) for r in SPEEDS for ds, _ in every[c, r][1].values()) for c in contacts}
    labels = list(every["hertz", fast][1])
    steps = [label for label in labels if label.startswith("stepwise")]
    directs = [label for label in labels if label.startswith("direct") and label != reference]

    def differences(regime, chosen):
        return "; ".join(f"{c} {_differences(every[c, regime][1], reference, chosen)}" for c in contacts)

    hunting = each(start, " mm")
    spread = {(c, r): max(relative_l2(ds, ref(c, r)) for label, (ds, _) in every[c, r][1].items() if label != reference)
              for c in new for r in SPEEDS}
    l2 = {(c, r): relative_l2(ref(c, r), ref("hertz", r)) for c in new for r in SPEEDS}
    larger = all(l2[k] > spread[k] for k in l2)
    calm_text = "".join(
        f" On the {c} tables the wheelset does not hunt on the new profiles from these starts (linear "
        f"critical speed {vc[c]:.1f} m/s, and no large cycle is reached); it wears the two contacts' "
        f"grooves and then runs a small cycle, up to {mm(later[c].max())} mm ({mm(later[c][-1])} mm at the end)."
        for c in calm)
    large = [c for c in contacts if c not in calm]
    own = {(c, r): relative_l2(every[c, r][1][directs[-1]][0], ref(c, r)) for c in contacts for r in SPEEDS}
    ratio = [float(np.min(every[c, slow][2].model.table.point_b.sel(y=0.0, side="right")[:2])
                   / np.max(every[c, slow][2].model.table.point_b.sel(y=0.0, side="right")[:2])) for c in new]
    return "\n".join([
        f"- **Several contacts per wheel: where the load sits.** At y = 0 on the new profiles the "
        f"contacts of a wheel (on the wheel profile) and their shares of the load: {where}. The Hertz "
        f"point becomes a main patch on the tread and a narrow one {', '.join(f'{mm(d)}' for d in apart)} mm "
        f"towards the flange ({', '.join(new)}; lateral semi-axes "
        + ", ".join(f"{mm(float(every[c, slow][2].model.table.point_b.sel(y=0.0, side='right')[0]))} / "
                    f"{mm(float(every[c, slow][2].model.table.point_b.sel(y=0.0, side='right')[1]))} mm" for c in new)
        + f" against the single point's {mm(float(every['hertz', slow][2].model.table.b.sel(y=0.0, side='right')))} mm). "
        f"In the first step of centred running ({SPEEDS[slow]:g} m/s) the band is {each({c: band(first[c], 1) for c in contacts}, ' mm')} "
        f"and the deepest point at {each(first_deepest, ' mm')}: on the new contact the narrow second patch "
        f"(its own power on {', '.join(f'{100 * r:.0f}' for r in ratio)} % of the main patch's "
        f"width) wears fastest. The linear critical speed "
        f"on the new profiles is {each(vc, ' m/s', lambda v: f'{v:.1f}')}.",
        f"- **Several contacts per wheel: what the wear does.** After {float(ref('hertz', slow).distance[-1]):g} km "
        f"of centred running ({SPEEDS[slow]:g} m/s, reference runs): " + "; ".join(worn(c, slow) for c in contacts)
        + ". From the start the wear goes into two grooves, under the main patch and under the second "
        "one, where the single point wears one band; the worn profile's linear critical speed falls to "
        + each({c: vc_worn[c, slow] for c in contacts}, " m/s", lambda v: f"{v:.1f}" if v else "0")
        + "".join(f" ({c}: its kinematic mode grows about y = 0 at every speed; on the worn profile the "
                  f"rolling-radius difference is already {mm(jump)} mm at the table's first shift, "
                  f"{mm(at)} mm: the contact jumps as the wheelset leaves the centre, as under Feedback above)"
                  for c in contacts if vc_worn[c, slow] == 0.0 for jump, at in [centre_jump(every[c, slow][2], ref(c, slow))])
        + ", and over the run the wheelset " + ", ".join(f"{motion(amplitude[c, slow])} on {c}" for c in contacts)
        + f". Hunting speed ({SPEEDS[fast]:g} m/s, starts of 1-3 mm): the largest lateral displacement after the "
        f"first transients is {hunting}."
        + calm_text + " Worn: " + "; ".join(worn(c, fast) for c in contacts)
        + ". Relative L2 difference of the final lateral depth from hertz's: "
        + ", ".join(f"{c} {l2[c, r]:.2f} ({SPEEDS[r]:g} m/s)" for c in new for r in SPEEDS)
        + (", each above the largest difference of that model's strategies from its own reference ("
           if larger else ", against the largest difference of that model's strategies from its own reference (")
        + ", ".join(f"{spread[k]:.2f}" for k in l2)
        + ("): the contact model changes the worn profile more than the choice of strategy does. " if larger else "). ")
        + "(The dynamics evaluate each contact on its own, `docs/dynamics.md`: its creepages in its own "
        "contact plane, its spin, its lever arm, its Kalker coefficients and its saturation at its own mu N; "
        "on the semi-hertzian tables each contact wears across the strips of its patch, each strip by its "
        "share of the contact's power, not under the equivalent ellipse.)",
        f"- **Several contacts per wheel: convergence and cost.** Differences from each model's own reference "
        f"at {SPEEDS[fast]:g} m/s for step limits {', '.join(s.split(', ')[1] for s in steps)}: "
        f"{differences(fast, steps)}; for {', '.join(d.split(', ')[1] for d in directs)}: "
        f"{differences(fast, directs)}. At {SPEEDS[slow]:g} m/s, step limits: {differences(slow, steps)}; factors: "
        f"{differences(slow, directs)}. Only the large hunting cycle ({', '.join(large)} at "
        f"{SPEEDS[fast]:g} m/s) converges at about first order; elsewhere the differences fall slowly and "
        f"not always monotonically (near the onset of a small cycle the random starts fall on either "
        f"side, as described above for hertz), and the reference's own error, about its difference from "
        f"the run at twice its factor, is "
        + ", ".join(f"{c} {own[c, r]:.3f} ({SPEEDS[r]:g} m/s)" for c in contacts for r in SPEEDS)
        + ". The cost is in "
        f"the tables: the reference runs of both speeds take {each(cost, ' s', lambda v: f'{v:.1f}')} of wall "
        f"time, all the runs of the comparison "
        + ", ".join(f"{c} {total[c]:.0f} s ({tables[c]} tables)" for c in contacts) + ".",
    ])


if __name__ == "__main__":
    print(wheelset_section("--quick" in sys.argv))
