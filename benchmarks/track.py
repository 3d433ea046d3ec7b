"""Speed of railwear's track receptance against a finite-element track solved frequency by frequency.

Run:  python benchmarks/track.py          (--maps: the growth map and the forecast alone)

Times, in the same run, the point receptance at midspan of a discrete 60E1 track (pads, sleepers,
ballast at 0.6 m) at 1000 frequencies from 10 to 3000 Hz:
  1. railwear.track.receptance (Floquet waves, exact for the infinite track, spans and waves in
     closed form), Euler and Timoshenko;
  2. the same waves by numpy.linalg.eig of the span and cell matrices and their amplitudes by
     numpy.linalg.solve, as a user writing Mead's method would (and as railwear did before), Euler;
  3. the alternative a user would write without a wave method: Euler-Bernoulli beam elements
     (Hermite cubics, consistent mass), 8 per bay, over 120 bays, the sleepers as masses on
     springs, assembled once with scipy.sparse and solved with spsolve at each frequency;
  4. railwear.track.finite.finite_track_receptance (exact spans, 120 bays, dense solves) for scale.
The FE result is compared with railwear's Euler receptance (it differs by the mesh and the
reflections from the ends of the finite track). Then the metro case's Fourier growth map (200
speeds from 30 to 120 km/h x orders 1-100, per cell), with railwear's receptance and with the
eig path, and a 128-sample metro forecast, against each sample's full result (its run's Dataset
and spectra, as railwear did before) with each receptance; then the time domain (ModalTrack).

BLAS runs on one thread (threadpoolctl where installed, else the environment variables set here
before numpy loads): a second thread waiting for a shared core made the dense solves swing 19x.
"""

import importlib.util
import os
import sys
import time

THREADPOOLCTL = importlib.util.find_spec("threadpoolctl") is not None
if not THREADPOOLCTL:
    for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
        os.environ.setdefault(_var, "1")

import numpy as np  # noqa: E402
import scipy.sparse as sp  # noqa: E402
from scipy.linalg import expm  # noqa: E402
from scipy.sparse.linalg import spsolve  # noqa: E402

from railwear.track import Support, Track, rail, receptance  # noqa: E402
from railwear.track.finite import finite_track_receptance  # noqa: E402
from railwear.track.modal import ModalTrack  # noqa: E402
from railwear.track.receptance import _split_waves  # noqa: E402

RECEPTANCE = sys.modules["railwear.track.receptance"]

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


class EigSpans:
    """``exp(A x)`` as ``V e^{μx} V⁻¹`` from one ``numpy.linalg.eig`` of ``A`` for every length
    (scipy's ``expm`` where ``|μ| x < 0.1``)."""

    def __init__(self, A):
        self.A = A
        self.mu, self.V = np.linalg.eig(A)
        self.V_inverse = np.linalg.inv(self.V)

    def at(self, x):
        if x == 0.0:
            return np.broadcast_to(np.eye(4, dtype=complex), self.A.shape).copy()
        mu, V = self.mu, self.V
        short = np.max(np.abs(mu), axis=-1) * abs(x) < 0.1
        P = np.empty(self.A.shape, dtype=complex)
        P[~short] = V[~short] @ (np.exp(mu[~short] * x)[..., None] * self.V_inverse[~short])
        if np.any(short):
            P[short] = expm(self.A[short] * x)
        return P

    def powers(self, X):
        return (X,)

    def apply(self, x, powers):
        return self.at(x) @ powers[0]


def eig_waves(T):
    """The Floquet waves from ``numpy.linalg.eig`` of the cell matrix, sorted by ``|λ| < 1``."""
    lam, vecs = np.linalg.eig(T)
    _, _, order = _split_waves(vecs, np.abs(lam) < 1.0)
    return np.take_along_axis(lam, order, axis=-1), np.take_along_axis(vecs, order[:, None, :], axis=-1)


def solve_amplitudes(track, right, left):
    """The waves' amplitudes from the jump condition by one ``numpy.linalg.solve`` per frequency."""
    row, unit = RECEPTANCE._jump_row(track)
    M = np.concatenate([right, -left], axis=-1)
    f = np.zeros(M.shape[:-1], dtype=complex)
    f[:, row] = unit
    c = np.linalg.solve(M, f[..., None])[..., 0]
    return c[:, :2], c[:, 2:]


class eig_path:
    """Within it, railwear's receptance takes its spans and waves from ``numpy.linalg.eig`` and the
    amplitudes from ``numpy.linalg.solve``, anew for every load position as a user's code does:
    the kept waves of the last track and frequencies are dropped before each call. Per load
    position, one ``eig`` of the span matrix, one of the cell matrix and one 4 x 4 solve."""

    def __enter__(self):
        self.saved = RECEPTANCE._Spans, RECEPTANCE._waves, RECEPTANCE._cell, RECEPTANCE._amplitudes
        cell = RECEPTANCE._cell

        def anew(track, omega):
            RECEPTANCE._CELL.clear()
            return cell(track, omega)

        RECEPTANCE._Spans, RECEPTANCE._waves, RECEPTANCE._cell = EigSpans, eig_waves, anew
        RECEPTANCE._amplitudes = solve_amplitudes

    def __exit__(self, *exc):
        RECEPTANCE._Spans, RECEPTANCE._waves, RECEPTANCE._cell, RECEPTANCE._amplitudes = self.saved
        RECEPTANCE._CELL.clear()


class full_runs:
    """Within it, the forecast takes each sample's states from its full result, ``strategy.run``
    with its Dataset and spectra (``longterm.spectra.describe``), as railwear did before."""

    def __enter__(self):
        import railwear.forecast as forecast

        self.module, self.saved = forecast, forecast._states

        def states(strategy, u0, until):
            u = strategy.run(u0, until=until).u
            return u.time.values, u.transpose("time", "angle").values

        forecast._states = states

    def __exit__(self, *exc):
        self.module._states = self.saved


def with_eig(fn):
    def run():
        with eig_path():
            return fn()
    return run


def fresh(fn):
    """``fn`` with railwear's receptance computing anew: it keeps the spans and waves of the last
    track and frequencies (for the next load position), which a repeat would find."""
    def run():
        RECEPTANCE._CELL.clear()
        return fn()
    return run


def best_of(fn, repeat=3, clock=time.perf_counter):
    times = []
    for _ in range(repeat):
        t0 = clock()
        value = fn()
        times.append(clock() - t0)
    return min(times), value


def cpu_best_of(fn, repeat=3):
    """``best_of`` in CPU time: on a shared machine a run of seconds seldom has a core to itself."""
    return best_of(fn, repeat, time.process_time)


def growth_map_and_forecast():
    """The metro case's growth map per (speed, order) cell with railwear's receptance and with the
    eig path, and a 128-sample forecast against each sample's full result (with either receptance);
    the results must agree to 1e-9 relative."""
    import warnings

    from railwear.analysis import stability
    from railwear.forecast import forecast
    from railwear.scenario import load_scenario

    speeds, orders = np.linspace(30.0, 120.0, 200), np.arange(1, 101)
    stability("metro", speeds[:2], orders[:2])  # imports, caches
    t_map, new = cpu_best_of(fresh(lambda: stability("metro", speeds, orders)), repeat=9)  # 0.3 s: the best of 9
    t_map_eig, old = cpu_best_of(with_eig(lambda: stability("metro", speeds, orders)), repeat=2)
    rate, rate_eig = new.growth_rate.values, old.growth_rate.values
    agree = np.max(np.abs(rate - rate_eig)) / np.max(np.abs(rate_eig))
    cells = speeds.size * orders.size
    print(f"  CPU time: metro growth map, {speeds.size} speeds x {orders.size} orders: {t_map:.3f} s "
          f"({t_map / cells * 1e6:.1f} us per cell); with the eig path {t_map_eig:.3f} s "
          f"({t_map_eig / cells * 1e6:.1f} us per cell); ratio {t_map_eig / t_map:.1f}; largest difference "
          f"{agree:.1e} of the largest rate")

    x = 2 * np.pi * np.arange(256) / 256
    deviation = 20e-6 * np.cos(8 * x + 0.3) + 5e-6 * np.cos(3 * x)  # a measured wheel: order 8 and 3

    def run(samples):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return forecast(load_scenario("metro", {"service.samples": samples}), x, deviation, "0.3mm")

    def full(fn):
        def timed():
            with full_runs():
                return fn()
        return timed

    run(2)
    t_fc, fc = cpu_best_of(fresh(lambda: run(128)), repeat=3)
    t_fc_full, fc_full = cpu_best_of(full(fresh(lambda: run(128))), repeat=2)
    t_fc_eig, fc_eig = cpu_best_of(full(with_eig(lambda: run(128))), repeat=1)
    same = max(np.max(np.abs(fc.peak_to_peak.values - other.peak_to_peak.values)) / np.max(np.abs(other.peak_to_peak.values))
               for other in (fc_full, fc_eig))
    print(f"  CPU time: metro forecast, 128 samples (order 8 at 20 um, limit 0.3 mm): {t_fc:.2f} s; each sample's full "
          f"result (run with its Dataset and spectra) {t_fc_full:.2f} s, ratio {t_fc_full / t_fc:.1f}; that and the eig "
          f"path {t_fc_eig:.2f} s, ratio {t_fc_eig / t_fc:.1f}; peak to peak differs by at most {same:.1e} relative; "
          f"the full results equal bit for bit: {np.array_equal(fc.peak_to_peak.values, fc_full.peak_to_peak.values)}")


def main():
    if THREADPOOLCTL:
        from threadpoolctl import threadpool_limits

        threadpool_limits(limits=1)
        blas = "1 (threadpoolctl)"
    else:
        blas = f"{os.environ['OPENBLAS_NUM_THREADS']} (OPENBLAS_NUM_THREADS set before numpy loaded)"
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    maps = "--maps" in sys.argv[1:]
    print(f"BLAS threads: {blas}; load average {load:.2f}; command: python benchmarks/track.py{' --maps' * maps}")
    if maps:  # the growth map and the forecast alone
        growth_map_and_forecast()
        return
    euler = Track(RAIL, SUPPORT, sleeper_spacing=0.6, beam="euler")
    timo = Track(RAIL, SUPPORT, sleeper_spacing=0.6, beam="timoshenko")
    receptance(euler, F[:3])  # imports warm
    t_e, w_e = best_of(fresh(lambda: receptance(euler, F, "midspan")))
    t_t, _ = best_of(fresh(lambda: receptance(timo, F, "midspan")))
    t_eig, w_eig = best_of(with_eig(lambda: receptance(euler, F, "midspan")))
    t_fe, w_fe = best_of(lambda: fe_receptance(euler, F), repeat=1)
    step = 20  # the dense exact finite track on every 20th frequency, scaled to 1000
    t_fin, w_fin = best_of(lambda: finite_track_receptance(euler, F[::step], "midspan", n_sleepers=121), repeat=1)
    t_fin *= step
    mesh = np.max(np.abs(w_fe[::step] / w_fin - 1))
    length = np.max(np.abs(w_fin / w_e[::step] - 1))
    print("receptance, discrete 60E1 track (rail loss factor 0.02), midspan, 1000 frequencies 10-3000 Hz")
    print(f"  railwear Floquet, Euler                    {t_e * 1e3:8.1f} ms")
    print(f"  railwear Floquet, Timoshenko               {t_t * 1e3:8.1f} ms")
    print(f"  Floquet waves by numpy.linalg.eig, Euler   {t_eig * 1e3:8.1f} ms, ratio to railwear {t_eig / t_e:5.1f}, "
          f"largest difference {np.max(np.abs(w_eig / w_e - 1)):.1e} relative")
    print(f"  FE track, 960 Hermite elements, 121 sleepers, spsolve per frequency: {t_fe:6.2f} s, "
          f"ratio to railwear (Euler) {t_fe / t_e:6.0f}")
    print(f"  exact finite track, 121 sleepers, dense solves:                      {t_fin:6.2f} s, "
          f"ratio {t_fin / t_e:6.0f}")
    print(f"  FE against the exact finite track of its length (mesh): {mesh:.1e}; finite against infinite "
          f"(121 sleepers, reflections from the ends): {length:.1e}")
    growth_map_and_forecast()

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
