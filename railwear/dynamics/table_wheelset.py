"""The suspended wheelset on real profiles through a contact table (``TableWheelsetModel``)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from railwear.contact.constants import creep_coefficients, shear_modulus
from railwear.dynamics import kernels as k
from railwear.dynamics._fields import check, number, pack
from railwear.dynamics.linear import numerical_state_matrix
from railwear.errors import ScenarioError

__all__ = ["TableWheelsetModel", "point_tracks", "table_arrays", "table_geometry", "table_params"]

# the table's variables behind the kernel's fields of one contact (kernels.TW_N_FIELDS, in order)
POINT_FIELDS = ("point_rolling_radius", "point_contact_angle", "point_normal_force", "point_f11", "point_f22",
                "point_f23", "point_f33", "point_wheel_y")
# kernels.table_point_rows per contact: result variable, units, long name
POINT_OUTPUTS = (
    ("point_longitudinal_creepage", "1", "longitudinal creepage of the contact"),
    ("point_lateral_creepage", "1", "lateral creepage of the contact in its contact plane"),
    ("point_spin_creepage", "m-1", "spin creepage of the contact"),
    ("point_longitudinal_creep_force", "N", "longitudinal creep force of the contact"),
    ("point_lateral_creep_force", "N", "lateral creep force of the contact in its contact plane"),
    ("point_spin_creep_moment", "N m", "spin creep moment of the contact"),
    ("point_frictional_power", "W", "frictional power in the contact"),
    ("point_normal_force", "N", "normal force of the contact"),
    ("point_contact_lateral_position", "m", "contact position on the wheel profile (profile coordinate)"),
)


@dataclass(frozen=True, eq=False)
class TableWheelsetModel:
    """Suspended wheelset on real profiles: ``WheelsetModel``'s lateral and yaw motion with the
    rolling radii, contact angles, normal loads and Kalker coefficients of each wheel read from a
    contact table (``railwear.geometry.contact_table``, whose ``y`` is to the right; here ``y`` is
    to the left as in the other models). Axle spin quasi-static, ``2 V / (r_L + r_R)``.
    ``creep_scale`` multiplies the creep coefficients (1000 or more: the kinematic limit, with
    ``spin=False``, since scaled spin creep forces are not kinematic);
    ``outside_stiffness`` [N/m] holds the wheelset inside the table's range of shifts.
    ``creep_law``: ``"cubic"`` (default: each contact's Kalker forces with the cubic saturation)
    or, on a semi-hertzian table, ``"strip-fastsim"``: each contact by FASTSIM strip by strip on
    the table's strips of its patch (``railwear.contact.strip_fastsim``; every strip its own
    rolling radius; the contact's power FASTSIM's local dissipation).
    """

    speed: float
    mass: float
    yaw_inertia: float
    lateral_stiffness: float
    yaw_stiffness: float
    table: object
    lateral_damping: float = 0.0
    yaw_damping: float = 0.0
    friction_coefficient: float = math.inf
    creep_scale: float = 1.0
    spin: bool = True
    outside_stiffness: float = 1e8
    initial_lateral_displacement: float = 1e-3
    initial_yaw_angle: float = 0.0
    initial_lateral_velocity: float = 0.0
    initial_yaw_rate: float = 0.0
    creep_law: str = "cubic"

    n_states = 4
    default_atol = 1e-10

    def __post_init__(self):
        check(
            self,
            positive=("speed", "mass", "yaw_inertia", "creep_scale"),
            nonnegative=("lateral_stiffness", "yaw_stiffness", "lateral_damping", "yaw_damping", "outside_stiffness"),
            finite=("lateral_stiffness", "yaw_stiffness", "lateral_damping", "yaw_damping", "outside_stiffness",
                    "initial_lateral_displacement", "initial_yaw_angle", "initial_lateral_velocity", "initial_yaw_rate"),
        )
        if not number(self, "friction_coefficient") > 0.0:
            raise ScenarioError(f"friction_coefficient: must be positive (inf for none), got {self.friction_coefficient!r}")
        object.__setattr__(self, "_geometry", table_geometry(self.table, bool(self.spin), creep_law_strips(self)))

    def params(self, speed=None) -> np.ndarray:
        return table_params(self, speed)

    @property
    def kind(self) -> int:
        """``KIND_TABLE_POINTS`` on a table whose contacts the dynamics follow one by one, else
        ``KIND_TABLE_WHEELSET``, compiled without that path (the same model)."""
        return k.KIND_TABLE_POINTS if self.contacts else k.KIND_TABLE_WHEELSET

    @property
    def contacts(self) -> int:
        """Contacts per wheel the dynamics evaluate one by one (0: the table's resultant, a table
        without a ``point`` dimension)."""
        return self._geometry[3]

    def point_outputs(self, ds):
        """Each contact's own creepages, forces, frictional power, normal force and position
        (``POINT_OUTPUTS``, over ``(time, wheel, point)``, ``point`` the contact as tracked across
        the table's shifts, ``point_tracks``) at the states of ``simulate``'s result ``ds``, as
        the compiled right-hand side saw them; their forces and powers sum to the per-wheel
        ones of ``ds``. Empty over ``point`` for a table of one contact per wheel. Under
        ``creep_law="strip-fastsim"`` also ``point_strip_frictional_power`` over ``(time, wheel,
        point, strip)``: each strip's own FASTSIM dissipation, summing to the contact's power."""
        states = np.column_stack([ds[v].values for v in ("lateral_displacement", "yaw_angle", "lateral_velocity",
                                                           "yaw_rate")])
        strips = strip_power_array(self, states.shape[0])
        rows = k.table_point_rows(states, self.params(), 0, self.surface(), np.arange(4), strips)
        return point_dataset(rows.reshape(-1, 2, self.contacts, k.TW_N_POINT_OUTPUTS), ("time",), {"time": ds.time},
                             strips)

    def surface(self) -> np.ndarray:
        return self._geometry[1]

    def initial_state(self) -> np.ndarray:
        return np.array([self.initial_lateral_displacement, self.initial_yaw_angle, self.initial_lateral_velocity,
                         self.initial_yaw_rate], dtype=float)

    def state_matrix(self, speed=None) -> np.ndarray:
        """Linearisation about centred running (saturation off), by central differences."""
        p = self.params(speed)
        p[k.TW_FRICTION] = math.inf
        return numerical_state_matrix(self.kind, p, self.n_states, self.surface())


CREEP_LAWS = ("cubic", "strip-fastsim")


def creep_law_strips(model):
    """Whether ``model.creep_law`` asks for strip-wise FASTSIM (checked: a one-line error for an
    unknown law, or for strips without a semi-hertzian table or without spin)."""
    law = getattr(model, "creep_law", "cubic")
    if law not in CREEP_LAWS:
        raise ScenarioError(f"creep_law: must be one of {', '.join(CREEP_LAWS)}, got {law!r}")
    if law == "cubic":
        return False
    if "point_strip_half_length" not in model.table.data_vars:
        raise ScenarioError("creep_law: 'strip-fastsim' needs a semi-hertzian contact table (its strips)")
    if not model.spin:
        raise ScenarioError("creep_law: 'strip-fastsim' takes the spin of every contact (spin=True)")
    return True


def table_params(model, speed, **derived):
    """The ``TW_*`` parameter array of a model on real profiles (its ``_geometry`` from
    ``table_arrays``); ``derived`` fills what the model's fields do not."""
    y, _, e0, contacts, strips, (left, right) = model._geometry
    return pack(model, "TW_", k.TW_N_PARAMS, speed, half_gauge=e0, y_min=y[0], dy=y[1] - y[0], n_points=y.size,
                n_contacts=contacts, strips=strips, wheel_y0_left=left, wheel_y0_right=right, **derived)


def strip_power_array(model, n):
    """``None``, or for strip-wise FASTSIM the zeroed array ``(n, 2 P, S)`` that
    ``kernels.table_point_rows`` fills with each strip's frictional power."""
    strips = model._geometry[4]
    return np.zeros((n, 2 * model.contacts, strips)) if strips else None


def point_dataset(rows, dims, coords, strip_power=None):
    """``table_point_rows``' values, shaped ``dims + (wheel, point, field)``, as an
    ``xarray.Dataset`` of ``POINT_OUTPUTS`` over ``dims + ("wheel", "point")`` (``coords`` those of
    ``dims``); with ``strip_power`` (``table_point_rows``' strip array, shaped ``dims + (2 P, S)``
    or flat over ``dims``) also ``point_strip_frictional_power`` over ``... + ("strip",)``."""
    import xarray as xr

    names = tuple(dims) + ("wheel", "point")
    data = {name: (names, rows[..., i], {"units": unit, "long_name": long})
            for i, (name, unit, long) in enumerate(POINT_OUTPUTS)}
    if strip_power is not None:
        data["point_strip_frictional_power"] = (
            names + ("strip",), strip_power.reshape(rows.shape[:-1] + strip_power.shape[-1:]),
            {"units": "W", "long_name": "frictional power of each strip of the contact (strip-wise FASTSIM)"})
    coords = dict(coords, wheel=("wheel", ["left", "right"], {"long_name": "wheel of the wheelset"}),
                  point=("point", np.arange(rows.shape[-2]),
                         {"long_name": "contact of the wheel, tracked across the table's shifts (point_tracks)"}))
    return xr.Dataset(data, coords=coords)


def table_geometry(table, spin=True, strips=False):
    """What the compiled table models read: ``(y, surf, e0, P, S, (y0_left, y0_right))``,
    ``table_arrays``' grid, kernel array and half distance, the array followed, for a table with a
    ``point`` dimension (``contact_model`` "multi-hertz", "semi-hertzian"), by the ``TW_N_FIELDS``
    columns of each of the ``P`` contacts per wheel that ``point_tracks`` follows across the shifts
    (left wheel's first; a contact's geometry held at its nearest loaded shift where it carries no
    load, its normal force and creep coefficients zero there), and with ``strips`` by the
    ``strip_block`` of the ``S`` strips per contact (else ``S = 0``). ``P = 0`` for a table without
    points: the kernels then read the per-wheel resultant only. ``y0_left``, ``y0_right``: each
    wheel's (resultant) contact position on its profile at ``y = 0`` (the shift nearest to it),
    the reference of each contact's lever arm ``e0 + (point_wheel_y - y0)``."""
    y, surf, e0 = table_arrays(table, spin)
    centre = table.sel(y=0.0, method="nearest")
    y0 = tuple(float(centre["wheel_contact_y"].sel(side=side)) for side in ("left", "right"))
    if "point_normal_force" not in table.data_vars:
        return y, surf, e0, 0, 0, y0
    missing = [name for name in POINT_FIELDS + ("point_b",) if name not in table.data_vars]
    if missing:
        raise ScenarioError(f"table: the contact table lacks {', '.join(missing)}")
    tracks = point_tracks(table)
    contacts = tracks["left"].shape[1]
    columns = []
    for side in ("left", "right"):
        for point in range(contacts):
            for name in POINT_FIELDS:
                value = tracked(table, side, tracks[side][:, point], name)
                if name in ("point_f23", "point_f33") and not spin:
                    value = 0.0 * value
                columns.append(value[::-1])  # y to the left: reverse
    block = np.concatenate(columns) if columns else np.zeros(0)
    if not np.all(np.isfinite(block)):
        raise ScenarioError("table: a loaded contact lacks a finite rolling radius, angle, position or creep "
                            "coefficient")
    if not strips:
        return y, np.concatenate([surf, block]), e0, contacts, 0, y0
    return y, np.concatenate([surf, block, strip_block(table, tracks, contacts)]), e0, contacts, \
        table.sizes["strip"], y0


def strip_block(table, tracks, contacts):
    """The kernels' strip columns (``kernels._strip_point``) of every tracked contact, left wheel
    first, ``y`` to the left: FASTSIM's flexibilities L1, L2, L3 of the patch's equivalent
    ellipse (``point_a``, ``point_b``), ``sqrt(a b)``, the strip width, then per strip its
    lateral position in the contact plane about the contact's load centroid, in Kalker's frame
    of the wheel (``+-(strip_wheel_y - wheel_y) / cos(angle)``, + left: the wheelset's y), its
    half-length and its rolling radius (held where the contact carries no load)."""
    from railwear.contact.fastsim import flexibilities

    youngs, poisson = float(table.attrs["youngs_modulus"]), float(table.attrs["poisson"])
    shear = shear_modulus(youngs, poisson)
    columns = []
    for side, sign in (("left", 1.0), ("right", -1.0)):
        for point in range(contacts):
            index = tracks[side][:, point]
            a, b, y, angle = (tracked(table, side, index, f"point_{v}") for v in ("a", "b", "wheel_y", "contact_angle"))
            a, b = np.where(a > 0, a, 1.0), np.where(b > 0, b, 1.0)  # never loaded: any finite ellipse
            head = list(flexibilities(a, b, shear, poisson)) + [np.sqrt(a * b),
                                                                 tracked(table, side, index, "point_strip_width")]
            columns += [np.asarray(v, dtype=float)[::-1] for v in head]
            lateral, half, radius = (tracked_strips(table, side, index, f"point_strip_{v}")
                                     for v in ("wheel_y", "half_length", "rolling_radius"))
            lateral = sign * (lateral - y[:, None]) / np.cos(angle)[:, None]
            for s in range(half.shape[1]):
                columns += [np.nan_to_num(v[::-1, s]) for v in (lateral, half, radius)]
    block = np.concatenate(columns)
    if not np.all(np.isfinite(block)):
        raise ScenarioError("table: a loaded contact's strips are not finite")
    return block


def tracked_strips(table, side, index, name):
    """``tracked`` for a variable over ``(y, point, strip)``: ``(y, strip)`` along one contact."""
    values = np.asarray(table[name].sel(side=side).values, dtype=float)
    loaded = index >= 0
    out = np.zeros((index.size, values.shape[-1]))
    if not loaded.any():
        return out
    where = np.flatnonzero(loaded)
    out[loaded] = values[where, index[loaded]]
    pos = np.searchsorted(where, np.arange(index.size))
    above, below = where[np.clip(pos, 0, where.size - 1)], where[np.clip(pos - 1, 0, where.size - 1)]
    nearest = np.where(np.abs(below - np.arange(index.size)) < np.abs(above - np.arange(index.size)), below, above)
    return out[nearest]


def point_tracks(table):
    """The contacts of each wheel followed across the table's shifts: ``{side: index}``, ``index``
    of shape ``(y, P)`` (the table's ``y`` order) holding for contact ``p`` the table's ``point``
    at each shift, -1 where it carries no load. The table numbers its contacts by gap at each
    shift, so the number of one physical contact changes (tread and flange root swap near 5 mm);
    here a loaded point continues the contact of the neighbouring shift nearest to it on the
    wheel profile (``point_wheel_y``) if within the larger of their lateral semi-axes
    (``point_b``), nearest pairs first, else it starts a new contact; a contact that loses its
    load ends, except that where as many points are left as contacts ended, they continue those
    in their order across the wheel however far they moved (the contacts jump and are
    interpolated between the shifts as the per-wheel resultant is: a table of one contact per
    wheel is one contact). Both wheels get the same ``P`` (unused columns -1)."""
    out = {}
    for side in ("left", "right"):
        row = table.sel(side=side)
        normal = np.asarray(row["point_normal_force"].values, dtype=float)
        position = np.asarray(row["point_wheel_y"].values, dtype=float)
        width = np.asarray(row["point_b"].values, dtype=float)
        index = []
        alive = []
        for j in range(normal.shape[0]):
            loaded = [i for i in range(normal.shape[1]) if normal[j, i] > 0.0]
            pairs = []
            for i in loaded:
                for t in alive:
                    q = index[t][j - 1]
                    distance = abs(position[j, i] - position[j - 1, q])
                    if distance <= max(width[j, i], width[j - 1, q]):
                        pairs.append((distance, i, t))
            now, taken = [], set()
            for _, i, t in sorted(pairs):
                if i not in taken and t not in now:
                    index[t][j] = i
                    taken.add(i)
                    now.append(t)
            points = sorted((position[j, i], i) for i in loaded if i not in taken)
            ends = sorted((position[j - 1, index[t][j - 1]], t) for t in alive if t not in now)
            if points and len(points) == len(ends):  # as many jumped as ended: paired in order across the wheel
                for (_, i), (_, t) in zip(points, ends):
                    index[t][j] = i
                    taken.add(i)
                    now.append(t)
            for i in loaded:
                if i not in taken:
                    index.append(np.full(normal.shape[0], -1))
                    index[-1][j] = i
                    now.append(len(index) - 1)
            alive = now
        out[side] = np.array(index, dtype=int).reshape(-1, normal.shape[0]).T
    contacts = max(v.shape[1] for v in out.values())
    return {side: np.pad(v, ((0, 0), (0, contacts - v.shape[1])), constant_values=-1) for side, v in out.items()}


def tracked(table, side, index, name):
    """Variable ``name`` of the table's ``point`` dimension along one tracked contact (``index``
    over ``y`` from ``point_tracks``): where the contact carries no load, 0 for its normal force and
    creep coefficients, and its value at the nearest shift where it does for the rest (its
    geometry, held); all 0 for a contact never loaded."""
    values = np.asarray(table[name].sel(side=side).values, dtype=float)
    loaded = index >= 0
    out = np.zeros(index.size)
    out[loaded] = values[np.flatnonzero(loaded), index[loaded]]
    if name in ("point_normal_force", "point_f11", "point_f22", "point_f23", "point_f33") or not loaded.any():
        return out
    where = np.flatnonzero(loaded)
    nearest = where[np.clip(np.searchsorted(where, np.arange(index.size)), 0, where.size - 1)]
    below = where[np.clip(np.searchsorted(where, np.arange(index.size)) - 1, 0, where.size - 1)]
    nearest = np.where(np.abs(below - np.arange(index.size)) < np.abs(nearest - np.arange(index.size)), below, nearest)
    return out[nearest]


def table_arrays(table, spin=True):
    """Grid ``y`` (to the left, ascending), the kernel's table array and the half distance of the
    contact points at ``y = 0`` from a contact table (``y`` to the right, sides right/left).
    ``spin=False`` drops the spin coefficients ``f23, f33``."""
    needed = ("rolling_radius", "contact_angle", "normal_force", "a", "b", "c11", "c22", "c23", "c33", "contact_Y",
              "wheel_contact_y")
    try:
        missing = [name for name in needed if name not in table.data_vars]
        shifts = np.asarray(table["y"].values, dtype=float)
        youngs, poisson = float(table.attrs["youngs_modulus"]), float(table.attrs["poisson"])
    except (AttributeError, KeyError, TypeError):
        raise ScenarioError("table: expected a contact table from railwear.geometry.contact_table") from None
    if missing:
        raise ScenarioError(f"table: the contact table lacks {', '.join(missing)}")
    step = np.diff(shifts)
    if shifts.size < 3 or np.any(step <= 0.0) or not np.allclose(step, step[0], rtol=1e-6, atol=1e-12):
        raise ScenarioError("table: the lateral shifts must be equally spaced and increasing")
    shear = shear_modulus(youngs, poisson)
    columns = []
    for side in ("left", "right"):
        row = table.sel(side=side)
        a, b = row["a"].values, row["b"].values
        if not (np.all(np.isfinite(a)) and np.all(np.isfinite(b))):
            raise ScenarioError("table: conformal contact (no Hertz ellipse) is not supported by the dynamics")
        f11, f22, f23, f33 = creep_coefficients(shear, a, b, *(row[c].values for c in ("c11", "c22", "c23", "c33")))
        values = (row["rolling_radius"].values, row["contact_angle"].values, row["normal_force"].values,
                  f11, f22, spin * f23, spin * f33, row["wheel_contact_y"].values)
        columns += [np.asarray(v, dtype=float)[::-1] for v in values]  # y to the left: reverse
    centre = table.sel(y=0.0, method="nearest")
    e0 = 0.5 * float(centre["contact_Y"].sel(side="right") - centre["contact_Y"].sel(side="left"))
    return -shifts[::-1], np.concatenate(columns), e0
