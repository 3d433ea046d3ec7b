"""Cost of a wheel revolution with several wheels on the time-domain ring track.

Run:  python benchmarks/wheels_on_ring.py

The metro wheel of railwear.longterm.vehicle_track (METRO) at 70 km/h (one revolution 0.136 s,
1357 RK4 steps of 100 us), each wheel with its own 256-cell radius deviation (2 um of order 8),
frictional energy swept, on the ring of its track with rail modes to 3 kHz and the residual
flexibility (railwear.dynamics.wheels_track.WheelsOnRing): one wheel, a bogie (0, 2.5 m) and a
car's four wheels (0, 2.5, 15.1, 17.6 m: bogie centres 12.6 m apart, an assumption for a metro
car), on 32 bays (19.2 m) and 64 bays (38.4 m), a set of wheels only where the ring is at least
twice its length (round the ring the last wheel would otherwise be the first one's neighbour). Prints the best of three
times per revolution and per wheel-revolution, and the single-wheel WheelOnRing beside.
"""

import time

import numpy as np

from railwear.dynamics.disk_wheel_track import WheelOnRing
from railwear.dynamics.wheels_track import WheelsOnRing
from railwear.longterm.disk_wheel import wheel_turn
from railwear.longterm.vehicle_track import METRO
from railwear.longterm.vehicle_track_body import ring_for

SPEED = 70 / 3.6
CASES = (("one wheel", (0.0,)), ("bogie", (0.0, 2.5)), ("car", (0.0, 2.5, 15.1, 17.6)))


def best(f, repeat=3):
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        f()
        times.append(time.perf_counter() - t)
    return min(times)


def main():
    from dataclasses import replace

    n = 256
    u = 2e-6 * np.cos(8 * 2 * np.pi * np.arange(n) / n)
    wheel = replace(METRO.wheel(SPEED), radius_deviation=u)
    turn = wheel_turn(wheel)
    steps = int(np.ceil(turn / 1e-4))
    dt = turn / steps
    for bays in (32, 64):
        ring = ring_for(METRO.track, bays)
        print(f"ring of {bays} bays ({ring.length:.1f} m), {ring.n_modes} rail modes, {steps} RK4 steps of "
              f"{dt * 1e6:.1f} us per revolution")
        single = WheelOnRing(wheel, ring, dt)
        y0, energy = single.static_state(0.3), np.zeros(n)
        single.run(y0, 0.0, 10, 0.3, wheel.params(), wheel.surface(), energy)
        t = best(lambda: single.run(y0, 0.0, steps, 0.3, wheel.params(), wheel.surface(), energy))
        print(f"  WheelOnRing (one wheel): {t * 1e3:.2f} ms per revolution")
        for name, positions in CASES:
            if 2 * positions[-1] > ring.length:  # the ring would make the last wheel the first one's neighbour
                continue
            dyn = WheelsOnRing(wheel, ring, dt, positions=positions)
            k = dyn.n_wheels
            p, surf = [wheel.params()] * k, [wheel.surface()] * k
            y0, energy = dyn.static_state(20.0), np.zeros((k, n))
            dyn.run(y0, 0.0, 10, 20.0, p, surf, energy)
            t = best(lambda: dyn.run(y0, 0.0, steps, 20.0, p, surf, energy))
            print(f"  WheelsOnRing, {name} ({k} wheels): {t * 1e3:.2f} ms per revolution, {t / k * 1e3:.2f} ms per "
                  f"wheel-revolution")


if __name__ == "__main__":
    main()
