"""One FASTSIM call (40 x 40, with traction, slip and power fields) as ``fastsim`` makes it now,
Kalker's coefficients on floats, against the same call with the coefficients in numpy on
one-element arrays (as before), in the same run; the two give the same result bit for bit.

    python benchmarks/fastsim_single.py

Best of 7 repeats of 2000 calls after a warm-up (numba's cache loaded).
"""

import os
import time

import numpy as np

import railwear.contact.fastsim  # noqa: F401
import sys

fs = sys.modules["railwear.contact.fastsim"]
from railwear.contact.kalker import _kalker_many, _kalker_scalar

ARGS = (6e-3, 4e-3, 80e3, 1e-3, -5e-4, 0.1, 0.3, 8e10, 0.28)  # a, b, N, xi, eta, phi, mu, G, nu


def with_numpy_coefficients(a, b, fz, xi, eta, phi, mu, G, nu, nx=40, ny=40):
    """The single call as it was: flexibilities (and Kalker's coefficients) through numpy."""
    L1, L2, L3 = (float(L) for L in fs.flexibilities(a, b, G, nu))
    return fs._fastsim_single(a, b, fz, xi, eta, phi, mu, L1, L2, L3, 1.0, nx, ny, False)


def best(fn, n=2000, repeats=7):
    out = np.inf
    for _ in range(repeats):
        t0 = time.perf_counter()
        for _ in range(n):
            fn()
        out = min(out, (time.perf_counter() - t0) / n)
    return out


def main():
    new, old = fs.fastsim(*ARGS), with_numpy_coefficients(*ARGS)
    assert np.array_equal(new.px, old[1]) and np.array_equal(new.power_density, old[3]) and new.Fx == old[0][0]
    print(f"load average {os.getloadavg()[0]:.1f}")
    t_new, t_old = best(lambda: fs.fastsim(*ARGS)), best(lambda: with_numpy_coefficients(*ARGS))
    aob, nu = np.array([1.5]), np.array([0.28])
    k_new, k_old = best(lambda: _kalker_scalar(1.5, 0.28), 20000), best(lambda: _kalker_many(aob, nu), 20000)
    print(f"FASTSIM 40 x 40, one contact: fastsim {t_new * 1e6:.1f} us; with the coefficients in numpy "
          f"{t_old * 1e6:.1f} us (ratio {t_old / t_new:.2f}); same result bit for bit")
    print(f"Kalker's coefficients, one pair: floats {k_new * 1e6:.2f} us, numpy {k_old * 1e6:.1f} us "
          f"(ratio {k_old / k_new:.0f})")


if __name__ == "__main__":
    main()
