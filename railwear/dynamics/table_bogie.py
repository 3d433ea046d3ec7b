"""The two-axle bogie with both wheelsets on real profiles (``TableBogieModel``)."""

from __future__ import annotations

import math
from dataclasses import dataclass, fields

import numpy as np

from railwear.dynamics import kernels as k
from railwear.dynamics._fields import number, pack
from railwear.dynamics.bogie import BogieFrame, BogieModel
from railwear.dynamics.linear import numerical_state_matrix
from railwear.dynamics.table_wheelset import (creep_law_strips, point_dataset, strip_power_array, table_geometry,
                                             table_params)
from railwear.errors import ScenarioError

__all__ = ["TableBogieModel"]


@dataclass(frozen=True, eq=False)
class TableBogieModel(BogieFrame):
    """``BogieModel``'s two-axle bogie with both wheelsets on real profiles: each reads the
    contact table as ``TableWheelsetModel`` does (rolling radii, contact angles, normal loads,
    Kalker coefficients; quasi-static axle spin; ``creep_scale``, ``spin``, ``outside_stiffness``
    as there). ``TableBogieModel.cooperrider(speed, table)`` takes the Cooperrider suspension.
    """

    table: object
    friction_coefficient: float = math.inf
    creep_scale: float = 1.0
    spin: bool = True
    outside_stiffness: float = 1e8
    initial_lateral_displacement: float = 1e-3
    creep_law: str = "cubic"

    kind = k.KIND_TABLE_BOGIE

    def __post_init__(self):
        self._check_frame(positive=("creep_scale",), nonnegative=("outside_stiffness",), finite=("outside_stiffness",))
        if not number(self, "friction_coefficient") > 0.0:
            raise ScenarioError(f"friction_coefficient: must be positive (inf for none), got {self.friction_coefficient!r}")
        object.__setattr__(self, "_geometry", table_geometry(self.table, bool(self.spin), creep_law_strips(self)))

    @classmethod
    def cooperrider(cls, speed, table, **overrides):
        """The suspension of ``BogieModel.cooperrider`` on the profiles of ``table``."""
        published = BogieModel.cooperrider(speed)
        params = {f.name: getattr(published, f.name) for f in fields(BogieFrame)}
        params.update(table=table, **overrides)
        return cls(**params)

    def params(self, speed=None) -> np.ndarray:
        """The bogie's ``BG_*`` parameters (the conical contact ones unused, 0) followed by the
        contact table's ``TW_*`` ones (``kernels.bogie_rhs`` with ``table``)."""
        unused = ("f11", "f22", "f23", "f33", "half_gauge", "rolling_radius", "conicity", "wheel_load",
                  "flange_clearance", "flange_stiffness", "law", "law_offset", "law_points")
        bogie = pack(self, "BG_", k.BG_N_PARAMS, speed, **dict.fromkeys(unused, 0.0))
        contact = table_params(self, speed, mass=self.wheelset_mass, yaw_inertia=self.wheelset_yaw_inertia,
                                lateral_stiffness=self.primary_lateral_stiffness,
                                yaw_stiffness=self.primary_yaw_stiffness, lateral_damping=0.0, yaw_damping=0.0)
        return np.concatenate([bogie, contact])

    def surface(self) -> np.ndarray:
        return self._geometry[1]

    @property
    def contacts(self) -> int:
        """Contacts per wheel evaluated one by one, as ``TableWheelsetModel.contacts``."""
        return self._geometry[3]

    def point_outputs(self, ds):
        """Each contact's own quantities (``TableWheelsetModel.point_outputs``) over
        ``(time, wheelset, wheel, point)`` at the states of ``simulate``'s result ``ds`` (and each
        strip's power over ``... + (strip,)`` under strip-wise FASTSIM)."""
        p, surf = self.params(), self.surface()
        states = np.column_stack([ds[v].values for v in ("lateral_displacement", "yaw_angle", "lateral_velocity",
                                                           "yaw_rate")])  # (time, 8): per variable front, rear
        strips = [strip_power_array(self, states.shape[0]) for _ in range(2)]
        rows = np.stack([k.table_point_rows(states, p, k.BG_N_PARAMS, surf, np.array([i, 2 + i, 4 + i, 6 + i]),
                                            strips[i]) for i in range(2)], 1)
        return point_dataset(rows.reshape(rows.shape[0], 2, 2, self.contacts, k.TW_N_POINT_OUTPUTS),
                             ("time", "wheelset"), {"time": ds.time, "wheelset": ds.wheelset},
                             None if strips[0] is None else np.stack(strips, 1))

    def state_matrix(self, speed=None) -> np.ndarray:
        """Linearisation about centred running (saturation off), by central differences."""
        p = self.params(speed)
        p[k.BG_N_PARAMS + k.TW_FRICTION] = math.inf
        return numerical_state_matrix(self.kind, p, self.n_states, self.surface())
