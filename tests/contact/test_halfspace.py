"""The elastic half-space normal contact (railwear.contact.halfspace) against Hertz, its
convergence with the element size, load, complementarity, and two bodies side by side.

Grid-convergence study (n × n elements on 2.5 a × 2.5 b, three ellipses, E = 210 GPa, ν = 0.28,
N = 66.7 kN; docs/contact.md, "Elastic half-space reference"): the errors of p0 and of the
approach fall at second order in the element size (fitted 1.8-1.95 over n = 12 ... 192; p0
-2.1e-3, -5.6e-4, -1.3e-4 at n = 24, 48, 96), the second-moment semi-axes
``sqrt(5 ∬ x² p / N)`` at 1.6-1.9; the patch extents, outer edges of the elements in contact,
stay within one element of Hertz's (first order, a staircase). The tolerances below are those
measured errors at n = 48 rounded up by a factor of about two.
"""

import numpy as np
import pytest
from scipy import integrate
from scipy.optimize import brentq

from railwear.contact import effective_modulus, halfspace_contact, hertz_contact
from railwear.contact.halfspace import influence_coefficients
from railwear.errors import ScenarioError

E, NU, N = 2.1e11, 0.28, 66.7e3
A = 0.5  # rolling curvature [1/m]
TOL_P0, TOL_APPROACH, TOL_MOMENT = 1.2e-3, 3e-4, 6e-4  # at n = 48 (module docstring)


def _curvature_for(ratio):
    """Lateral curvature B giving the Hertz ellipse a/b = ratio with A."""
    return np.exp(brentq(lambda lb: float(hertz_contact(N, A, np.exp(lb), E, NU).a_over_b) - ratio, -8.0, 8.0))


def _hertz_grid(B, n, H):
    dx, ds = 2.5 * H.a / n, 2.5 * H.b / n
    x = -1.25 * H.a + dx * (np.arange(n) + 0.5)
    s = -1.25 * H.b + ds * (np.arange(n) + 0.5)
    return x, s, A * x[:, None] ** 2 + B * s[None, :] ** 2


def _errors(ratio, n):
    B = _curvature_for(ratio)
    H = hertz_contact(N, A, B, E, NU)
    x, s, h = _hertz_grid(B, n, H)
    r = halfspace_contact(x, s, h, N, E, NU)
    am = np.sqrt(5.0 * (r.pressure.sum(1) @ x**2) / r.pressure.sum())
    bm = np.sqrt(5.0 * (r.pressure.sum(0) @ s**2) / r.pressure.sum())
    return dict(p0=r.p0 / H.p0 - 1, approach=r.approach / H.approach - 1, am=am / H.a - 1, bm=bm / H.b - 1,
                a=(r.half_length - H.a) / (x[1] - x[0]), b=(r.half_width - H.b) / (s[1] - s[0]), result=r, hertz=H)


def test_influence_coefficient_is_the_integral_over_the_rectangle():
    """Love's closed form against numerical quadrature of ∬ 1/r off the element and in each quadrant."""
    estar = effective_modulus(E, NU)
    for X, S in ((1.3e-3, 0.2e-3), (-2e-3, 5e-3), (-0.9e-3, -0.7e-3), (0.3e-3, -2.1e-3)):
        ref, _ = integrate.dblquad(lambda eta, xi: 1.0 / np.hypot(X - xi, S - eta), -0.5e-3, 0.5e-3, -0.25e-3, 0.25e-3,
                                   epsabs=1e-13)
        assert influence_coefficients(X, S, 1e-3, 0.5e-3, estar) == pytest.approx(ref / (np.pi * estar), rel=1e-9)
    # centre of a square of side 2c: (8 c ln(1 + sqrt 2)) / (pi E*)
    c = 1e-3
    assert influence_coefficients(0.0, 0.0, 2 * c, 2 * c, estar) == pytest.approx(8 * c * np.log(1 + np.sqrt(2)) / (np.pi * estar), rel=1e-12)


@pytest.mark.parametrize("ratio", [0.3, 1.0, 3.0])
def test_hertz_ellipses(ratio):
    """At 48 elements across: p0, approach and second-moment semi-axes within the tolerances of
    the convergence study; patch extents within one element; load to round-off."""
    e = _errors(ratio, 48)
    assert abs(e["p0"]) < TOL_P0
    assert abs(e["approach"]) < TOL_APPROACH
    assert abs(e["am"]) < TOL_MOMENT and abs(e["bm"]) < TOL_MOMENT
    assert abs(e["a"]) <= 1.0 and abs(e["b"]) <= 1.0
    r = e["result"]
    assert r.normal_force == pytest.approx(N, rel=1e-12)
    assert len(r.patches()) == 1
    assert abs(r.centroid_x) < 1e-9 and abs(r.centroid_s) < 1e-9


@pytest.mark.parametrize("ratio", [0.3, 1.0])
def test_errors_fall_at_second_order(ratio):
    """p0 and approach: halving the element twice divides the error by at least 2^1.5 each time
    on average (measured orders 1.5-2.7 on n = 24, 48, 96); the finest error is small."""
    errs = [_errors(ratio, n) for n in (24, 48, 96)]
    for key in ("p0", "approach"):
        v = np.abs([e[key] for e in errs])
        order = np.log2(v[0] / v[2]) / 2.0
        assert order > 1.5, (key, v)
        assert v[2] < 0.3 * TOL_P0


def test_load_is_the_prescribed_one_and_complementarity_holds():
    r = _errors(1.0, 32)["result"]
    p, g = r.pressure, r.gap
    assert np.all(p >= 0.0)
    assert r.normal_force == pytest.approx(N, rel=1e-13)
    scale = r.approach
    assert np.all(g[~r.contact] > -1e-9 * scale)  # no interpenetration outside the patch
    assert np.max(np.abs(g[r.contact])) < 1e-9 * scale  # closed inside it
    assert np.max(np.abs(p * g)) < 1e-9 * r.p0 * scale


def test_approach_control_gives_hertz_load():
    B = _curvature_for(1.0)
    H = hertz_contact(N, A, B, E, NU)
    x, s, h = _hertz_grid(B, 48, H)
    r = halfspace_contact(x, s, h, approach=float(H.approach), youngs_modulus=E, poisson=NU)
    assert r.approach == H.approach
    # δ ∝ N^(2/3): the load error is 1.5 times the approach error of the load-controlled solve
    assert r.normal_force == pytest.approx(N, rel=1.5 * TOL_APPROACH)
    none = halfspace_contact(x, s, h + 1e-3, approach=float(H.approach), youngs_modulus=E, poisson=NU)
    assert none.normal_force == 0.0 and none.area == 0.0


def test_two_separated_bodies_each_give_their_own_hertz_solution():
    """Two quadrics 60 mm apart under one approach: each patch is Hertz's for its own load; the
    loads are Hertz's for the approach less the other patch's far-field displacement
    N_other / (π E* d) (without that correction they would be 7-9 % higher: the patches interact)."""
    B1, B2, d, ds, delta = 0.5, 2.0, 0.06, 0.3e-3, 80e-6
    x = (np.arange(80) - 39.5) * ds
    s = np.arange(-12e-3, d + 8e-3, ds) + 0.5 * ds
    h = np.minimum(A * x[:, None] ** 2 + B1 * s[None, :] ** 2, A * x[:, None] ** 2 + B2 * (s[None, :] - d) ** 2)
    r = halfspace_contact(x, s, h, approach=delta, youngs_modulus=E, poisson=NU)
    patches = sorted(r.patches(), key=lambda q: q.centroid_s)
    assert len(patches) == 2
    estar = effective_modulus(E, NU)

    def load(approach, B):
        return (approach / hertz_contact(1.0, A, B, E, NU).approach) ** 1.5

    N1, N2 = load(delta, B1), load(delta, B2)
    for _ in range(30):
        N1, N2 = load(delta - N2 / (np.pi * estar * d), B1), load(delta - N1 / (np.pi * estar * d), B2)
    for q, B, expected in zip(patches, (B1, B2), (N1, N2)):
        assert q.normal_force == pytest.approx(expected, rel=2e-3)
        assert q.normal_force < 0.95 * load(delta, B)
        H = hertz_contact(q.normal_force, A, B, E, NU)
        assert q.p0 == pytest.approx(float(H.p0), rel=2e-3)
        assert abs(q.half_length - H.a) <= ds and abs(q.half_width - H.b) <= ds
    assert patches[1].centroid_s == pytest.approx(d, abs=0.5 * ds)
    assert sum(q.normal_force for q in patches) == pytest.approx(r.normal_force, rel=1e-12)


@pytest.mark.parametrize("kwargs, name", [
    (dict(x=np.array([0.0, 1.0, 3.0])), "x"),
    (dict(s=np.array([[0.0, 1.0, 2.0]])), "s"),
    (dict(h=np.zeros((4, 4))), "h"),
    (dict(h=np.full((5, 6), np.nan)), "h"),
    (dict(normal_force=-1.0), "normal_force"),
    (dict(normal_force=None), "normal_force"),
    (dict(youngs_modulus=0.0), "youngs_modulus"),
    (dict(poisson=0.5), "poisson"),
    (dict(tol=0.0), "tol"),
    (dict(max_iterations=0), "max_iterations"),
])
def test_bad_input_names_the_argument(kwargs, name):
    args = dict(x=np.arange(5) * 1e-4, s=np.arange(6) * 1e-4, h=np.zeros((5, 6)), normal_force=1e3,
                youngs_modulus=E, poisson=NU)
    args.update(kwargs)
    with pytest.raises(ScenarioError, match=name) as info:
        halfspace_contact(**args)
    assert "\n" not in str(info.value)
