import numpy as np
import pytest

from railwear.errors import ScenarioError
from railwear.geometry.profiles import (
    Profile,
    circular_profile,
    conical_profile,
    load_profile,
    read_simpack_profile,
    worn_profile,
)


def test_s1002_facts():
    w = load_profile("S1002")
    assert w.kind == "wheel" and w.name == "S1002"
    lo, hi = w.span
    # the file spans y from -60 mm to 69.6 mm; mirror.y puts the flange on the gauge side (y < 0)
    assert lo == pytest.approx(-69.612628e-3, abs=1e-9) and hi == pytest.approx(60.0e-3, abs=1e-9)
    assert w(0.0) == pytest.approx(0.0, abs=1e-7)  # taping line
    assert np.max(w.z) == pytest.approx(28.0e-3, abs=0.01e-3)  # flange height 28.0 mm
    assert w.y[np.argmax(w.z)] < -0.04  # flange tip on the gauge side


def test_uic60_facts_and_head_radii():
    r = load_profile("uic60")
    assert r.kind == "rail" and r.cant == pytest.approx(1 / 40)
    lo, hi = r.span
    assert lo == pytest.approx(-43.704898e-3, abs=1e-9) and hi == pytest.approx(30.595912e-3, abs=1e-9)
    # origin at the highest point of the canted head: z = 0 with zero slope
    assert r(0.0) == pytest.approx(0.0, abs=1e-7) and abs(r.slope(0.0)) < 1e-3
    assert np.min(r.z) >= -1e-9
    # head radii 300 / 80 / 13 mm (REFERENCES.md), on both sides of the head
    radius = 1.0 / r.curvature(np.array([-0.005, 0.0, -0.02, 0.01, -0.035, 0.022]))
    assert radius == pytest.approx([0.300, 0.300, 0.080, 0.080, 0.013, 0.013], rel=2e-3)


@pytest.mark.parametrize("name", ["S1002", "UIC60"])
def test_profile_is_continuous_and_smooth(name):
    p = load_profile(name)
    y = np.linspace(*p.span, 20001)
    z = p(y)
    # no jumps: neighbouring values differ by at most the steepest slope times the step
    assert np.max(np.abs(np.diff(z))) <= np.max(np.abs(p.slope(y))) * (y[1] - y[0]) * 1.01
    # the spline passes through the table and, where contact can occur (slopes below 3, contact
    # angles below 72 deg), stays within 0.01 mm of a shape-preserving (monotone) interpolant
    from scipy.interpolate import PchipInterpolator

    assert np.allclose(p(p.y), p.z, atol=1e-12)
    mid = 0.5 * (p.y[1:] + p.y[:-1])
    usable = np.abs(p.slope(mid)) < 3.0
    assert np.max(np.abs(p(mid) - PchipInterpolator(p.y, p.z)(mid))[usable]) < 0.01e-3


def test_reader_honours_mirror_units_and_rejects_missing_table(tmp_path):
    f = tmp_path / "cone.prw"
    f.write_text(
        "header.begin\n type = 1\nheader.end\nspline.begin\n mirror.y = 1 ! flip\n units.len.f = 1000\n"
        " point.begin\n 10 0.5\n 0 0\n! 5 9 commented out\n -10 -0.5\n -20 -1.0\n point.end\nspline.end\n"
    )
    p = read_simpack_profile(f)
    assert p.kind == "wheel"
    assert p.y == pytest.approx([-0.01, 0.0, 0.01, 0.02]) and p.z == pytest.approx([5e-4, 0, -5e-4, -1e-3])
    bad = tmp_path / "empty.prr"
    bad.write_text("header.begin\n type = 0\nheader.end\n")
    with pytest.raises(ScenarioError, match="no point table"):
        read_simpack_profile(bad)
    with pytest.raises(ScenarioError, match="cannot be read"):
        load_profile(tmp_path / "missing.prr")


def test_analytic_profiles():
    cone = conical_profile(0.05)
    y = np.linspace(-0.06, 0.06, 7)
    assert cone(y) == pytest.approx(-0.05 * y, abs=1e-15) and cone.curvature(y) == pytest.approx(0, abs=1e-9)  # rounding in the spline
    head = circular_profile(0.3, kind="rail")
    assert 1 / head.curvature(np.array([-0.02, 0.0, 0.02])) == pytest.approx(0.3, rel=1e-6)
    barrel = circular_profile(0.5, kind="wheel")
    assert barrel(0.01) < 0 and barrel.curvature(0.0) == pytest.approx(-2.0, rel=1e-6)
    with pytest.raises(ScenarioError, match="radius"):
        circular_profile(0.01, half_width=0.03)


def test_worn_profile():
    w = load_profile("S1002")
    u = -1e-4 * np.exp(-((w.y / 0.01) ** 2))  # 0.1 mm hollow worn at the taping line
    worn = worn_profile(w, u)
    assert worn(0.0) == pytest.approx(-1e-4, abs=1e-9)
    assert worn(0.04) == pytest.approx(w(0.04), abs=1e-9)
    rows = worn_profile(w, np.vstack([u, 2 * u]))
    assert len(rows) == 2 and rows[1](0.0) == pytest.approx(-2e-4, abs=1e-9)
    with pytest.raises(ScenarioError, match="deviation"):
        worn_profile(w, u[:-1])


@pytest.mark.parametrize("inclination", [1 / 20, 1 / 10, 0.0])
def test_recanted_rail_stays_a_function_of_y(inclination):
    """UIC60 re-canted from its 1/40: the near-vertical gauge face rotated past the vertical folds
    back under the corner; the hidden part is dropped, so the spline stays on the head (it had
    swung by kilometres at 1/20) and rotating back to 1/40 gives the original head to 1e-9 m."""
    rail = load_profile("UIC60")
    tilted = rail.canted(inclination)
    assert np.all(np.diff(tilted.y) > 0.0)
    ys = np.linspace(*tilted.span, 20001)
    assert np.max(np.abs(tilted(ys))) < np.max(np.abs(rail.z)) + 1e-3
    back = tilted.canted(1 / 40)
    head = np.linspace(-0.030, 0.028, 300)  # crown and gauge corner, away from the dropped face
    np.testing.assert_allclose(back(head), rail(head), atol=1e-9)


def test_contact_table_on_a_rail_at_1_in_20():
    """S1002 on UIC60 at 1/20: finite Hertz patches near the tread at small shifts (it had put the
    axle 110 mm low with b = 0.4 um)."""
    from railwear.geometry import contact_table

    table = contact_table(load_profile("S1002"), load_profile("UIC60"), y=np.array([-0.002, 0.0, 0.002]), cant=1 / 20)
    right = table.sel(side="right")
    assert np.all(np.abs(right.rolling_radius.values - 0.46) < 1e-3)
    assert np.all((right.a.values > 2e-3) & (right.a.values < 15e-3))
    assert np.all((right.b.values > 1e-3) & (right.b.values < 15e-3))


def test_a_spline_that_swings_between_points_is_refused():
    rail = load_profile("UIC60")
    c, s = np.cos(0.025), np.sin(0.025)
    with pytest.raises(ScenarioError, match="swings"):
        Profile(y=c * rail.y + s * rail.z, z=-s * rail.y + c * rail.z, kind="rail", name="raw")
