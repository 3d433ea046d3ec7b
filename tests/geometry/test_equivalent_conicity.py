"""Equivalent conicity by EN 15302 (integration, Annex B) when Δr(y) is not odd.

EN 15302's integration method: the reference point is where Δr = 0; the kinematic motion runs
between two turning points on one level of the potential ``∫ Δr dy``, and its amplitude is half the
distance between them (half the peak-to-peak motion); the wavelength of that motion gives the
conicity by Klingel's formula. The Δr tables here are built so that the answer is known in closed
form (piecewise-linear Δr: harmonic arcs and uniformly decelerated flight), or, on real profiles,
from an independent time integration of Klingel's equation.
"""

import numpy as np
import pytest
import xarray as xr
from scipy.integrate import solve_ivp

from railwear.errors import ScenarioError
from railwear.geometry.contact_geometry import contact_table, equivalent_conicity
from railwear.geometry.profiles import load_profile
from railwear.units import MM

E0, R0 = 0.75, 0.46  # half the contact-point distance and rolling radius of the built tables [m]
Y = np.round(np.linspace(-12 * MM, 12 * MM, 481), 12)  # 0.05 mm: every kink below is a node


def dr_table(dr, y=Y):
    """A contact table reduced to what the conicity reads: Δr(y), contact_Y, rolling_radius."""
    n = y.size
    return xr.Dataset(
        dict(rolling_radius_difference=("y", dr),
             contact_Y=(("y", "side"), np.stack([np.full(n, E0), np.full(n, -E0)], axis=1)),
             rolling_radius=(("y", "side"), np.full((n, 2), R0))),
        coords=dict(y=y, side=["right", "left"]),
    )


def test_offset_linear_dr_has_its_slope_at_every_amplitude():
    """Δr = 2 λ (y - y0): harmonic about y0 for every amplitude, conicity λ, turning points y0 ± A.
    (Started at rest at y = +A, as before, small amplitudes came out 4 λ.)"""
    lam, y0 = 0.15, 2 * MM
    t = dr_table(2 * lam * (Y - y0))
    amps = np.array([0.2, 0.5, 1.0, 1.9, 3.0, 6.0]) * MM
    got, orbit = equivalent_conicity(t, amps, full_output=True)
    print("\noffset linear, conicity - 0.15:", got - lam)
    assert np.allclose(got, lam, rtol=1e-8)
    assert orbit.equilibrium == pytest.approx(y0, abs=1e-15)
    assert np.allclose(orbit.y_min, y0 - amps, rtol=0, atol=1e-12)
    assert np.allclose(orbit.y_max, y0 + amps, rtol=0, atol=1e-12)
    assert np.allclose(orbit.wavelength, 2 * np.pi * np.sqrt(E0 * R0 / lam), rtol=1e-8)


def _flat_centred_orbit(k, d, b, z1):
    """Orbit of Δr = 2k (y + d) + c (y < -d), c (|y| <= d), 2k (y - d) + c (y > d), c = 2 k b > 0,
    from its left turning point z1 < 0 (z = y - y*, y* = -d - b): (amplitude, conicity)."""
    level = k * z1**2  # potential W(z) = k z² on the left branch
    half = (np.arcsin(min(b / -z1, 1.0)) + np.pi / 2) / np.sqrt(k)  # harmonic arc to z = b (or back)
    if level <= k * b**2:
        z2 = -z1
    else:
        flat_top = k * b**2 + 4 * k * b * d  # W at the far edge of the flat zone, z = b + 2d
        z_end = b + (min(level, flat_top) - k * b**2) / (2 * k * b)
        half += (np.sqrt(level - k * b**2) - np.sqrt(max(level - flat_top, 0.0))) / (k * b)  # W linear
        z2 = z_end
        if level > flat_top:  # on the right branch, W = 4 k b d + k (z - 2d)²: harmonic about 2d
            radius = np.sqrt((level - 4 * k * b * d) / k)
            half += (np.pi / 2 - np.arcsin(b / radius)) / np.sqrt(k)
            z2 = 2 * d + radius
    return 0.5 * (z2 - z1), np.pi**2 / half**2


def test_flat_centred_offset_dr_against_closed_form():
    """A flat centre (Δr = c = 0.6 mm for |y| <= 3 mm, slope 2 × 0.6 outside): the wheelset
    settles at y* = -3.5 mm, where Δr = 0. Small orbits stay on the steep branch (conicity 0.6),
    larger ones cross the flat zone and come back from the far branch. The least-squares slope
    over |y| <= A is zero for A <= 3 mm, which used to return 0."""
    k, d, c = 0.6, 3 * MM, 0.6 * MM
    b = c / (2 * k)
    dr = np.where(Y < -d, 2 * k * (Y + d), np.where(Y > d, 2 * k * (Y - d), 0.0)) + c
    t = dr_table(dr)
    z1 = -np.array([0.2, 0.45, 0.8, 1.5, 2.5, 3.5]) * MM  # left turning points about y*
    amps, exact = np.array([_flat_centred_orbit(k, d, b, z) for z in z1]).T
    got, orbit = equivalent_conicity(t, amps, full_output=True)
    print("\nflat centre: amplitude [mm]", np.round(amps / MM, 4), "\n  closed form", np.round(exact, 5),
          "\n  railwear   ", np.round(got, 5), "\n  regression slope",
          np.round(equivalent_conicity(t, amps, method="regression"), 4))
    assert exact[0] == exact[1] == pytest.approx(k, rel=1e-12)  # harmonic on the branch
    assert exact[2:].min() < 0.3 and exact[-1] > exact[-2]  # through the flat zone, then the far branch
    assert np.allclose(got, exact, rtol=1e-6)
    assert orbit.equilibrium == pytest.approx(-d - b, abs=1e-15)
    assert np.allclose(orbit.y_min, -d - b + z1, rtol=0, atol=1e-10)


def test_flat_bottomed_well_off_centre():
    """Δr = 0 over 2 mm about y = +1 mm (e.g. a worn pair), slope 2 × 0.3 outside: no restoring
    force inside the flat bottom, so no motion of amplitude below 1 mm (conicity 0); above it the
    wheelset crosses the bottom freely and turns on the branches, half period
    π / sqrt(k) + 2 d / sqrt(E) at the level E = k (A - d)²."""
    k, d, s = 0.3, 1 * MM, 1 * MM
    u = Y - s
    t = dr_table(np.where(u < -d, 2 * k * (u + d), np.where(u > d, 2 * k * (u - d), 0.0)))
    amps = np.array([0.5, 0.99, 1.2, 2.0, 3.0, 5.0]) * MM
    got, orbit = equivalent_conicity(t, amps, full_output=True)
    level = k * np.maximum(amps - d, 0.0) ** 2
    with np.errstate(divide="ignore"):
        exact = np.where(amps > d, np.pi**2 / (np.pi / np.sqrt(k) + 2 * d / np.sqrt(level)) ** 2, 0.0)
    print("\nflat-bottomed well: closed form", np.round(exact, 5), "railwear", np.round(got, 5))
    assert np.all(got[:2] == 0.0) and np.all(np.isnan(orbit.y_min[:2]))
    assert np.allclose(got, exact, rtol=1e-6)
    assert orbit.equilibrium == pytest.approx(s, abs=1e-15)
    assert np.allclose(0.5 * (orbit.y_min + orbit.y_max)[2:], s, rtol=0, atol=1e-12)


@pytest.fixture(scope="module")
def s1002_table():
    w, r = load_profile("S1002"), load_profile("UIC60")
    return contact_table(w, r, gauge=1.435, cant=1 / 40, back_to_back=1.360, axle_load=133.4e3,
                         y=np.round(np.linspace(-10 * MM, 10 * MM, 401), 12))


def _time_integration(table, y_start, e0r0):
    """Klingel's equation integrated in distance from rest at y_start until the velocity has
    crossed zero twice (solve_ivp, linear Δr as the conicity code reads it): (y_min, y_max,
    wavelength, its Klingel conicity, the three turning points)."""
    y, dr = table.y.values, table.rolling_radius_difference.values

    def turning(_, s):
        return s[1]

    state, travelled, ends = np.array([y_start, 0.0]), 0.0, [y_start]
    for direction in (-1.0, 1.0):  # rest at the left turning point: first the velocity falls to 0
        turning.direction = direction
        sol = solve_ivp(lambda _, s: [s[1], -np.interp(s[0], y, dr) / (2 * e0r0)], (0.0, 200.0), state,
                        events=turning, rtol=1e-8, atol=1e-12)
        travelled += sol.t_events[0][0]
        state = sol.y_events[0][0]
        ends.append(state[0])
    return min(ends), max(ends), travelled, 4 * np.pi**2 * e0r0 / travelled**2, ends


def test_diameter_difference_on_s1002_uic60(s1002_table):
    """Wheels 2 mm apart in diameter (Δr + 1 mm, the first-order effect; EN 15302's own asymmetric
    reference cases use 920 / 918 mm): the wheelset runs about y* ≈ -3 mm, where Δr = 0. The
    orbit railwear finds for the amplitude of a time-integrated oscillation has its turning points,
    wavelength and conicity."""
    t = s1002_table.copy()
    t["rolling_radius_difference"] = s1002_table.rolling_radius_difference + 1 * MM
    at = t.isel(y=int(np.argmin(np.abs(t.rolling_radius_difference.values))))  # where e0, r0 are read
    e0r0 = 0.5 * float(at.contact_Y.sel(side="right") - at.contact_Y.sel(side="left")) * float(at.rolling_radius.mean())
    rows = []
    for y_start in (-4.0 * MM, -5.6 * MM):  # on the tread; the second reaches the flange
        lo, hi, wavelength, lam_ode, ends = _time_integration(t, y_start, e0r0)
        assert ends[2] == pytest.approx(ends[0], abs=1e-8)  # a closed orbit
        amp = 0.5 * (hi - lo)
        lam, orbit = equivalent_conicity(t, amp, full_output=True)
        rows.append((amp / MM, lam, lam_ode))
        assert lam == pytest.approx(lam_ode, rel=1e-5)  # the time integration's tolerance
        assert float(orbit.y_min[0]) == pytest.approx(lo, abs=2e-8)
        assert float(orbit.y_max[0]) == pytest.approx(hi, abs=2e-8)
        assert float(orbit.wavelength[0]) == pytest.approx(wavelength, rel=1e-5)
    eq = orbit.equilibrium
    assert np.interp(eq, t.y.values, t.rolling_radius_difference.values) == pytest.approx(0.0, abs=1e-15)
    assert -3.2 * MM < eq < -2.8 * MM
    print("\nS1002/UIC60, Δr + 1 mm: y* = %.3f mm; amplitude [mm], conicity:" % (eq / MM),
          [(round(float(a), 3), round(float(c), 4)) for a, c, _ in rows],
          "\n  relative difference from the time integration:", [float(f"{c / o - 1:.1e}") for _, c, o in rows])
    # the symmetric pair at the same amplitude: the offset changes the answer, not just the centre
    sym = equivalent_conicity(s1002_table, np.array([r[0] for r in rows]) * MM)
    print("  symmetric pair at those amplitudes:", np.round(sym, 4))
    assert np.all(np.abs(np.array([r[1] for r in rows]) - sym) > 0.02)
    # and for the odd Δr of the symmetric pair the orbit about y* = 0 is the one started at rest at
    # +A: the values of the previous integration (an rtol 1e-10 ODE) at 1 ... 5 mm
    before = {1: 0.3698003393, 2: 0.2292615831, 3: 0.1835858802, 4: 0.1649549092, 5: 0.2183451114}
    got = equivalent_conicity(s1002_table, np.array(list(before)) * MM)
    assert np.allclose(got, list(before.values()), rtol=2e-7)


def test_no_well_no_motion_and_table_range():
    # Δr > 0 everywhere: the potential has no minimum, nothing brings the wheelset back
    assert equivalent_conicity(dr_table(0.3 * Y + 5 * MM), 1 * MM) == 0.0
    # an orbit about y* = 2 mm of amplitude 11 mm would leave the table (-12 ... 12 mm); 9.9 mm fits
    with pytest.raises(ScenarioError, match="amplitude"):
        equivalent_conicity(dr_table(0.3 * (Y - 2 * MM)), 11 * MM)
    assert equivalent_conicity(dr_table(0.3 * (Y - 2 * MM)), 9.9 * MM) == pytest.approx(0.15, rel=1e-8)
    with pytest.raises(ScenarioError, match="amplitude"):
        equivalent_conicity(dr_table(0.3 * Y), -1 * MM)
