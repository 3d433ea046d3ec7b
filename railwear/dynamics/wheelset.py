"""The suspended conical wheelset on straight track (``WheelsetModel``)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from railwear.dynamics import kernels as k
from railwear.dynamics._fields import check, number, pack
from railwear.dynamics.creep_law import check_creep_law, law_params, law_table, linear_slope
from railwear.dynamics.linear import wheelset_state_matrix
from railwear.errors import ScenarioError

__all__ = ["WheelsetModel"]


@dataclass(frozen=True)
class WheelsetModel:
    """Suspended wheelset on straight track: lateral displacement and yaw (REFERENCES.md, Dynamics).

    Conical wheels (``conicity``), Kalker's linear creep coefficients ``f11, f22`` [N],
    ``f23`` [N m], ``f33`` [N m^2] per wheel, Johnson-Vermeulen saturation at
    ``friction_coefficient * wheel_load`` (``inf``: none), flange contact as a linear spring
    outside the dead band ``|y| <= flange_clearance``. The frame moves at ``speed`` [m/s].
    ``lateral_irregularity``: optional lateral alignment of the track [m] at equally spaced
    points over ``irregularity_wavelength`` [m], repeated periodically.
    ``spin_inertia`` [kg m^2]: the axle's polar inertia; finite, it adds the spin deviation
    ``omega`` [rad/s] from ``V / r0`` as a fifth state (start ``initial_spin_deviation``), driven
    by the torque of the longitudinal creep forces; ``inf`` (default): constant spin ``V / r0``.
    ``creep_law``: ``"cubic"`` (Johnson-Vermeulen saturation) or ``"fastsim"`` (FASTSIM's
    creep curve, see ``railwear.contact.fastsim_factor_table``).
    """

    mass: float
    yaw_inertia: float
    lateral_stiffness: float
    yaw_stiffness: float
    f11: float
    f22: float
    half_gauge: float
    rolling_radius: float
    conicity: float
    speed: float
    f23: float = 0.0
    f33: float = 0.0
    lateral_damping: float = 0.0
    yaw_damping: float = 0.0
    wheel_load: float = 50e3
    friction_coefficient: float = math.inf
    flange_clearance: float = math.inf
    flange_stiffness: float = 0.0
    initial_lateral_displacement: float = 1e-3
    initial_yaw_angle: float = 0.0
    initial_lateral_velocity: float = 0.0
    initial_yaw_rate: float = 0.0
    lateral_irregularity: tuple | None = None
    irregularity_wavelength: float = 100.0
    spin_inertia: float = math.inf
    initial_spin_deviation: float = 0.0
    creep_law: str = "cubic"

    kind = k.KIND_WHEELSET
    CREEP_LAWS = ("cubic", "fastsim")
    default_atol = 1e-10

    @property
    def n_states(self) -> int:
        """4, or 5 with the spin deviation state (finite ``spin_inertia``)."""
        return 4 if self.spin_inertia == math.inf else 5

    def __post_init__(self):
        check(
            self,
            positive=("mass", "yaw_inertia", "half_gauge", "rolling_radius", "speed", "wheel_load"),
            nonnegative=(
                "lateral_stiffness", "yaw_stiffness", "f11", "f22", "f33", "conicity", "lateral_damping",
                "yaw_damping", "flange_stiffness",
            ),
            finite=(
                "lateral_stiffness", "yaw_stiffness", "f11", "f22", "f23", "f33", "conicity",
                "lateral_damping", "yaw_damping", "flange_stiffness", "initial_lateral_displacement",
                "initial_yaw_angle", "initial_lateral_velocity", "initial_yaw_rate", "initial_spin_deviation",
            ),
        )
        for name in ("friction_coefficient", "flange_clearance", "spin_inertia"):
            if not number(self, name) > 0.0:
                raise ScenarioError(f"{name}: must be positive (inf to switch it off), got {getattr(self, name)!r}")
        check(self, positive=("irregularity_wavelength",))
        check_creep_law(self)
        if self.lateral_irregularity is not None:
            values = np.asarray(self.lateral_irregularity, dtype=float)
            if values.ndim != 1 or values.size < 2 or not np.all(np.isfinite(values)):
                raise ScenarioError("lateral_irregularity: must be at least 2 finite lateral track positions [m]")
            object.__setattr__(self, "lateral_irregularity", tuple(float(v) for v in values))

    def params(self, speed=None) -> np.ndarray:
        """Parameter array for ``kernels.wheelset_rhs`` (``speed`` overrides the model's)."""
        cells = 0 if self.lateral_irregularity is None else len(self.lateral_irregularity)
        return pack(self, "WS_", k.WS_N_PARAMS, speed, irregularity_cells=cells, **law_params(self, cells))

    def surface(self) -> np.ndarray:
        """The lateral track alignment ``y_t`` [m] at ``j L / n`` along one wavelength ``L``,
        followed by the FASTSIM factor table where that creep law is chosen."""
        track = np.zeros(0) if self.lateral_irregularity is None else np.array(self.lateral_irregularity)
        return np.concatenate([track, law_table(self)])

    def initial_state(self) -> np.ndarray:
        y = [self.initial_lateral_displacement, self.initial_yaw_angle, self.initial_lateral_velocity,
             self.initial_yaw_rate, self.initial_spin_deviation]
        return np.array(y[:self.n_states], dtype=float)

    def state_matrix(self, speed=None) -> np.ndarray:
        """Linearisation about the centred rolling state at ``speed`` (default the model's); with
        the spin state 5x5. Under FASTSIM the creep coefficients carry its linear slope."""
        slope = linear_slope(self)
        return wheelset_state_matrix(
            self.speed if speed is None else speed,
            self.mass,
            self.yaw_inertia,
            self.lateral_stiffness,
            self.yaw_stiffness,
            slope * self.f11,
            slope * self.f22,
            self.half_gauge,
            self.rolling_radius,
            self.conicity,
            f23=slope * self.f23,
            f33=slope * self.f33,
            lateral_damping=self.lateral_damping,
            yaw_damping=self.yaw_damping,
            spin_inertia=self.spin_inertia,
        )

    def klingel_wavelength(self) -> float:
        """Klingel's kinematic wavelength ``2 pi sqrt(r0 e / lam)`` [m]."""
        return 2.0 * math.pi * math.sqrt(self.rolling_radius * self.half_gauge / self.conicity)
