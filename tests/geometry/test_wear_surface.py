"""Deposition on the wear surface: volume conserved to round-off, exact overlaps, the seam."""

import numpy as np
import pytest

from railwear.contact import fastsim
from railwear.errors import ScenarioError
from railwear.geometry.wear_surface import WearSurface


def surface(n_angle=360, n_lateral=20):
    return WearSurface(0.46, n_angle, np.linspace(-0.02, 0.02, n_lateral + 1))


@pytest.mark.parametrize("footprint", ["hertz", "uniform", "point"])
def test_volume_conserved_everywhere_and_at_the_seam(footprint):
    rng = np.random.default_rng(2)
    w = surface()
    n = 200
    angle = np.concatenate([rng.uniform(0, 2 * np.pi, n - 3), [0.0, 2 * np.pi - 1e-5, 2 * np.pi]])
    volume = rng.uniform(0, 1e-9, n)
    added = w.deposit(volume, angle, rng.uniform(-0.025, 0.025, n), a=6e-3, b=5e-3, footprint=footprint)
    assert added == pytest.approx(volume.sum(), rel=1e-13)
    assert w.removed_volume() == pytest.approx(volume.sum(), rel=1e-13)


def test_rectangle_overlap_is_exact():
    """A uniform patch from 0.25 to 1.75 cells along and one cell across: half in each of two cells."""
    w = surface(n_angle=100, n_lateral=4)
    dx = w.circumference / 100
    w.deposit_cells(2e-9, 0.0, -0.015, x=np.array([dx]), s=0.0, dx=1.5 * dx, ds=0.01, density=1.0)
    expected = np.zeros_like(w.depth)
    expected[0, 0] = expected[1, 0] = 1e-9 / w.cell_area
    np.testing.assert_allclose(w.depth, expected, rtol=1e-12, atol=1e-12 * expected.max())


def test_patch_on_the_seam_splits_evenly():
    w = surface(n_angle=120, n_lateral=4)
    w.deposit(1e-9, 0.0, -0.015, a=6e-3, b=4e-3, footprint="uniform")
    assert w.depth[0].sum() == pytest.approx(w.depth[-1].sum(), rel=1e-12)
    assert w.depth[1:-1].sum() == 0


def test_point_mode_hits_one_cell():
    w = surface(n_angle=100, n_lateral=4)
    w.deposit(1e-9, 2 * np.pi * 42.5 / 100, 0.001, footprint="point")
    assert np.count_nonzero(w.depth) == 1 and w.depth[42, 2] == pytest.approx(1e-9 / w.cell_area)


def test_hertz_footprint_is_resolved_and_centred():
    w = WearSurface(0.46, 4096, np.linspace(-0.02, 0.02, 161))
    w.deposit(1e-9, np.pi, 0.0, a=6e-3, b=5e-3, n=32)
    x = (w.angle - np.pi) * w.radius
    s = 0.5 * (w.lateral_edges[1:] + w.lateral_edges[:-1])
    weights = w.depth / w.depth.sum()
    assert abs((weights.sum(axis=1) * x).sum()) < 1e-6 and abs((weights.sum(axis=0) * s).sum()) < 1e-6
    # second moment of the Hertz pressure over the ellipse: a²/5 along, b²/5 across
    assert (weights.sum(axis=1) * x**2).sum() == pytest.approx(6e-3**2 / 5, rel=0.03)
    assert (weights.sum(axis=0) * s**2).sum() == pytest.approx(5e-3**2 / 5, rel=0.03)


def test_fastsim_power_density_deposit_conserves():
    r = fastsim(6e-3, 5e-3, 80e3, 1e-3, 0.0, 0.0, 0.3, 82e9, 0.28, nx=20, ny=20)
    w = surface(n_angle=2048, n_lateral=80)
    added = w.deposit_fastsim(3e-10, 1.0, 0.0, r)
    assert added == pytest.approx(3e-10, rel=1e-13)
    # the power is spread over the patch length: the cells span about 2a along and 2b across
    rows = np.flatnonzero(w.depth.sum(axis=1))
    assert (rows.size - 2) * w.circumference / 2048 <= 2 * 6e-3 + 1e-12


def test_bad_input():
    with pytest.raises(ScenarioError):
        surface().deposit(-1.0, 0.0, 0.0, a=6e-3, b=5e-3)
    with pytest.raises(ScenarioError):
        surface().deposit(1.0, 0.0, 0.0, a=0.0, b=5e-3)
    with pytest.raises(ScenarioError):
        WearSurface(0.46, 100, [0.0, 0.1, 0.15])
