"""Speed of railwear's contact code against a plain-numpy FASTSIM written the obvious way.

Run:  python benchmarks/contact.py

Times, in the same run:
  1. FASTSIM at 40 x 40 cells, one contact per call (railwear.contact.fastsim, with fields);
  2. a batch of 10 000 contacts (railwear.contact.fastsim_batch);
  3. a contact table of 2001 lateral shifts for S1002 / UIC60 1:40 (railwear.geometry.contact_table).
The plain-numpy FASTSIM marches along the rolling direction in a Python loop and handles all
strips of a contact at once with array operations; it uses the same grid and bound, so it must
give the same forces (checked below).
"""

import time

import numpy as np

from railwear.contact import fastsim, fastsim_batch, flexibilities
from railwear.geometry import contact_table, load_profile

A, B, FN, MU, G, NU = 6.304e-3, 12.61e-3, 106.7e3, 0.33, 82e9, 0.28


def numpy_fastsim(a, b, fz, xi, eta, phi, mu, shear_modulus, poisson, nx=40, ny=40):
    """FASTSIM with numpy: loop over the nx cells of every strip, strips as arrays."""
    L1, L2, L3 = (float(v) for v in flexibilities(a, b, shear_modulus, poisson))
    dy = 2 * b / ny
    y = -b + (np.arange(ny) + 0.5) * dy
    ay = a * np.sqrt(1 - (y / b) ** 2)
    dx = 2 * ay / nx
    pmax = mu * 1.5 * fz / (np.pi * a * b)
    px = np.zeros(ny)
    py = np.zeros(ny)
    x_prev = ay.copy()
    Fx = Fy = Mz = 0.0
    for i in range(nx):
        x = ay - (i + 0.5) * dx
        step = x_prev - x
        hx = px - (xi / L1 - phi * y / L3) * step
        hy = py - (eta / L2 + phi * 0.5 * (x + x_prev) / L3) * step
        bound = pmax * np.sqrt(np.maximum(0.0, 1 - (x / a) ** 2 - (y / b) ** 2))
        h = np.hypot(hx, hy)
        scale = np.where(h > bound, bound / np.where(h > 0, h, 1.0), 1.0)
        px, py = hx * scale, hy * scale
        cell = dx * dy
        Fx += np.sum(px * cell)
        Fy += np.sum(py * cell)
        Mz += np.sum((x * py - y * px) * cell)
        x_prev = x
    return Fx, Fy, Mz


def best_of(fn, repeat=5):
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return min(times)


def main():
    rng = np.random.default_rng(1)
    # warm up (numba loads its cache or compiles)
    fastsim(A, B, FN, 1e-3, 0.0, 0.0, MU, G, NU)
    fastsim_batch(A, B, FN, np.array([1e-3, 2e-3]), 0.0, 0.0, MU, G, NU)

    # agreement of the two implementations
    ref = numpy_fastsim(A, B, FN, 1e-3, 3e-4, 0.2, MU, G, NU)
    got = fastsim(A, B, FN, 1e-3, 3e-4, 0.2, MU, G, NU)
    assert np.allclose(ref, (got.Fx, got.Fy, got.Mz), rtol=1e-10), (ref, got)

    # 1. one contact, 40 x 40
    n_calls = 2000
    t_rw = best_of(lambda: [fastsim(A, B, FN, 1e-3, 3e-4, 0.2, MU, G, NU) for _ in range(n_calls)]) / n_calls
    n_np = 100
    t_np = best_of(lambda: [numpy_fastsim(A, B, FN, 1e-3, 3e-4, 0.2, MU, G, NU) for _ in range(n_np)]) / n_np
    print(f"FASTSIM 40x40, one contact per call: railwear {t_rw * 1e6:8.1f} us   "
          f"numpy {t_np * 1e6:8.1f} us   ratio {t_np / t_rw:6.1f}")

    # 2. batch of 10 000 contacts
    n = 10_000
    xi = rng.uniform(-3e-3, 3e-3, n)
    eta = rng.uniform(-1e-3, 1e-3, n)
    phi = rng.uniform(-0.5, 0.5, n)
    a = A * rng.uniform(0.7, 1.3, n)
    t_batch = best_of(lambda: fastsim_batch(a, B, FN, xi, eta, phi, MU, G, NU), repeat=3)
    m = 300  # the numpy version is timed on a subset and scaled
    t_np_batch = best_of(lambda: [numpy_fastsim(a[k], B, FN, xi[k], eta[k], phi[k], MU, G, NU)
                                  for k in range(m)], repeat=2) * n / m
    print(f"FASTSIM 40x40, batch of {n} contacts: railwear {t_batch:8.3f} s ({t_batch / n * 1e6:.1f} us/contact)   "
          f"numpy {t_np_batch:8.2f} s (from {m})   ratio {t_np_batch / t_batch:6.1f}")

    # 3. contact table, 2001 shifts
    w, r = load_profile("S1002"), load_profile("UIC60")
    y = np.linspace(-0.010, 0.010, 2001)
    contact_table(w, r, y=y[:3])  # warm-up
    t_table = best_of(lambda: contact_table(w, r, axle_load=133.4e3, y=y), repeat=3)
    print(f"contact table S1002/UIC60, 2001 shifts: railwear {t_table:.2f} s")


if __name__ == "__main__":
    main()
