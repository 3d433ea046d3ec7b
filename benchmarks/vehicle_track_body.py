"""Speed of one wheel revolution of the time-domain vehicle-track model against what a user would write.

Run:  python benchmarks/vehicle_track_body.py

The metro case of railwear.longterm.vehicle_track (METRO: 770 kg unsprung under an 855 kg frame
share, Hertz contact, Kalker creep under 5 % traction) at 70 km/h (one revolution 0.136 s) on its
track (Timoshenko 60E1 on pads, sleepers and ballast at 0.6 m), a 256-cell radius deviation:
  1. railwear: WheelOnRing on the ring track (32 bays, rail modes to 3 kHz with the residual
     flexibility), wheel and track in one compiled RK4 loop at 1e-4 s, frictional energy swept;
  2. the same equations stepped by scipy.integrate.solve_ivp (RK45, rtol 1e-6) calling the same
     compiled right-hand side from Python (timed over a tenth of a revolution, scaled);
  3. the track the package had: ModalTrack (81 pinned-pinned bays, Timoshenko modes to 5 kHz,
     RK4 at 2e-5 s) under a moving constant load for one revolution, without the wheel (its loop
     over every sleeper and mode per stage is what a user coupling it would pay).
Prints the best of three times and the ratios.
"""

import time

import numpy as np
from scipy.integrate import solve_ivp

from railwear.dynamics.disk_wheel_track import _derivatives
from railwear.longterm.disk_wheel import wheel_turn
from railwear.longterm.vehicle_track import METRO
from railwear.longterm.vehicle_track_body import VehicleTrackBody, ring_for
from railwear.track.modal import ModalTrack
from railwear.wear import EnergyLaw

SPEED = 70 / 3.6


def best(f, repeat=3):
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        f()
        times.append(time.perf_counter() - t)
    return min(times)


def main():
    n = 256
    u = 2e-6 * np.cos(8 * 2 * np.pi * np.arange(n) / n)
    wheel = METRO.wheel(SPEED)
    body = VehicleTrackBody(wheel, EnergyLaw(), METRO.band_width, 1e8, ring=ring_for(METRO.track))
    from dataclasses import replace
    model = replace(wheel, radius_deviation=u)
    dyn = body.dynamics(model)
    p, surf = model.params(), model.surface()
    turn = wheel_turn(model)
    steps = int(round(turn / dyn.dt))
    y0 = dyn.static_state(0.3)
    energy = np.zeros(n)
    dyn.run(y0, 0.0, 10, 0.3, p, surf, energy)
    ours = best(lambda: dyn.run(y0, 0.0, steps, 0.3, p, surf, energy))
    print(f"railwear WheelOnRing: {dyn.ring.n_modes} rail modes, {dyn.ring.n_sleepers} sleepers, "
          f"{steps} RK4 steps of {dyn.dt * 1e6:.1f} us: {ours * 1e3:.2f} ms per revolution (target 10 ms)")

    ring = dyn.ring
    arrays = ring.arrays()[:-1]
    scratch = (np.empty(ring.n_modes), np.empty(ring.n_near, np.int64), np.empty(ring.n_near),
               np.empty(2 * ring.n_sleepers))
    y8, d8, none = np.zeros(8), np.zeros(8), np.empty(0)
    length, spacing, residual = ring.tp[6], ring.tp[7], ring.tp[8]
    kh = p[10]

    def f(t, y):
        out = np.empty(y.size)
        _derivatives(t, y, p, surf, (0.3 + SPEED * t) % length, length, spacing, residual, kh, arrays, scratch, y8,
                     d8, p[12], out, none)
        return out

    span = turn / 10
    solve_ivp(f, (0.0, 1e-4), y0, rtol=1e-6, atol=1e-12)
    holder = {}

    def scipy_run():
        holder["sol"] = solve_ivp(f, (0.0, span), y0, rtol=1e-6, atol=1e-12)

    theirs = best(scipy_run, 1) * 10
    sol = holder["sol"]
    ref, _ = dyn.run(y0, 0.0, steps // 10, 0.3, p, surf)
    diff = abs(sol.y[2, -1] - ref[2]) / abs(ref[2] - y0[2] + 1e-30)
    print(f"solve_ivp RK45 on the same right-hand side: {sol.nfev} evaluations over a tenth of a revolution, "
          f"{theirs:.2f} s per revolution (scaled), ratio {theirs / ours:.0f} (wheel displacement change agrees to {diff:.1e})")

    modal = ModalTrack(METRO.track, 81, 5000.0, 60.0)
    modal.run(1e-3, dt=2e-5, speed=SPEED, force=wheel.static_load, x0=5.0)
    old = best(lambda: modal.run(turn, dt=2e-5, speed=SPEED, force=wheel.static_load, x0=5.0, every=1000))
    print(f"ModalTrack ({modal.n_modes} modes, 81 sleepers, dt 20 us), moving load only: {old * 1e3:.0f} ms per "
          f"revolution, ratio {old / ours:.0f}")


if __name__ == "__main__":
    main()
