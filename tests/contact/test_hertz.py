import numpy as np
import pytest
from scipy.integrate import quad

from railwear.contact import hertz_contact, hertz_mnr
from railwear.errors import ScenarioError

# Hertz coefficients m, n, r against the auxiliary angle theta (REFERENCES.md, "Hertz")
MNR_TABLE = [
    (10, 6.6115, 0.3110, 0.4280),
    (30, 2.7306, 0.4931, 0.7263),
    (50, 1.7541, 0.6407, 0.8867),
    (60, 1.4858, 0.7171, 0.9376),
    (80, 1.1278, 0.8927, 0.9932),
    (90, 1.0, 1.0, 1.0),
]


@pytest.mark.parametrize("theta_deg, m_ref, n_ref, r_ref", MNR_TABLE)
def test_mnr_table(theta_deg, m_ref, n_ref, r_ref):
    m, n, r = hertz_mnr(np.radians(theta_deg))
    # the table is printed to 4 decimals: a correct solver lies within half a unit of the last digit
    assert abs(m - m_ref) <= 1e-4
    assert abs(n - n_ref) <= 1e-4
    assert abs(r - r_ref) <= 1e-4


def test_mnr_vectorised_matches_scalar():
    theta = np.radians([t for t, *_ in MNR_TABLE])
    m, n, r = hertz_mnr(theta)
    for i, t in enumerate(theta):
        assert np.allclose((m[i], n[i], r[i]), hertz_mnr(t), rtol=1e-14)


def _reference_ellipse(F, A, B, e_star):
    """Independent solution: K and E by quadrature, g from the curvature ratio by brentq."""
    from scipy.optimize import brentq

    def KE(k2):
        K = quad(lambda p: 1.0 / np.sqrt(1.0 - k2 * np.sin(p) ** 2), 0.0, np.pi / 2)[0]
        E = quad(lambda p: np.sqrt(1.0 - k2 * np.sin(p) ** 2), 0.0, np.pi / 2)[0]
        return K, E

    def ratio_minus(g):
        k2 = 1.0 - g * g
        K, E = KE(k2)
        # Johnson eq. (4.39): B/A (large over small curvature) = ((major/minor)^2 E - K) / (K - E)
        return (K - E) / (E / g**2 - K) - min(A, B) / max(A, B)

    g = brentq(ratio_minus, 1e-4, 1.0 - 1e-9, xtol=1e-15)
    K, E = KE(1.0 - g * g)
    # (A + B) = p0 E / (E* minor), p0 = 3F / (2 pi major minor), major = minor / g
    minor = (3.0 * F * E * g / (2.0 * np.pi * e_star * (A + B))) ** (1.0 / 3.0)
    major = minor / g
    approach = 3.0 * F * K / (2.0 * np.pi * major * e_star)
    return major, minor, approach


@pytest.mark.parametrize("A, B", [(0.5, 2.0), (3.0, 0.7), (1.0, 40.0), (1.0, 1.02)])
def test_against_quadrature_reference(A, B):
    F, E, nu = 8.0e4, 2.1e11, 0.3
    e_star = E / (2.0 * (1.0 - nu**2))
    h = hertz_contact(F, A, B, E, nu)
    major, minor, approach = _reference_ellipse(F, A, B, e_star)
    a_ref, b_ref = (major, minor) if A <= B else (minor, major)
    assert h.a == pytest.approx(a_ref, rel=1e-8)
    assert h.b == pytest.approx(b_ref, rel=1e-8)
    assert h.approach == pytest.approx(approach, rel=1e-8)
    assert h.p0 == pytest.approx(3.0 * F / (2.0 * np.pi * h.a * h.b), rel=1e-12)


def test_sphere_closed_form():
    # equal curvatures: a = (3 F R / (4 E*))^(1/3), delta = a^2 / R with R = 1 / (2 A)
    F, R, E, nu = 1.0e3, 0.02, 2.0e11, 0.25
    e_star = E / (2.0 * (1.0 - nu**2))
    h = hertz_contact(F, 1.0 / (2 * R), 1.0 / (2 * R), E, nu)
    a = (3.0 * F * R / (4.0 * e_star)) ** (1.0 / 3.0)
    assert h.a == pytest.approx(a, rel=1e-12)
    assert h.b == pytest.approx(a, rel=1e-12)
    assert h.approach == pytest.approx(a * a / R, rel=1e-12)


def test_swapping_curvatures_swaps_axes_and_broadcasts():
    h = hertz_contact([5e4, 1e5], [0.6, 2.5], [2.5, 0.6], 2.1e11, 0.28)
    assert h.a.shape == (2,)
    h1 = hertz_contact(5e4, 0.6, 2.5, 2.1e11, 0.28)
    h2 = hertz_contact(5e4, 2.5, 0.6, 2.1e11, 0.28)
    assert h1.a == pytest.approx(h2.b, rel=1e-14) and h1.b == pytest.approx(h2.a, rel=1e-14)
    assert h.a[0] == pytest.approx(h1.a, rel=1e-14)
    assert h1.a > h1.b  # larger semi-axis along the smaller curvature


def test_two_materials_and_load_scaling():
    # a steel wheel on a stiffer-than-steel rail: E* from both bodies
    h = hertz_contact(1e5, 1.0, 2.0, 2.1e11, 0.3, youngs_modulus_2=4.2e11, poisson_2=0.3)
    e_star = 1.0 / ((1 - 0.09) / 2.1e11 + (1 - 0.09) / 4.2e11)
    h_same = hertz_contact(1e5, 1.0, 2.0, 2.0 * e_star * (1 - 0.09), 0.3)
    assert h.a == pytest.approx(h_same.a, rel=1e-12)
    # a ~ F^(1/3), delta ~ F^(2/3)
    h8 = hertz_contact(8e5, 1.0, 2.0, 2.1e11, 0.3, youngs_modulus_2=4.2e11, poisson_2=0.3)
    assert h8.a == pytest.approx(2.0 * h.a, rel=1e-12)
    assert h8.approach == pytest.approx(4.0 * h.approach, rel=1e-12)


def test_zero_force_gives_empty_patch():
    h = hertz_contact(0.0, 1.0, 2.0, 2.1e11, 0.3)
    assert h.a == 0.0 and h.b == 0.0 and h.p0 == 0.0 and h.approach == 0.0


@pytest.mark.parametrize(
    "kwargs, name",
    [
        (dict(normal_force=-1.0), "normal_force"),
        (dict(A=0.0), "A"),
        (dict(B=-2.0), "B"),
        (dict(poisson=0.5), "poisson"),
        (dict(poisson=-0.1), "poisson"),
        (dict(youngs_modulus=0.0), "youngs_modulus"),
    ],
)
def test_bad_input(kwargs, name):
    args = dict(normal_force=1e5, A=1.0, B=2.0, youngs_modulus=2.1e11, poisson=0.3)
    args.update(kwargs)
    with pytest.raises(ScenarioError, match=name):
        hertz_contact(**args)
