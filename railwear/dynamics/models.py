"""The dynamics models as frozen, validated dataclasses (SI units throughout).

Each model knows its compiled kernel (``kind``), packs its parameters into the float64 array the
kernels read (``params``), gives its initial state and, where it has one, its linear state matrix.
Bad values raise ``railwear.errors.ScenarioError`` with a one-line message naming the field.
"""

from __future__ import annotations

import math
from dataclasses import MISSING, dataclass, fields

import numpy as np
from scipy.optimize import brentq

from railwear.dynamics import kernels as k
from railwear.dynamics.linear import wheelset_state_matrix
from railwear.errors import ScenarioError

__all__ = [
    "BogieModel",
    "DiskWheelModel",
    "MODEL_KINDS",
    "TableBogieModel",
    "TableWheelsetModel",
    "WheelsetModel",
    "build_model",
    "contact_constants",
    "numerical_state_matrix",
]


def _number(model, name):
    value = getattr(model, name)
    try:
        value = float(value)
    except (TypeError, ValueError):
        raise ScenarioError(f"{name}: must be a number, got {value!r}") from None
    if math.isnan(value):
        raise ScenarioError(f"{name}: must be a number, got nan")
    return value


def _check(model, positive=(), nonnegative=(), finite=()):
    """Validate fields: ``positive`` > 0 and finite, ``nonnegative`` >= 0 (may be inf), ``finite``."""
    for name in positive:
        value = _number(model, name)
        if not (value > 0.0 and math.isfinite(value)):
            raise ScenarioError(f"{name}: must be a positive finite number, got {value!r}")
    for name in nonnegative:
        value = _number(model, name)
        if value < 0.0:
            raise ScenarioError(f"{name}: must not be negative, got {value!r}")
    for name in finite:
        value = _number(model, name)
        if not math.isfinite(value):
            raise ScenarioError(f"{name}: must be finite, got {value!r}")


def _pack(model, prefix, size, speed=None, **derived):
    """Parameter array of ``model`` for its kernel: field ``name`` goes to ``kernels.<prefix>NAME``,
    as do the ``derived`` values. The friction coefficient goes to ``<prefix>FRICTION``; every
    index must be filled."""
    p = np.full(size, np.nan)
    for name, value in derived.items():
        p[getattr(k, prefix + name.upper())] = value
    for fld in fields(model):
        name = "FRICTION" if fld.name == "friction_coefficient" else fld.name.upper()
        index = getattr(k, prefix + name, None)
        if index is not None:
            p[index] = getattr(model, fld.name)
    if speed is not None:
        p[getattr(k, prefix + "SPEED")] = speed
    if np.isnan(p).any():
        raise RuntimeError(f"{type(model).__name__}: kernel parameter(s) {np.flatnonzero(np.isnan(p))} not set")
    return p


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
    creep curve, see ``_fastsim_factor_table``).
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
        _check(
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
            if not _number(self, name) > 0.0:
                raise ScenarioError(f"{name}: must be positive (inf to switch it off), got {getattr(self, name)!r}")
        _check(self, positive=("irregularity_wavelength",))
        _check_creep_law(self)
        if self.lateral_irregularity is not None:
            values = np.asarray(self.lateral_irregularity, dtype=float)
            if values.ndim != 1 or values.size < 2 or not np.all(np.isfinite(values)):
                raise ScenarioError("lateral_irregularity: must be at least 2 finite lateral track positions [m]")
            object.__setattr__(self, "lateral_irregularity", tuple(float(v) for v in values))

    def params(self, speed=None) -> np.ndarray:
        """Parameter array for ``kernels.wheelset_rhs`` (``speed`` overrides the model's)."""
        cells = 0 if self.lateral_irregularity is None else len(self.lateral_irregularity)
        return _pack(self, "WS_", k.WS_N_PARAMS, speed, irregularity_cells=cells, **_law_params(self, cells))

    def surface(self) -> np.ndarray:
        """The lateral track alignment ``y_t`` [m] at ``j L / n`` along one wavelength ``L``,
        followed by the FASTSIM factor table where that creep law is chosen."""
        track = np.zeros(0) if self.lateral_irregularity is None else np.array(self.lateral_irregularity)
        return np.concatenate([track, _law_table(self)])

    def initial_state(self) -> np.ndarray:
        y = [self.initial_lateral_displacement, self.initial_yaw_angle, self.initial_lateral_velocity,
             self.initial_yaw_rate, self.initial_spin_deviation]
        return np.array(y[:self.n_states], dtype=float)

    def state_matrix(self, speed=None) -> np.ndarray:
        """Linearisation about the centred rolling state at ``speed`` (default the model's); with
        the spin state 5x5. Under FASTSIM the creep coefficients carry its linear slope."""
        slope = _linear_slope(self)
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
        _check(
            self,
            positive=("speed", "mass", "yaw_inertia", "creep_scale"),
            nonnegative=("lateral_stiffness", "yaw_stiffness", "lateral_damping", "yaw_damping", "outside_stiffness"),
            finite=("lateral_stiffness", "yaw_stiffness", "lateral_damping", "yaw_damping", "outside_stiffness",
                    "initial_lateral_displacement", "initial_yaw_angle", "initial_lateral_velocity", "initial_yaw_rate"),
        )
        if not _number(self, "friction_coefficient") > 0.0:
            raise ScenarioError(f"friction_coefficient: must be positive (inf for none), got {self.friction_coefficient!r}")
        object.__setattr__(self, "_geometry", _table_arrays(self.table, bool(self.spin)))

    def params(self, speed=None) -> np.ndarray:
        return _table_params(self, speed)

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


def _table_params(model, speed, **derived):
    """The ``TW_*`` parameter array of a model on real profiles (its ``_geometry`` from
    ``_table_arrays``); ``derived`` fills what the model's fields do not."""
    y, _, e0 = model._geometry
    return _pack(model, "TW_", k.TW_N_PARAMS, speed, half_gauge=e0, y_min=y[0], dy=y[1] - y[0], n_points=y.size,
                 **derived)


def _table_arrays(table, spin=True):
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
    shear = youngs / (2.0 * (1.0 + poisson))
    columns = []
    for side in ("left", "right"):
        row = table.sel(side=side)
        a, b = row["a"].values, row["b"].values
        if not (np.all(np.isfinite(a)) and np.all(np.isfinite(b))):
            raise ScenarioError("table: conformal contact (no Hertz ellipse) is not supported by the dynamics")
        c2 = a * b
        values = (row["rolling_radius"].values, row["contact_angle"].values, row["normal_force"].values,
                  shear * c2 * row["c11"].values, shear * c2 * row["c22"].values,
                  spin * shear * c2 * np.sqrt(c2) * row["c23"].values, spin * shear * c2 * c2 * row["c33"].values,
                  row["wheel_contact_y"].values)
        columns += [np.asarray(v, dtype=float)[::-1] for v in values]  # y to the left: reverse
    centre = table.sel(y=0.0, method="nearest")
    e0 = 0.5 * float(centre["contact_Y"].sel(side="right") - centre["contact_Y"].sel(side="left"))
    return -shifts[::-1], np.concatenate(columns), e0


def numerical_state_matrix(kind, params, n_states, surf=None, step=1e-7) -> np.ndarray:
    """Central-difference Jacobian of the compiled right-hand side at the zero state.

    Exact to round-off where the right-hand side is linear about zero (saturation off, flange
    dead band wider than ``step``), which is how the models call it; ``surf`` is the model's
    table or surface array."""
    jac = np.empty((n_states, n_states))
    f_plus, f_minus = np.empty(n_states), np.empty(n_states)
    surf = np.zeros(0) if surf is None else surf
    for j in range(n_states):
        y = np.zeros(n_states)
        y[j] = step
        k.rhs(kind, 0.0, y, params, surf, f_plus)
        y[j] = -step
        k.rhs(kind, 0.0, y, params, surf, f_minus)
        jac[:, j] = (f_plus - f_minus) / (2.0 * step)
    return jac


@dataclass(frozen=True)
class _BogieFrame:
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
        _check(self, positive=("speed", "wheelset_mass", "wheelset_yaw_inertia", "frame_mass", "frame_yaw_inertia",
                               "half_wheelbase") + positive,
               nonnegative=springs + nonnegative, finite=springs + ("initial_lateral_displacement",) + finite)


@dataclass(frozen=True)
class BogieModel(_BogieFrame):
    """Two-axle bogie on straight track (the Cooperrider bogie): lateral and yaw motion of two
    conical wheelsets (``x = +-half_wheelbase``) and of the frame, which hangs from a car body moving
    at ``speed`` through a secondary lateral and yaw spring-damper. Primary: a lateral spring per
    wheelset and a yaw spring per wheelset (``2 k_longitudinal d^2``). Creep, saturation and flange
    dead band as in ``WheelsetModel`` (``creep_law`` ``"cubic"`` or ``"fastsim"``).
    ``BogieModel.cooperrider`` gives the published parameters.
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
            if not _number(self, name) > 0.0:
                raise ScenarioError(f"{name}: must be positive (inf to switch it off), got {getattr(self, name)!r}")
        _check_creep_law(self)

    @classmethod
    def cooperrider(cls, speed, **overrides):
        """The Cooperrider bogie as used by Kaas-Petersen (1986) and True and co-workers.

        From REFERENCES.md: masses and yaw inertias, primary stiffnesses k1 = 1.823 MN/m (lateral)
        and k2 = 3.646 MN/m (longitudinal), secondary lateral damping 20 kN s/m, ``G pi a b`` =
        6.563 MN, rolling radius, half gauge and conicity (the last three to confirm). Not yet
        confirmed from a primary source (taken as recalled from True's papers; override to
        change): the longitudinal spring half-spacing 0.620 m, half wheelbase 1.074 m, secondary
        lateral stiffness 0.1823 MN/m, secondary yaw stiffness 0.3333 MN m/rad, secondary yaw
        damping 29.2 kN m s/rad, flange dead band 9.1 mm and stiffness 14.60 MN/m, and the linear
        creep coefficients ``f11 = f22 = G pi a b`` (no Kalker ellipse factors).
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
        return _pack(self, "BG_", k.BG_N_PARAMS, speed, **_law_params(self, 0))

    def surface(self) -> np.ndarray:
        return _law_table(self)

    def state_matrix(self, speed=None) -> np.ndarray:
        """Linearisation about centred running (saturation off; the flange dead band is open)."""
        p = self.params(speed)
        p[k.BG_FRICTION] = math.inf
        if not self.flange_clearance > 1e-6:
            raise ScenarioError("flange_clearance: the linearisation needs a dead band wider than 1 um")
        return numerical_state_matrix(self.kind, p, self.n_states, self.surface())


@dataclass(frozen=True, eq=False)
class TableBogieModel(_BogieFrame):
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

    kind = k.KIND_TABLE_BOGIE

    def __post_init__(self):
        self._check_frame(positive=("creep_scale",), nonnegative=("outside_stiffness",), finite=("outside_stiffness",))
        if not _number(self, "friction_coefficient") > 0.0:
            raise ScenarioError(f"friction_coefficient: must be positive (inf for none), got {self.friction_coefficient!r}")
        object.__setattr__(self, "_geometry", _table_arrays(self.table, bool(self.spin)))

    @classmethod
    def cooperrider(cls, speed, table, **overrides):
        """The suspension of ``BogieModel.cooperrider`` on the profiles of ``table``."""
        published = BogieModel.cooperrider(speed)
        params = {f.name: getattr(published, f.name) for f in fields(_BogieFrame)}
        params.update(table=table, **overrides)
        return cls(**params)

    def params(self, speed=None) -> np.ndarray:
        """The bogie's ``BG_*`` parameters (the conical contact ones unused, 0) followed by the
        contact table's ``TW_*`` ones (``kernels.bogie_rhs`` with ``table``)."""
        unused = ("f11", "f22", "f23", "f33", "half_gauge", "rolling_radius", "conicity", "wheel_load",
                  "flange_clearance", "flange_stiffness", "law", "law_offset", "law_points")
        bogie = _pack(self, "BG_", k.BG_N_PARAMS, speed, **dict.fromkeys(unused, 0.0))
        contact = _table_params(self, speed, mass=self.wheelset_mass, yaw_inertia=self.wheelset_yaw_inertia,
                                lateral_stiffness=self.primary_lateral_stiffness,
                                yaw_stiffness=self.primary_yaw_stiffness, lateral_damping=0.0, yaw_damping=0.0)
        return np.concatenate([bogie, contact])

    def surface(self) -> np.ndarray:
        return self._geometry[1]

    def state_matrix(self, speed=None) -> np.ndarray:
        """Linearisation about centred running (saturation off), by central differences."""
        p = self.params(speed)
        p[k.BG_N_PARAMS + k.TW_FRICTION] = math.inf
        return numerical_state_matrix(self.kind, p, self.n_states, self.surface())


def _check_creep_law(model):
    if model.creep_law not in model.CREEP_LAWS:
        raise ScenarioError(f"creep_law: must be one of {model.CREEP_LAWS}, got {model.creep_law!r}")


def _law_table(model) -> np.ndarray:
    """The kernel's FASTSIM factor table for ``model`` (empty under the cubic law)."""
    return _fastsim_factor_table().copy() if model.creep_law == "fastsim" else np.zeros(0)


def _law_params(model, offset) -> dict:
    """``_pack`` values selecting the creep law, its table at ``offset`` in the surface array."""
    return dict(law=model.CREEP_LAWS.index(model.creep_law), law_offset=offset, law_points=_law_table(model).size)


def _linear_slope(model) -> float:
    """Ratio of the creep law's small-creepage forces to Kalker's: 1 for the cubic law, FASTSIM's
    discretised slope (``1 + 1 / (2 ny^2)``, ``ny`` strips) for ``"fastsim"``."""
    return float(_fastsim_factor_table()[0]) if model.creep_law == "fastsim" else 1.0


@dataclass(frozen=True, eq=False)
class DiskWheelModel:
    """Disk wheel of paper Fig. 5: vertical and rotational motion of a wheel rolling at ``speed``.

    The wheel (``wheel_mass``, polar ``wheel_inertia``) hangs from a primary spring-damper under a
    ``sprung_mass`` (``None``: a rigid frame). The rail is rigid (``rail_mass=None``) or a mass on
    a pad-sleeper spring-damper (the P2 resonance). Hertzian contact ``N = k_H delta^(3/2)``
    (``hertz_constant`` [N/m^1.5]) carrying ``static_load`` [N] at rest, no tension (N >= 0).
    ``f11`` [N] is Kalker's longitudinal coefficient at the static load; it scales with
    ``(N/W)^(2/3)``. ``traction_torque`` [N m] sets the creepage. ``radius_deviation`` holds
    ``u`` [m] at the angles ``2 pi j / n`` (``None``: round wheel); the contact reads its mean
    over ``+- patch_half_length / radius`` about the contact angle. ``creep_law``: ``"cubic"``
    (Johnson-Vermeulen saturation of Kalker's linear force) or ``"fastsim"`` (FASTSIM's creep
    curve for pure longitudinal creepage, from ``railwear.contact.fastsim``).
    """

    speed: float
    radius: float
    wheel_mass: float
    wheel_inertia: float
    static_load: float
    hertz_constant: float
    primary_stiffness: float
    f11: float
    primary_damping: float = 0.0
    sprung_mass: float | None = None
    rail_mass: float | None = None
    pad_stiffness: float = 0.0
    pad_damping: float = 0.0
    friction_coefficient: float = math.inf
    traction_torque: float = 0.0
    patch_half_length: float = 0.0
    radius_deviation: np.ndarray | None = None
    initial_angle: float = 0.0
    initial_lift: float = 0.0
    initial_vertical_velocity: float = 0.0
    creep_law: str = "cubic"

    kind = k.KIND_DISK_WHEEL
    CREEP_LAWS = ("cubic", "fastsim")
    n_states = 8
    default_atol = 1e-13

    def __post_init__(self):
        positive = ["speed", "radius", "wheel_mass", "wheel_inertia", "static_load", "hertz_constant"]
        if self.sprung_mass is not None:
            positive.append("sprung_mass")
        if self.rail_mass is not None:
            positive += ["rail_mass", "pad_stiffness"]
        _check(
            self,
            positive=positive,
            nonnegative=("primary_stiffness", "primary_damping", "pad_damping", "f11", "patch_half_length"),
            finite=(
                "primary_stiffness", "primary_damping", "pad_damping", "f11", "traction_torque", "patch_half_length",
                "initial_angle", "initial_lift", "initial_vertical_velocity",
            ),
        )
        if not _number(self, "friction_coefficient") > 0.0:
            raise ScenarioError(
                f"friction_coefficient: must be positive (inf for no saturation), got {self.friction_coefficient!r}"
            )
        if self.creep_law not in self.CREEP_LAWS:
            raise ScenarioError(f"creep_law: must be one of {self.CREEP_LAWS}, got {self.creep_law!r}")
        object.__setattr__(self, "_creep_curve", _fastsim_creep_curve() if self.creep_law == "fastsim" else np.zeros(0))
        if self.radius_deviation is not None:
            u = np.array(self.radius_deviation, dtype=float)
            if u.ndim != 1 or u.size < 2 or not np.all(np.isfinite(u)):
                raise ScenarioError("radius_deviation: must be a 1-D array of at least 2 finite values [m]")
            if np.max(np.abs(u)) >= 0.1 * self.radius:
                raise ScenarioError("radius_deviation: deviations must stay below 10 % of the radius")
            u.setflags(write=False)
            object.__setattr__(self, "radius_deviation", u)
        if self.patch_half_length >= 0.5 * self.radius:
            raise ScenarioError(f"patch_half_length: must be well below the radius, got {self.patch_half_length!r}")
        approach = self.initial_approach()
        if approach <= 0.0:
            raise ScenarioError(
                f"initial_lift: the wheel starts above the rail (approach {approach:.3g} m from lift "
                f"{self.initial_lift!r} m and the radius deviation under the contact)"
            )
        self.steady_creepage()  # validates the traction torque

    @property
    def static_approach(self) -> float:
        """Hertzian approach under the static load, ``(W / k_H)^(2/3)`` [m]."""
        return (self.static_load / self.hertz_constant) ** (2.0 / 3.0)

    @property
    def contact_stiffness(self) -> float:
        """Linearised contact stiffness ``dN/d delta = 3 W / (2 delta_0)`` [N/m]."""
        return 1.5 * self.static_load / self.static_approach

    def surface(self) -> np.ndarray:
        """The kernel's surface array for the model's own ``radius_deviation``."""
        if self.radius_deviation is None:
            return self._creep_curve.copy()
        return self.surface_for(self.radius_deviation)

    def surface_for(self, u) -> np.ndarray:
        """The kernel's surface array for another radius deviation ``u`` [m] on the model's grid
        (a wear step changes ``u`` but not the model): ``u`` at the nodes, its cumulative
        trapezoidal integral, then the FASTSIM creep curve if that law is chosen. Use it with
        ``params()``, whose offsets assume this layout."""
        u = np.asarray(u, dtype=float)
        if u.shape != (self.n_cells(),):
            raise ScenarioError(f"radius_deviation: expected {self.n_cells()} values on the model's grid, got {u.shape}")
        dx = 2.0 * math.pi / u.size
        cum = np.concatenate([[0.0], np.cumsum(0.5 * dx * (u + np.roll(u, -1)))])
        return np.concatenate([u, cum, self._creep_curve])

    def n_cells(self) -> int:
        return 0 if self.radius_deviation is None else int(self.radius_deviation.size)

    def filtered_deviation(self, angle) -> float:
        """The contact filter at ``angle`` [rad]: ``u`` averaged over the patch [m]."""
        return float(k.patch_average(self.surface(), self.n_cells(), float(angle), self.patch_half_length / self.radius))

    def initial_approach(self) -> float:
        """Approach ``delta`` at the start [m]; must be positive (wheel in contact)."""
        ubar = 0.0 if self.radius_deviation is None else self.filtered_deviation(self.initial_angle)
        return self.static_approach - self.initial_lift + ubar

    def steady_creepage(self) -> float:
        """Creepage at which the creep force at the static load balances the torque, ``F = T / R0``."""
        demand = self.traction_torque / self.radius
        if demand == 0.0:
            return 0.0
        limit = self.friction_coefficient * self.static_load
        if abs(demand) >= limit:
            raise ScenarioError(
                f"traction_torque: {self.traction_torque!r} N m needs more than the adhesion limit "
                f"mu W R0 = {limit * self.radius:.6g} N m"
            )
        if self.f11 <= 0.0:
            raise ScenarioError("f11: must be positive when a traction_torque is applied")

        def residual(xi):
            force = self.f11 * xi
            if self.creep_law == "fastsim":
                curve, s = self._creep_curve, abs(force) / limit
                ratio = np.interp(s / (1.0 + s), np.linspace(0.0, 1.0, curve.size), curve)
                return math.copysign(limit * ratio, force) - demand
            return force * k.saturation_factor(abs(force), limit) - demand

        xi_lin = demand / self.f11
        if not math.isfinite(limit):
            return xi_lin
        upper = 3.0 * xi_lin
        while residual(upper) * np.sign(demand) < 0.0:  # FASTSIM approaches full slip slowly
            upper *= 2.0
        return brentq(residual, 0.0, upper, xtol=1e-16, rtol=1e-14)

    def params(self) -> np.ndarray:
        p = np.zeros(k.DW_N_PARAMS)
        p[k.DW_SPEED] = self.speed
        p[k.DW_RADIUS] = self.radius
        p[k.DW_WHEEL_MASS] = self.wheel_mass
        p[k.DW_WHEEL_INERTIA] = self.wheel_inertia
        p[k.DW_SPRUNG_MASS] = 0.0 if self.sprung_mass is None else self.sprung_mass
        p[k.DW_PRIMARY_STIFFNESS] = self.primary_stiffness
        p[k.DW_PRIMARY_DAMPING] = self.primary_damping
        p[k.DW_RAIL_MASS] = 0.0 if self.rail_mass is None else self.rail_mass
        p[k.DW_PAD_STIFFNESS] = self.pad_stiffness
        p[k.DW_PAD_DAMPING] = self.pad_damping
        p[k.DW_HERTZ_CONSTANT] = self.hertz_constant
        p[k.DW_STATIC_LOAD] = self.static_load
        p[k.DW_STATIC_APPROACH] = self.static_approach
        p[k.DW_F11] = self.f11
        p[k.DW_FRICTION] = self.friction_coefficient
        p[k.DW_TORQUE] = self.traction_torque
        p[k.DW_PATCH_HALF_ANGLE] = self.patch_half_length / self.radius
        p[k.DW_INITIAL_ANGLE] = self.initial_angle
        p[k.DW_N_CELLS] = self.n_cells()
        p[k.DW_CREEP_LAW] = self.CREEP_LAWS.index(self.creep_law)
        p[k.DW_CREEP_TABLE_OFFSET] = 0 if self.radius_deviation is None else 2 * self.n_cells() + 1
        p[k.DW_CREEP_TABLE_POINTS] = self._creep_curve.size
        return p

    def initial_state(self) -> np.ndarray:
        """``[phi, Omega, z_w, z_w', z_s, z_s', z_r, z_r']`` at the start: steady rolling at the
        steady creepage, the wheel lifted by ``initial_lift`` from static equilibrium."""
        y = np.zeros(self.n_states)
        ubar = 0.0 if self.radius_deviation is None else self.filtered_deviation(self.initial_angle)
        y[1] = self.speed * (1.0 + self.steady_creepage()) / (self.radius + ubar)
        y[2] = self.initial_lift
        y[3] = self.initial_vertical_velocity
        return y

    def vertical_matrices(self):
        """Mass, damping and stiffness matrices of the vertical motion linearised about static
        equilibrium, DOFs ``[z_w, z_s?, z_r?]``, with the forcing vector of ``u_bar`` [N/m]."""
        kc = self.contact_stiffness
        dofs = ["wheel"]
        dofs += ["sprung"] if self.sprung_mass is not None else []
        dofs += ["rail"] if self.rail_mass is not None else []
        n = len(dofs)
        m, c, kk, f = np.zeros((n, n)), np.zeros((n, n)), np.zeros((n, n)), np.zeros(n)
        m[0, 0] = self.wheel_mass
        kk[0, 0] += self.primary_stiffness + kc
        c[0, 0] += self.primary_damping
        f[0] = kc
        if "sprung" in dofs:
            i = dofs.index("sprung")
            m[i, i] = self.sprung_mass
            kk[i, i] += self.primary_stiffness
            c[i, i] += self.primary_damping
            kk[0, i] = kk[i, 0] = -self.primary_stiffness
            c[0, i] = c[i, 0] = -self.primary_damping
        if "rail" in dofs:
            i = dofs.index("rail")
            m[i, i] = self.rail_mass
            kk[i, i] += self.pad_stiffness + kc
            c[i, i] += self.pad_damping
            kk[0, i] = kk[i, 0] = -kc
            f[i] = -kc
        return dofs, m, c, kk, f

    LINEAR_OUTPUTS = ("normal_force", "creepage", "creep_force", "frictional_power")

    def linearisation(self):
        """``(A, B, C, D)`` of steady rolling (at the steady creepage of the torque) with the
        filtered radius deviation ``u_bar`` as input: ``x' = A x + B u_bar``,
        ``[N, xi, Fx, power] = C x + D u_bar`` (deviations from steady rolling), by central
        differences of the compiled kernel. The rotation angle ``phi`` only drifts and does not
        act on the rest (a uniform ``u`` makes ``x_c`` irrelevant)."""
        p = self.params()
        p[k.DW_N_CELLS] = 2
        y0 = self.initial_state()
        n = self.n_states
        omega_c = math.sqrt(self.contact_stiffness / self.wheel_mass)
        d0 = self.static_approach
        steps = np.array([1e-6, 1e-7 * y0[1], 1e-4 * d0, 1e-4 * d0 * omega_c, 1e-4 * d0, 1e-4 * d0 * omega_c,
                          1e-4 * d0, 1e-4 * d0 * omega_c])
        du = 1e-4 * d0

        def uniform(u):
            dx = math.pi
            return np.array([u, u, 0.0, u * dx, 2.0 * u * dx])

        def evaluate(y, u):
            f = np.empty(n)
            surf = uniform(u)
            k.rhs(self.kind, 0.0, y, p, surf, f)
            g = k.outputs(self.kind, np.zeros(1), y[None, :], p, surf, k.DW_N_OUTPUTS)[0, :4]
            return f, g

        a, c = np.zeros((n, n)), np.zeros((4, n))
        for j in range(n):
            yp, ym = y0.copy(), y0.copy()
            yp[j] += steps[j]
            ym[j] -= steps[j]
            (fp, gp), (fm, gm) = evaluate(yp, 0.0), evaluate(ym, 0.0)
            a[:, j] = (fp - fm) / (2 * steps[j])
            c[:, j] = (gp - gm) / (2 * steps[j])
        (fp, gp), (fm, gm) = evaluate(y0, du), evaluate(y0, -du)
        return a, (fp - fm) / (2 * du), c, (gp - gm) / (2 * du)

    def transfer(self, angular_frequency, output="frictional_power") -> np.ndarray:
        """Linear transfer function from ``u_bar`` to ``output`` (one of ``LINEAR_OUTPUTS``) at
        ``angular_frequency`` [rad/s]: ``C (i w - A)^-1 B + D`` (complex, ``exp(i w t)``).
        A harmonic ``u`` of order ``n`` excites ``w = n Omega`` with ``Omega`` the wheel's
        angular velocity (``V (1 + xi) / R0`` under traction)."""
        if output not in self.LINEAR_OUTPUTS:
            raise ScenarioError(f"output: must be one of {self.LINEAR_OUTPUTS}, got {output!r}")
        a, b, c, d = self.linearisation()
        row = self.LINEAR_OUTPUTS.index(output)
        omega = np.atleast_1d(np.asarray(angular_frequency, dtype=float))
        out = np.array([c[row] @ np.linalg.solve(1j * w * np.eye(self.n_states) - a, b) + d[row] for w in omega])
        return out if np.ndim(angular_frequency) else out[0]

    def contact_force_transfer(self, angular_frequency) -> np.ndarray:
        """Linear transfer function ``N_hat / u_hat`` [N/m] from the filtered radius deviation to
        the dynamic normal force at ``angular_frequency`` [rad/s] (complex, ``exp(i w t)``)."""
        dofs, m, c, kk, f = self.vertical_matrices()
        omega = np.atleast_1d(np.asarray(angular_frequency, dtype=float))
        out = np.empty(omega.shape, dtype=complex)
        rail = dofs.index("rail") if "rail" in dofs else None
        for j, w in enumerate(omega):
            z = np.linalg.solve(-w * w * m + 1j * w * c + kk, f.astype(complex))
            relative = (z[rail] if rail is not None else 0.0) - z[0]
            out[j] = self.contact_stiffness * (relative + 1.0)
        return out if np.ndim(angular_frequency) else out[0]


def model_fields(model) -> dict:
    """The model's scalar fields as plain values for result attributes (``None`` as "none");
    arrays, tuples and tables are left out, except a contact table's profile names."""
    out = {}
    for fld in fields(model):
        value = getattr(model, fld.name)
        if value is None:
            out[fld.name] = "none"
        elif isinstance(value, (bool, np.bool_)):
            out[fld.name] = int(value)
        elif isinstance(value, (int, float, str, np.integer, np.floating)):
            out[fld.name] = value
        elif fld.name == "table":
            attrs = getattr(value, "attrs", {})
            out["table_profiles"] = f"{attrs.get('wheel_profile', '?')}/{attrs.get('rail_profile', '?')}"
    return out


_CREEP_CURVE_POINTS = 257
_creep_curve_cache = {}


def _fastsim_ratio(s) -> float:
    """FASTSIM's ``F / (mu N)`` for pure longitudinal creepage at ``s = f11 xi / (mu N)`` (elliptic
    traction bound, the default 40 x 40 grid, on a fixed patch: the ratio depends on ``s`` only)."""
    from railwear.contact import fastsim, kalker_coefficients

    a, b, normal, mu, shear, poisson = 6e-3, 6e-3, 1e5, 0.3, 8e10, 0.28
    f11 = shear * a * b * float(kalker_coefficients(a / b, poisson)[0])
    return -fastsim(a, b, normal, s * mu * normal / f11, 0.0, 0.0, mu, shear, poisson).Fx / (mu * normal)


def _fastsim_creep_curve():
    """FASTSIM's creep curve for pure longitudinal creepage, ``F / (mu N)`` at ``r = s / (1 + s)``
    on ``_CREEP_CURVE_POINTS`` equal steps, ``s = f11 xi / (mu N)`` (``r = 1``: full slip, 1).
    With the elliptic traction bound the curve does not depend on the load, the friction
    coefficient, the modulus or the patch shape, so one evaluation serves every model."""
    if "curve" not in _creep_curve_cache:
        r = np.linspace(0.0, 1.0, _CREEP_CURVE_POINTS)
        curve = np.ones_like(r)
        for i, ri in enumerate(r[:-1]):
            curve[i] = _fastsim_ratio(ri / (1.0 - ri))
        curve.setflags(write=False)
        _creep_curve_cache["curve"] = curve
    return _creep_curve_cache["curve"]


def _fastsim_factor_table():
    """FASTSIM as a factor on Kalker's linear forces, ``F / F_lin = (F / (mu N)) / s``, on the
    grid of ``_fastsim_creep_curve`` (``kernels.creep_factor``). Without spin FASTSIM's traction
    keeps the direction of ``(f11 xi, f22 eta)`` and its magnitude depends on
    ``s = |(f11 xi, f22 eta)| / (mu N)`` alone, so the factor is exact for combined ``xi, eta``.
    At ``s = 0`` it is FASTSIM's linear slope, ``1 + 1 / (2 ny^2)`` for ``ny`` strips."""
    if "factor" not in _creep_curve_cache:
        r = np.linspace(0.0, 1.0, _CREEP_CURVE_POINTS)
        factor = np.zeros_like(r)
        inner = slice(1, -1)
        factor[inner] = _fastsim_creep_curve()[inner] * (1.0 - r[inner]) / r[inner]
        tiny = 1e-9
        factor[0] = _fastsim_ratio(tiny) / tiny
        factor.setflags(write=False)
        _creep_curve_cache["factor"] = factor
    return _creep_curve_cache["factor"]


def contact_constants(static_load, A, B, youngs_modulus, poisson) -> dict:
    """Hertz and Kalker constants of one wheel-rail contact at ``static_load`` [N].

    ``A, B`` [1/m]: gap curvatures (``A`` along rolling), steel ``youngs_modulus`` [Pa] and
    ``poisson`` for both bodies. Returns ``hertz_constant`` (``N = k_H delta^(3/2)`` through the
    static point; exact for Hertz since ``delta ~ N^(2/3)``), ``static_approach``,
    ``patch_half_length`` (``a``), and Kalker's ``f11 = G c^2 C11``, ``f22 = G c^2 C22``,
    ``f23 = G c^3 C23``, ``f33 = G c^4 C33`` with ``c^2 = a b``, ``G = E / (2 (1 + nu))``.
    """
    from railwear.contact import hertz_contact, kalker_coefficients

    patch = hertz_contact(static_load, A, B, youngs_modulus, poisson)
    a, b, approach = float(patch.a), float(patch.b), float(patch.approach)
    c11, c22, c23, c33 = (float(c) for c in kalker_coefficients(a / b, poisson))
    shear = youngs_modulus / (2.0 * (1.0 + poisson))
    c2 = a * b
    return {
        "hertz_constant": static_load / approach**1.5,
        "static_approach": approach,
        "patch_half_length": a,
        "f11": shear * c2 * c11,
        "f22": shear * c2 * c22,
        "f23": shear * c2 * math.sqrt(c2) * c23,
        "f33": shear * c2 * c2 * c33,
    }


MODEL_KINDS = {"wheelset": WheelsetModel, "disk_wheel": DiskWheelModel, "bogie": BogieModel,
               "table_wheelset": TableWheelsetModel, "table_bogie": TableBogieModel}


def build_model(kind, section):
    """A model from a scenario section: ``kind`` in ``MODEL_KINDS`` (or ``"cooperrider"``, the
    published bogie with ``section`` overriding its fields) and a mapping of field values in SI
    units. Unknown or missing fields raise ``ScenarioError`` naming the field."""
    if kind not in MODEL_KINDS and kind != "cooperrider":
        raise ScenarioError(f"model: unknown model kind {kind!r}; expected one of {sorted(MODEL_KINDS) + ['cooperrider']}")
    cls = BogieModel if kind == "cooperrider" else MODEL_KINDS[kind]
    known = {fld.name: fld for fld in fields(cls)}
    for name in section:
        if name not in known:
            raise ScenarioError(f"{name}: not a field of the {kind} model")
    if kind == "cooperrider":
        if "speed" not in section:
            raise ScenarioError("speed: missing (required for the cooperrider model)")
        return BogieModel.cooperrider(**dict(section))
    required = [n for n, fld in known.items() if fld.default is MISSING and fld.default_factory is MISSING]
    for name in required:
        if name not in section:
            raise ScenarioError(f"{name}: missing (required for the {kind} model)")
    return cls(**dict(section))
