"""The high-speed built-in with the two wheels of a bogie on one rail: does the rail's bending mode
between them select an order? Prints the tables of docs/vehicle_track.md ("Several wheels on one
rail", the high-speed bogie) and draws docs/figures/wheelbase-high-speed.png.

One wheel against a bogie of 2.5 m (``[body] wheel_positions_m = [0, 2.5]``) under net traction
(+0.035 of the load at one speed) and under the line's duty cycle (top speeds 250, 300, 350
km/h); then the wheelbase from 2.0 to 3.0 m on the 300 km/h line, with the rail's third mode
between the wheels (``railwear.track.between.localised_modes``) and its order ``f π D / V``.

    python docs/wheelbase_high_speed.py
"""

import tomllib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from railwear.longterm.vehicle_track import HIGH_SPEED  # noqa: E402
from railwear.scenario import build, builtin_text, parse_scenario  # noqa: E402
from railwear.units import KM, kmh_to_m_s, m_s_to_kmh  # noqa: E402

ORDERS = np.arange(1, 61)
SPEEDS_KMH = (250.0, 300.0, 350.0)
WHEELBASES_M = (2.0, 2.25, 2.5, 2.75, 3.0)
TRACTION = 0.035  # net traction of docs/vehicle_track.md's high-speed section (every order decays under it)
FIELD_BAND = (18, 26)  # 0.92 m high-speed wheels (docs/vehicle_track.md)


def scenario(top_kmh=300.0, wheelbase=None, traction=None):
    """The built-in at the line's top speed, with a bogie of ``wheelbase`` (m; None: one wheel);
    with ``traction`` one operating point at the top speed under that demand instead of the line."""
    data = tomllib.loads(builtin_text("high-speed"))
    data["operation"]["line"]["top_speed_kmh"] = top_kmh
    if wheelbase is not None:
        data["body"]["wheel_positions_m"] = [0.0, wheelbase]
    if traction is not None:
        del data["operation"]["line"]
        data["operation"]["speed_kmh"] = top_kmh
        data["contact"]["traction_coefficient"] = traction
    return parse_scenario(data)


def growth(sc):
    """``(rates per 10 000 km over ORDERS, the technique)``; with a bogie, the fastest combination."""
    technique = build.fourier_technique(sc)
    return technique.rates(ORDERS).real / technique.speed * KM * 1e4, technique


def mode_order(frequency, speed):
    """``f π D / V`` of a mode at ``frequency`` [Hz] at ``speed`` [m/s]."""
    return frequency * np.pi * HIGH_SPEED.diameter / speed


def wheelbase_row(wheelbase):
    """One row of the wheelbase table on the 300 km/h line, and what the figure draws of it."""
    rate, technique = growth(scenario(300.0, wheelbase))
    k = int(np.argmax(rate))
    _, modes = technique.combinations(ORDERS[k:k + 1])
    phase = np.angle(modes[0, 1, 0] / modes[0, 0, 0], deg=True)
    rail = technique.parts[0].rail_modes()
    top, mean = kmh_to_m_s(300.0), technique.speed
    held = rail["held"][2]
    at_top, at_mean = mode_order(held, top), mode_order(held, mean)
    near = "yes" if np.isfinite(held) and abs(ORDERS[k] - at_top) <= 1 else "no"
    braking = growth(scenario(300.0, wheelbase, traction=-0.101))[0]
    text = (f"| {wheelbase:g} | {ORDERS[k]} | {rate[k]:+.3f} | {'in phase' if abs(phase) < 90 else 'anti-phase'} "
            f"| {rail['pinned'][2]:.0f}-{rail['clamped'][2]:.0f} | "
            + ("none" if not np.isfinite(held) else f"{held:.0f}") + " | "
            + ("-" if not np.isfinite(held) else f"{at_top:.1f} / {at_mean:.1f}")
            + f" | {near} | {ORDERS[int(np.argmax(braking))]} |")
    return text, rate, at_top


def main():
    print("| 300 km/h unless stated | wheels | fastest order (1-60) | its rate per 10 000 km | mean speed [km/h] |")
    print("|---|---|---|---|---|")
    for label, traction in ((f"net traction {TRACTION:+.3f}", TRACTION), ("line cycle", None)):
        for top in SPEEDS_KMH:
            for wheelbase in (None, 2.5):
                rate, technique = growth(scenario(top, wheelbase, traction))
                k = int(np.argmax(rate))
                wheels = "one" if wheelbase is None else f"0, {wheelbase:g} m"
                print(f"| {label}, {top:g} km/h | {wheels} | {ORDERS[k]} | {rate[k]:+.3f} "
                      f"| {m_s_to_kmh(technique.speed):.0f} |")
    print()
    print("| wheelbase [m] | fastest order (1-60) | its rate per 10 000 km | combination | third mode, pinned-clamped "
          "span [Hz] | held by the wheels [Hz] | its f π D / V, top / mean speed | fastest within one order of it "
          "(top speed) | braking at 300 km/h: fastest order |")
    print("|---|---|---|---|---|---|---|---|---|")
    single = growth(scenario(300.0))[0]
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(11, 4.2), constrained_layout=True)
    ax.plot(ORDERS, single, color="k", lw=2, label="one wheel")
    fastest, marks = [], []
    for wheelbase, colour in zip(WHEELBASES_M, plt.cm.viridis(np.linspace(0, 0.9, len(WHEELBASES_M)))):
        text, rate, at_top = wheelbase_row(wheelbase)
        print(text)
        ax.plot(ORDERS, rate, color=colour, label=f"bogie {wheelbase:g} m")
        if np.isfinite(at_top):
            ax.axvline(at_top, color=colour, ls=":", lw=1)
        fastest.append(ORDERS[int(np.argmax(rate))])
        marks.append(at_top)
    ax.axvspan(*FIELD_BAND, color="0.9", zorder=0, label="field's orders (0.92 m wheels)")
    ax.set(xlabel="polygon order", ylabel="growth rate per 10 000 km [-]", xlim=(1, 60),
           title="300 km/h line cycle; dotted: third rail mode, f π D / V at 300 km/h")
    ax.legend(fontsize=8)
    bx.plot(WHEELBASES_M, fastest, "o-", color="C0", label="fastest order, bogie")
    bx.plot(WHEELBASES_M, marks, "s--", color="C3", label="third rail mode held by the wheels, f π D / V")
    bx.axhline(ORDERS[int(np.argmax(single))], color="k", lw=1, label="fastest order, one wheel")
    bx.axhspan(*FIELD_BAND, color="0.9", zorder=0, label="field's orders")
    bx.set(xlabel="wheelbase [m]", ylabel="polygon order", ylim=(10, 40), title="300 km/h line cycle")
    bx.legend(fontsize=8, loc="upper right")
    fig.savefig("docs/figures/wheelbase-high-speed.png", dpi=110)


if __name__ == "__main__":
    main()
