"""Multi-point load sharing and the semi-Hertzian patch against Hertz (railwear.contact)."""

import numpy as np
import pytest

from railwear.contact import hertz_contact
from railwear.contact.multipoint import hertz_stiffness, semi_hertz_share, share_load
from railwear.contact.semi_hertz import hertz_matched_factors, semi_hertz_contact
from railwear.errors import ScenarioError

E, NU, LOAD = 2.1e11, 0.28, 66.7e3


@pytest.mark.parametrize("A, B, step", [
    (1 / 0.92, 0.5 * (1 / 0.3 - 1 / 0.5), 1e-4),  # the docs' tread contact, a/b = 0.72
    (1.0, 1.0, 1e-4),                              # circle
    (1 / 0.92, 1 / 0.6 * 0.2, 1e-4),               # long lateral axis
    (1 / 0.92, 20.0, 2.5e-5),                       # narrow (flange-like), b/a = 0.25
])
def test_semi_hertz_on_a_quadric_gives_hertz(A, B, step):
    """f = B s², A x²: Hertz's a, b, p0 and approach within 3e-4 (grid of 80-130 strips over
    the width). At the same approach Kik-Piotrowski's fixed ε = 0.55 would make the width
    sqrt(0.55 / ε) times Hertz's, 1-36 % off for these four."""
    hz = hertz_contact(LOAD, A, B, E, NU)
    s = np.arange(-600, 601) * step
    r = semi_hertz_contact(s, B * s**2, A, LOAD, E, NU)
    assert r.normal_force == pytest.approx(LOAD, rel=1e-10)
    assert r.half_length == pytest.approx(hz.a, rel=3e-4)
    assert r.b == pytest.approx(hz.b, rel=3e-4)
    assert r.a == pytest.approx(hz.a, rel=3e-4)  # equivalent ellipse: area / (pi b)
    assert r.p0 == pytest.approx(hz.p0, rel=3e-4)
    assert r.approach == pytest.approx(hz.approach, rel=3e-4)
    assert r.curvature == pytest.approx(B, rel=1e-3)
    assert abs(r.centroid) < 1e-3 * hz.b


def test_hertz_matched_factors():
    """The circle: ε = 1/2 and A' = A (Kik-Piotrowski with ε = 0.5 is Hertz there); a long
    lateral axis needs a larger ε (b² B / δ), a narrow patch a smaller one."""
    eps, ap = hertz_matched_factors(1.0, 1.0)
    assert eps == pytest.approx(0.5, abs=1e-6) and ap == pytest.approx(1.0, abs=1e-6)
    eps, _ = hertz_matched_factors(1.0, np.array([0.1, 10.0]))
    assert eps[0] > 0.55 > 0.5 > eps[1]


def test_share_load_one_point_is_hertz():
    """One point at contact angle γ: N = Q / cos γ, normal approach Hertz's (1e-12)."""
    A, B, gamma = 1.087, 0.667, 0.4
    K = hertz_stiffness(A, B, E, NU)
    d, N = share_load(np.array([0.0, np.inf]), np.array([K, 0.0]), np.cos(gamma), LOAD)
    assert N[0] == pytest.approx(LOAD / np.cos(gamma), rel=1e-12) and N[1] == 0.0
    hz = hertz_contact(N[0], A, B, E, NU)
    assert d * np.cos(gamma) == pytest.approx(hz.approach, rel=1e-12)


def test_share_load_sums_to_the_load():
    """Σ N cos γ = Q to 1e-12 over random gaps, stiffnesses and angles; equal points share equally."""
    rng = np.random.default_rng(3)
    g = np.where(rng.random((200, 4)) < 0.3, np.inf, rng.uniform(0, 80e-6, (200, 4)))
    g[:, 0] = 0.0
    K = rng.uniform(0.5e11, 3e11, (200, 4))
    c = np.cos(rng.uniform(0, 1.2, (200, 4)))
    d, N = share_load(g, K, c, LOAD)
    assert np.allclose((N * c).sum(-1), LOAD, rtol=1e-12, atol=0)
    assert np.all(N[g > d[:, None]] == 0.0) and np.all(N[g < d[:, None]] > 0.0)
    _, N2 = share_load(np.zeros(2), np.full(2, 1e11), 1.0, LOAD)
    assert np.allclose(N2, LOAD / 2, rtol=1e-12)


def _two_wells(g2=20e-6, B1=0.7, B2=4.0, angles=(0.02, 0.6)):
    s = np.arange(-30e-3, 30e-3 + 1e-9, 0.1e-3)
    gap = np.minimum(B1 * (s + 12e-3) ** 2, g2 + B2 * (s - 12e-3) ** 2)
    gamma = np.where(s < 0, angles[0], angles[1])
    return s, gap, gamma, (B1, B2)


def test_two_separated_semi_hertz_patches_are_their_own_hertz():
    """Two wells 24 mm apart (tread-like and flange-like): the shared vertical load is the
    multi-Hertz share within 2e-4, each patch Hertz's ellipse for its own force within 1e-3,
    and Σ N cos γ = Q to 1e-9."""
    A = 1 / 0.92
    s, gap, gamma, Bs = _two_wells()
    d, c = semi_hertz_share(s, gap, A, gamma, LOAD, E, NU)
    cos = np.cos(gamma[c["index"]])
    assert (c["normal_force"] * cos).sum() == pytest.approx(LOAD, rel=1e-9)
    # multi-Hertz with the normal-frame curvatures B cos³γ (gap curvature over the tangent plane)
    Bn = np.array(Bs) * cos**3
    K = hertz_stiffness(A, Bn, E, NU)
    dm, N = share_load(c["gap"], K, cos, LOAD)
    assert d == pytest.approx(dm, rel=2e-4)
    assert np.allclose(c["normal_force"], N, rtol=2e-4)
    for i in range(2):
        hz = hertz_contact(c["normal_force"][i], A, Bn[i], E, NU)
        assert c["half_length"][i] == pytest.approx(hz.a, rel=1e-3)
        assert 0.5 * (c["s_max"][i] - c["s_min"][i]) == pytest.approx(hz.b, rel=1e-3)
        assert c["p0"][i] == pytest.approx(hz.p0, rel=1e-3)


def test_a_far_second_well_carries_nothing():
    """A second well whose gap exceeds the approach leaves the first one alone: Hertz (3e-4)."""
    A = 1 / 0.92
    s, gap, gamma, (B1, _) = _two_wells(g2=300e-6, angles=(0.0, 0.6))
    d, c = semi_hertz_share(s, gap, A, gamma, LOAD, E, NU)
    assert c["normal_force"][1] == 0.0
    hz = hertz_contact(LOAD, A, B1, E, NU)
    assert c["normal_force"][0] == pytest.approx(LOAD, rel=1e-9)
    assert d == pytest.approx(hz.approach, rel=3e-4)


def test_inputs_are_checked():
    with pytest.raises(ScenarioError):
        share_load(np.array([-1e-6]), np.array([1e11]), 1.0, LOAD)
    with pytest.raises(ScenarioError):
        semi_hertz_contact(np.array([0.0, 1.0, 3.0, 4.0, 5.0]), np.zeros(5), 1.0, LOAD, E, NU)
