"""The published Cooperrider bogie: seven degrees of freedom, frame roll included
(``CooperriderBogie``; Cooperrider 1972, in the form of Kaas-Petersen 1986).

Degrees of freedom (Kaas-Petersen, Acta Mech. 61 (1986) 89, section 1): lateral displacement and
yaw of the front and of the rear wheelset, lateral displacement, yaw and roll of the frame; the car
body moves straight at constant speed. Conical wheels, Kalker's linear creep without spin, the
Vermeulen-Johnson saturation of the resultant (``u - u^2/3 + u^3/27`` of ``mu N``, ``u`` the
linear resultant over ``mu N``; the cubic law of ``kernels.saturation_factor``), and the flange as
a linear spring outside a dead band. Equations: ``kernels.cooperrider_rhs``.

Sources of the defaults (see docs/dynamics.md, "The published Cooperrider bogie"):

- [KP] Kaas-Petersen 1986: the degrees of freedom and the dead-band flange spring (summary and
  introduction); ``G pi a_e b_e = 6.563 MN`` with ``a_e = 6.578 mm``, ``b_e = 3.934 mm`` (the
  paper's printed ``G = 8.08e8`` Pa is 100 times too small: Hassard's worksheet on the paper's
  misprints, bifurcation.de/brian/whset1.html).
- [DTU] the Cooperrider model of DYTSI (Bigoni, DTU 2011-2014, ``CooperriderModel.cpp`` and its
  input file): frame mass 2918.9 kg, frame roll and yaw inertias 6780 kg m^2, k1 = 1.823 MN/m,
  k2 = k3 = 3.646 MN/m, k4 = 0.1823 MN/m (lateral), k5 = 0.3333 MN/m (vertical), one spring of
  each per side; half wheelbase 1.074 m; d1 = 0.62 m, d2 = 0.68 m; h1 = 0.0762 m (frame centre of
  mass above the axles), h2 = 0.6584 m (secondary lateral spring above it); D1 = 20 kN s/m and
  D2 = 29.2 kN s/m (DYTSI puts D2 with the lateral spring and D1 with the vertical one; here D1
  is lateral, as in Kaas-Petersen's equations as recalled: not confirmed from the paper). Not
  taken from DYTSI: its own additions to the car it builds (yaw dampers D6 = 166.7 kN s/m, in
  the fixed-car-body variant longitudinal yaw springs k6 = 0.90335 MN/m at +-1.5 m, shear
  springs on the secondary vertical springs, profile tables): Kaas-Petersen's seven degrees of
  freedom are described without them (docs/dynamics.md compares them).
- [REF] REFERENCES.md (Cooperrider 1972 via Kaas-Petersen and True's group): wheelset mass
  1022 kg, wheelset yaw inertia 678 kg m^2; rolling radius 0.4572 m (18 in), half gauge 0.7163 m,
  conicity 0.05, flange dead band 9.1 mm and stiffness 14.6 MN/m: to confirm (the mass, the yaw
  inertia and mu = 0.15 are DYTSI's wheelset's too; its gauge and radius are its profiles').
- [R] recalled, not confirmed from a retrieved source: Vermeulen-Johnson's creep coefficients
  psi = 0.54219 (longitudinal) and phi = 0.60252 (lateral), ``f11 = G pi a b / psi``,
  ``f22 = G pi a b / phi``; friction coefficient 0.15. The wheel load 66.7 kN (15,000 lbf) is an
  assumption consistent with the patch: Hertz gives a_e = 6.578 mm, a_e/b_e = 1.672 on the 18 in
  wheel at 65.9 kN (E = 207 GPa, nu = 0.3).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from railwear.dynamics import kernels as k
from railwear.dynamics._fields import check, number, pack
from railwear.dynamics.creep_law import check_creep_law, law_params, law_table
from railwear.dynamics.linear import numerical_state_matrix
from railwear.errors import ScenarioError

__all__ = ["CooperriderBogie", "G_PI_AB", "PSI", "PHI", "PUBLISHED_HOPF_SPEED"]

G_PI_AB = 6.563e6  # N, [KP] as corrected by Hassard
PSI = 0.54219  # [R] Vermeulen-Johnson longitudinal creep coefficient
PHI = 0.60252  # [R] Vermeulen-Johnson lateral creep coefficient
PUBLISHED_HOPF_SPEED = 68.66  # m/s: Seydel, bifurcation.de example exd10 (Hassard's equations of [KP])


@dataclass(frozen=True)
class CooperriderBogie:
    """The Cooperrider bogie with frame roll (7 degrees of freedom, 14 states). SI units; springs
    and dampers are per side (the model has one on the left and one on the right of each), so a
    wheelset's primary lateral stiffness is ``2 k1`` and its yaw stiffness ``2 k2 d1^2``. Every
    default is the published value as traced in the module docstring ([KP], [DTU], [REF], [R]).

    Fields: speed [m/s]; masses [kg] and inertias [kg m^2]; ``primary_*`` (k1 lateral, k2
    longitudinal at ``+-primary_spring_half_spacing`` d1, k3 vertical at ``+-d1``) and
    ``secondary_*`` (k4 lateral at ``secondary_height`` h2 above the frame's centre of mass, k5
    vertical at ``+-secondary_spring_half_spacing`` d2) stiffnesses [N/m] and dampings [N s/m]
    (D1 with k4, D2 with k5); ``primary_height`` h1 [m] (the frame's centre of mass above the
    primary lateral springs); creep coefficients [N]; wheel load [N]; flange dead band [m] and
    stiffness [N/m]; ``creep_law`` ``"cubic"`` (Vermeulen-Johnson) or ``"fastsim"``.
    """

    speed: float
    wheelset_mass: float = 1022.0  # [REF]
    wheelset_yaw_inertia: float = 678.0  # [REF]
    frame_mass: float = 2918.9  # [DTU]
    frame_yaw_inertia: float = 6780.0  # [DTU]
    frame_roll_inertia: float = 6780.0  # [DTU]
    primary_lateral_stiffness: float = 1.823e6  # k1 [DTU]
    primary_longitudinal_stiffness: float = 3.646e6  # k2 [DTU]
    primary_vertical_stiffness: float = 3.646e6  # k3 [DTU]
    secondary_lateral_stiffness: float = 0.1823e6  # k4 [DTU]
    secondary_vertical_stiffness: float = 0.3333e6  # k5 [DTU]
    secondary_lateral_damping: float = 20e3  # D1 [DTU], lateral as recalled from [KP]
    secondary_vertical_damping: float = 29.2e3  # D2 [DTU], vertical as recalled from [KP]
    half_wheelbase: float = 1.074  # b [DTU]
    primary_spring_half_spacing: float = 0.620  # d1 [DTU]
    secondary_spring_half_spacing: float = 0.680  # d2 [DTU]
    primary_height: float = 0.0762  # h1 [DTU]
    secondary_height: float = 0.6584  # h2 [DTU]
    f11: float = G_PI_AB / PSI  # [KP], [R]
    f22: float = G_PI_AB / PHI  # [KP], [R]
    half_gauge: float = 0.7163  # [REF]
    rolling_radius: float = 0.4572  # [REF]
    conicity: float = 0.05  # [REF]
    wheel_load: float = 66.7e3  # assumption, see the module docstring
    friction_coefficient: float = 0.15  # [R]
    flange_clearance: float = 9.1e-3  # [REF]
    flange_stiffness: float = 14.6e6  # [REF]
    initial_lateral_displacement: float = 1e-3
    creep_law: str = "cubic"

    kind = k.KIND_COOPERRIDER
    n_states = 14
    default_atol = 1e-10
    CREEP_LAWS = ("cubic", "fastsim")

    def __post_init__(self):
        springs = ("primary_lateral_stiffness", "primary_longitudinal_stiffness", "primary_vertical_stiffness",
                   "secondary_lateral_stiffness", "secondary_vertical_stiffness", "secondary_lateral_damping",
                   "secondary_vertical_damping", "f11", "f22", "conicity", "flange_stiffness")
        check(self, positive=("speed", "wheelset_mass", "wheelset_yaw_inertia", "frame_mass", "frame_yaw_inertia",
                              "frame_roll_inertia", "half_wheelbase", "primary_spring_half_spacing",
                              "secondary_spring_half_spacing", "half_gauge", "rolling_radius", "wheel_load"),
              nonnegative=springs, finite=springs + ("primary_height", "secondary_height",
                                                     "initial_lateral_displacement"))
        for name in ("friction_coefficient", "flange_clearance"):
            if not number(self, name) > 0.0:
                raise ScenarioError(f"{name}: must be positive (inf to switch it off), got {getattr(self, name)!r}")
        check_creep_law(self)

    def initial_state(self) -> np.ndarray:
        """The front wheelset displaced by ``initial_lateral_displacement`` [m], all else at rest."""
        y = np.zeros(self.n_states)
        y[0] = self.initial_lateral_displacement
        return y

    def params(self, speed=None) -> np.ndarray:
        """Parameter array for ``kernels.cooperrider_rhs`` (``speed`` overrides the model's)."""
        return pack(self, "CP_", k.CP_N_PARAMS, speed, **law_params(self, 0))

    def surface(self) -> np.ndarray:
        return law_table(self)

    def state_matrix(self, speed=None) -> np.ndarray:
        """Linearisation about centred running (saturation off; the flange dead band is open)."""
        p = self.params(speed)
        p[k.CP_FRICTION] = math.inf
        if not self.flange_clearance > 1e-6:
            raise ScenarioError("flange_clearance: the linearisation needs a dead band wider than 1 um")
        return numerical_state_matrix(self.kind, p, self.n_states, self.surface())
