"""The metro wheel of docs/vehicle_track.md under duty cycles: the Fourier growth rate per order
at one traction level (the built-in), braking, and the derived cycles of a metro line for a motor
and a trailer wheel. Writes docs/figures/duty-cycles.png and prints the table of
docs/vehicle_track.md's "Duty cycles" section.

    python docs/duty_cycles.py
"""

import tomllib
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

from railwear.scenario import build, builtin_text, parse_scenario
from railwear.units import KM

ORDERS = np.arange(1, 121)
LINE = {"station_spacing_km": 1.2, "top_speed_kmh": 80.0, "acceleration_m_s2": 1.0, "braking_m_s2": 1.0}
CASES = {  # label -> [operation] and [contact] traction, or None for the built-in's
    "traction +0.05 at 70 km/h (built-in)": None,
    "braking -0.05 at 70 km/h": {"cycle": [{"share": 1.0, "speed_kmh": 70.0, "traction_coefficient": -0.05}]},
    "metro line, motor wheel": {"line": dict(LINE, wheel="motor")},
    "metro line, trailer wheel": {"line": dict(LINE, wheel="trailer")},
}


def scenario(operation):
    data = tomllib.loads(builtin_text("metro"))
    if operation is not None:
        data["operation"] = {"life_distance_km": data["operation"]["life_distance_km"], **operation}
        data["contact"].pop("traction_coefficient")
    return parse_scenario(data)


def main():
    rows, fig = [], plt.figure(figsize=(8, 4.5), layout="constrained")
    ax = fig.add_subplot()
    for label, operation in CASES.items():
        sc = scenario(operation)
        technique = build.fourier_technique(sc)
        rate = technique.rates(ORDERS).real / technique.speed * KM * 1e4  # per 10 000 km
        duty = sc.operation.duty()
        mean = duty.mean_traction_coefficient if duty else sc.contact.traction_coefficient
        braking = duty.braking_share if duty else float(mean < 0)
        ax.plot(ORDERS, rate, label=f"{label}: mean {mean:+.3f}, braking {braking:.0%}")
        fastest = int(ORDERS[np.argmax(rate)])
        rows.append((label, mean, braking, fastest, rate.max(), rate[7]))
    ax.axhline(0.0, color="0.6", lw=0.8)
    ax.axvspan(6, 9, color="0.9", zorder=0, label="metro field band, orders 6-9")
    ax.set_xlabel("polygon order n")
    ax.set_ylabel("growth rate per 10 000 km (1)")
    ax.set_title("Metro wheel on ballasted track (Fourier technique): duty cycle and polygon growth")
    ax.legend(fontsize=8, loc="upper left")
    out = Path(__file__).parent / "figures" / "duty-cycles.png"
    fig.savefig(out, dpi=120)
    print("| duty | mean creep force / load | braking share | fastest order (1-120) | its rate per 10 000 km | order 8 |")
    print("|---|---|---|---|---|---|")
    for label, mean, braking, fastest, top, eight in rows:
        print(f"| {label} | {mean:+.4f} | {braking:.0%} | {fastest} | {top:+.3f} | {eight:+.3f} |")
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
