"""The two-axle bogie with conical wheelsets and no frame roll (``BogieModel``) and the
frame fields every bogie shares (``BogieFrame``)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from railwear.dynamics import kernels as k
from railwear.dynamics._fields import check, number, pack
from railwear.dynamics.creep_law import check_creep_law, law_params, law_table
from railwear.dynamics.linear import numerical_state_matrix
from railwear.errors import ScenarioError

__all__ = ["BogieFrame", "BogieModel"]


@dataclass(frozen=True)
class BogieFrame:
    """The fields every bogie has: speed [m/s], masses [kg], yaw inertias [kg m^2], primary and
    secondary stiffnesses [N/m, N m/rad] and dampings [N s/m, N m s/rad], half wheelbase [m]."""

    speed: float
    wheelset_mass: float
    wheelset_yaw_inertia: float
    frame_mass: float
    frame_yaw_inertia: float
    primary_lateral_stiffness: float
    primary_yaw_stiffness: float
    secondary_lateral_stiffness: float
    secondary_lateral_damping: float
    secondary_yaw_stiffness: float
    secondary_yaw_damping: float
    half_wheelbase: float

    n_states = 12
    default_atol = 1e-10

    def initial_state(self) -> np.ndarray:
        """The front wheelset displaced by ``initial_lateral_displacement`` [m], all else at rest."""
        y = np.zeros(self.n_states)
        y[0] = self.initial_lateral_displacement
        return y

    def _check_frame(self, positive=(), nonnegative=(), finite=()):
        springs = ("primary_lateral_stiffness", "primary_yaw_stiffness", "secondary_lateral_stiffness",
                   "secondary_lateral_damping", "secondary_yaw_stiffness", "secondary_yaw_damping")
        check(self, positive=("speed", "wheelset_mass", "wheelset_yaw_inertia", "frame_mass", "frame_yaw_inertia",
                               "half_wheelbase") + positive,
               nonnegative=springs + nonnegative, finite=springs + ("initial_lateral_displacement",) + finite)


@dataclass(frozen=True)
class BogieModel(BogieFrame):
    """Two-axle bogie on straight track without frame roll: lateral and yaw motion of two
    conical wheelsets (``x = +-half_wheelbase``) and of the frame, which hangs from a car body moving
    at ``speed`` through a secondary lateral and yaw spring-damper. Primary: a lateral spring per
    wheelset and a yaw spring per wheelset (``2 k_longitudinal d^2``). Creep, saturation and flange
    dead band as in ``WheelsetModel`` (``creep_law`` ``"cubic"`` or ``"fastsim"``).
    ``BogieModel.cooperrider`` gives a six-degree-of-freedom reading of the Cooperrider numbers
    (the published seven-degree-of-freedom bogie is ``CooperriderBogie``).
    """

    f11: float
    f22: float
    half_gauge: float
    rolling_radius: float
    conicity: float
    f23: float = 0.0
    f33: float = 0.0
    wheel_load: float = 50e3
    friction_coefficient: float = math.inf
    flange_clearance: float = math.inf
    flange_stiffness: float = 0.0
    initial_lateral_displacement: float = 1e-3
    creep_law: str = "cubic"

    kind = k.KIND_BOGIE
    CREEP_LAWS = ("cubic", "fastsim")

    def __post_init__(self):
        self._check_frame(positive=("half_gauge", "rolling_radius", "wheel_load"),
                          nonnegative=("f11", "f22", "f33", "conicity", "flange_stiffness"), finite=("f23",))
        for name in ("friction_coefficient", "flange_clearance"):
            if not number(self, name) > 0.0:
                raise ScenarioError(f"{name}: must be positive (inf to switch it off), got {getattr(self, name)!r}")
        check_creep_law(self)

    @classmethod
    def cooperrider(cls, speed, **overrides):
        """A six-degree-of-freedom simplification with Cooperrider-like numbers: NOT the published
        Cooperrider bogie (that is ``railwear.dynamics.CooperriderBogie``, with frame roll).

        It reads the published per-side springs per wheelset: primary lateral stiffness k1 =
        1.823 MN/m for the wheelset (the published model has ``2 k1``), secondary lateral 0.1823
        MN/m and 20 kN s/m for the frame (published ``2 k4``, ``2 D1``), and takes the secondary
        vertical spring k5 = 0.3333 MN/m and damper D2 = 29.2 kN s/m as a secondary yaw stiffness
        [N m/rad] and damping [N m s/rad]; no frame roll; ``f11 = f22 = G pi a b`` = 6.563 MN (no
        Vermeulen-Johnson coefficients). Yaw stiffness ``2 k2 d1^2`` (k2 = 3.646 MN/m, d1 =
        0.620 m), half wheelbase 1.074 m, masses and inertias, wheel geometry and flange (9.1 mm,
        14.6 MN/m) as in ``CooperriderBogie``. Hopf point 47.87 m/s. Kept as the bogie whose
        kernel the DAE form, the switch cuts and the FASTSIM comparison are tested on.
        """
        k2, spacing = 3.646e6, 0.620
        params = dict(
            speed=speed, wheelset_mass=1022.0, wheelset_yaw_inertia=678.0, frame_mass=2918.9,
            frame_yaw_inertia=6780.0, primary_lateral_stiffness=1.823e6, primary_yaw_stiffness=2.0 * k2 * spacing**2,
            secondary_lateral_stiffness=0.1823e6, secondary_lateral_damping=20e3, secondary_yaw_stiffness=0.3333e6,
            secondary_yaw_damping=29.2e3, half_wheelbase=1.074, f11=6.563e6, f22=6.563e6, half_gauge=0.7163,
            rolling_radius=0.4572, conicity=0.05, flange_clearance=9.1e-3, flange_stiffness=14.60e6,
        )
        params.update(overrides)
        return cls(**params)

    def params(self, speed=None) -> np.ndarray:
        """Parameter array for ``kernels.bogie_rhs`` (``speed`` overrides the model's)."""
        return pack(self, "BG_", k.BG_N_PARAMS, speed, **law_params(self, 0))

    def surface(self) -> np.ndarray:
        return law_table(self)

    def state_matrix(self, speed=None) -> np.ndarray:
        """Linearisation about centred running (saturation off; the flange dead band is open)."""
        p = self.params(speed)
        p[k.BG_FRICTION] = math.inf
        if not self.flange_clearance > 1e-6:
            raise ScenarioError("flange_clearance: the linearisation needs a dead band wider than 1 um")
        return numerical_state_matrix(self.kind, p, self.n_states, self.surface())
