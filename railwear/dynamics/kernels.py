"""Compiled right-hand sides of the dynamics models and their dispatch (numba, ``cache=True``).

Every model is a top-level ``@njit`` function ``f(t, y, p, surf, dydt)`` taking its parameters as a
float64 array ``p`` (index constants below) and an array ``surf``: the disk wheel's radius
deviation grid, the wheelset's track alignment, a contact table, or the FASTSIM factor table.
``rhs(kind, ...)`` selects the model by an integer, so the integrators in
``railwear.dynamics.integrators`` compile the loop and the model together without closures.

The caches of the integrators are keyed on this file too (``railwear._numba_cache``), so an edit
here recompiles them.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
from numba import literally, njit, typeof, types
from numba.core.errors import NumbaIRAssumptionWarning
from numba.extending import overload

from railwear.contact.strip_fastsim import STRIP_CELLS, strip_march

# model kinds
KIND_LINEAR = 0  # y' = A y, A in p[1:] (n = p[0]); tests of the integrators
KIND_VAN_DER_POL = 1  # y0' = y1, y1' = mu (1 - y0^2) y1 - y0, mu = p[0]; stiff test
KIND_WHEELSET = 2
KIND_DISK_WHEEL = 3
KIND_BOGIE = 4
KIND_TABLE_WHEELSET = 5
KIND_TABLE_BOGIE = 6  # the bogie's parameters (BG_*) followed by a table wheelset's (TW_*, offset BG_N_PARAMS)
KIND_COOPERRIDER = 7  # the published Cooperrider bogie with frame roll (CP_*; railwear.dynamics.cooperrider)
KIND_TABLE_POINTS = 8  # the table wheelset (TW_*) on a table with contacts of their own (TW_N_CONTACTS > 0);
# KIND_TABLE_WHEELSET is the same model on the per-wheel resultant only, compiled without the contacts' path

# ---- wheelset parameters --------------------------------------------------------------------
WS_SPEED = 0
WS_MASS = 1
WS_YAW_INERTIA = 2
WS_LATERAL_STIFFNESS = 3
WS_YAW_STIFFNESS = 4
WS_LATERAL_DAMPING = 5
WS_YAW_DAMPING = 6
WS_F11 = 7
WS_F22 = 8
WS_F23 = 9
WS_F33 = 10
WS_HALF_GAUGE = 11
WS_ROLLING_RADIUS = 12
WS_CONICITY = 13
WS_WHEEL_LOAD = 14
WS_FRICTION = 15  # inf: no saturation
WS_FLANGE_CLEARANCE = 16
WS_FLANGE_STIFFNESS = 17
WS_IRREGULARITY_CELLS = 18  # 0: ideal track; else lateral alignment y_t at n points in surf
WS_IRREGULARITY_WAVELENGTH = 19  # length of track over which surf repeats [m]
WS_SPIN_INERTIA = 20  # axle polar inertia [kg m^2]; acts only with the spin state y[4]
WS_LAW = 21  # creep law: 0 Johnson-Vermeulen cubic saturation, 1 FASTSIM (factor table in surf)
WS_LAW_OFFSET = 22  # where the FASTSIM factor table starts in surf
WS_LAW_POINTS = 23
WS_N_PARAMS = 24
WS_N_OUTPUTS = 19  # see wheelset_outputs

# ---- bogie parameters (two wheelsets in a frame, frame on a secondary suspension) -----------
BG_SPEED = 0
BG_WHEELSET_MASS = 1
BG_WHEELSET_YAW_INERTIA = 2
BG_FRAME_MASS = 3
BG_FRAME_YAW_INERTIA = 4
BG_PRIMARY_LATERAL_STIFFNESS = 5  # per wheelset
BG_PRIMARY_YAW_STIFFNESS = 6  # per wheelset, 2 k_long d^2
BG_SECONDARY_LATERAL_STIFFNESS = 7
BG_SECONDARY_LATERAL_DAMPING = 8
BG_SECONDARY_YAW_STIFFNESS = 9
BG_SECONDARY_YAW_DAMPING = 10
BG_HALF_WHEELBASE = 11
BG_F11 = 12
BG_F22 = 13
BG_F23 = 14
BG_F33 = 15
BG_HALF_GAUGE = 16
BG_ROLLING_RADIUS = 17
BG_CONICITY = 18
BG_WHEEL_LOAD = 19
BG_FRICTION = 20
BG_FLANGE_CLEARANCE = 21
BG_FLANGE_STIFFNESS = 22
BG_LAW = 23  # as WS_LAW
BG_LAW_OFFSET = 24
BG_LAW_POINTS = 25
BG_N_PARAMS = 26
BG_N_OUTPUTS = 10  # see bogie_outputs

# ---- the published Cooperrider bogie (7 degrees of freedom; railwear.dynamics.cooperrider) ----
# springs and dampers per side (one of each on the left and on the right), as in Kaas-Petersen 1986
CP_SPEED = 0
CP_WHEELSET_MASS = 1
CP_WHEELSET_YAW_INERTIA = 2
CP_FRAME_MASS = 3
CP_FRAME_YAW_INERTIA = 4
CP_FRAME_ROLL_INERTIA = 5
CP_PRIMARY_LATERAL_STIFFNESS = 6  # k1
CP_PRIMARY_LONGITUDINAL_STIFFNESS = 7  # k2, at +-d1
CP_PRIMARY_VERTICAL_STIFFNESS = 8  # k3, at +-d1
CP_SECONDARY_LATERAL_STIFFNESS = 9  # k4, h2 above the frame's centre of mass
CP_SECONDARY_VERTICAL_STIFFNESS = 10  # k5, at +-d2
CP_SECONDARY_LATERAL_DAMPING = 11  # D1, with k4
CP_SECONDARY_VERTICAL_DAMPING = 12  # D2, with k5
CP_HALF_WHEELBASE = 13  # b
CP_PRIMARY_SPRING_HALF_SPACING = 14  # d1
CP_SECONDARY_SPRING_HALF_SPACING = 15  # d2
CP_PRIMARY_HEIGHT = 16  # h1: the frame's centre of mass above the primary lateral springs
CP_SECONDARY_HEIGHT = 17  # h2: the secondary lateral spring above the frame's centre of mass
CP_F11 = 18
CP_F22 = 19
CP_HALF_GAUGE = 20
CP_ROLLING_RADIUS = 21
CP_CONICITY = 22
CP_WHEEL_LOAD = 23
CP_FRICTION = 24
CP_FLANGE_CLEARANCE = 25
CP_FLANGE_STIFFNESS = 26
CP_LAW = 27  # as WS_LAW
CP_LAW_OFFSET = 28
CP_LAW_POINTS = 29
CP_N_PARAMS = 30
CP_N_OUTPUTS = 10  # as BG_N_OUTPUTS

# ---- wheelset on real profiles (contact table) -------------------------------------------
TW_SPEED = 0
TW_MASS = 1
TW_YAW_INERTIA = 2
TW_LATERAL_STIFFNESS = 3
TW_YAW_STIFFNESS = 4
TW_LATERAL_DAMPING = 5
TW_YAW_DAMPING = 6
TW_HALF_GAUGE = 7  # half the distance between the contact points at y = 0
TW_FRICTION = 8
TW_CREEP_SCALE = 9
TW_Y_MIN = 10  # first grid point of the table [m], lateral displacement to the left
TW_DY = 11
TW_N_POINTS = 12
TW_OUTSIDE_STIFFNESS = 13  # lateral spring beyond the table's range [N/m]
TW_N_CONTACTS = 14  # contacts per wheel evaluated one by one (0: the per-wheel resultant only)
TW_STRIPS = 15  # strips per contact for strip-wise FASTSIM (creep_law "strip-fastsim"); 0: Kalker + cubic law
TW_WHEEL_Y0_LEFT = 16  # contact position on the left wheel's profile at y = 0: each contact's lever arm is
TW_WHEEL_Y0_RIGHT = 17  # TW_HALF_GAUGE + (its position on the profile - this), per wheel (TW_N_CONTACTS > 0)
TW_N_PARAMS = 18
TW_N_STRIP_HEAD = 5  # per contact in surf after the point block: L1, L2, L3, sqrt(a b), strip width; then
TW_N_STRIP_FIELDS = 3  # per strip: lateral position in the contact plane (Kalker's y), half-length, rolling radius
TW_N_FIELDS = 8  # per side in surf: rolling radius, contact angle, normal force, f11, f22, f23, f33,
# contact position on the wheel profile; with TW_N_CONTACTS = P > 0 the same 8 fields follow for each
# of the P contacts of the left wheel, then of the right (``_point_column``)
TW_N_OUTPUTS = 20  # see table_wheelset_outputs
TW_N_POINT_OUTPUTS = 9  # per contact, see _table_point_rows

# ---- disk wheel parameters ------------------------------------------------------------------
DW_SPEED = 0
DW_RADIUS = 1
DW_WHEEL_MASS = 2
DW_WHEEL_INERTIA = 3
DW_SPRUNG_MASS = 4  # 0: rigid frame (no sprung-mass motion)
DW_PRIMARY_STIFFNESS = 5
DW_PRIMARY_DAMPING = 6
DW_RAIL_MASS = 7  # 0: rigid rail
DW_PAD_STIFFNESS = 8
DW_PAD_DAMPING = 9
DW_HERTZ_CONSTANT = 10  # N = k_H delta^(3/2)
DW_STATIC_LOAD = 11
DW_STATIC_APPROACH = 12
DW_F11 = 13  # at the static load; scales with (N/W)^(2/3)
DW_FRICTION = 14
DW_TORQUE = 15
DW_PATCH_HALF_ANGLE = 16  # a / R0 [rad]; 0: point contact
DW_INITIAL_ANGLE = 17
DW_N_CELLS = 18
DW_CREEP_LAW = 19  # 0: Johnson-Vermeulen cubic saturation; 1: FASTSIM creep curve from surf
DW_CREEP_TABLE_OFFSET = 20  # where the creep curve starts in surf
DW_CREEP_TABLE_POINTS = 21
DW_N_PARAMS = 22
DW_N_OUTPUTS = 7  # see disk_wheel_outputs

TWO_PI = 2.0 * math.pi


@njit(cache=True, inline="always")
def saturation_factor(force, limit):
    """Johnson-Vermeulen cubic saturation (Shen, Hedrick & Elkins 1983): factor on linear forces.

    ``r = F/(mu N)``; factor ``1 - r/3 + r^2/27`` for ``r < 3``, ``1/r`` above; 0 without load.
    """
    if limit <= 0.0:
        return 0.0
    r = force / limit
    if r < 3.0:
        return 1.0 - r / 3.0 + r * r / 27.0
    return 1.0 / r


@njit(cache=True, inline="always")
def creep_factor(force, limit, law, surf, offset, points):
    """Factor on Kalker's linear creep forces of resultant ``force`` [N] at ``limit = mu N``:
    the cubic law (``law`` 0, ``saturation_factor``) or FASTSIM (``law`` 1: the ratio of FASTSIM's
    force to the linear one, tabulated in ``surf`` against ``s = force / limit`` as in
    ``creep_curve``; at ``s = 0`` it is FASTSIM's discretised linear slope, close to 1)."""
    if law == 0.0:
        return saturation_factor(force, limit)
    return _fastsim_factor(force, limit, surf, offset, points)


@njit(cache=True)
def _fastsim_factor(force, limit, surf, offset, points):
    """The FASTSIM branch of ``creep_factor`` (a call, not inlined: it keeps the inlined creep
    code of the cubic law small)."""
    if limit <= 0.0:
        return 0.0
    return creep_curve(surf, offset, points, force / limit)


# ---- wheelset -------------------------------------------------------------------------------
@njit(cache=True, inline="always")
def _creep(sign, lat, yaw, vlat, vyaw, v, e, r0, lam, f11, f22, f23, f33, limit, omega, law, surf, offset, points):
    """Creepages, forces and frictional power of one conical wheel of a wheelset.

    ``sign`` +1 for the left wheel at ``+e``, -1 for the right; ``omega`` [rad/s] the axle's
    spin deviation from ``V / r0``. ``xi = -sign (e psi'/V + lam y/r0) - omega (r0 + sign lam y)/V``,
    ``eta = y'/V - psi``, ``phi = psi'/V - sign lam/r0``; ``Fx = -f11 xi``,
    ``Fy = -f22 eta - f23 phi``, ``Mz = f23 eta - f33 phi``, all scaled by ``creep_factor`` of
    ``|(Fx, Fy)|`` against ``limit = mu N``; power ``-V (Fx xi + Fy eta + Mz phi)``.
    """
    eta = vlat / v - yaw
    xi = -sign * (e * vyaw / v + lam * lat / r0) - omega * (r0 + sign * lam * lat) / v
    phi = vyaw / v - sign * lam / r0
    fx = -f11 * xi
    fy = -f22 * eta - f23 * phi
    mz = f23 * eta - f33 * phi
    s = creep_factor(math.sqrt(fx * fx + fy * fy), limit, law, surf, offset, points)
    fx *= s
    fy *= s
    mz *= s
    return xi, eta, phi, fx, fy, mz, -v * (fx * xi + fy * eta + mz * phi)


@njit(cache=True, inline="always")
def _track_alignment(t, p, surf):
    """Lateral position of the track centre line [m] under the wheelset at distance ``V t``:
    periodic piecewise-linear in ``surf`` (``n`` points over ``WS_IRREGULARITY_WAVELENGTH``)."""
    n = int(p[WS_IRREGULARITY_CELLS])
    if n == 0:
        return 0.0
    return surface_value(surf, n, TWO_PI * p[WS_SPEED] * t / p[WS_IRREGULARITY_WAVELENGTH])


@njit(cache=True, inline="always")
def _spin(y):
    """The axle's spin deviation from ``V / r0`` [rad/s]: the fifth state where there is one."""
    return y[4] if y.shape[0] > 4 else 0.0


@njit(cache=True, inline="always")
def _wheel(sign, y, p, surf, relative):
    """``_creep`` for the single wheelset, state ``y = [y, psi, y', psi'(, omega)]``, parameters
    ``WS_*``; ``relative`` is the lateral displacement from the track centre line (sets the rolling
    radii). The frame and its suspension follow the ideal line; a lateral alignment of the rails
    changes the rolling radii and the flange gap, while the lateral creepage, taken in the
    direction of the rails, is unchanged to first order."""
    return _creep(sign, relative, y[1], y[2], y[3], p[WS_SPEED], p[WS_HALF_GAUGE], p[WS_ROLLING_RADIUS],
                  p[WS_CONICITY], p[WS_F11], p[WS_F22], p[WS_F23], p[WS_F33], p[WS_FRICTION] * p[WS_WHEEL_LOAD],
                  _spin(y), p[WS_LAW], surf, int(p[WS_LAW_OFFSET]), int(p[WS_LAW_POINTS]))


@njit(cache=True, inline="always")
def _dead_band(lateral, clearance, stiffness):
    """Flange force [N]: a linear spring outside the dead band ``|y| <= clearance``."""
    if lateral > clearance:
        return -stiffness * (lateral - clearance)
    if lateral < -clearance:
        return -stiffness * (lateral + clearance)
    return 0.0


@njit(cache=True, inline="always")
def _flange(lateral, p):
    return _dead_band(lateral, p[WS_FLANGE_CLEARANCE], p[WS_FLANGE_STIFFNESS])


@njit(cache=True, inline="always")
def wheelset_rhs(t, y, p, surf, dydt):
    """Suspended wheelset on straight track: state ``[y, psi, y', psi']``, or with the axle's
    spin deviation ``omega`` from ``V / r0`` as a fifth state.

    ``m y'' = Fy_L + Fy_R + F_flange - k_y y - c_y y'``,
    ``I psi'' = e (Fx_R - Fx_L) + Mz_L + Mz_R - k_psi psi - c_psi psi'``,
    ``J omega' = -(r_L Fx_L + r_R Fx_R)`` with ``r = r0 +- lam y``; Kalker's linear creep forces
    with optional spin and saturation, conical wheels, flange dead band, small yaw angles.
    """
    relative = y[0] - _track_alignment(t, p, surf)
    _, _, _, fx_l, fy_l, mz_l, _ = _wheel(1.0, y, p, surf, relative)
    _, _, _, fx_r, fy_r, mz_r, _ = _wheel(-1.0, y, p, surf, relative)
    force = fy_l + fy_r + _flange(relative, p) - p[WS_LATERAL_STIFFNESS] * y[0] - p[WS_LATERAL_DAMPING] * y[2]
    moment = p[WS_HALF_GAUGE] * (fx_r - fx_l) + mz_l + mz_r - p[WS_YAW_STIFFNESS] * y[1] - p[WS_YAW_DAMPING] * y[3]
    dydt[0] = y[2]
    dydt[1] = y[3]
    dydt[2] = force / p[WS_MASS]
    dydt[3] = moment / p[WS_YAW_INERTIA]
    if y.shape[0] > 4:
        dr = p[WS_CONICITY] * relative
        dydt[4] = -((p[WS_ROLLING_RADIUS] + dr) * fx_l + (p[WS_ROLLING_RADIUS] - dr) * fx_r) / p[WS_SPIN_INERTIA]


@njit(cache=True)
def wheelset_outputs(t, y, p, surf, out):
    """Outputs per time: per wheel (left 0-7, right 8-15) ``xi, eta, phi, Fx, Fy, Mz, power, s``
    (``s`` the contact position on the tread towards the flange, ``+-(y - y_t)``); 16 flange
    force; 17 contact angle on the wheel ``V t / r0 mod 2 pi``; 18 track alignment ``y_t``."""
    track = _track_alignment(t, p, surf)
    for w in range(2):
        sign = 1.0 - 2.0 * w
        vals = _wheel(sign, y, p, surf, y[0] - track)
        for k in range(7):
            out[8 * w + k] = vals[k]
        out[8 * w + 7] = sign * (y[0] - track)
    out[16] = _flange(y[0] - track, p)
    out[17] = (p[WS_SPEED] * t / p[WS_ROLLING_RADIUS]) % TWO_PI
    out[18] = track


# ---- wheelset on real profiles --------------------------------------------------------------
# The table helpers read the TW_* parameters at offset ``o`` in ``p`` (0 for the table wheelset,
# BG_N_PARAMS for the table bogie, whose wheelsets share one table). The node of the table is
# found once per evaluation and handed down: each inlined call of a helper is compiled again,
# and LLVM did not merge the repeated look-ups either.
@njit(cache=True, inline="always")
def _table_node(p, o, lateral):
    """``(n, j, w)``: the table's points, the node below ``lateral`` and the weight of the node above
    (clamped to the table's range)."""
    n = int(p[o + TW_N_POINTS])
    pos = (lateral - p[o + TW_Y_MIN]) / p[o + TW_DY]
    if pos <= 0.0:
        pos = 0.0
    elif pos >= n - 1:
        pos = n - 1.0
    j = min(int(pos), n - 2)
    return n, j, pos - j


@njit(cache=True, inline="always")
def _table_value(surf, n, j, w, side, field):
    """Linear interpolation of table column ``field`` of wheel ``side`` (0 left, 1 right) at the
    node ``(j, w)`` of ``_table_node``."""
    base = (side * TW_N_FIELDS + field) * n
    return (1.0 - w) * surf[base + j] + w * surf[base + j + 1]


@njit(cache=True, inline="always")
def _table_wheel(side, yaw, vlat, vyaw, p, o, surf, n, j, w, ratio):
    """Creep of one wheel from the contact table at the node ``(j, w)`` of ``_table_node``: returns
    ``(xi, eta, phi, Fx, Feta, Mz, power, N, delta)``. ``ratio = (r_R - r_L) / (r_L + r_R)``
    (quasi-static axle spin ``2 V / (r_L + r_R)``). Creepages in the contact plane:
    ``xi = -+ratio -+ e psi'/V`` (upper sign left), ``eta = (y'/V - psi) / cos(delta)``,
    ``phi = psi' cos(delta) / V -+ sin(delta) / r``."""
    v = p[o + TW_SPEED]
    sign = 1.0 - 2.0 * side
    radius = _table_value(surf, n, j, w, side, 0)
    delta = _table_value(surf, n, j, w, side, 1)
    normal = _table_value(surf, n, j, w, side, 2)
    scale = p[o + TW_CREEP_SCALE]
    cosd = math.cos(delta)
    sind = math.sin(delta)
    xi = sign * (ratio - p[o + TW_HALF_GAUGE] * vyaw / v)
    eta = (vlat / v - yaw) / cosd
    phi = vyaw * cosd / v - sign * sind / radius
    f23 = scale * _table_value(surf, n, j, w, side, 5)
    fx = -scale * _table_value(surf, n, j, w, side, 3) * xi
    fy = -scale * _table_value(surf, n, j, w, side, 4) * eta - f23 * phi
    mz = f23 * eta - scale * _table_value(surf, n, j, w, side, 6) * phi
    s = saturation_factor(math.sqrt(fx * fx + fy * fy), p[o + TW_FRICTION] * normal)
    fx *= s
    fy *= s
    mz *= s
    return xi, eta, phi, fx, fy, mz, -v * (fx * xi + fy * eta + mz * phi), normal, delta


@njit(cache=True, inline="always")
def _point_column(surf, n, j, w, side, contacts, point, field):
    """Field ``field`` of contact ``point`` of wheel ``side`` at the node ``(j, w)`` of
    ``_table_node`` (``contacts`` contacts per wheel)."""
    base = ((2 + side * contacts + point) * TW_N_FIELDS + field) * n
    return (1.0 - w) * surf[base + j] + w * surf[base + j + 1]


@njit(cache=True, inline="always")
def _table_point(side, point, yaw, vlat, vyaw, p, o, surf, n, j, w, contacts, ratio, r_wheel, radii, strip_power):
    """Creep of contact ``point`` of wheel ``side`` on its own: ``(xi, eta, phi, Fx, Feta, Mz,
    power, N, delta, position, lever)``, ``N <= 0`` for a contact not loaded here (then the rest is
    not computed). ``lever`` is the contact's own lateral distance from the wheelset's centre,
    ``e + (position - position at y = 0)`` (``e = TW_HALF_GAUGE``, the positions on the wheel
    profile, the reference ``TW_WHEEL_Y0_*`` the wheel's contact at ``y = 0``; the profile
    coordinate is fixed to the wheelset, positive towards the field side). The axle spins at
    ``2 V / radii`` (``radii = r_L + r_R`` of the wheels' resultants, ``ratio`` as in
    ``_table_wheel``), so the contact of rolling radius ``r`` has
    ``xi = (V - 2 V r / radii) / V -+ lever psi'/V``, written as the wheel's ``-+ratio`` less
    ``2 (r - r_wheel) / radii`` (``r_wheel`` the wheel's resultant radius: exactly the wheel's
    creepage for ``r = r_wheel``); ``eta = (y'/V - psi) / cos(delta)``,
    ``phi = psi' cos(delta) / V -+ sin(delta) / r`` with the contact's own angle and radius, its
    own Kalker coefficients and the cubic saturation at its own ``mu N``. ``strip_power``: ``None``,
    or an array that receives each strip's frictional power [W] under strip-wise FASTSIM (zeros
    for a contact without load)."""
    normal = _point_column(surf, n, j, w, side, contacts, point, 2)
    if not normal > 0.0:
        return 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    v = p[o + TW_SPEED]
    sign = 1.0 - 2.0 * side
    radius = _point_column(surf, n, j, w, side, contacts, point, 0)
    delta = _point_column(surf, n, j, w, side, contacts, point, 1)
    position = _point_column(surf, n, j, w, side, contacts, point, 7)
    lever = p[o + TW_HALF_GAUGE] + (position - p[o + TW_WHEEL_Y0_LEFT + side])
    scale = p[o + TW_CREEP_SCALE]
    cosd = math.cos(delta)
    sind = math.sin(delta)
    xi = sign * (ratio - lever * vyaw / v) - 2.0 * (radius - r_wheel) / radii
    eta = (vlat / v - yaw) / cosd
    phi = vyaw * cosd / v - sign * sind / radius
    strips = int(p[o + TW_STRIPS])
    if strips > 0:
        fx, fy, mz, power = _strip_point(side, point, xi, eta, phi, -sign * sind / radius, radius, r_wheel, radii,
                                         normal, p, o, surf, n, j, w, contacts, strips, v, strip_power)
        return xi, eta, phi, fx, fy, mz, v * power, normal, delta, position, lever
    f23 = scale * _point_column(surf, n, j, w, side, contacts, point, 5)
    fx = -scale * _point_column(surf, n, j, w, side, contacts, point, 3) * xi
    fy = -scale * _point_column(surf, n, j, w, side, contacts, point, 4) * eta - f23 * phi
    mz = f23 * eta - scale * _point_column(surf, n, j, w, side, contacts, point, 6) * phi
    s = saturation_factor(math.sqrt(fx * fx + fy * fy), p[o + TW_FRICTION] * normal)
    fx *= s
    fy *= s
    mz *= s
    return xi, eta, phi, fx, fy, mz, -v * (fx * xi + fy * eta + mz * phi), normal, delta, position, lever


@njit(cache=True)
def _strip_point(side, point, xi, eta, phi, spin_geo, radius, r_wheel, radii, normal, p, o, surf, n, j, w, contacts,
                 strips, speed, strip_power):
    """Strip-wise FASTSIM of one contact (``railwear.contact.strip_fastsim``, semi-elliptic pressure
    carrying ``normal``, flexibilities of the patch's equivalent ellipse): ``(Fx, Feta, Mz, power
    per unit speed)``, Mz about the contact's load centroid. Strip ``k`` has the longitudinal
    creepage of its own rolling radius, ``xi - 2 (r_k - r) / radii`` (``xi``, ``r`` the contact's),
    and the spin of the contact; the radius already holds the first-order change of the rolling
    speed across the plane that Kalker's ``-phi y`` term carries (the axle's rotation seen in the
    tangent plane, ``spin_geo`` = ``-+ sin(delta) / r``), so that part is taken out of the strip's
    creepage (``+ spin_geo y_k``) and left to FASTSIM's spin term: on a cone the strips then have
    the contact's ``xi`` and FASTSIM's kinematics, on a curved profile the remainder of the
    radius change. ``strip_power`` (``None`` or an array over the strips) receives each strip's
    frictional power times ``speed`` [W], the terms of the returned power's sum."""
    if strip_power is not None:
        for k in range(strips):
            strip_power[k] = 0.0
    stride = TW_N_STRIP_HEAD + TW_N_STRIP_FIELDS * strips
    base = (2 + 2 * contacts) * TW_N_FIELDS * n + (side * contacts + point) * stride * n
    scale = p[o + TW_CREEP_SCALE]
    L1 = (1.0 - w) * surf[base + j] + w * surf[base + j + 1]
    L2 = (1.0 - w) * surf[base + n + j] + w * surf[base + n + j + 1]
    L3 = (1.0 - w) * surf[base + 2 * n + j] + w * surf[base + 2 * n + j + 1]
    c = (1.0 - w) * surf[base + 3 * n + j] + w * surf[base + 3 * n + j + 1]
    width = (1.0 - w) * surf[base + 4 * n + j] + w * surf[base + 4 * n + j + 1]
    L1 /= scale
    L2 /= scale
    L3 /= scale
    shape = 0.0
    for k in range(strips):
        at = base + (TW_N_STRIP_HEAD + TW_N_STRIP_FIELDS * k + 1) * n + j
        half = (1.0 - w) * surf[at] + w * surf[at + 1]
        shape += half * half
    if not shape > 0.0:
        return 0.0, 0.0, 0.0, 0.0
    pressure = normal / (0.5 * math.pi * shape * width)
    mu = p[o + TW_FRICTION]
    fx = 0.0
    fy = 0.0
    mz = 0.0
    power = 0.0
    for k in range(strips):
        at = base + (TW_N_STRIP_HEAD + TW_N_STRIP_FIELDS * k) * n + j
        y = (1.0 - w) * surf[at] + w * surf[at + 1]
        half = (1.0 - w) * surf[at + n] + w * surf[at + n + 1]
        r_k = (1.0 - w) * surf[at + 2 * n] + w * surf[at + 2 * n + 1]
        if not half > 0.0:
            continue
        xi_k = xi - 2.0 * (r_k - radius) / radii + spin_geo * y
        sx, sy, sm, sp, _ = strip_march(y, half, mu * pressure * half, xi_k, eta, phi, L1, L2, L3, c, STRIP_CELLS)
        fx += sx * width
        fy += sy * width
        mz += sm * width
        power += sp * width
        if strip_power is not None:
            strip_power[k] = speed * (sp * width)
    return fx, fy, mz, power


@njit(cache=True, inline="always")
def _radius_ratio(surf, n, j, w):
    """``(r_R - r_L) / (r_L + r_R)`` and ``r_L + r_R`` at the node ``(j, w)`` of ``_table_node``."""
    r_left = _table_value(surf, n, j, w, 0, 0)
    r_right = _table_value(surf, n, j, w, 1, 0)
    return (r_right - r_left) / (r_left + r_right), r_left + r_right


@njit(cache=True)
def _table_forces(lat, yaw, vlat, vyaw, p, o, surf, points=True):
    """Contact forces on a wheelset on real profiles (no suspension): ``(lateral force, yaw
    moment, power left, power right, lateral component of the normal forces)``. With
    ``TW_N_CONTACTS = 0`` each wheel's resultant contact (``_table_wheel``), else each of its
    contacts on its own (``_table_point``), their forces summed in the order of the contacts (one
    loaded contact per wheel gives the resultant's numbers to the bit). ``points``: None for a
    table without contacts of its own (``KIND_TABLE_WHEELSET``): numba then prunes the contacts'
    path, strip-wise FASTSIM with it, when it compiles the caller."""
    n, j, w = _table_node(p, o, lat)
    ratio, radii = _radius_ratio(surf, n, j, w)
    force = 0.0
    moment = 0.0
    normal_lateral = 0.0
    power_left = 0.0
    power_right = 0.0
    for side in range(2):
        sign = 1.0 - 2.0 * side
        resultant = True
        if points is not None:
            contacts = int(p[o + TW_N_CONTACTS])
            if contacts > 0:
                resultant = False
                power = 0.0
                r_wheel = _table_value(surf, n, j, w, side, 0)
                for point in range(contacts):
                    _, _, _, fx, fy, mz, pw, normal, delta, _, lever = _table_point(side, point, yaw, vlat, vyaw, p,
                                                                                    o, surf, n, j, w, contacts, ratio,
                                                                                    r_wheel, radii, None)
                    if not normal > 0.0:
                        continue
                    cosd = math.cos(delta)
                    normal_lateral -= sign * normal * math.sin(delta)
                    force += fy * cosd
                    moment += mz * cosd - sign * lever * fx
                    power += pw
        if resultant:
            _, _, _, fx, fy, mz, power, normal, delta = _table_wheel(side, yaw, vlat, vyaw, p, o, surf, n, j, w, ratio)
            cosd = math.cos(delta)
            # the normal force leans towards the track centre by the contact angle
            normal_lateral -= sign * normal * math.sin(delta)
            force += fy * cosd
            moment += mz * cosd - sign * p[o + TW_HALF_GAUGE] * fx
        if side == 0:
            power_left = power
        else:
            power_right = power
    lo = p[o + TW_Y_MIN]
    hi = lo + (p[o + TW_N_POINTS] - 1.0) * p[o + TW_DY]
    if lat > hi:
        normal_lateral -= p[o + TW_OUTSIDE_STIFFNESS] * (lat - hi)
    elif lat < lo:
        normal_lateral -= p[o + TW_OUTSIDE_STIFFNESS] * (lat - lo)
    return force + normal_lateral, moment, power_left, power_right, normal_lateral


@njit(cache=True)
def table_wheelset_rhs(t, y, p, surf, dydt, points=True):
    """Wheelset on real profiles, state ``[y, psi, y', psi']`` (``y`` to the left): rolling radii,
    contact angles, normal loads and Kalker coefficients from the contact table at ``y``; the
    lateral components of the normal forces give the gravitational stiffness and, in flange
    contact, the flange force. ``points``: as ``_table_forces``."""
    force, moment, _, _, _ = _table_forces(y[0], y[1], y[2], y[3], p, 0, surf, points)
    dydt[0] = y[2]
    dydt[1] = y[3]
    dydt[2] = (force - p[TW_LATERAL_STIFFNESS] * y[0] - p[TW_LATERAL_DAMPING] * y[2]) / p[TW_MASS]
    dydt[3] = (moment - p[TW_YAW_STIFFNESS] * y[1] - p[TW_YAW_DAMPING] * y[3]) / p[TW_YAW_INERTIA]


@njit(cache=True)
def table_wheelset_outputs(t, y, p, surf, out, points=True):
    """Outputs: per wheel (left 0-7, right 8-15) ``xi, eta, phi, Fx, Feta, Mz, power, N``;
    16 rolling radius difference left - right; 17, 18 contact position on the left and right
    wheel profile; 19 contact angle on the wheel ``x = 2 V t / (r_L + r_R) mod 2 pi``. With
    several contacts per wheel (``TW_N_CONTACTS > 0``) ``Fx, Feta, Mz, power`` are the sums over
    the wheel's contacts (``_table_point``); the creepages, ``N`` and the position stay the
    resultant's (the table's per-wheel columns). ``points``: as ``_table_forces``."""
    n, j, w = _table_node(p, 0, y[0])
    ratio, radii = _radius_ratio(surf, n, j, w)
    for side in range(2):
        vals = _table_wheel(side, y[1], y[2], y[3], p, 0, surf, n, j, w, ratio)
        for k in range(8):
            out[8 * side + k] = vals[k]
        if points is not None:
            contacts = int(p[TW_N_CONTACTS])
            if contacts > 0:
                r_wheel = _table_value(surf, n, j, w, side, 0)
                for k in range(3, 7):
                    out[8 * side + k] = 0.0
                for point in range(contacts):
                    pv = _table_point(side, point, y[1], y[2], y[3], p, 0, surf, n, j, w, contacts, ratio, r_wheel,
                                      radii, None)
                    if pv[7] > 0.0:
                        for k in range(3, 7):
                            out[8 * side + k] += pv[k]
    out[16] = -ratio * radii
    out[17] = _table_value(surf, n, j, w, 0, 7)
    out[18] = _table_value(surf, n, j, w, 1, 7)
    out[19] = (2.0 * p[TW_SPEED] * t / radii) % TWO_PI


@njit(cache=True)
def table_point_rows(ys, p, o, surf, columns, strip_power=None):
    """Each contact's own quantities at every state of ``ys`` (time, state): the wheelset's
    lateral displacement, yaw, lateral velocity and yaw rate are ``ys[:, columns[0..3]]``, its
    parameters the ``TW_*`` at offset ``o``. Row ``i``, column ``((side * P + point) * 9 + k)``
    (``P = TW_N_CONTACTS``): ``xi, eta, phi, Fx, Feta, Mz, power, N, position`` of ``_table_point``
    (zeros where the contact carries no load). Their ``Fx ... power`` sum to
    ``table_wheelset_outputs``' per-wheel values. Under strip-wise FASTSIM ``strip_power``, an
    array ``(time, 2 P, TW_STRIPS)``, receives each strip's frictional power [W] (they sum to the
    contact's ``power``)."""
    contacts = int(p[o + TW_N_CONTACTS])
    res = np.zeros((ys.shape[0], 2 * contacts * TW_N_POINT_OUTPUTS))
    for i in range(ys.shape[0]):
        lat = ys[i, columns[0]]
        n, j, w = _table_node(p, o, lat)
        ratio, radii = _radius_ratio(surf, n, j, w)
        for side in range(2):
            r_wheel = _table_value(surf, n, j, w, side, 0)
            for point in range(contacts):
                if strip_power is None:
                    pv = _table_point(side, point, ys[i, columns[1]], ys[i, columns[2]], ys[i, columns[3]], p, o, surf,
                                      n, j, w, contacts, ratio, r_wheel, radii, None)
                else:
                    pv = _table_point(side, point, ys[i, columns[1]], ys[i, columns[2]], ys[i, columns[3]], p, o, surf,
                                      n, j, w, contacts, ratio, r_wheel, radii, strip_power[i, side * contacts + point])
                if pv[7] > 0.0:
                    base = (side * contacts + point) * TW_N_POINT_OUTPUTS
                    for k in range(TW_N_POINT_OUTPUTS):
                        res[i, base + k] = pv[k]
    return res


# ---- bogie ----------------------------------------------------------------------------------
@njit(cache=True, inline="always")
def _conical_wheelset(lat, yaw, vlat, vyaw, v, e, r0, lam, f11, f22, f23, f33, limit, law, surf, offset, points):
    """Creep forces on a conical wheelset in a bogie, summed over both wheels (``_creep``, no spin
    deviation): ``(Fy, Mz, power_left, power_right)``; ``law`` as ``WS_LAW``."""
    fy = 0.0
    mz = 0.0
    power_left = 0.0
    power_right = 0.0
    for w in range(2):
        sign = 1.0 - 2.0 * w
        _, _, _, fx, fyw, mzw, power = _creep(sign, lat, yaw, vlat, vyaw, v, e, r0, lam, f11, f22, f23, f33, limit,
                                              0.0, law, surf, offset, points)
        fy += fyw
        mz += mzw - sign * e * fx
        if w == 0:
            power_left = power
        else:
            power_right = power
    return fy, mz, power_left, power_right


@njit(cache=True, inline="always")
def _bogie_wheelset(i, y, p, surf, law):
    """Creep and flange forces on wheelset ``i`` (0 front, 1 rear) of the bogie:
    ``(Fy, Mz, power_left, power_right, flange)`` summed over both wheels; ``law`` as ``WS_LAW``."""
    lat = y[2 * i]
    fy, mz, power_left, power_right = _conical_wheelset(
        lat, y[2 * i + 1], y[6 + 2 * i], y[7 + 2 * i], p[BG_SPEED], p[BG_HALF_GAUGE], p[BG_ROLLING_RADIUS],
        p[BG_CONICITY], p[BG_F11], p[BG_F22], p[BG_F23], p[BG_F33], p[BG_FRICTION] * p[BG_WHEEL_LOAD], law, surf,
        int(p[BG_LAW_OFFSET]), int(p[BG_LAW_POINTS]))
    flange = _dead_band(lat, p[BG_FLANGE_CLEARANCE], p[BG_FLANGE_STIFFNESS])
    return fy + flange, mz, power_left, power_right, flange


@njit(cache=True, inline="always")
def _bogie_contact(table, law, i, y, p, surf):
    """``(Fy, Mz, power_left, power_right, flange)`` of wheelset ``i``: conical wheels, or real
    profiles through the contact table (``table``; ``flange`` is then the lateral component of
    the normal forces)."""
    if table:
        return _table_forces(y[2 * i], y[2 * i + 1], y[6 + 2 * i], y[7 + 2 * i], p, BG_N_PARAMS, surf)
    return _bogie_wheelset(i, y, p, surf, law)


@njit(cache=True)
def bogie_rhs(t, y, p, surf, dydt, table):
    """Two-axle bogie, conical (the Cooperrider bogie) or on real profiles (``table``: both
    wheelsets read one contact table); see ``_bogie_motion``. The conical bogie under the cubic
    law has its own compiled copy: a branch on the creep law inside the wheel loop costs a third
    of its speed."""
    if not table and p[BG_LAW] == 0.0:
        _bogie_motion(False, 0.0, y, p, surf, dydt)
    else:
        _bogie_motion(table, p[BG_LAW], y, p, surf, dydt)


@njit(cache=True, inline="always")
def _bogie_motion(table, law, y, p, surf, dydt):
    """Two-axle bogie: state ``[y1, psi1, y2, psi2, y_f, psi_f]`` and their rates; conical wheels
    (the Cooperrider bogie) or, with ``table``, both wheelsets on real profiles through one
    contact table.

    Wheelset ``i`` at ``x_i = +b`` (front) or ``-b`` (rear): ``m y_i'' = Fy_i - k1 (y_i - y_f - x_i psi_f)``,
    ``I psi_i'' = Mz_i - k_psi (psi_i - psi_f)``; frame: ``m_f y_f'' = sum k1 d_i - k4 y_f - D1 y_f'``,
    ``I_f psi_f'' = sum (x_i k1 d_i + k_psi (psi_i - psi_f)) - k6 psi_f - D2 psi_f'`` (car body fixed).
    """
    b = p[BG_HALF_WHEELBASE]
    k1 = p[BG_PRIMARY_LATERAL_STIFFNESS]
    kpsi = p[BG_PRIMARY_YAW_STIFFNESS]
    frame_force = -p[BG_SECONDARY_LATERAL_STIFFNESS] * y[4] - p[BG_SECONDARY_LATERAL_DAMPING] * y[10]
    frame_moment = -p[BG_SECONDARY_YAW_STIFFNESS] * y[5] - p[BG_SECONDARY_YAW_DAMPING] * y[11]
    for i in range(2):
        x = b if i == 0 else -b
        fy, mz, _, _, _ = _bogie_contact(table, law, i, y, p, surf)
        deflection = y[2 * i] - y[4] - x * y[5]
        twist = y[2 * i + 1] - y[5]
        dydt[6 + 2 * i] = (fy - k1 * deflection) / p[BG_WHEELSET_MASS]
        dydt[7 + 2 * i] = (mz - kpsi * twist) / p[BG_WHEELSET_YAW_INERTIA]
        frame_force += k1 * deflection
        frame_moment += x * k1 * deflection + kpsi * twist
    dydt[10] = frame_force / p[BG_FRAME_MASS]
    dydt[11] = frame_moment / p[BG_FRAME_YAW_INERTIA]
    for j in range(6):
        dydt[j] = y[6 + j]


@njit(cache=True)
def bogie_outputs(table, y, p, surf, out):
    """Outputs per time: per wheelset (front 0-4, rear 5-9) ``power_left, power_right, flange, Fy, Mz``
    (``table``: on real profiles, ``flange`` the lateral component of the normal forces)."""
    for i in range(2):
        _put_wheelset_outputs(out, i, _bogie_contact(table, p[BG_LAW], i, y, p, surf))


@njit(cache=True, inline="always")
def _put_wheelset_outputs(out, i, forces):
    """Write wheelset ``i``'s ``(Fy, Mz, power_left, power_right, flange)`` into ``out[5 i:5 i + 5]``
    as ``power_left, power_right, flange, Fy, Mz``."""
    fy, mz, power_left, power_right, flange = forces
    out[5 * i + 0] = power_left
    out[5 * i + 1] = power_right
    out[5 * i + 2] = flange
    out[5 * i + 3] = fy
    out[5 * i + 4] = mz


# ---- the published Cooperrider bogie --------------------------------------------------------
@njit(cache=True, inline="always")
def _cooperrider_wheelset(i, y, p, surf):
    """``(Fy, Mz, power_left, power_right, flange)`` of wheelset ``i`` (0 front, 1 rear) of the
    seven-degree-of-freedom bogie: both wheels' creep forces (``_creep``, no spin, linear
    coefficients ``f11``, ``f22``, saturated together at ``mu N``) and the dead-band flange spring."""
    lat = y[2 * i]
    fy, mz, power_left, power_right = _conical_wheelset(
        lat, y[2 * i + 1], y[7 + 2 * i], y[8 + 2 * i], p[CP_SPEED], p[CP_HALF_GAUGE], p[CP_ROLLING_RADIUS],
        p[CP_CONICITY], p[CP_F11], p[CP_F22], 0.0, 0.0, p[CP_FRICTION] * p[CP_WHEEL_LOAD], p[CP_LAW], surf,
        int(p[CP_LAW_OFFSET]), int(p[CP_LAW_POINTS]))
    flange = _dead_band(lat, p[CP_FLANGE_CLEARANCE], p[CP_FLANGE_STIFFNESS])
    return fy + flange, mz, power_left, power_right, flange


@njit(cache=True)
def cooperrider_rhs(t, y, p, surf, dydt):
    """The Cooperrider bogie of Kaas-Petersen (1986): state ``[y1, psi1, y2, psi2, y_f, psi_f,
    phi_f]`` and their rates (front wheelset at ``x = +b``; frame roll ``phi_f`` about the
    direction of travel, right-handed, so a frame point ``z`` above the centre of mass moves
    ``-z phi_f`` laterally). Springs per side, the car body moving straight at ``speed``:

    wheelset: ``m_w y_i'' = Fy_i + F_T(y_i) - 2 k1 d_i``, ``d_i = y_i - y_f - x_i psi_f - h1 phi_f``;
    ``I_w psi_i'' = Mz_i - 2 k2 d1^2 (psi_i - psi_f)``;
    frame: ``m_f y_f'' = 2 k1 (d_1 + d_2) - 2 k4 s - 2 D1 s'``, ``s = y_f - h2 phi_f``;
    ``I_fz psi_f'' = sum_i (2 k1 x_i d_i + 2 k2 d1^2 (psi_i - psi_f))``;
    ``I_fx phi_f'' = 2 k1 h1 (d_1 + d_2) + 2 h2 (k4 s + D1 s') - (4 k3 d1^2 + 2 k5 d2^2) phi_f
    - 2 D2 d2^2 phi_f'``.
    """
    b = p[CP_HALF_WHEELBASE]
    k1 = p[CP_PRIMARY_LATERAL_STIFFNESS]
    kpsi = 2.0 * p[CP_PRIMARY_LONGITUDINAL_STIFFNESS] * p[CP_PRIMARY_SPRING_HALF_SPACING] ** 2
    h1 = p[CP_PRIMARY_HEIGHT]
    h2 = p[CP_SECONDARY_HEIGHT]
    s = y[4] - h2 * y[6]
    ds = y[11] - h2 * y[13]
    secondary = p[CP_SECONDARY_LATERAL_STIFFNESS] * s + p[CP_SECONDARY_LATERAL_DAMPING] * ds
    frame_force = -2.0 * secondary
    frame_moment = 0.0
    d1 = p[CP_PRIMARY_SPRING_HALF_SPACING]
    d2 = p[CP_SECONDARY_SPRING_HALF_SPACING]
    roll_moment = (2.0 * h2 * secondary
                   - (4.0 * p[CP_PRIMARY_VERTICAL_STIFFNESS] * d1 * d1
                      + 2.0 * p[CP_SECONDARY_VERTICAL_STIFFNESS] * d2 * d2) * y[6]
                   - 2.0 * p[CP_SECONDARY_VERTICAL_DAMPING] * d2 * d2 * y[13])
    for i in range(2):
        x = b if i == 0 else -b
        fy, mz, _, _, _ = _cooperrider_wheelset(i, y, p, surf)
        spring = 2.0 * k1 * (y[2 * i] - y[4] - x * y[5] - h1 * y[6])
        twist = kpsi * (y[2 * i + 1] - y[5])
        dydt[7 + 2 * i] = (fy - spring) / p[CP_WHEELSET_MASS]
        dydt[8 + 2 * i] = (mz - twist) / p[CP_WHEELSET_YAW_INERTIA]
        frame_force += spring
        frame_moment += x * spring + twist
        roll_moment += h1 * spring
    dydt[11] = frame_force / p[CP_FRAME_MASS]
    dydt[12] = frame_moment / p[CP_FRAME_YAW_INERTIA]
    dydt[13] = roll_moment / p[CP_FRAME_ROLL_INERTIA]
    for j in range(7):
        dydt[j] = y[7 + j]


@njit(cache=True)
def cooperrider_outputs(y, p, surf, out):
    """Outputs per time, as ``bogie_outputs``: per wheelset (front 0-4, rear 5-9)
    ``power_left, power_right, flange, Fy, Mz``."""
    for i in range(2):
        _put_wheelset_outputs(out, i, _cooperrider_wheelset(i, y, p, surf))


# ---- disk wheel -----------------------------------------------------------------------------
@njit(cache=True, inline="always")
def surface_primitive(surf, n, x):
    """Integral of the periodic piecewise-linear ``u`` from 0 to ``x`` [m rad].

    ``surf[:n]`` holds ``u`` at the nodes ``x_j = 2 pi j / n``, ``surf[n:2n+1]`` its cumulative
    trapezoidal integral at the nodes (``surf[2n]`` over one period).
    """
    dx = TWO_PI / n
    periods = math.floor(x / TWO_PI)
    xr = x - periods * TWO_PI
    j = int(xr / dx)
    if j >= n:
        j = n - 1
    s = xr - j * dx
    u0 = surf[j]
    u1 = surf[(j + 1) % n]
    return periods * surf[2 * n] + surf[n + j] + u0 * s + (u1 - u0) * s * s / (2.0 * dx)


@njit(cache=True, inline="always")
def surface_value(surf, n, x):
    """Piecewise-linear periodic interpolation of ``u`` at angle ``x`` [m]."""
    dx = TWO_PI / n
    xr = x - math.floor(x / TWO_PI) * TWO_PI
    j = int(xr / dx)
    if j >= n:
        j = n - 1
    s = (xr - j * dx) / dx
    return (1.0 - s) * surf[j] + s * surf[(j + 1) % n]


@njit(cache=True, inline="always")
def patch_average(surf, n, x, half_angle):
    """Contact filter: mean of ``u`` over ``[x - w, x + w]``, ``w`` the patch half-angle [m]."""
    if n == 0:
        return 0.0
    if half_angle <= 0.0:
        return surface_value(surf, n, x)
    hi = surface_primitive(surf, n, x + half_angle)
    lo = surface_primitive(surf, n, x - half_angle)
    return (hi - lo) / (2.0 * half_angle)


@njit(cache=True, inline="always")
def creep_curve(surf, offset, points, s):
    """``F / (mu N)`` at the normalised creepage ``s = f11 |xi| / (mu N) >= 0`` from a curve
    tabulated at ``r = s / (1 + s)`` on ``points`` equal steps over ``[0, 1]`` (``r = 1`` is full
    slip), linear in ``r``."""
    r = s / (1.0 + s)
    pos = r * (points - 1)
    j = min(int(pos), points - 2)
    w = pos - j
    return (1.0 - w) * surf[offset + j] + w * surf[offset + j + 1]


@njit(cache=True, inline="always")
def _disk_contact(t, y, p, surf):
    """Contact of the disk wheel: ``(N, creepage, Fx, power, x_c mod 2 pi, u_bar, delta)``.

    ``N = k_H delta_+^(3/2)``; creepage ``xi = (Omega (R0 + u_bar) - V) / V``;
    ``Fx = f11 (N/W)^(2/3) xi`` (Kalker, ``c^2 ~ N^(2/3)``) saturated at ``mu N`` by the cubic
    law or by FASTSIM's creep curve; frictional power ``Fx xi V``.
    """
    v = p[DW_SPEED]
    r0 = p[DW_RADIUS]
    xc = p[DW_INITIAL_ANGLE] + v / r0 * t + y[0]
    ubar = patch_average(surf, int(p[DW_N_CELLS]), xc, p[DW_PATCH_HALF_ANGLE])
    delta = p[DW_STATIC_APPROACH] + y[6] - y[2] + ubar
    normal = 0.0
    if delta > 0.0:
        normal = p[DW_HERTZ_CONSTANT] * delta * math.sqrt(delta)
    creepage = (y[1] * (r0 + ubar) - v) / v
    force = 0.0
    if normal > 0.0:
        # Kalker's f11 ~ c^2 ~ N^(2/3), and for Hertz (N/W)^(2/3) = delta/delta_0
        f11 = p[DW_F11] * delta / p[DW_STATIC_APPROACH]
        force = f11 * creepage
        limit = p[DW_FRICTION] * normal
        if p[DW_CREEP_LAW] == 0.0 or not limit < np.inf:
            force *= saturation_factor(abs(force), limit)
        else:
            ratio = creep_curve(surf, int(p[DW_CREEP_TABLE_OFFSET]), int(p[DW_CREEP_TABLE_POINTS]), abs(force) / limit)
            force = math.copysign(limit * ratio, creepage)
    return normal, creepage, force, force * creepage * v, xc - math.floor(xc / TWO_PI) * TWO_PI, ubar, delta


@njit(cache=True, inline="always")
def disk_wheel_rhs(t, y, p, surf, dydt):
    """Disk wheel (paper Fig. 5), state ``[phi, Omega, z_w, z_w', z_s, z_s', z_r, z_r']``.

    Wheel angle ``theta = V t / R0 + phi``; contact angle ``x_c = x0 + theta``; vertical
    displacements upward from static equilibrium. ``J Omega' = T - (R0 + u_bar) Fx``,
    ``m_w z_w'' = -P + N - W``, ``m_s z_s'' = P``, ``m_r z_r'' = -k_p z_r - c_p z_r' - (N - W)``,
    ``P = k_1 (z_w - z_s) + c_1 (z_w' - z_s')``, ``delta = delta_0 + z_r - z_w + u_bar(x_c)``.
    The sprung mass carries a dead load (the car body), so the static load ``W`` is a parameter.
    """
    normal, _, force, _, _, ubar, _ = _disk_contact(t, y, p, surf)
    r0 = p[DW_RADIUS]
    dydt[0] = y[1] - p[DW_SPEED] / r0
    dydt[1] = (p[DW_TORQUE] - (r0 + ubar) * force) / p[DW_WHEEL_INERTIA]
    if p[DW_SPRUNG_MASS] > 0.0:
        primary = p[DW_PRIMARY_STIFFNESS] * (y[2] - y[4]) + p[DW_PRIMARY_DAMPING] * (y[3] - y[5])
        dydt[4] = y[5]
        dydt[5] = primary / p[DW_SPRUNG_MASS]
    else:
        primary = p[DW_PRIMARY_STIFFNESS] * y[2] + p[DW_PRIMARY_DAMPING] * y[3]
        dydt[4] = 0.0
        dydt[5] = 0.0
    dydt[2] = y[3]
    dydt[3] = (normal - p[DW_STATIC_LOAD] - primary) / p[DW_WHEEL_MASS]
    if p[DW_RAIL_MASS] > 0.0:
        dydt[6] = y[7]
        dydt[7] = (-p[DW_PAD_STIFFNESS] * y[6] - p[DW_PAD_DAMPING] * y[7] - (normal - p[DW_STATIC_LOAD])) / p[DW_RAIL_MASS]
    else:
        dydt[6] = 0.0
        dydt[7] = 0.0


@njit(cache=True)
def disk_wheel_outputs(t, y, p, surf, out):
    """Outputs per time: ``N, creepage, Fx, power, x_c, u_bar, delta`` (see ``_disk_contact``)."""
    vals = disk_contact(t, y, p, surf)
    for k in range(DW_N_OUTPUTS):
        out[k] = vals[k]


@njit(cache=True)
def disk_contact(t, y, p, surf):
    """``_disk_contact`` called, not inlined, by the outputs and the swept power: one compiled copy
    for them, where each inlined copy was compiled again (the energy deposit's four took about
    10 s of a cold run). The right-hand side and the event function, evaluated every step, keep
    theirs inlined (the event as a call made the loop 10 % slower)."""
    return _disk_contact(t, y, p, surf)


@njit(cache=True, inline="always")
def disk_wheel_event(t, y, p, surf):
    """Contact event function: the approach ``delta`` [m]; zero at contact loss and regain."""
    return _disk_contact(t, y, p, surf)[6]


@njit(cache=True, inline="always")
def _ramp_integral(u, w):
    """``K(u) = integral_0^u clamp(s, 0, 2w) ds``."""
    if u <= 0.0:
        return 0.0
    if u < 2.0 * w:
        return 0.5 * u * u
    return 2.0 * w * u - 2.0 * w * w


@njit(cache=True, inline="always")
def _sweep_cdf(x, xa, xb, w):
    """Fraction of the energy below angle ``x`` when a patch of half-width ``w`` moves uniformly
    from ``xa`` to ``xb >= xa`` (the box of the patch convolved with the sweep)."""
    length = xb - xa
    if w <= 0.0:
        if length <= 0.0:
            return 1.0 if x >= xa else 0.0
        return min(max((x - xa) / length, 0.0), 1.0)
    if length <= 1e-12 * w:
        return min(max((x + w - xa) / (2.0 * w), 0.0), 1.0)
    return (_ramp_integral(x + w - xa, w) - _ramp_integral(x + w - xb, w)) / (2.0 * w * length)


@njit(cache=True)
def sweep(energy, xa, xb, half_angle, amount):
    """Add ``amount`` [J] to the cells of ``energy`` as a contact patch of half-width
    ``half_angle`` sweeps uniformly from angle ``xa`` to ``xb`` (cell ``j`` covers
    ``[x_j - dx/2, x_j + dx/2]``, ``x_j = 2 pi j / n``, periodic). Exact for a uniform sweep;
    the cells receive exactly ``amount``."""
    if xb < xa:
        xa, xb = xb, xa
    n = energy.shape[0]
    dx = TWO_PI / n
    first = int(math.floor((xa - half_angle) / dx + 0.5))
    last = int(math.floor((xb + half_angle) / dx + 0.5))
    below = _sweep_cdf((first - 0.5) * dx, xa, xb, half_angle)
    for c in range(first, last + 1):
        above = _sweep_cdf((c + 0.5) * dx, xa, xb, half_angle)
        energy[c % n] += amount * (above - below)
        below = above


def contact_power(kind, t, y, p, surf):
    """``(x_c, power)``: the contact angle on the wheel, not wrapped [rad], and the frictional
    power [W] (disk wheel; ``(0, 0)`` for the other models). Compiled code only."""
    raise TypeError("contact_power is for compiled code")


@overload(contact_power, inline="always", prefer_literal=True)
def _contact_power(kind, t, y, p, surf):
    if not isinstance(kind, types.IntegerLiteral):
        return None
    if kind.literal_value == KIND_DISK_WHEEL:  # _PARTS["cells"]
        def impl(kind, t, y, p, surf):
            power = disk_contact(t, y, p, surf)[3]
            return p[DW_INITIAL_ANGLE] + p[DW_SPEED] / p[DW_RADIUS] * t + y[0], power
        return impl
    return lambda kind, t, y, p, surf: (0.0, 0.0)


def model_has(kind, part):
    """True where model ``kind`` has ``part`` (a constant string: "cells", a contact power deposited
    on the wheel's cells; "events", an event function; "switches", a switching function), None
    where it has not (its ``contact_power`` is 0, its event or switching function the constant 1):
    an argument on which numba prunes that part from the integrator's loop. Compiled code only."""
    raise TypeError("model_has is for compiled code")


_PARTS = {"cells": (KIND_DISK_WHEEL,), "events": (KIND_DISK_WHEEL,),
          "switches": (KIND_WHEELSET, KIND_BOGIE, KIND_COOPERRIDER)}


@overload(model_has, inline="always", prefer_literal=True)
def _model_has(kind, part):
    if not (isinstance(kind, types.IntegerLiteral) and isinstance(part, types.StringLiteral)):
        return None
    if kind.literal_value in _PARTS[part.literal_value]:
        return lambda kind, part: True
    return lambda kind, part: None


def patch_half_angle(kind, p):
    """Half-width of the contact patch on the wheel [rad] (disk wheel; 0 otherwise). Compiled code only."""
    raise TypeError("patch_half_angle is for compiled code")


@overload(patch_half_angle, inline="always", prefer_literal=True)
def _patch_half_angle(kind, p):
    if not isinstance(kind, types.IntegerLiteral):
        return None
    if kind.literal_value == KIND_DISK_WHEEL:
        return lambda kind, p: p[DW_PATCH_HALF_ANGLE]
    return lambda kind, p: 0.0


# ---- test systems ---------------------------------------------------------------------------
@njit(cache=True, inline="always")
def linear_rhs(t, y, p, surf, dydt):
    """``y' = A y`` with ``n = p[0]`` and ``A = p[1:1+n*n]`` row by row."""
    n = int(p[0])
    for i in range(n):
        acc = 0.0
        for j in range(n):
            acc += p[1 + i * n + j] * y[j]
        dydt[i] = acc


@njit(cache=True, inline="always")
def van_der_pol_rhs(t, y, p, surf, dydt):
    """Van der Pol oscillator ``y'' = mu (1 - y^2) y' - y`` (stiff for large ``mu = p[0]``)."""
    dydt[0] = y[1]
    dydt[1] = p[0] * (1.0 - y[0] * y[0]) * y[1] - y[0]


# ---- dispatch -------------------------------------------------------------------------------
# The model kind is a compile-time constant: a compiled caller takes ``kind`` as a literal
# (``literally(kind)``), and the functions below pick the model's function when they are typed,
# so a run compiles the one model it integrates instead of all of them (the first run of a
# command compiled every model into every integrator). The numbers are the same: the same
# functions run, inlined where they were.


def _literal_kind(kind):
    """The value of a numba integer literal type, or None for a kind only known at run time."""
    return kind.literal_value if isinstance(kind, types.IntegerLiteral) else None


def rhs_inline(kind, t, y, p, surf, dydt):
    """Right-hand side of model ``kind`` into ``dydt``, inlined where it is called (``rhs_call``);
    compiled code only."""
    raise TypeError("rhs_inline is for compiled code; call rhs")


def _pick(kind, impls, none):
    """The implementation in ``impls`` (model kind -> function) for the literal ``kind``; ``none``
    for a kind of no model (it does nothing, as before); None (no match) for a non-literal kind."""
    value = _literal_kind(kind)
    return None if value is None else impls.get(value, none)


_RHS = {
    KIND_WHEELSET: lambda kind, t, y, p, surf, dydt: wheelset_rhs(t, y, p, surf, dydt),
    KIND_DISK_WHEEL: lambda kind, t, y, p, surf, dydt: disk_wheel_rhs(t, y, p, surf, dydt),
    KIND_BOGIE: lambda kind, t, y, p, surf, dydt: bogie_rhs(t, y, p, surf, dydt, False),
    KIND_TABLE_BOGIE: lambda kind, t, y, p, surf, dydt: bogie_rhs(t, y, p, surf, dydt, True),
    KIND_TABLE_WHEELSET: lambda kind, t, y, p, surf, dydt: table_wheelset_rhs(t, y, p, surf, dydt, None),
    KIND_TABLE_POINTS: lambda kind, t, y, p, surf, dydt: table_wheelset_rhs(t, y, p, surf, dydt, True),
    KIND_COOPERRIDER: lambda kind, t, y, p, surf, dydt: cooperrider_rhs(t, y, p, surf, dydt),
    KIND_LINEAR: lambda kind, t, y, p, surf, dydt: linear_rhs(t, y, p, surf, dydt),
    KIND_VAN_DER_POL: lambda kind, t, y, p, surf, dydt: van_der_pol_rhs(t, y, p, surf, dydt),
}


@overload(rhs_inline, inline="always", prefer_literal=True)
def _rhs_inline(kind, t, y, p, surf, dydt):
    return _pick(kind, _RHS, lambda kind, t, y, p, surf, dydt: None)


@njit(cache=True)
def rhs_call(kind, t, y, p, surf, dydt):
    """Right-hand side of model ``kind`` into ``dydt`` (a plain call, from compiled code)."""
    literally(kind)
    rhs_inline(kind, t, y, p, surf, dydt)


def event_inline(kind, t, y, p, surf):
    """Event function of model ``kind`` (sign changes are events); 1 where a model has none.
    Compiled code only (``event`` from Python)."""
    raise TypeError("event_inline is for compiled code; call event")


@overload(event_inline, prefer_literal=True)  # a call (inlined, numba's SSA check warns)
def _event_inline(kind, t, y, p, surf):
    value = _literal_kind(kind)
    if value == KIND_DISK_WHEEL:  # _PARTS["events"]
        return lambda kind, t, y, p, surf: disk_wheel_event(t, y, p, surf)
    if value is not None:
        return lambda kind, t, y, p, surf: 1.0
    return None


@njit(cache=True)
def event_call(kind, t, y, p, surf):
    """Event function of model ``kind`` (a plain call, from compiled code: the integrator's loop and
    its event location share this one compiled copy)."""
    literally(kind)
    return event_inline(kind, t, y, p, surf)


def switching_inline(kind, t, y, p, surf):
    """Switching function of model ``kind``: its sign changes where the right-hand side has a kink
    that the integrators cut their steps at. Flange contact made or lost: ``|y - y_t| - clearance``
    [m] for the wheelset, the product of the two wheelsets' gaps [m^2] for the conical bogies; 1
    where a model has none. Compiled code only (``switching`` from Python)."""
    raise TypeError("switching_inline is for compiled code; call switching")


@overload(switching_inline, prefer_literal=True)  # a call: only rejected steps ask
def _switching_inline(kind, t, y, p, surf):  # the kinds of _PARTS["switches"]
    value = _literal_kind(kind)
    if value == KIND_WHEELSET:
        return lambda kind, t, y, p, surf: abs(y[0] - _track_alignment(t, p, surf)) - p[WS_FLANGE_CLEARANCE]
    if value == KIND_BOGIE:
        return lambda kind, t, y, p, surf: (abs(y[0]) - p[BG_FLANGE_CLEARANCE]) * (abs(y[2]) - p[BG_FLANGE_CLEARANCE])
    if value == KIND_COOPERRIDER:
        return lambda kind, t, y, p, surf: (abs(y[0]) - p[CP_FLANGE_CLEARANCE]) * (abs(y[2]) - p[CP_FLANGE_CLEARANCE])
    if value is not None:
        return lambda kind, t, y, p, surf: 1.0
    return None


@njit(cache=True)
def _switching(kind, t, y, p, surf):
    literally(kind)
    return switching_inline(kind, t, y, p, surf)


def outputs_row(kind, t, y, p, surf, out):
    """The model's derived quantities at one time into ``out``; compiled code only."""
    raise TypeError("outputs_row is for compiled code; call outputs")


_OUTPUTS = {
    KIND_WHEELSET: lambda kind, t, y, p, surf, out: wheelset_outputs(t, y, p, surf, out),
    KIND_DISK_WHEEL: lambda kind, t, y, p, surf, out: disk_wheel_outputs(t, y, p, surf, out),
    KIND_BOGIE: lambda kind, t, y, p, surf, out: bogie_outputs(False, y, p, surf, out),
    KIND_TABLE_BOGIE: lambda kind, t, y, p, surf, out: bogie_outputs(True, y, p, surf, out),
    KIND_TABLE_WHEELSET: lambda kind, t, y, p, surf, out: table_wheelset_outputs(t, y, p, surf, out, None),
    KIND_TABLE_POINTS: lambda kind, t, y, p, surf, out: table_wheelset_outputs(t, y, p, surf, out, True),
    KIND_COOPERRIDER: lambda kind, t, y, p, surf, out: cooperrider_outputs(y, p, surf, out),
}


@overload(outputs_row, inline="always", prefer_literal=True)
def _outputs_row(kind, t, y, p, surf, out):
    return _pick(kind, _OUTPUTS, lambda kind, t, y, p, surf, out: None)


@njit(cache=True)
def _outputs(kind, ts, ys, p, surf, n_out):
    literally(kind)
    res = np.zeros((ts.shape[0], n_out))
    for i in range(ts.shape[0]):
        outputs_row(kind, ts[i], ys[i], p, surf, res[i])
    return res


class ByLiteral:
    """A compiled function that takes some of its arguments (the model kind, the method) as
    compile-time constants (``literally``), called from Python. numba would type every such call
    again to find the specialisation (milliseconds), so each (constant values, argument types) is
    looked up once and its compiled entry point called directly after. ``literal``: the positions
    of the constant arguments (integers)."""

    def __init__(self, dispatcher, doc, literal=(0,)):
        self.dispatcher, self.__doc__, self.literal = dispatcher, doc, literal
        self._entries = {}

    @staticmethod
    def _type_key(a):
        if isinstance(a, np.ndarray):
            f = a.flags
            return a.dtype.str, a.ndim, f.c_contiguous, f.f_contiguous, f.writeable, f.aligned
        return type(a)

    def __call__(self, *args):
        args = tuple(int(a) if i in self.literal else a for i, a in enumerate(args))
        key = tuple(a if i in self.literal else self._type_key(a) for i, a in enumerate(args))
        entry = self._entries.get(key)
        if entry is not None:
            return entry[0](*args, *entry[1])
        return self._first_call(key, args)

    def bind(self, *args):
        """The compiled entry point for arguments like ``args`` (the same constants, arrays of the
        same dtype, dimensions and layout), for a Python loop that calls it many times: it skips
        the look-up of :meth:`__call__` (3.9 us a call against 0.6 us). It is called once here
        with ``args``, so output arrays among them are written. Arguments of other types must
        not be passed to it: numba does not check them again."""
        args = tuple(int(a) if i in self.literal else a for i, a in enumerate(args))
        key = tuple(a if i in self.literal else self._type_key(a) for i, a in enumerate(args))
        if key not in self._entries:
            self._first_call(key, args)
        entry, defaults = self._entries[key]
        if not defaults:
            return entry
        return lambda *given: entry(*given, *defaults)

    def _first_call(self, key, args):
        with warnings.catch_warnings():  # numba's own inliner check, on the disk wheel's deposit
            warnings.simplefilter("ignore", NumbaIRAssumptionWarning)
            result = self.dispatcher(*args)  # compiles, or loads from the cache
        signature = tuple(types.literal(a) if i in self.literal else typeof(a) for i, a in enumerate(args))
        for sig, compiled in self.dispatcher.overloads.items():  # omitted defaults at the end
            if tuple(sig[:len(args)]) == signature and all(isinstance(s, types.Omitted) for s in sig[len(args):]):
                self._entries[key] = compiled.entry_point, tuple(s.value for s in sig[len(args):])
        return result


rhs = ByLiteral(rhs_call, """Right-hand side of model ``kind`` into ``dydt``: ``rhs(kind, t, y, p, surf, dydt)``.""")
event = ByLiteral(event_call, """Event function of model ``kind`` (sign changes are events): ``event(kind, t, y, p,
surf)``; 1 where a model has none.""")
switching = ByLiteral(_switching, """Switching function of model ``kind`` (``switching_inline``): ``switching(kind,
t, y, p, surf)``.""")
outputs = ByLiteral(_outputs, """Derived quantities of model ``kind`` at every output time: ``outputs(kind, ts,
ys, p, surf, n_out)``, an array ``(len(ts), n_out)``.""")
