"""Speed of the Fourier growth map of several wheels on one rail.

Run:  python benchmarks/wheels_on_rail.py

Times, in the same run, the growth map of the fastest combination of four wheels on one rail (a
car: 0, 2.5, 17.5, 20 m) over 50 speeds x orders 1-40, for the metro and the high-speed cases:
  1. railwear.longterm.vehicle_track.wheels_growth_map (the rail matrix evaluated once for every
     speed's frequencies);
  2. what a user would write with the class alone: WheelsOnRail(...).rates at each speed (the
     rail matrix evaluated speed by speed);
  3. the one-wheel map (VehicleCase.growth_map) for scale.
The two four-wheel maps are compared (they must agree to round-off). The target: under 5 s.
Best of three runs each, warm (one map first to compile and load).
"""

import time

import numpy as np

from railwear.longterm.vehicle_track import HIGH_SPEED, METRO, VehicleTrackModel, WheelsOnRail, wheels_growth_map
from railwear.scenario import build, load_scenario
from railwear.units import KM, kmh_to_m_s

CAR = (0.0, 2.5, 17.5, 20.0)
ORDERS = np.arange(1, 41)


def best(f, runs=3):
    times, out = [], None
    for _ in range(runs):
        start = time.perf_counter()
        out = f()
        times.append(time.perf_counter() - start)
    return min(times), out


def by_class(case, speeds, law):
    """The map with WheelsOnRail at each speed, as a user without wheels_growth_map would."""
    rows = []
    for v in speeds:
        wheels = WheelsOnRail(VehicleTrackModel(case.wheel(v), case.track, 8, case.wheel_modes), CAR)
        rows.append(wheels.rates(ORDERS, law, case.band_width)[0][:, 0].real / v * KM)
    return np.array(rows)


def main():
    law = build.wear_law(load_scenario("metro"))
    for case, (low, high) in ((METRO, (40.0, 120.0)), (HIGH_SPEED, (200.0, 350.0))):
        speeds = kmh_to_m_s(np.linspace(low, high, 50))
        wheels_growth_map(case, CAR, speeds[:2], ORDERS[:2], law)  # warm
        t_map, ds = best(lambda: wheels_growth_map(case, CAR, speeds, ORDERS, law))
        t_loop, rows = best(lambda: by_class(case, speeds, law))
        t_one, _ = best(lambda: case.growth_map(speeds, ORDERS, law))
        diff = np.max(np.abs(ds.growth_rate.values - rows)) / np.max(np.abs(rows))
        print(f"{case.name}: four wheels, 50 speeds x 40 orders: wheels_growth_map {t_map:.2f} s, WheelsOnRail per "
              f"speed {t_loop:.2f} s ({t_loop / t_map:.1f}x), one wheel {t_one:.2f} s; maps agree to {diff:.1e}")


if __name__ == "__main__":
    main()
