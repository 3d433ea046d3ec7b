"""Speed of railwear's track receptance against a finite-element track solved frequency by frequency.

Run:  python benchmarks/track.py

Times, in the same run, the point receptance at midspan of a discrete 60E1 track (pads, sleepers,
ballast at 0.6 m) at 1000 frequencies from 10 to 3000 Hz:
  1. railwear.track.receptance (Floquet waves, exact for the infinite track), Euler and Timoshenko;
  2. the alternative a user would write: Euler-Bernoulli beam elements (Hermite cubics, consistent
     mass), 8 per bay, over 120 bays, the sleepers as masses on springs, assembled once with
     scipy.sparse and solved with spsolve at each frequency;
  3. railwear.track.finite.finite_track_receptance (exact spans, 120 bays, dense solves) for scale.
The FE result is compared with railwear's Euler receptance (it differs by the mesh and the
reflections from the ends of the finite track).
"""

import time

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import spsolve

from railwear.track import Support, Track, rail, receptance
from railwear.track.finite import finite_track_receptance
from railwear.track.modal import ModalTrack

F = np.linspace(10.0, 3000.0, 1000)
SUPPORT = Support(pad_stiffness=1.2e8, pad_loss_factor=0.25, sleeper_mass=150.0, ballast_stiffness=5e7,
                  ballast_loss_factor=1.0)
RAIL = rail("60E1", loss_factor=0.02)


def fe_receptance(track, frequency_hz, n_bays=120, per_bay=8):
    """Point receptance at the middle midspan of a finite FE track (Euler-Bernoulli Hermite elements)."""
    r, L = track.rail, track.sleeper_spacing
    h = L / per_bay
    n_el = n_bays * per_bay
    EI, m = r.bending_stiffness, r.mass_per_metre
    ke = EI / h**3 * np.array([[12, 6 * h, -12, 6 * h], [6 * h, 4 * h * h, -6 * h, 2 * h * h],
                               [-12, -6 * h, 12, -6 * h], [6 * h, 2 * h * h, -6 * h, 4 * h * h]])
    me = m * h / 420 * np.array([[156, 22 * h, 54, -13 * h], [22 * h, 4 * h * h, 13 * h, -3 * h * h],
                                 [54, 13 * h, 156, -22 * h], [-13 * h, -3 * h * h, -22 * h, 4 * h * h]])
    rows, cols = np.meshgrid(np.arange(4), np.arange(4), indexing="ij")
    base = 2 * np.arange(n_el)[:, None, None]
    I, J = (base + rows).ravel(), (base + cols).ravel()
    n_rail = 2 * (n_el + 1)
    n_sl = n_bays + 1
    n = n_rail + n_sl
    K = sp.coo_matrix((np.tile(ke.ravel(), n_el), (I, J)), shape=(n, n)).tocsc()
    M = sp.coo_matrix((np.tile(me.ravel(), n_el), (I, J)), shape=(n, n)).tocsc()
    s = track.support
    rail_dof = 2 * per_bay * np.arange(n_sl)
    sl_dof = n_rail + np.arange(n_sl)
    kp = s.pad_stiffness * (1 + 1j * s.pad_loss_factor)
    kb = s.ballast_stiffness * (1 + 1j * s.ballast_loss_factor)
    Kp = sp.coo_matrix((np.concatenate([np.full(n_sl, kp), np.full(n_sl, kp), np.full(n_sl, -kp), np.full(n_sl, -kp),
                                        np.full(n_sl, kb)]),
                        (np.concatenate([rail_dof, sl_dof, rail_dof, sl_dof, sl_dof]),
                         np.concatenate([rail_dof, sl_dof, sl_dof, rail_dof, sl_dof]))), shape=(n, n)).tocsc()
    Ms = sp.coo_matrix((np.full(n_sl, s.sleeper_mass), (sl_dof, sl_dof)), shape=(n, n)).tocsc()
    K, M = (K + Kp).astype(complex), (M + Ms).astype(complex)
    load = 2 * (n_bays // 2 * per_bay + per_bay // 2)
    rhs = np.zeros(n, dtype=complex)
    rhs[load] = 1.0
    out = np.empty(len(frequency_hz), dtype=complex)
    for i, f in enumerate(frequency_hz):
        out[i] = spsolve((K - (2 * np.pi * f) ** 2 * M).tocsc(), rhs)[load]
    return out


def best_of(fn, repeat=3):
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        value = fn()
        times.append(time.perf_counter() - t0)
    return min(times), value


def main():
    euler = Track(RAIL, SUPPORT, sleeper_spacing=0.6, beam="euler")
    timo = Track(RAIL, SUPPORT, sleeper_spacing=0.6, beam="timoshenko")
    receptance(euler, F[:3])  # imports warm
    t_e, w_e = best_of(lambda: receptance(euler, F, "midspan"))
    t_t, _ = best_of(lambda: receptance(timo, F, "midspan"))
    t_fe, w_fe = best_of(lambda: fe_receptance(euler, F), repeat=1)
    step = 20  # the dense exact finite track on every 20th frequency, scaled to 1000
    t_fin, w_fin = best_of(lambda: finite_track_receptance(euler, F[::step], "midspan", n_sleepers=121), repeat=1)
    t_fin *= step
    mesh = np.max(np.abs(w_fe[::step] / w_fin - 1))
    length = np.max(np.abs(w_fin / w_e[::step] - 1))
    print("receptance, discrete 60E1 track (rail loss factor 0.02), midspan, 1000 frequencies 10-3000 Hz")
    print(f"  railwear Floquet, Euler                    {t_e * 1e3:8.1f} ms")
    print(f"  railwear Floquet, Timoshenko               {t_t * 1e3:8.1f} ms")
    print(f"  FE track, 960 Hermite elements, 121 sleepers, spsolve per frequency: {t_fe:6.2f} s, "
          f"ratio to railwear (Euler) {t_fe / t_e:6.0f}")
    print(f"  exact finite track, 121 sleepers, dense solves:                      {t_fin:6.2f} s, "
          f"ratio {t_fin / t_e:6.0f}")
    print(f"  FE against the exact finite track of its length (mesh): {mesh:.1e}; finite against infinite "
          f"(121 sleepers, reflections from the ends): {length:.1e}")

    # time domain: one revolution of a 0.92 m wheel at 300 km/h (2.89 m, 34.7 ms) under a moving load
    for beam, fmax in (("euler", 5000.0), ("euler", 10000.0), ("timoshenko", 10000.0)):
        model = ModalTrack(Track(RAIL, SUPPORT, sleeper_spacing=0.6, beam=beam), n_sleepers=81, max_frequency_hz=fmax)
        model.run(1e-3, dt=2e-5, x0=10.0)  # compile / load the cache
        speed = 300 / 3.6
        t_rev = np.pi * 0.92 / speed
        t_run, _ = best_of(lambda: model.run(t_rev, dt=2e-5, x0=10.0, speed=speed, force=1e5))
        print(f"  time domain, {beam}, 81 sleepers, {model.n_modes} modes to {fmax:.0f} Hz + 162 sleeper states, "
              f"dt 20 us: one wheel revolution at 300 km/h in {t_run * 1e3:.0f} ms")


if __name__ == "__main__":
    main()
