"""The metro wheel at 70 km/h with other wheels on its rail (railwear.longterm.vehicle_track.
WheelsOnRail): the fastest order of orders 1-40, its combination of the wheels' polygons and the
eigen-rates per 10 000 km; prints the table of docs/vehicle_track.md, 'Several wheels on one rail'.

    python docs/wheels_on_rail.py
"""

import numpy as np

from railwear.longterm.fourier import Fourier
from railwear.longterm.vehicle_track import WheelsOnRail
from railwear.scenario import build, load_scenario
from railwear.units import KM

ORDERS = np.arange(1, 41)
LAYOUTS = {"0, 2": (0.0, 2.0), "0, 2.2": (0.0, 2.2), "0, 2.5": (0.0, 2.5), "0, 3": (0.0, 3.0),
           "0, 2.5, 12.5, 15 (a car)": (0.0, 2.5, 12.5, 15.0)}


def main():
    sc = load_scenario("metro")
    model, band = build.linear_model(sc, build.one_speed(sc))
    law = build.wear_law(sc)
    per = model.speed / KM / 1e4  # 1/s per (1 per 10 000 km)
    single = Fourier.disk_wheel(model, law, band).rates(ORDERS).real / per
    print("| wheels (m along the rail) | fastest order | fastest combination (phases) | its rate | the others "
          "| one wheel, order 8 |")
    print("|---|---|---|---|---|---|")
    for label, positions in LAYOUTS.items():
        lam, modes = WheelsOnRail(model, positions).rates(ORDERS, law, band)
        rate = lam.real / per
        k = int(np.argmax(rate[:, 0]))
        phases = np.angle(modes[k, :, 0] / modes[k, 0, 0], deg=True)
        combination = ", ".join("0" if abs(p) < 90 else "180°" for p in phases)
        others = ", ".join(f"{r:+.3f}" for r in rate[k, 1:])
        print(f"| {label} | {ORDERS[k]} | {combination} | {rate[k, 0]:+.3f} | {others} | {single[7]:+.3f} |")


if __name__ == "__main__":
    main()
