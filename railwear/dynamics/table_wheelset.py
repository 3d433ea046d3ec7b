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

__all__ = ["TableWheelsetModel", "table_arrays", "table_params"]


@dataclass(frozen=True, eq=False)
class TableWheelsetModel:
    """Suspended wheelset on real profiles: ``WheelsetModel``'s lateral and yaw motion with the
    rolling radii, contact angles, normal loads and Kalker coefficients of each wheel read from a
    contact table (``railwear.geometry.contact_table``, whose ``y`` is to the right; here ``y`` is
    to the left as in the other models). Axle spin quasi-static, ``2 V / (r_L + r_R)``.
    ``creep_scale`` multiplies the creep coefficients (1000 or more: the kinematic limit, with
    ``spin=False``, since scaled spin creep forces are not kinematic);
    ``outside_stiffness`` [N/m] holds the wheelset inside the table's range of shifts.
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

    kind = k.KIND_TABLE_WHEELSET
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
        object.__setattr__(self, "_geometry", table_arrays(self.table, bool(self.spin)))

    def params(self, speed=None) -> np.ndarray:
        return table_params(self, speed)

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


def table_params(model, speed, **derived):
    """The ``TW_*`` parameter array of a model on real profiles (its ``_geometry`` from
    ``table_arrays``); ``derived`` fills what the model's fields do not."""
    y, _, e0 = model._geometry
    return pack(model, "TW_", k.TW_N_PARAMS, speed, half_gauge=e0, y_min=y[0], dy=y[1] - y[0], n_points=y.size,
                 **derived)


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
