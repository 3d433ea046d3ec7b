"""Kalker's exact steady-state rolling contact (railwear.contact.rolling_contact).

Tolerances come from the grid convergence measured with this solver (first order in the element
size, the upwind difference along rolling): on a Hertz ellipse with n elements per semi-axis
the linear coefficients are off Kalker's table by (a/b = 1, 0.5, 2) C11 +5 / +1.6-2.0 / +0.6-0.9 %
at n = 8 / 16 / 32, C22 +5-6 / +1.9-2.5 / +0.9-1.3 %, C23 +0.4-0.8 / -0.3..-0.9 / -0.1..-0.7 %,
C33 +12..41 / +4..18 / +2..9 % (C33 converges slowest and is the least sure entry of the table);
Carter's strip +1.55 / +0.8 / +0.4 % at 10 / 20 / 40 elements per half-length; CONTACT's exact
creep curve (tractcurv) within 3.6-4 / 0.8 / 0.6 % at n = 8 / 16 / 32.
"""

import numpy as np
import pytest

from railwear.contact import kalker_coefficients, rolling_contact
from railwear.contact.halfspace import tangential_influence_coefficients
from railwear.errors import ScenarioError

G, NU = 8.2e10, 0.28


def hertz_grid(a, b, n, normal_force):
    """2n x 2n elements exactly covering the ellipse's box; Hertz pressure at the centres."""
    x = (np.arange(2 * n) - n + 0.5) * a / n
    s = (np.arange(2 * n) - n + 0.5) * b / n
    r2 = (x[:, None] / a) ** 2 + (s[None, :] / b) ** 2
    return x, s, 1.5 * normal_force / (np.pi * a * b) * np.sqrt(np.clip(1.0 - r2, 0.0, None))


def test_tangential_coefficients_against_quadrature():
    """Cerruti's kernel integrated over an element in closed form against a 1000 x 1000
    midpoint rule (off the element: 1e-6 agreement; the xy term vanishes on the axes)."""
    dx, ds, n = 1e-3, 2e-3, 1000
    u, v = ((np.arange(n) + 0.5) / n - 0.5) * dx, ((np.arange(n) + 0.5) / n - 0.5) * ds
    for X, S in ((5e-3, 3e-3), (2e-3, -2e-3), (-1.5e-3, 2.5e-3)):
        XX, SS = X - u[:, None], S - v[None, :]
        r = np.hypot(XX, SS)
        w = dx * ds / n**2 / (np.pi * G)
        ref = (np.sum((1 - NU) / r + NU * XX**2 / r**3) * w, np.sum(NU * XX * SS / r**3) * w,
               np.sum((1 - NU) / r + NU * SS**2 / r**3) * w)
        got = tangential_influence_coefficients(X, S, dx, ds, G, NU)
        for g, q in zip(got, ref):
            assert float(g) == pytest.approx(q, rel=1e-6)
    assert float(tangential_influence_coefficients(1e-3, 0.0, dx, ds, G, NU)[1]) == 0.0


def _coefficients(a, b, n):
    x, s, p = hertz_grid(a, b, n, 1e5)
    c = np.sqrt(a * b)
    r1 = rolling_contact(x, s, p, 1e-6, 0.0, 0.0, np.inf, G, NU)
    r2 = rolling_contact(x, s, p, 0.0, 1e-6, 0.0, np.inf, G, NU)
    r3 = rolling_contact(x, s, p, 0.0, 0.0, 1e-4, np.inf, G, NU)
    assert r1.slip_area == r2.slip_area == r3.slip_area == 0.0
    return (np.array([-r1.Fx / (G * c * c * 1e-6), -r2.Fy / (G * c * c * 1e-6), -r3.Fy / (G * c**3 * 1e-4),
                      -r3.Mz / (G * c**4 * 1e-4)]), r2.Mz / (G * c**3 * 1e-6))


def test_kalker_linear_coefficients_converge_to_the_table():
    """a/b = 0.5, full adhesion (mu = inf): at n = 16 C11, C22 within 3 %, C23 within 1.5 %, C33
    within 6 % (measured 1.8, 1.9, -0.8, 4.2 %); the errors of C11, C22, C33 fall from n = 8 to
    16 by 0.25-0.55 (first order); C23 from Mz(eta) equals C23 from Fy(phi) (reciprocity)."""
    a, b = 4e-3, 8e-3
    kalker = np.array(kalker_coefficients(a / b, NU))
    c8, _ = _coefficients(a, b, 8)
    c16, c23_reciprocal = _coefficients(a, b, 16)
    err8, err16 = c8 / kalker - 1, c16 / kalker - 1
    assert np.all(np.abs(err16) < [0.03, 0.03, 0.015, 0.06]), err16
    ratio = np.abs(err16 / err8)[[0, 1, 3]]
    assert np.all((0.25 < ratio) & (ratio < 0.55)), ratio
    assert c23_reciprocal == pytest.approx(c16[2], rel=1e-3)


# CONTACT examples/tractcurv (as in test_fastsim.py)
FN, MU, A, B, GC = 106.7e3, 0.33, 6.304e-3, 12.61e-3, 82e9
XI = np.array([4e-4, 1.2e-3, 2.0e-3, 2.8e-3])
EXACT = np.array([0.2588, 0.6482, 0.8816, 0.9832])


def test_creep_curve_against_contacts_exact_solution():
    """CONTACT's exact solver on the tractcurv case, 16 elements per semi-axis: within 1.2 %
    (measured 0.45-0.75 %); slip grows with creepage; adhesion at the leading edge."""
    x, s, p = hertz_grid(A, B, 16, FN)
    results = [rolling_contact(x, s, p, xi, 0.0, 0.0, MU, GC, NU) for xi in XI]
    curve = np.array([-r.Fx / (MU * FN) for r in results])
    assert np.max(np.abs(curve / EXACT - 1)) < 0.012, curve / EXACT - 1
    fractions = [r.slip_fraction for r in results]
    assert all(f0 < f1 for f0, f1 in zip(fractions, fractions[1:]))
    r = results[0]
    assert r.adhesion[-1, 16] and not r.adhesion[0, 16]  # x increases with the row: leading edge last
    assert np.all(r.traction <= MU * r.pressure * (1 + 1e-9))
    assert r.residual <= 1e-8 and r.adhesion_residual < 1e-6


def test_carter_strip():
    """A strip 16 half-lengths long with Carter's pressure, pure longitudinal creep: in its
    middle F/(mu N) = 1 - (1 - kappa)^2, kappa = |xi| G / (2 (1 - nu) mu p0) (identical
    half-spaces in plane strain). 20 elements per half-length: +0.8 % (10: +1.55 %, 40: +0.4 %),
    tested at 1.2 %; the error halves from 10 to 20 elements."""
    mu, p0, a = 0.3, 1e9, 1e-3
    out = {}
    for n in (10, 20):
        x = (np.arange(2 * n) - n + 0.5) * a / n
        s = (np.arange(32) - 15.5) * 0.5 * a
        p = p0 * np.sqrt(np.clip(1 - (x / a) ** 2, 0, None))[:, None] * np.ones(s.size)
        mid = np.abs(s) < 2.4 * a
        for kappa in (0.2, 0.7):
            r = rolling_contact(x, s, p, kappa * 2 * (1 - NU) * mu * p0 / G, 0.0, 0.0, mu, G, NU)
            ratio = r.px[:, mid].sum() / p[:, mid].sum() / -mu
            out[n, kappa] = ratio / (1 - (1 - kappa) ** 2) - 1
    assert all(0 < out[20, k] < 0.012 for k in (0.2, 0.7)), out
    assert all(0.4 < out[20, k] / out[10, k] < 0.6 for k in (0.2, 0.7)), out


def test_full_slip_limit_and_symmetry():
    """At large creepage the whole patch slips, |p| = mu pn everywhere (Σ |p| dA = mu N to
    1e-9) and |F| = mu N within 1e-4 (the elastic part of the slip still turns the tractions a
    little), opposite to the creepage; reversing every creepage reverses forces and moment."""
    x, s, p = hertz_grid(A, B, 8, FN)
    r = rolling_contact(x, s, p, 0.03, 0.04, 0.0, MU, GC, NU)
    assert r.slip_fraction == 1.0
    cell = (x[1] - x[0]) * (s[1] - s[0])
    assert r.traction.sum() * cell == pytest.approx(MU * r.normal_force, rel=1e-9)
    assert np.hypot(r.Fx, r.Fy) == pytest.approx(MU * r.normal_force, rel=1e-4)
    assert -(0.6 * r.Fx + 0.8 * r.Fy) / (MU * r.normal_force) > 0.999
    r1 = rolling_contact(x, s, p, 1e-3, 5e-4, 0.5, MU, GC, NU)
    r2 = rolling_contact(x, s, p, -1e-3, -5e-4, -0.5, MU, GC, NU)
    for k in ("Fx", "Fy", "Mz"):
        assert getattr(r2, k) == pytest.approx(-getattr(r1, k), rel=1e-6)
    assert r2.power_local == pytest.approx(r1.power_local, rel=1e-6)


def test_frictional_power_local_equals_global_in_the_limit():
    """The identity used: for the exact solution Σ V |p| |s| dA (local) = -V Σ p · w dA =
    -V (xi Fx + eta Fy + phi Mz) (the rigid slip work), because Σ p · ∂(A p)/∂x vanishes.
    Kalker's upwind difference leaves a first-order defect: with spin and creepage together
    (here the whole patch slips) 7.5 / 4.0 / 2.0 % at n = 8 / 16 / 32, local below global;
    tested: below 5 % at n = 16 and falling by 0.45-0.6 from n = 8. The power density is
    non-negative and zero in adhesion."""
    gaps = []
    for n in (8, 16):
        x, s, p = hertz_grid(A, B, n, FN)
        r = rolling_contact(x, s, p, 1.5e-3, 1e-3, 0.5, MU, GC, NU, speed=30.0)
        assert r.power_global == pytest.approx(-30.0 * (1.5e-3 * r.Fx + 1e-3 * r.Fy + 0.5 * r.Mz), rel=1e-12)
        assert np.all(r.power_density >= 0.0) and np.all(r.power_density[r.adhesion] == 0.0)
        gaps.append(abs(r.power_local / r.power_global - 1))
    assert gaps[1] < 0.05 and 0.45 < gaps[1] / gaps[0] < 0.6, gaps


def test_per_strip_longitudinal_creepage():
    """xi may vary across rolling (one value per strip, e.g. from the rolling radius of a wide
    patch): a constant array is the scalar; a varying one enters the rigid slip work strip by
    strip, and its linear part -phi s alone gives a spin moment of the sign of Kalker's C33 term."""
    x, s, p = hertz_grid(A, B, 8, FN)
    r0 = rolling_contact(x, s, p, 1e-3, 2e-4, 0.0, MU, GC, NU)
    r1 = rolling_contact(x, s, p, np.full(s.size, 1e-3), 2e-4, 0.0, MU, GC, NU)
    assert (r0.Fx, r0.Fy, r0.Mz) == (r1.Fx, r1.Fy, r1.Mz)
    xi = 1e-3 - 0.3 * s
    r2 = rolling_contact(x, s, p, xi, 2e-4, 0.0, MU, GC, NU)
    cell = (x[1] - x[0]) * (s[1] - s[0])
    assert r2.power_global == pytest.approx(-np.sum(r2.px * xi[None, :] + 2e-4 * r2.py) * cell, rel=1e-12)
    assert r2.Mz < r0.Mz  # -phi s with phi = 0.3 /m: Mz = -G c^4 C33 phi < 0 added


@pytest.mark.parametrize("kwargs, name", [
    (dict(x=np.zeros(4)), "x"), (dict(pressure=-np.ones((8, 6))), "pressure"),
    (dict(pressure=np.ones((6, 8))), "pressure"), (dict(xi=np.zeros(5)), "xi"), (dict(eta=[1, 2]), "eta"),
    (dict(phi="a"), "phi"), (dict(mu=-0.1), "mu"), (dict(mu=float("nan")), "mu"),
    (dict(shear_modulus=0.0), "shear_modulus"), (dict(poisson=0.5), "poisson"), (dict(speed=-1.0), "speed"),
    (dict(tol=0.0), "tol"), (dict(max_iterations=0), "max_iterations")])
def test_bad_input(kwargs, name):
    args = dict(x=np.arange(8) * 1e-3, s=np.arange(6) * 1e-3, pressure=np.ones((8, 6)), xi=1e-3, eta=0.0,
                phi=0.0, mu=0.3, shear_modulus=G, poisson=NU)
    args.update(kwargs)
    with pytest.raises(ScenarioError, match=name) as err:
        rolling_contact(**args)
    assert "\n" not in str(err.value)
