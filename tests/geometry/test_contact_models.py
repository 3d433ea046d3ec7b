"""Contact tables with several contacts per wheel (contact_model="multi-hertz" / "semi-hertzian")."""

import numpy as np
import pytest

from railwear.dynamics.table_wheelset import table_arrays
from railwear.errors import ScenarioError
from railwear.geometry import contact_table, load_profile

SHIFTS = np.round(np.linspace(-0.010, 0.010, 201), 12)
MODELS = ("multi-hertz", "semi-hertzian")


@pytest.fixture(scope="module")
def tables():
    wheel, rail = load_profile("S1002"), load_profile("UIC60")
    return {m: contact_table(wheel, rail, y=SHIFTS, contact_model=m) for m in ("hertz",) + MODELS}


@pytest.mark.parametrize("model", MODELS)
def test_forces_sum_to_the_load(tables, model):
    """Every wheel's vertical force components sum to half the axle load (1e-9), and the
    resultant's vertical part too."""
    t = tables[model]
    Q = 0.5 * t.attrs["axle_load"]
    vertical = (t.point_normal_force * np.cos(t.point_contact_angle.fillna(0.0))).sum("point")
    assert np.allclose(vertical, Q, rtol=1e-9, atol=0)
    assert np.allclose(t.normal_force * np.cos(t.contact_angle), Q, rtol=1e-9, atol=0)


def test_one_point_multi_hertz_is_the_hertz_table(tables):
    """Where one contact carries the load, the multi-Hertz table is the single-point table (1e-9)."""
    t, h = tables["multi-hertz"], tables["hertz"]
    one = (t.contact_count == 1).values
    assert one.sum() > 300
    for name in ("normal_force", "contact_angle", "rolling_radius", "wheel_contact_y", "a", "b", "c11", "c22", "c23",
                 "c33"):
        assert np.allclose(t[name].values[one], h[name].values[one], rtol=1e-9, atol=1e-13), name


@pytest.mark.parametrize("model", MODELS)
def test_dynamics_read_the_sum_of_the_points(tables, model):
    """The compiled wheelset's creep coefficients (table_arrays) are the sums over the contacts
    (1e-9), its normal force and angle the resultant's, on both wheels."""
    t = tables[model]
    _, surf, _ = table_arrays(t)
    n = t.sizes["y"]
    columns = surf.reshape(2, 8, n)  # left, right; fields; y to the left (reversed)
    for w, side in enumerate(("left", "right")):
        p = t.sel(side=side)
        for field, name in ((3, "f11"), (4, "f22"), (5, "f23"), (6, "f33")):
            assert np.allclose(columns[w, field][::-1], p[f"point_{name}"].sum("point"), rtol=1e-9, atol=0), name
        assert np.allclose(columns[w, 2][::-1], p.normal_force, rtol=1e-12)


@pytest.mark.parametrize("model", MODELS)
def test_centred_running_shares_the_tread(tables, model):
    """At y = 0 the S1002/UIC60 gap is under 10 um over 14 mm: two contacts share the load
    (3.3 / 1.9 mm and -7.7 / -7.4 mm on the wheel), against the published single patch of
    5.95 x 6.65 mm (REFERENCES.md): measured (main patch) multi-Hertz 4.30 x 8.67 mm, semi-Hertzian
    4.83 x 7.71 mm, pinned to 1 %."""
    d = tables[model].sel(y=0.0, side="right")
    N = d.point_normal_force.values
    assert (N > 0).sum() == 2
    assert N[0] / N.sum() == pytest.approx({"multi-hertz": 0.6956, "semi-hertzian": 0.6911}[model], abs=0.01)
    a, b = {"multi-hertz": (4.30e-3, 8.67e-3), "semi-hertzian": (4.83e-3, 7.71e-3)}[model]
    assert float(d.point_a[0]) == pytest.approx(a, rel=0.01)
    assert float(d.point_b[0]) == pytest.approx(b, rel=0.01)


@pytest.mark.xfail(strict=True, reason="the published 5.95 x 6.65 mm patch at y = 0 is not met (within 10 %)")
@pytest.mark.parametrize("model", MODELS)
def test_centred_patch_against_the_published_one(tables, model):
    d = tables[model].sel(y=0.0, side="right")
    assert float(d.point_a[0]) == pytest.approx(5.95e-3, rel=0.1)
    assert float(d.point_b[0]) == pytest.approx(6.65e-3, rel=0.1)


@pytest.mark.parametrize("model", MODELS)
def test_flange_contact_shares_with_the_tread(tables, model):
    """From the jump to the flange (4.9 mm) to 5.3 mm tread and flange share the load: the
    single point over-states the flange normal force by 14-139 % (pinned: at 4.9 mm more than
    120 %, at 5.3 mm 10-20 %); before the jump (4.4-4.8 mm) the flange already carries 1-22 kN
    that the single point gives to the tread."""
    t, h = tables[model].sel(side="right"), tables["hertz"].sel(side="right")

    def flange(y):
        p = t.sel(y=y)
        k = int(np.nanargmax(p.point_contact_angle.values))
        return float(p.point_normal_force[k]), float(p.point_contact_angle[k])

    over = {y: float(h.normal_force.sel(y=y)) / flange(y)[0] - 1 for y in (0.0049, 0.0053)}
    assert over[0.0049] > 1.2 and 0.1 < over[0.0053] < 0.2
    n, angle = flange(0.0046)
    assert 5e3 < n < 15e3 and angle > 0.25
    assert float(h.contact_angle.sel(y=0.0046)) < 0.15  # the single point sits on the tread (7 deg)
    assert int(t.contact_count.sel(y=0.008)) == 1  # deep in the flange the tread is lifted off


def test_contact_model_is_checked():
    wheel, rail = load_profile("S1002"), load_profile("UIC60")
    with pytest.raises(ScenarioError, match="contact_model"):
        contact_table(wheel, rail, y=SHIFTS[:5], contact_model="kalker")


def test_semi_hertzian_tables_carry_the_strips(tables):
    """Each loaded semi-hertzian patch as STRIPS strips of equal width across it: their area
    2 Σ L w is the patch's within 0.3 % (measured 0.24 % at most, the strips' midpoint rule), the
    longest is the patch's half-length within 0.5 %, the centres lie inside the patch's edges on
    the wheel profile and their radii are the wheel's there. The other models carry none."""
    from railwear.contact.semi_hertz import STRIPS

    t = tables["semi-hertzian"]
    N, L, w = (t[v].values for v in ("point_normal_force", "point_strip_half_length", "point_strip_width"))
    on = N > 0
    assert L.shape == N.shape + (STRIPS,) and t.point_strip_half_length.dims[-1] == "strip"
    area = 2 * L.sum(-1) * w
    assert np.max(np.abs(area[on] / t.point_area.values[on] - 1)) < 3e-3
    assert np.max(np.abs(L.max(-1)[on] / t.point_half_length.values[on] - 1)) < 5e-3
    y = t.point_strip_wheel_y.values
    assert np.all(y[on] >= t.point_lateral_min.values[on][:, None] - 1e-12)
    assert np.all(y[on] <= t.point_lateral_max.values[on][:, None] + 1e-12)
    assert np.all(np.diff(y[on], axis=-1) > 0) and np.all(L[~on] == 0)
    wheel = load_profile("S1002")
    assert np.allclose(t.point_strip_rolling_radius.values[on], t.attrs["nominal_rolling_radius"] + wheel(y[on]),
                       rtol=0, atol=1e-12)
    for model in ("hertz", "multi-hertz"):
        assert not any(v.startswith("point_strip") for v in tables[model].data_vars)


def test_strips_of_a_quadric_gap_are_hertz():
    """On a quadric separation the semi-Hertzian patch is Hertz's ellipse (module docstring), so
    its strips have L = a sqrt(1 - s²/b²) to the sampling's accuracy (0.025 mm)."""
    from railwear.contact.hertz import effective_modulus, hertz_contact
    from railwear.contact.semi_hertz import _APRIME, _EPS, _U, patch_kernel, patch_strips, semi_hertz_contact

    s = np.arange(-2400, 2401) * 2.5e-5
    f = 0.667 * s**2
    r = semi_hertz_contact(s, f, 1.087, 66.7e3, 2.1e11, 0.28)
    h = hertz_contact(66.7e3, 1.087, 0.667, 2.1e11, 0.28)
    estar = float(effective_modulus(2.1e11, 0.28))
    out = patch_kernel(f, 2400, 2.5e-5, 1.087, r.approach, estar, _U, _EPS, _APRIME, np.empty(s.size))
    L = np.empty(32)
    width = patch_strips(f, 2400, 2.5e-5, 1.087, r.approach, out[7], out[8], out[3], out[4], _U, _EPS, _APRIME, L)
    centre = out[3] + (np.arange(32) + 0.5) * width
    assert width == pytest.approx(2 * h.b / 32, rel=1e-3)
    assert np.max(np.abs(L - h.a * np.sqrt(np.clip(1 - (centre / h.b) ** 2, 0, None)))) < 2e-3 * h.a
