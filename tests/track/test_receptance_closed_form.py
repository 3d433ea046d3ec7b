"""The closed-form spans and Floquet waves against the eigen-decomposition path they replace.

The reference is the former implementation: ``P = V e^{μx} V⁻¹`` from ``numpy.linalg.eig`` of
``A`` (scipy's ``expm`` where ``|μ| x < 0.1``), and the waves from ``numpy.linalg.eig`` of the
cell matrix sorted by ``|λ| < 1`` (here of the cell from a sleeper, carried to the load as the
module carries its own). Both carry round-off that grows with ``e^{2 k L}`` (about 1e-12 at 6 kHz);
they agree to 1e-10 relative from 0 to 10 kHz.
"""

import sys

import numpy as np
import pytest
from scipy.linalg import expm

from railwear.track import Support, Track, rail, receptance
from railwear.track.receptance import _split_waves, _Spans, system_matrix

module = sys.modules["railwear.track.receptance"]
SEAT = Support(pad_stiffness=1.2e8, pad_loss_factor=0.25, sleeper_mass=150.0, ballast_stiffness=5e7,
               ballast_loss_factor=1.0)
F = np.concatenate([[0.0, 0.5], np.geomspace(1.0, 1e4, 200)])  # Hz


def eig_span(A, x):
    if x == 0.0:
        return np.broadcast_to(np.eye(4, dtype=complex), A.shape).copy()
    mu, V = np.linalg.eig(A)
    short = np.max(np.abs(mu), axis=-1) * abs(x) < 0.1
    P = np.empty(A.shape, dtype=complex)
    P[~short] = V[~short] @ (np.exp(mu[~short] * x)[..., None] * np.linalg.inv(V[~short]))
    if np.any(short):
        P[short] = expm(A[short] * x)
    return P


class EigSpans:
    def __init__(self, A):
        self.A = A

    def at(self, x):
        return eig_span(self.A, x)

    def powers(self, X):
        return (X,)

    def apply(self, x, powers):
        return self.at(x) @ powers[0]


def eig_waves(T):
    lam, vecs = np.linalg.eig(T)
    _, _, order = _split_waves(vecs, np.abs(lam) < 1.0)
    return np.take_along_axis(lam, order, axis=-1), np.take_along_axis(vecs, order[:, None, :], axis=-1)


def eig_receptance(monkeypatch, *args):
    with monkeypatch.context() as m:
        m.setattr(module, "_Spans", EigSpans)
        m.setattr(module, "_waves", eig_waves)
        m.setattr(module, "_CELL", {})  # the waves of the last call are kept: not these
        return receptance(*args)


@pytest.mark.parametrize("beam", ["euler", "timoshenko"])
@pytest.mark.parametrize("loss_factor", [0.0, 0.02])
def test_discrete_receptance_equals_the_eigen_decomposition(monkeypatch, beam, loss_factor):
    track = Track(rail("60E1", loss_factor=loss_factor), SEAT, sleeper_spacing=0.6, beam=beam)
    for position in ("midspan", "sleeper", 0.07):
        new, old = receptance(track, F, position), eig_receptance(monkeypatch, track, F, position)
        assert np.max(np.abs(new / old - 1)) < 1e-10, position
    at = np.linspace(-2.7, 2.7, 7)  # transfer, four bays either side
    new, old = receptance(track, F, "midspan", at), eig_receptance(monkeypatch, track, F, "midspan", at)
    assert np.max(np.abs(new - old) / np.max(np.abs(old), axis=1, keepdims=True)) < 1e-10


@pytest.mark.parametrize("beam", ["euler", "timoshenko"])
def test_spans_equal_the_matrix_exponential(beam):
    """Entry by entry against the eigen path (and expm below ``|μ| x = 0.1``), on the series
    (``|s| x² < 1``) and the closed-form branches, at 0 Hz too (then ``A`` is nilpotent)."""
    track = Track(rail("60E1", loss_factor=0.02), SEAT, sleeper_spacing=0.6, beam=beam)
    A = system_matrix(track, 2 * np.pi * F)
    spans = _Spans(A)
    for x in (1e-3, 0.07, 0.3, 0.6):
        new, old = spans.at(x), eig_span(A, x)
        scale = np.max(np.abs(old), axis=(1, 2), keepdims=True)
        assert np.max(np.abs(new - old) / scale) < 1e-11, x
    assert np.array_equal(spans.at(0.0), np.broadcast_to(np.eye(4), A.shape))


def test_a_singular_shift_falls_back_on_eig(monkeypatch):
    """Where a shifted cell matrix is singular to the last bit, the waves come from
    ``numpy.linalg.eig`` (forced here: the inverse iteration's solve refuses)."""
    track = Track(rail("60E1", loss_factor=0.02), SEAT, sleeper_spacing=0.6, beam="timoshenko")
    solve = np.linalg.solve

    def refuse(a, b):
        if np.ndim(a) == 4:  # the inverse iteration's stack, one 4 x 4 system per frequency and wave
            raise np.linalg.LinAlgError("Singular matrix")
        return solve(a, b)

    expected = receptance(track, F[::20], "midspan")
    with monkeypatch.context() as m:
        m.setattr(module.np.linalg, "solve", refuse)
        m.setattr(module, "_CELL", {})
        fallback = receptance(track, F[::20], "midspan")
    assert np.max(np.abs(fallback / expected - 1)) < 1e-10


@pytest.mark.parametrize("beam", ["euler", "timoshenko"])
def test_spans_carry_waves_as_the_matrix_does(beam):
    """``apply`` (a sum over the powers ``A^j X``) is ``P(x) X`` to round-off of ``P``'s scale, at
    0 m exactly, and on the ``expm`` branch (roots forced close) too."""
    track = Track(rail("60E1", loss_factor=0.02), SEAT, sleeper_spacing=0.6, beam=beam)
    spans = _Spans(system_matrix(track, 2 * np.pi * F))
    X = np.random.default_rng(3).standard_normal((F.size, 4, 2)) * (1 + 1j)
    powers = spans.powers(X)
    for x in (-0.6, -0.07, 1e-3, 0.3):
        P = spans.at(x)
        scale = np.max(np.abs(P), axis=(1, 2))[:, None, None] * np.max(np.abs(X), axis=(1, 2))[:, None, None]
        assert np.max(np.abs(spans.apply(x, powers) - P @ X) / scale) < 1e-13, x
    assert np.array_equal(spans.apply(0.0, powers), X)
    spans.s2 = spans.s1 * (1 + 1e-8)  # every root pair "close": expm of A x carries X
    assert np.max(np.abs(spans.apply(0.3, powers) - spans.at(0.3) @ X)) <= 1e-13 * np.max(np.abs(spans.at(0.3) @ X))


def test_amplitudes_solve_the_jump_condition():
    """Cramer's rule on the waves at the load gives ``right a - left b = f`` (the unit force's jump)
    to round-off, against ``numpy.linalg.solve`` on the same matrices."""
    for beam in ("euler", "timoshenko"):
        track = Track(rail("60E1", loss_factor=0.02), SEAT, sleeper_spacing=0.6, beam=beam)
        omega = 2 * np.pi * F
        spans, _, _, right_waves, left_waves = module._cell(track, omega)
        right, left = spans.apply(0.25 - 0.6, right_waves), spans.apply(0.25, left_waves)
        a, b = module._amplitudes(track, right, left)
        row, unit = module._jump_row(track)
        M = np.concatenate([right, -left], axis=-1)
        f = np.zeros((omega.size, 4), complex)
        f[:, row] = unit
        expected = np.linalg.solve(M, f[..., None])[..., 0]
        got = np.concatenate([a, b], axis=1)
        assert np.max(np.abs(got - expected) / np.max(np.abs(expected), axis=1, keepdims=True)) < 1e-11, beam
