"""Figure and numbers of docs/vehicle_track_time.md, "Several wheels on the ring track".

Run:  python docs/wheels_on_ring.py   (about 20 s; writes docs/figures/wheels-on-ring.png)

The metro case (METRO) at 70 km/h on its ring track (32 bays, rail modes to 3 kHz): a bogie of
wheelbase 2.5 m whose leading wheel carries 25 um of order 8 (0.05 mm peak to peak), the trailing
wheel round, beside the round bogie; and the forces per unit filtered deviation at both wheels
for orders 3-20 on the leading wheel against the linear model (WheelsOnRail).
"""

from dataclasses import replace
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from railwear.dynamics.wheels_track import WheelsOnRing, force_transfer
from railwear.longterm.disk_wheel import start_lift, wheel_turn
from railwear.longterm.vehicle_track import METRO, VehicleTrackModel, WheelsOnRail
from railwear.longterm.vehicle_track_body import ring_for

SPEED = 70 / 3.6
WHEELBASE = 2.5
CELLS = 256
ORDERS = np.arange(3, 21)


def bogie_forces(dyn, u, revolutions=2, transient=4):
    """Normal forces [N] of both wheels, the leading one over ``u``: ``(t, N)`` over the last revolutions."""
    base = dyn.wheel
    per = int(round(wheel_turn(base) / dyn.dt))
    lead = replace(base, radius_deviation=u, initial_lift=start_lift(base, u, 0.0))
    flat = replace(base, radius_deviation=0 * u)
    ms = [lead, flat]
    p, surf = [m.params() for m in ms], [m.surface() for m in ms]
    y = dyn.static_state(1.0, [lead.initial_lift, 0.0], models=ms)
    y, _ = dyn.run(y, 0.0, transient * per, 1.0, p, surf)
    t1 = transient * per * dyn.dt
    _, rec = dyn.run(y, t1, revolutions * per, 1.0 + base.speed * t1, p, surf, every=1)
    return rec[:, 0, 0] - t1, rec[:, :, 1]


def main():
    base = METRO.wheel(SPEED)
    turn = wheel_turn(base)
    dt = turn / int(np.ceil(turn / 1e-4))
    dyn = WheelsOnRing(base, ring_for(METRO.track), dt, positions=(0.0, WHEELBASE))
    x = 2 * np.pi * np.arange(CELLS) / CELLS
    W = base.static_load
    t, polygon = bogie_forces(dyn, 25e-6 * np.cos(8 * x))
    _, flat = bogie_forces(dyn, 0 * x)
    for a, name in enumerate(("leading (order 8, 25 um)", "trailing (round)")):
        print(f"{name}: peak {polygon[:, a].max() / 1e3:.1f} kN, minimum {polygon[:, a].min() / 1e3:.1f} kN "
              f"(static {W / 1e3:.1f} kN; round bogie {flat[:, a].max() / 1e3:.1f}-{flat[:, a].min() / 1e3:.1f} kN)")

    model = WheelsOnRail(VehicleTrackModel(base, METRO.track), (0.0, WHEELBASE))
    Y = model.transfer_matrix(model.frequencies(ORDERS), "normal_force")[:, :, 0]
    sim = np.array([force_transfer(dyn, int(n), which=0) for n in ORDERS])
    for n, s, y in zip(ORDERS, sim, Y):
        print(f"order {n:2d} ({model.frequencies(n)[0] / 2 / np.pi:5.1f} Hz): leading {abs(s[0] / y[0]) - 1:+.2%}, "
              f"trailing {abs(s[1] / y[1]) - 1:+.2%} of the linear model's |N/u|, |N_trail/N_lead| "
              f"{abs(s[1] / s[0]):.3f}")
    back = np.array([force_transfer(dyn, int(n), which=1)[0] for n in ORDERS])  # the polygon on the trailing wheel
    for n, s, b, y in zip(ORDERS, sim, back, Y):
        print(f"order {n:2d}: the other wheel's force, polygon leading {abs(s[1] / y[1]) - 1:+.2%}, trailing "
              f"{abs(b / y[1]) - 1:+.2%}, mean {0.5 * (abs(s[1] / y[1]) + abs(b / y[1])) - 1:+.2%}")

    fig, (ax, bx) = plt.subplots(1, 2, figsize=(11, 4.2))
    ax.plot(t * 1e3, polygon[:, 0] / 1e3, color="C3", label="leading wheel, 25 µm of order 8")
    ax.plot(t * 1e3, polygon[:, 1] / 1e3, color="C0", label="trailing wheel, round")
    ax.plot(t * 1e3, flat[:, 1] / 1e3, color="0.5", lw=0.8, ls="--", label="round bogie (sleeper passing)")
    ax.axhline(W / 1e3, color="k", lw=0.6)
    ax.set_xlabel("time [ms] (two wheel revolutions)")
    ax.set_ylabel("normal contact force [kN]")
    ax.set_title(f"Metro bogie, wheelbase {WHEELBASE:g} m, 70 km/h")
    ax.set_ylim(W / 1e3 - 14, W / 1e3 + 10)
    ax.legend(fontsize=8, loc="lower center", ncol=2)
    kn_mm = 1e-6  # N/m -> kN/mm
    bx.semilogy(ORDERS, np.abs(Y[:, 0]) * kn_mm, color="C3", label="leading wheel, linear model")
    bx.semilogy(ORDERS, np.abs(Y[:, 1]) * kn_mm, color="C0", label="trailing wheel, linear model")
    bx.semilogy(ORDERS, np.abs(sim[:, 0]) * kn_mm, "o", color="C3", mfc="none", label="leading wheel, time domain")
    bx.semilogy(ORDERS, np.abs(sim[:, 1]) * kn_mm, "s", color="C0", mfc="none", label="trailing wheel, time domain")
    bx.set_xlabel("polygon order on the leading wheel")
    bx.set_ylabel("|normal force / filtered deviation| [kN/mm]")
    bx.set_title("Force at each wheel per unit deviation (±1 µm)")
    bx.set_xticks(ORDERS[::2])
    bx.legend(fontsize=8)
    fig.tight_layout()
    out = Path(__file__).parent / "figures" / "wheels-on-ring.png"
    fig.savefig(out, dpi=120)
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
