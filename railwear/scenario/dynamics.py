"""Short-time dynamics scenarios: one model of ``railwear.dynamics`` run at one or more speeds.

A TOML file with a ``[model]`` section (``kind`` and the model's fields, each with its unit in
its name: ``mass_kg``, ``wheel_load_kN``, ``flange_clearance_mm``, ...; :data:`QUANTITIES` maps
each to the field of the :mod:`railwear.dynamics` model it sets, its unit and its bounds, and
:func:`build` converts to SI; for the disk wheel an out-of-round wheel may be
given as ``out_of_round = {orders = [...], amplitudes_um = [...], points = 512}``; the wheelset
and the Cooperrider bogie run on real profiles with ``profiles = {wheel = "S1002", rail = "UIC60"}``
(built-in names or profile files), through the contact table) and a ``[run]`` section.
Built-in ones ship in ``builtin_dynamics/`` (``railwear simulate NAME``).
"""

import functools
import math
from decimal import Decimal
from importlib import resources
from typing import Annotated, Literal, NamedTuple

import numpy as np
from pydantic import BaseModel, ConfigDict, Field, model_validator

from railwear.errors import ScenarioError
from railwear.scenario import parse_toml, scenario_text, validated
from railwear.scenario.schema import MAX_LIST, Count, Name, PathText, Speed_kmh, Text, _printable
from railwear.units import UM

STRICT = ConfigDict(extra="forbid", frozen=True, strict=True, allow_inf_nan=False)

# Published linear critical speeds (m/s) of models whose railwear version does not reproduce them,
# with their source: a run of the conical model says the published value beside its own
# (docs/dynamics.md, "The published Cooperrider bogie": 52.245 m/s here, 24 % low).
PUBLISHED_HOPF = {"cooperrider": (68.66, "Seydel, bifurcation.de example exd10, from Kaas-Petersen's model")}


def published_hopf(scenario):
    """``(speed in m/s, source)`` of the published Hopf point of the scenario's model on conical
    wheels, or None (a model on real profiles, or one without a published value)."""
    if scenario.model.profiles is not None:
        return None
    return PUBLISHED_HOPF.get(scenario.model.kind)


class Quantity(NamedTuple):
    """A scenario field of a dynamics model: the model's field it sets (SI), the unit of the
    scenario's value (``factor`` SI units per unit, a power of ten written as text so that the
    conversion is exact in decimal), and the physical bounds in that unit (inclusive)."""

    model: str
    unit: str
    factor: str
    low: float
    high: float


_M = ("", "1")  # a dimensionless number or a name: no suffix
_MASS, _INERTIA = (10.0, 1e5), (1.0, 1e6)  # kg: a light wheelset to a locomotive frame; kg m^2
_SPRING, _DAMPER = (0.0, 1e9), (0.0, 1e7)  # N/m or N m/rad: none to a rigid guidance; N s/m

#: Every field a dynamics scenario may give, by its name in the scenario (unit in the name).
QUANTITIES = {
    # wheelset (conical and on real profiles)
    "mass_kg": Quantity("mass", "kg", "1", *_MASS),
    "yaw_inertia_kg_m2": Quantity("yaw_inertia", "kg m^2", "1", *_INERTIA),
    "lateral_stiffness_N_m": Quantity("lateral_stiffness", "N/m", "1", *_SPRING),
    "yaw_stiffness_N_m_rad": Quantity("yaw_stiffness", "N m/rad", "1", *_SPRING),
    "lateral_damping_N_s_m": Quantity("lateral_damping", "N s/m", "1", *_DAMPER),
    "yaw_damping_N_m_s_rad": Quantity("yaw_damping", "N m s/rad", "1", *_DAMPER),
    "spin_inertia_kg_m2": Quantity("spin_inertia", "kg m^2", "1", 0.1, 1e5),  # axle polar inertia
    "initial_spin_deviation_rad_s": Quantity("initial_spin_deviation", "rad/s", "1", -100.0, 100.0),
    "initial_yaw_angle_mrad": Quantity("initial_yaw_angle", "mrad", "1e-3", -100.0, 100.0),  # small angles
    "initial_lateral_velocity_m_s": Quantity("initial_lateral_velocity", "m/s", "1", -10.0, 10.0),
    "initial_yaw_rate_rad_s": Quantity("initial_yaw_rate", "rad/s", "1", -10.0, 10.0),
    # contact of the conical wheelset and bogies
    "f11_MN": Quantity("f11", "MN", "1e6", 0.0, 1e4),  # 1e4 MN: the kinematic limit
    "f22_MN": Quantity("f22", "MN", "1e6", 0.0, 1e4),
    "f23_N_m": Quantity("f23", "N m", "1", -1e7, 1e7),
    "f33_N_m2": Quantity("f33", "N m^2", "1", 0.0, 1e7),
    "half_gauge_m": Quantity("half_gauge", "m", "1", 0.15, 1.5),  # 300 mm gauge to twice broad gauge
    "rolling_radius_m": Quantity("rolling_radius", "m", "1", 0.05, 2.0),
    "conicity": Quantity("conicity", *_M, 0.0, 1.0),
    "wheel_load_kN": Quantity("wheel_load", "kN", "1e3", 0.01, 1000.0),
    "friction_coefficient": Quantity("friction_coefficient", *_M, 0.01, 1.0),
    "flange_clearance_mm": Quantity("flange_clearance", "mm", "1e-3", 0.1, 50.0),
    "flange_stiffness_N_m": Quantity("flange_stiffness", "N/m", "1", 0.0, 1e10),
    "initial_lateral_displacement_mm": Quantity("initial_lateral_displacement", "mm", "1e-3", -50.0, 50.0),
    # on real profiles
    "creep_scale": Quantity("creep_scale", *_M, 0.01, 100.0),
    "outside_stiffness_N_m": Quantity("outside_stiffness", "N/m", "1", 0.0, 1e11),
    # bogies
    "wheelset_mass_kg": Quantity("wheelset_mass", "kg", "1", *_MASS),
    "wheelset_yaw_inertia_kg_m2": Quantity("wheelset_yaw_inertia", "kg m^2", "1", *_INERTIA),
    "frame_mass_kg": Quantity("frame_mass", "kg", "1", *_MASS),
    "frame_yaw_inertia_kg_m2": Quantity("frame_yaw_inertia", "kg m^2", "1", *_INERTIA),
    "frame_roll_inertia_kg_m2": Quantity("frame_roll_inertia", "kg m^2", "1", *_INERTIA),
    "primary_lateral_stiffness_N_m": Quantity("primary_lateral_stiffness", "N/m", "1", *_SPRING),
    "primary_longitudinal_stiffness_N_m": Quantity("primary_longitudinal_stiffness", "N/m", "1", *_SPRING),
    "primary_vertical_stiffness_N_m": Quantity("primary_vertical_stiffness", "N/m", "1", *_SPRING),
    "primary_yaw_stiffness_N_m_rad": Quantity("primary_yaw_stiffness", "N m/rad", "1", *_SPRING),
    "secondary_lateral_stiffness_N_m": Quantity("secondary_lateral_stiffness", "N/m", "1", *_SPRING),
    "secondary_vertical_stiffness_N_m": Quantity("secondary_vertical_stiffness", "N/m", "1", *_SPRING),
    "secondary_yaw_stiffness_N_m_rad": Quantity("secondary_yaw_stiffness", "N m/rad", "1", *_SPRING),
    "secondary_lateral_damping_N_s_m": Quantity("secondary_lateral_damping", "N s/m", "1", *_DAMPER),
    "secondary_vertical_damping_N_s_m": Quantity("secondary_vertical_damping", "N s/m", "1", *_DAMPER),
    "secondary_yaw_damping_N_m_s_rad": Quantity("secondary_yaw_damping", "N m s/rad", "1", *_DAMPER),
    "half_wheelbase_m": Quantity("half_wheelbase", "m", "1", 0.2, 5.0),
    "primary_spring_half_spacing_m": Quantity("primary_spring_half_spacing", "m", "1", 0.1, 2.0),
    "secondary_spring_half_spacing_m": Quantity("secondary_spring_half_spacing", "m", "1", 0.1, 2.0),
    "primary_height_m": Quantity("primary_height", "m", "1", -2.0, 2.0),
    "secondary_height_m": Quantity("secondary_height", "m", "1", -2.0, 2.0),
    # disk wheel (the names and bounds of the long-term [wheel] and [body] kind = "disk_wheel" sections)
    "radius_m": Quantity("radius", "m", "1", 0.05, 2.0),
    "wheel_mass_kg": Quantity("wheel_mass", "kg", "1", 1.0, 1e5),
    "wheel_inertia_kg_m2": Quantity("wheel_inertia", "kg m^2", "1", 1e-3, 1e5),
    "static_load_kN": Quantity("static_load", "kN", "1e3", 0.01, 1000.0),
    "hertz_constant_N_m1_5": Quantity("hertz_constant", "N/m^1.5", "1", 1e8, 1e12),  # steel: 1e11
    "primary_stiffness_N_m": Quantity("primary_stiffness", "N/m", "1", 0.0, 1e11),
    "primary_damping_N_s_m": Quantity("primary_damping", "N s/m", "1", 0.0, 1e8),
    "sprung_mass_kg": Quantity("sprung_mass", "kg", "1", 1.0, 1e6),
    "rail_mass_kg": Quantity("rail_mass", "kg", "1", 1.0, 1e5),
    "pad_stiffness_N_m": Quantity("pad_stiffness", "N/m", "1", 1e3, 1e10),
    "pad_damping_N_s_m": Quantity("pad_damping", "N s/m", "1", 0.0, 1e8),
    "traction_torque_N_m": Quantity("traction_torque", "N m", "1", -1e5, 1e5),  # braking below 0
    "patch_half_length_mm": Quantity("patch_half_length", "mm", "1e-3", 0.0, 50.0),
    "initial_angle_rad": Quantity("initial_angle", "rad", "1", -2 * math.pi, 2 * math.pi),
    "initial_lift_mm": Quantity("initial_lift", "mm", "1e-3", -10.0, 10.0),
    "initial_vertical_velocity_m_s": Quantity("initial_vertical_velocity", "m/s", "1", -10.0, 10.0),
}
#: Fields that are names, with the model field they set.
NAMES = {"creep_law": "creep_law"}

_WHEELSET_SUSPENSION = ("mass_kg", "yaw_inertia_kg_m2", "lateral_stiffness_N_m", "yaw_stiffness_N_m_rad",
                        "lateral_damping_N_s_m", "yaw_damping_N_m_s_rad", "friction_coefficient",
                        "initial_lateral_displacement_mm", "initial_yaw_angle_mrad",
                        "initial_lateral_velocity_m_s", "initial_yaw_rate_rad_s")
_CONICAL = ("f11_MN", "f22_MN", "half_gauge_m", "rolling_radius_m", "conicity", "wheel_load_kN",
            "flange_clearance_mm", "flange_stiffness_N_m", "creep_law")
_BOGIE = ("wheelset_mass_kg", "wheelset_yaw_inertia_kg_m2", "frame_mass_kg", "frame_yaw_inertia_kg_m2",
          "primary_lateral_stiffness_N_m", "secondary_lateral_stiffness_N_m", "secondary_lateral_damping_N_s_m",
          "half_wheelbase_m", "friction_coefficient", "initial_lateral_displacement_mm")

#: The fields of each model a scenario builds: ``(kind, on real profiles)``.
MODEL_FIELDS = {
    ("wheelset", False): _WHEELSET_SUSPENSION + _CONICAL + ("f23_N_m", "f33_N_m2", "spin_inertia_kg_m2",
                                                            "initial_spin_deviation_rad_s"),
    ("wheelset", True): _WHEELSET_SUSPENSION + ("creep_scale", "outside_stiffness_N_m", "creep_law"),
    ("cooperrider", False): _BOGIE + _CONICAL + (
        "frame_roll_inertia_kg_m2", "primary_longitudinal_stiffness_N_m", "primary_vertical_stiffness_N_m",
        "secondary_vertical_stiffness_N_m", "secondary_vertical_damping_N_s_m", "primary_spring_half_spacing_m",
        "secondary_spring_half_spacing_m", "primary_height_m", "secondary_height_m"),
    ("cooperrider", True): _BOGIE + ("primary_yaw_stiffness_N_m_rad", "secondary_yaw_stiffness_N_m_rad",
                                     "secondary_yaw_damping_N_m_s_rad", "creep_scale", "outside_stiffness_N_m",
                                     "creep_law"),
    ("disk_wheel", False): (
        "radius_m", "wheel_mass_kg", "wheel_inertia_kg_m2", "static_load_kN", "hertz_constant_N_m1_5",
        "primary_stiffness_N_m", "primary_damping_N_s_m", "f11_MN", "sprung_mass_kg", "rail_mass_kg",
        "pad_stiffness_N_m", "pad_damping_N_s_m", "friction_coefficient", "traction_torque_N_m",
        "patch_half_length_mm", "initial_angle_rad", "initial_lift_mm", "initial_vertical_velocity_m_s",
        "creep_law"),
}
#: The names of SI fields without units that scenarios used to give, with their names now.
RENAMED = {q.model: name for name, q in QUANTITIES.items() if q.model != name}
assert len(RENAMED) == len({q.model for q in QUANTITIES.values()} - set(QUANTITIES)), "one name per model field"


def _model_name(kind, profiles):
    return f"{kind} model" + (" on real profiles" if profiles else "")


def check_field(kind, profiles, name, value):
    """``value`` of the scenario field ``name`` of the model ``(kind, profiles)``, checked; a bad
    one raises ``ValueError`` in one line naming the field (and, for an old name, the new one)."""
    known = MODEL_FIELDS.get((kind, profiles), ())
    if name not in known:
        new = RENAMED.get(name)
        if new in known:
            q = QUANTITIES[new]
            raise ValueError(f"{name}: renamed {new} (in {q.unit}); units are in the field names")
        raise ValueError(f"{name}: not a field of the {_model_name(kind, profiles)}")
    if name in NAMES:
        if not isinstance(value, str):
            raise ValueError(f"{name}: must be a name, got {value!r}")
        _printable(value)
        return value
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise ValueError(f"{name}: must be a number, got {value!r}")
    q = QUANTITIES[name]
    if not (math.isfinite(value) and q.low <= value <= q.high):
        unit = f" {q.unit}" if q.unit else ""
        raise ValueError(f"{name}: must be between {q.low:g} and {q.high:g}{unit}, got {value!r}")
    return value


def to_model(name, value):
    """``(model field, value in SI)`` of a checked scenario field: the one conversion of units."""
    if name in NAMES:
        return NAMES[name], value
    q = QUANTITIES[name]
    if q.factor == "1":
        return q.model, float(value)
    return q.model, float(Decimal(repr(float(value))) * Decimal(q.factor))


class OutOfRound(BaseModel):
    model_config = STRICT

    orders: Annotated[list[Count], Field(max_length=MAX_LIST)]
    amplitudes_um: Annotated[list[Annotated[float, Field(ge=-1e4, le=1e4)]], Field(max_length=MAX_LIST)]
    points: Annotated[int, Field(ge=8, le=65536)] = 512


class Profiles(BaseModel):
    model_config = STRICT

    wheel: PathText = "S1002"
    rail: PathText = "UIC60"
    contact_model: Literal["hertz", "multi-hertz", "semi-hertzian"] = "hertz"  # docs/contact.md


class ModelSection(BaseModel):
    """``kind`` and the model's own fields (checked by ``build_model``, which names a wrong one)."""

    model_config = ConfigDict(extra="allow", frozen=True)

    kind: Literal["wheelset", "disk_wheel", "cooperrider"]
    out_of_round: OutOfRound | None = None
    profiles: Profiles | None = None

    @model_validator(mode="after")
    def _fields(self):
        """Each of the model's fields is one of :data:`MODEL_FIELDS` for the kind (on profiles or
        not), a number within its bounds in the unit its name ends with, or a name."""
        if self.kind == "disk_wheel" and self.profiles is not None:
            raise ValueError("model.profiles: only the wheelset and the cooperrider bogie run on real profiles")
        for name, value in (self.model_extra or {}).items():
            check_field(self.kind, self.profiles is not None, name, value)
        return self


class RunSection(BaseModel):
    model_config = STRICT

    speeds_kmh: Annotated[list[Speed_kmh], Field(min_length=1, max_length=MAX_LIST)]
    duration_s: Annotated[float, Field(gt=0, le=3600)] = 5.0  # simulated seconds
    n_output: Annotated[int, Field(ge=2, le=10**6)] = 2001


class DynamicsScenario(BaseModel):
    """A dynamics run: the model and the speeds (for the bogie, the speeds of the ramp down)."""

    model_config = STRICT

    name: Name = "unnamed"
    description: Text = ""
    model: ModelSection
    run: RunSection


def _builtin_dir():
    return resources.files("railwear.scenario") / "builtin_dynamics"


def builtin_names():
    """Names of the built-in dynamics scenarios, sorted."""
    return sorted(p.name[:-5] for p in _builtin_dir().iterdir() if p.name.endswith(".toml"))


def load_dynamics_scenario(path_or_name):
    """A dynamics scenario from a TOML file or a built-in name."""
    text, source, _ = scenario_text(path_or_name, builtin_names(), _builtin_dir(), "dynamics scenario")
    return validated(DynamicsScenario, parse_toml(text, source), source)


@functools.lru_cache(maxsize=4)
def _contact_table(wheel, rail, contact_model="hertz"):
    from railwear.geometry import contact_table, load_profile

    try:
        wheel, rail = load_profile(wheel), load_profile(rail)
    except ScenarioError as e:
        raise ScenarioError(f"model.profiles: {e}") from None
    return contact_table(wheel, rail, contact_model=contact_model)


def _on_profiles(scenario, speed, fields):
    """The wheelset or Cooperrider bogie of the scenario on the profiles of ``model.profiles``."""
    from dataclasses import fields as dataclass_fields

    from railwear.dynamics import TableBogieModel, build_model

    kind = scenario.model.kind
    if kind == "disk_wheel":
        raise ScenarioError("model.profiles: only the wheelset and the cooperrider bogie run on real profiles")
    profiles = scenario.model.profiles
    table = _contact_table(profiles.wheel, profiles.rail, profiles.contact_model)
    if kind == "wheelset":
        return build_model("table_wheelset", dict(fields, table=table, speed=speed))
    known = {f.name for f in dataclass_fields(TableBogieModel)}
    for name in fields:
        if name not in known:
            raise ScenarioError(f"{name}: not a field of the cooperrider model on real profiles")
    return TableBogieModel.cooperrider(speed, table, **fields)


def build(scenario: DynamicsScenario, speed):
    """The model of the scenario at ``speed`` (m/s), its fields converted to SI here."""
    from railwear.dynamics import build_model

    fields = dict(to_model(k, v) for k, v in (scenario.model.model_extra or {}).items())
    if scenario.model.profiles is not None:
        return _on_profiles(scenario, speed, fields)
    if scenario.model.kind == "cooperrider":
        return build_model("cooperrider", dict(fields, speed=speed))
    ring = scenario.model.out_of_round
    if ring is not None:
        if scenario.model.kind != "disk_wheel":
            raise ScenarioError("model.out_of_round: only the disk wheel has a radius deviation")
        if len(ring.orders) != len(ring.amplitudes_um):
            raise ScenarioError("model.out_of_round: one amplitude per order")
        x = 2 * np.pi * np.arange(ring.points) / ring.points
        fields["radius_deviation"] = sum(a * UM * np.cos(n * x) for n, a in zip(ring.orders, ring.amplitudes_um))
    fields["speed"] = speed
    return build_model(scenario.model.kind, fields)
