"""Cost of the four long-term strategies on the comparison case of docs/strategies.md.

Run: python benchmarks/longterm.py [--quick]

The disk wheel of the built-in 'direct' scenario at 70 km/h (the P2 order 8 grows) on 32 angles,
from a rough wheel (40 um rms, orders 2-12) until 1 mm has gone at the most worn spot (one
disk-wheel life of the issue's targets): the direct coupled integration at acceleration factor
500 (feasible: under 10 minutes?), the stepwise strategy with its step limited on u and on the
shape, and second order with cheaper draws (under 60 s?), the Fourier technique, and the
phenomenological strategy with the fitted drift and dispersion (the fit's dynamics and the PDE
solve apart). Wall times are single runs after every case has run once to 2 um (compilation and
the numba caches' loading excluded: the phenomenological PDE alone compiles for about 6 s on a
cold cache), on a shared machine; revolutions simulated are exact. The last column is the
relative L2 difference of the final deviation from the mean radius against the direct run (the
first case).
"""

import os
import platform
import sys
import time

import numpy as np

from railwear.geometry import roundness
from railwear.longterm.direct import Direct
from railwear.longterm.fitting import fit_h, gather
from railwear.longterm.fourier import Fourier, FourierStrategy
from railwear.longterm.phenomenological import Phenomenological
from railwear.longterm.disk_wheel import DiskWheel, ServiceSpeeds
from railwear.longterm.stepwise import Stepwise
from railwear.scenario import build, load_scenario

QUICK = "--quick" in sys.argv
DEPTH = 0.1e-3 if QUICK else 1e-3
SPEED = 70 / 3.6
POINTS = 32


def timed(fn):
    t = time.perf_counter()
    out = fn()
    return time.perf_counter() - t, out


def main():
    sc = load_scenario("direct")
    law, band, life = build.wear_law(sc), build.band_width(sc), sc.operation.life_distance_km * 1e3
    model = build.disk_wheel_model(sc, SPEED)
    u0 = roundness.random_perturbation(POINTS, 40e-6, 2, 12, np.random.default_rng(1))
    frozen = DiskWheel(model, law, band, life, ServiceSpeeds((SPEED,)), revolutions=4,
                            transient_revolutions=4, samples=4)
    fast = DiskWheel(model, law, band, life, ServiceSpeeds((SPEED,)), revolutions=2,
                          transient_revolutions=2, samples=2)

    def phenomenological(depth):
        rng = np.random.default_rng(0)
        geometries = [u0] + [roundness.random_perturbation(POINTS, r, 2, 12, rng) for r in (20e-6, 40e-6, 60e-6, 80e-6)]
        fit_frozen = DiskWheel(model, law, band, life, ServiceSpeeds((SPEED,)), revolutions=4,
                                    transient_revolutions=4, samples=2)
        t_fit, fit = timed(lambda: fit_h(gather(lambda v: fit_frozen, [SPEED], geometries, rng), degree=3, bins=16))
        t_pde, ds = timed(lambda: Phenomenological(fit.table, SPEED, sc.solver.epsilon, sc.solver.nu, fit.drift[0],
                                                   fit.dispersion[0]).run(u0, 1.0, depth))
        ds.attrs["fit_seconds"], ds.attrs["pde_seconds"] = t_fit, t_pde
        return ds

    cases = {  # each a run to the removed depth given (m)
        "direct, A = 500": lambda depth: Direct(DiskWheel(model, law, band, life), 500.0).run(u0, 1.0, depth),
        "stepwise, 5 um on u": lambda depth: Stepwise(frozen, 5e-6).run(u0, 1.0, depth),
        "stepwise, 2 um on the shape": lambda depth: Stepwise(frozen, 2e-6, limit_on="shape").run(u0, 1.0, depth),
        "stepwise, 2nd order, 20 um shape": lambda depth: Stepwise(fast, 20e-6, limit_on="shape",
                                                                   scheme="adams-bashforth").run(u0, 1.0, depth),
        "Fourier": lambda depth: FourierStrategy(Fourier.disk_wheel(model, law, band), life).run(u0, 1.0, depth),
        "phenomenological (fit + PDE)": phenomenological,
    }
    for fn in cases.values():  # compile and load the caches outside the timings
        fn(2e-6)
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    print(f"railwear long-term strategies, disk wheel at {SPEED * 3.6:g} km/h, {POINTS} angles, to "
          f"{DEPTH * 1e3:g} mm removed; Python {platform.python_version()}, {platform.machine()}, load "
          f"average {load:.2f}; command: python benchmarks/longterm.py{' --quick' if QUICK else ''}")
    print(f"{'strategy':32s} {'wall [s]':>10s} {'revolutions':>12s} {'RHS evals':>12s} {'dominant order':>15s} "
          f"{'km':>8s} {'L2 vs direct':>13s}")
    times, reference = {}, None
    for name, fn in cases.items():
        t, ds = timed(lambda: fn(DEPTH))
        times[name] = t
        shape = ds.u.values[-1] - ds.u.values[-1].mean()
        reference = shape if reference is None else reference
        error = np.linalg.norm(shape - reference) / np.linalg.norm(reference)
        revs = float(ds.cost_revolutions) if "cost_revolutions" in ds else 0.0
        rhs = int(ds.cost_rhs_evaluations) if "cost_rhs_evaluations" in ds else 0
        extra = ""
        if "pde_seconds" in ds.attrs:
            extra = f"  (fit {ds.attrs['fit_seconds']:.3g} s, PDE {ds.attrs['pde_seconds']:.3g} s)"
        print(f"{name:32s} {t:10.3g} {revs:12.0f} {rhs:12d} {int(ds.dominant_order):15d} "
              f"{float(ds.stop_time) * life / 1e3:8.0f} {error:13.3g}{extra}")
    ref = times["direct, A = 500"]
    print("wall time / direct: " + ", ".join(f"{k} {v / ref:.3g}" for k, v in times.items() if k != "direct, A = 500"))


if __name__ == "__main__":
    main()
