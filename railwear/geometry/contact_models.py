"""Multi-point and semi-Hertzian contact of a wheelset on real profiles, for ``contact_table``.

The rigid geometry (``contact_geometry``) gives, per shift and wheel, every local minimum of the
vertical gap across the profile: its gap ``g_i`` over the touching point (0 for the primary),
its place on the wheel and the rail. With ``contact_model``:

- ``"multi-hertz"``: every minimum is a Hertz contact of its own local curvatures
  (``A = cos γ / (2 r)``, ``B = (κ_rail + κ_wheel) / 2``); the wheel's vertical approach is
  shared, ``Σ N_i cos γ_i = Q`` (:func:`railwear.contact.multipoint.share_load`);
- ``"semi-hertzian"``: around every minimum the gap is sampled on ``step`` (0.1 mm) across the
  wheel profile, turned into the normal separation of its tangent plane
  (``f = (g - g_i) cos γ_i`` over ``s = Δy / cos γ_i``), and each interpenetration region is a
  semi-Hertzian patch (:mod:`railwear.contact.semi_hertz`) under the shared approach
  (:func:`railwear.contact.multipoint._semi_wheel`), cut at the largest gap between it and its
  neighbouring minimum (the watershed).
  Its place is the load centroid, its creep coefficients Kalker's for the ellipse of the same
  area and width (``b`` half the width, ``a = area / (π b)``).

The compiled dynamics read one contact per wheel, so the table also gives the *resultant*:
normal force and contact angle of the vector sum of the points' normal forces (the vertical part
is ``Q``, the lateral part exact); creep coefficients ``F_kl = Σ f_kl,i`` (exact for the linear
forces when the points share the creepages); rolling radius, contact position and ``contact_X``
weighted by each point's share ``w_i = f11,i / F11`` (so the longitudinal creep force
``Σ f11,i ξ_i`` is exact: ``ξ`` is linear in the rolling radius); ``a = Σ w_i a_i`` and
``b = Σ a_i b_i / a`` (the total area); Kalker's ``C_kl`` of the table are then
``F_kl / (G c^k)`` with ``c² = a b``, so that ``table_arrays`` returns ``F_kl``.
"""

import numpy as np
from railwear.contact import hertz_contact, kalker_coefficients
from railwear.contact.constants import creep_coefficients, shear_modulus
from railwear.contact.hertz import effective_modulus
from railwear.contact.multipoint import SEMI_FIELDS, hertz_stiffness, share_load
from railwear.contact.semi_hertz import STRIPS, factor_table
from railwear.errors import ScenarioError

__all__ = ["CONTACT_MODELS", "point_contacts", "resultant"]

CONTACT_MODELS = ("hertz", "multi-hertz", "semi-hertzian")
_WINDOW = 0.030  # half-width of the sampled gap around a minimum [m]


def _order(gaps, where, rails, xs):
    """Sort each wheel's minima by gap (smallest first)."""
    order = np.argsort(gaps, axis=-1, kind="stable")
    return tuple(np.take_along_axis(v, order, axis=-1) for v in (gaps, where, rails, xs))


def point_contacts(model, shifts, yaws, theta, drop, gaps, where, rails, xs, wheel, rail_c, spline, yw0, yr0,
                   rolling_radius, axle_load, youngs_modulus, poisson, step=1e-4, semi_table=None):
    """Per-point contacts of every shift and wheel: a dict of arrays (n, 2, P) and the vertical
    approach (n, 2) [m]. ``gaps`` etc. are the rigid solver's minima (n, 2, P), gaps including
    the axle drop ``drop`` (n,); ``spline`` = (wx, wc, rx, rc) as compiled; ``step`` [m] the
    sampling of the semi-Hertzian separation; ``semi_table`` the compiled sampler and solver
    (``contact_geometry._semi_table``, which owns the gap function)."""
    if model not in CONTACT_MODELS[1:]:
        raise ScenarioError(f"contact_model must be one of {', '.join(CONTACT_MODELS)}, got {model!r}")
    G = gaps - drop[:, None, None]
    G, yp, yr, X = _order(G, where, rails, xs)
    valid = np.isfinite(G)
    G = np.where(valid, np.maximum(G, 0.0), np.inf)
    ypv, yrv = np.where(valid, yp, 0.0), np.where(valid, yr, 0.0)
    gamma = -np.arctan(rail_c.slope(yrv))
    radius = rolling_radius + wheel(ypv)
    A = 0.5 * np.cos(gamma) / radius
    B = 0.5 * (rail_c.curvature(yrv) - wheel.curvature(ypv))
    usable = valid & (B > 0.0)
    K = np.zeros(G.shape)
    K[usable] = hertz_stiffness(A[usable], B[usable], youngs_modulus, poisson)
    Q = 0.5 * axle_load
    cosg = np.cos(gamma)
    shear = shear_modulus(youngs_modulus, poisson)
    if model == "multi-hertz":
        Gm = np.where(usable, G, np.inf)
        delta, N = share_load(Gm, K, cosg, np.full(G.shape[:2], Q))
        on = N > 0.0
        h = hertz_contact(N[on], A[on], B[on], youngs_modulus, poisson)
        a, b, p0 = np.zeros(G.shape), np.zeros(G.shape), np.zeros(G.shape)
        a[on], b[on], p0[on] = h.a, h.b, h.p0
        pos, rail_pos, rad = yp, yr, radius
        extra = {}
    else:
        wx, wc, rx, rc = spline
        J = int(round(_WINDOW / step))
        P = G.shape[2]
        out = np.zeros(G.shape + (len(SEMI_FIELDS),))
        delta = np.empty(G.shape[:2])
        K0 = K[:, :, 0].copy()
        soft = ~(K0 > 0) & np.isfinite(A[:, :, 0])
        K0[soft] = hertz_stiffness(A[:, :, 0][soft], A[:, :, 0][soft], youngs_modulus, poisson)
        estar = float(effective_modulus(youngs_modulus, poisson))
        strips = np.zeros(G.shape + (STRIPS,))
        semi_table(shifts, yaws, theta, drop, np.ascontiguousarray(G), np.ascontiguousarray(ypv), np.ascontiguousarray(cosg),
                    np.ascontiguousarray(A), np.ascontiguousarray(K0), Q, estar, wx, wc, rx, rc, yw0, yr0,
                    rolling_radius, step, J, *factor_table(), out, delta, strips)
        if np.any(~np.isfinite(delta)):
            raise ScenarioError("semi-hertzian contact: no approach carries the load (check the profiles)")
        field = {name: out[..., k] for k, name in enumerate(SEMI_FIELDS)}
        active = field["normal_force"] > 0.0
        N = np.where(active, field["normal_force"], 0.0)
        width = field["s_max"] - field["s_min"]
        b = np.where(active, 0.5 * width, 0.0)
        a = np.where(active, field["area"] / (np.pi * np.where(active, b, 1.0)), 0.0)
        p0 = field["p0"]
        pos = np.where(active, yp + field["centroid"] * cosg, np.nan)
        rail_pos = np.where(active, yr + (pos - yp), np.nan)
        rad = rolling_radius + wheel(np.where(active, pos, 0.0))
        extra = {"area": np.where(active, field["area"], 0.0),
                 "half_length": np.where(active, field["half_length"], 0.0),
                 "lateral_min": np.where(active, yp + field["s_min"] * cosg, np.nan),
                 "lateral_max": np.where(active, yp + field["s_max"] * cosg, np.nan),
                 "virtual_penetration_ratio": np.where(active, field["epsilon"], np.nan),
                 "patch_curvature": np.where(active, field["curvature"], np.nan)}
        # the strips (semi_hertz.patch_strips): centres across the patch in its plane, on the wheel profile
        strip_width = np.where(active, width / STRIPS, 0.0)
        centre = field["s_min"][..., None] + (np.arange(STRIPS) + 0.5) * strip_width[..., None]
        strip_y = np.where(active[..., None], yp[..., None] + centre * cosg[..., None], np.nan)
        extra.update(strip_width=strip_width, strip_wheel_y=strip_y,
                     strip_half_length=np.where(active[..., None], strips, 0.0),
                     strip_rolling_radius=np.where(active[..., None],
                                                   rolling_radius + wheel(np.nan_to_num(strip_y)), np.nan))
    loaded = N > 0.0
    c11, c22, c23, c33 = (np.full(G.shape, np.nan) for _ in range(4))
    c11[loaded], c22[loaded], c23[loaded], c33[loaded] = kalker_coefficients(a[loaded] / b[loaded], poisson)
    f = [np.where(loaded, v, 0.0) for v in creep_coefficients(shear, a, b, *(np.nan_to_num(c) for c in (c11, c22, c23, c33)))]
    nan = np.nan
    points = dict(
        gap=np.where(valid, G, nan), wheel_y=np.where(loaded, pos, nan), rail_y=np.where(loaded, rail_pos, nan),
        contact_X=np.where(loaded, X, nan), contact_angle=np.where(loaded, gamma, nan),
        rolling_radius=np.where(loaded, rad, nan), normal_force=N, a=np.where(loaded, a, 0.0),
        b=np.where(loaded, b, 0.0), p0=np.where(loaded, p0, 0.0), c11=c11, c22=c22, c23=c23, c33=c33,
        f11=f[0], f22=f[1], f23=f[2], f33=f[3], **extra,
    )
    return points, delta


def resultant(points, poisson, youngs_modulus, yr0):
    """One equivalent contact per wheel from the points (module docstring): dict of (n, 2)."""
    N = points["normal_force"]
    gamma = np.nan_to_num(points["contact_angle"])
    F = [points[k].sum(-1) for k in ("f11", "f22", "f23", "f33")]
    w = points["f11"] / F[0][..., None]

    def weighted(name):
        return np.nansum(w * np.nan_to_num(points[name]), axis=-1)

    vertical = (N * np.cos(gamma)).sum(-1)
    lateral = (N * np.sin(gamma)).sum(-1)
    a = weighted("a")
    b = (points["a"] * points["b"]).sum(-1) / a
    shear = shear_modulus(youngs_modulus, poisson)
    c2 = a * b
    side = np.array([1.0, -1.0])
    rail_y = weighted("rail_y")
    return dict(
        normal_force=np.hypot(vertical, lateral), contact_angle=np.arctan2(lateral, vertical),
        rolling_radius=weighted("rolling_radius"), wheel_contact_y=weighted("wheel_y"), rail_contact_y=rail_y,
        contact_Y=side * (rail_y + yr0), contact_X=weighted("contact_X"), a=a, b=b,
        c11=F[0] / (shear * c2), c22=F[1] / (shear * c2), c23=F[2] / (shear * c2**1.5), c33=F[3] / (shear * c2**2),
    )
