"""Short-time dynamics scenarios: one model of ``railwear.dynamics`` run at one or more speeds.

A TOML file with a ``[model]`` section (``kind`` and the model's fields in SI units, as
:func:`railwear.dynamics.build_model` takes them; for the disk wheel an out-of-round wheel may be
given as ``out_of_round = {orders = [...], amplitudes_um = [...], points = 512}``; the wheelset
and the Cooperrider bogie run on real profiles with ``profiles = {wheel = "S1002", rail = "UIC60"}``
(built-in names or profile files), through the contact table) and a ``[run]`` section.
Built-in ones ship in ``builtin_dynamics/`` (``railwear simulate NAME``).
"""

import functools
import math
from importlib import resources
from typing import Annotated, Literal

import numpy as np
from pydantic import BaseModel, ConfigDict, Field, model_validator

from railwear.errors import ScenarioError
from railwear.scenario import parse_toml, scenario_text, validated
from railwear.scenario.schema import MAX_LIST, Count, Name, PathText, Speed_kmh, Text, _printable
from railwear.units import UM

LARGEST = 1e13  # SI: above the Hertz constant of steel (1e11 N/m^1.5), the stiffest field there is
STRICT = ConfigDict(extra="forbid", frozen=True, strict=True, allow_inf_nan=False)


class OutOfRound(BaseModel):
    model_config = STRICT

    orders: Annotated[list[Count], Field(max_length=MAX_LIST)]
    amplitudes_um: Annotated[list[Annotated[float, Field(ge=-1e4, le=1e4)]], Field(max_length=MAX_LIST)]
    points: Annotated[int, Field(ge=8, le=65536)] = 512


class Profiles(BaseModel):
    model_config = STRICT

    wheel: PathText = "S1002"
    rail: PathText = "UIC60"


class ModelSection(BaseModel):
    """``kind`` and the model's own fields (checked by ``build_model``, which names a wrong one)."""

    model_config = ConfigDict(extra="allow", frozen=True)

    kind: Literal["wheelset", "disk_wheel", "cooperrider"]
    out_of_round: OutOfRound | None = None
    profiles: Profiles | None = None

    @model_validator(mode="after")
    def _plain(self):
        """The model's own fields are a name or a finite number (never ``true``) of at most
        :data:`LARGEST` in magnitude; ``build_model`` checks each against its model."""
        for name, value in (self.model_extra or {}).items():
            if isinstance(value, str):
                _printable(value)
            elif isinstance(value, bool) or not isinstance(value, (int, float)):
                raise ValueError(f"{name}: must be a number or a name, not {type(value).__name__}")
            elif not (math.isfinite(value) and abs(value) <= LARGEST):
                raise ValueError(f"{name}: must be finite and at most {LARGEST:g} in magnitude, got {value!r}")
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
def _contact_table(wheel, rail):
    from railwear.geometry import contact_table, load_profile

    try:
        wheel, rail = load_profile(wheel), load_profile(rail)
    except ScenarioError as e:
        raise ScenarioError(f"model.profiles: {e}") from None
    return contact_table(wheel, rail)


def _on_profiles(scenario, speed, fields):
    """The wheelset or Cooperrider bogie of the scenario on the profiles of ``model.profiles``."""
    from dataclasses import fields as dataclass_fields

    from railwear.dynamics import TableBogieModel, build_model

    kind = scenario.model.kind
    if kind == "disk_wheel":
        raise ScenarioError("model.profiles: only the wheelset and the cooperrider bogie run on real profiles")
    table = _contact_table(scenario.model.profiles.wheel, scenario.model.profiles.rail)
    if kind == "wheelset":
        return build_model("table_wheelset", dict(fields, table=table, speed=speed))
    known = {f.name for f in dataclass_fields(TableBogieModel)}
    for name in fields:
        if name not in known:
            raise ScenarioError(f"{name}: not a field of the cooperrider model on real profiles")
    return TableBogieModel.cooperrider(speed, table, **fields)


def _typed(cls, fields):
    """Refuse a name where ``cls`` (a model dataclass) takes a number, or a number where it takes a name."""
    from dataclasses import fields as dataclass_fields

    names = {f.name for f in dataclass_fields(cls) if f.type in (str, "str")}
    for name, value in fields.items():
        if (name in names) != isinstance(value, str):
            raise ScenarioError(f"{name}: must be {'a name' if name in names else 'a number'}, got {value!r}")


def build(scenario: DynamicsScenario, speed):
    """The model of the scenario at ``speed`` (m/s)."""
    from railwear.dynamics import BogieModel, build_model
    from railwear.dynamics.models import MODEL_KINDS

    fields = {k: v for k, v in scenario.model.model_dump().items() if k not in ("kind", "out_of_round", "profiles")}
    kind = scenario.model.kind
    if scenario.model.profiles is None:
        _typed(BogieModel if kind == "cooperrider" else MODEL_KINDS[kind], fields)
    else:
        _typed(MODEL_KINDS["table_bogie" if kind == "cooperrider" else "table_wheelset"], fields)
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
