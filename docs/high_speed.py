"""The high-speed built-in under its line's duty cycle: the table of docs/vehicle_track.md ("The
high-speed built-in") and the figure docs/figures/high-speed-line.png.

For top speeds 250, 300 and 350 km/h (``--set operation.line.top_speed_kmh=...``): the fastest
order of 1-120 and its growth per 10 000 km, ``f* π D / V`` of the wheelset mode at the top speed
and at the cycle's mean speed, and the mean radial wear per 100 000 km; then the trailer wheel
without its disc braking and a motor wheel braking electrically. Steady contact, as the built-in.

    python docs/high_speed.py
"""

import tomllib
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from railwear.longterm.vehicle_track import HIGH_SPEED, VehicleTrackModel  # noqa: E402
from railwear.scenario import build, builtin_text, parse_scenario  # noqa: E402
from railwear.units import KM, kmh_to_m_s, m_s_to_kmh  # noqa: E402

ORDERS = np.arange(1, 121)
SPEEDS_KMH = (250.0, 300.0, 350.0)
FIELD_BAND = (18, 26)  # high-speed EMU wheels, 0.92 m (docs/vehicle_track.md)
FIELD_WEAR_MM = (0.5, 0.6)  # per 100 000 km, round wheels on Chinese high-speed lines (Hou, Liu & Hu 2022)


def scenario(top_kmh=300.0, **line):
    """The built-in with the line's top speed and any other ``[operation.line]`` fields changed."""
    data = tomllib.loads(builtin_text("high-speed"))
    data["operation"]["line"].update(top_speed_kmh=top_kmh, **line)
    return parse_scenario(data)


def without_disc_braking(sc):
    """The built-in's cycle with the trailer's disc braking replaced by its rolling resistance:
    the motor wheels brake electrically and the trailer wheel only rolls."""
    duty, r = sc.operation.duty(), sc.operation.line.resistance
    data = tomllib.loads(builtin_text("high-speed"))
    data["operation"] = {"life_distance_km": data["operation"]["life_distance_km"], "cycle": [
        {"share": s.share, "speed_kmh": m_s_to_kmh(s.speed), "traction_coefficient": max(s.traction_coefficient, -r)}
        for s in duty.segments]}
    shares = np.array([c["share"] for c in data["operation"]["cycle"]])
    data["operation"]["cycle"][-1]["share"] += 1.0 - shares.sum()  # round-off of the shares' sum
    return parse_scenario(data)


def growth(sc):
    """``(rates per 10 000 km over ORDERS, mean radial wear in mm per 100 000 km, the cycle)``."""
    technique = build.fourier_technique(sc)
    rate = technique.rates(ORDERS).real / technique.speed * KM * 1e4
    wear = -technique.mean_rate / technique.speed * 1e8 / 1e-3
    return rate, float(wear), sc.operation.duty()


def mode_frequency(speed):
    """``f*`` [Hz]: where the wheelset mode adds most to the growth (``-Re ΔH_π``, 300-900 Hz)
    at ``speed`` (m/s) under the case's disc braking."""
    f = np.linspace(300.0, 900.0, 3001)
    wheel = HIGH_SPEED.wheel(speed)
    flexible = VehicleTrackModel(wheel, HIGH_SPEED.track, 8, HIGH_SPEED.wheel_modes)
    rigid = VehicleTrackModel(wheel, HIGH_SPEED.track, 8)
    return float(f[np.argmax(-np.real(flexible.transfer(2 * np.pi * f) - rigid.transfer(2 * np.pi * f)))])


def table():
    """Rows at each top speed: dicts of the measured numbers."""
    rows = []
    for kmh in SPEEDS_KMH:
        sc = scenario(kmh)
        rate, wear, duty = growth(sc)
        i = int(np.argmax(rate))
        v = kmh_to_m_s(kmh)
        f_star = mode_frequency(v)
        rows.append({"top_kmh": kmh, "mean_kmh": m_s_to_kmh(duty.mean_speed), "order": int(ORDERS[i]),
                     "rate": float(rate[i]), "rate_10": float(rate[9]), "f_star": f_star,
                     "n_top": f_star * np.pi * HIGH_SPEED.diameter / v,
                     "n_mean": f_star * np.pi * HIGH_SPEED.diameter / duty.mean_speed, "wear": wear,
                     "mean_demand": duty.mean_traction_coefficient,
                     "disc_share": float(sum(s.share for s in duty.segments if s.traction_coefficient < -0.01)),
                     "rates": rate})
    return rows


def braking_rows(kmh=300.0):
    """The trailer wheel with and without disc braking, and a motor wheel braking electrically
    (half the train's weight on motor wheels, the China Standardized EMU's 4M4T)."""
    cases = {"trailer wheel, disc braking (built-in)": scenario(kmh),
             "trailer wheel, no disc braking (electric braking on the motor wheels)": without_disc_braking(scenario(kmh)),
             "motor wheel, electric braking": scenario(kmh, wheel="motor", motored_share=0.5)}
    out = []
    for label, sc in cases.items():
        rate, wear, duty = growth(sc)
        i = int(np.argmax(rate))
        out.append((label, duty.mean_traction_coefficient, int(ORDERS[i]), float(rate[i]), float(rate[21]), wear))
    return out


def main(out=Path(__file__).parent / "figures" / "high-speed-line.png"):
    rows = table()
    print("| top speed [km/h] | mean speed [km/h] | fastest order (1-120) | its rate per 10 000 km | order 10 | "
          "f* [Hz] | f* π D / V, top speed | f* π D / V, mean speed | mean wear [mm per 100 000 km] |")
    print("|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        print(f"| {r['top_kmh']:.0f} | {r['mean_kmh']:.0f} | {r['order']} | {r['rate']:+.3f} | {r['rate_10']:+.3f} | "
              f"{r['f_star']:.0f} | {r['n_top']:.1f} | {r['n_mean']:.1f} | {r['wear']:.2f} |")
    print(f"field: orders {FIELD_BAND[0]}-{FIELD_BAND[1]} on 0.92 m wheels; {FIELD_WEAR_MM[0]}-{FIELD_WEAR_MM[1]} mm "
          "per 100 000 km")
    print()
    print("| 300 km/h line | mean creep force / load | fastest order | its rate per 10 000 km | order 22 | "
          "mean wear [mm per 100 000 km] |")
    print("|---|---|---|---|---|---|")
    for label, mean, order, top, o22, wear in braking_rows():
        print(f"| {label} | {mean:+.4f} | {order} | {top:+.3f} | {o22:+.3f} | {wear:.3f} |")

    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4.3), constrained_layout=True)
    for r in rows:
        ax1.plot(ORDERS, r["rates"], label=f"top {r['top_kmh']:.0f} km/h (fastest {r['order']})")
    ax1.axvspan(*FIELD_BAND, color="0.88", zorder=0, label=f"field, orders {FIELD_BAND[0]}-{FIELD_BAND[1]}")
    ax1.axhline(0.0, color="0.5", lw=0.8)
    ax1.set_xlabel("polygon order n [-]")
    ax1.set_ylabel("growth rate [1 per 10 000 km]")
    ax1.set_title("Trailer wheel, 56.6 km line, disc braking 0.92 m/s²", fontsize=10)
    ax1.legend(fontsize=8)
    tops = np.array(SPEEDS_KMH)
    ax2.axhspan(*FIELD_BAND, color="0.88", label=f"field, orders {FIELD_BAND[0]}-{FIELD_BAND[1]} (0.92 m wheels)")
    ax2.plot(tops, [r["order"] for r in rows], "ko-", label="fastest order under the line's cycle")
    ax2.plot(tops, [r["n_top"] for r in rows], "C3--", label="f* π D / V at the top speed")
    ax2.plot(tops, [r["n_mean"] for r in rows], "C0:", label="f* π D / V at the cycle's mean speed")
    ax2.set_xlabel("line top speed [km/h]")
    ax2.set_ylabel("polygon order [-]")
    ax2.set_ylim(10, 40)
    ax2.set_title(f"Fastest order against speed (f* = {rows[1]['f_star']:.0f} Hz)", fontsize=10)
    ax2.legend(fontsize=8)
    out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out, dpi=120)
    plt.close(fig)
    print(f"wrote {out}")
    return rows


if __name__ == "__main__":
    main()
