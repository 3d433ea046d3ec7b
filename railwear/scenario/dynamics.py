"""Short-time dynamics scenarios: one model of ``railwear.dynamics`` run at one or more speeds.

A TOML file with a ``[model]`` section (``kind`` and the model's fields in SI units, as
:func:`railwear.dynamics.build_model` takes them; for the disk wheel an out-of-round wheel may be
given as ``out_of_round = {orders = [...], amplitudes_um = [...], points = 512}``; the wheelset
and the Cooperrider bogie run on real profiles with ``profiles = {wheel = "S1002", rail = "UIC60"}``
(built-in names or profile files), through the contact table) and a ``[run]`` section.
Built-in ones ship in ``builtin_dynamics/`` (``railwear simulate NAME``).
"""

import functools
import tomllib
from importlib import resources
from pathlib import Path
from typing import Annotated, Literal

import numpy as np
from pydantic import BaseModel, ConfigDict, Field, ValidationError

from railwear.errors import ScenarioError
from railwear.scenario import _one_line
from railwear.units import UM

Positive = Annotated[float, Field(gt=0, allow_inf_nan=False)]


class OutOfRound(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True)

    orders: list[Annotated[int, Field(ge=1)]]
    amplitudes_um: list[Annotated[float, Field(allow_inf_nan=False)]]
    points: Annotated[int, Field(ge=8, le=65536)] = 512


class Profiles(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True)

    wheel: str = "S1002"
    rail: str = "UIC60"


class ModelSection(BaseModel):
    """``kind`` and the model's own fields (checked by ``build_model``, which names a wrong one)."""

    model_config = ConfigDict(extra="allow", frozen=True)

    kind: Literal["wheelset", "disk_wheel", "cooperrider"]
    out_of_round: OutOfRound | None = None
    profiles: Profiles | None = None


class RunSection(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True)

    speeds_kmh: list[Positive]
    duration_s: Positive = 5.0
    n_output: Annotated[int, Field(ge=2, le=10**6)] = 2001


class DynamicsScenario(BaseModel):
    """A dynamics run: the model and the speeds (for the bogie, the speeds of the ramp down)."""

    model_config = ConfigDict(extra="forbid", frozen=True)

    name: str = "unnamed"
    description: str = ""
    model: ModelSection
    run: RunSection


def _builtin_dir():
    return resources.files("railwear.scenario") / "builtin_dynamics"


def builtin_names():
    """Names of the built-in dynamics scenarios, sorted."""
    return sorted(p.name[:-5] for p in _builtin_dir().iterdir() if p.name.endswith(".toml"))


def load_dynamics_scenario(path_or_name):
    """A dynamics scenario from a TOML file or a built-in name."""
    path = Path(str(path_or_name))
    if path.suffix == ".toml" or path.exists():
        if not path.is_file():
            raise ScenarioError(f"scenario file {path} does not exist")
        text, source = path.read_text(), path.name
    elif str(path_or_name) in builtin_names():
        text, source = (_builtin_dir() / f"{path_or_name}.toml").read_text(), str(path_or_name)
    else:
        raise ScenarioError(f"no dynamics scenario {path_or_name!r}; built-in: {', '.join(builtin_names())}")
    try:
        return DynamicsScenario.model_validate(tomllib.loads(text))
    except tomllib.TOMLDecodeError as e:
        raise ScenarioError(f"{source}: not valid TOML: {e}") from None
    except ValidationError as e:
        raise ScenarioError(_one_line(e, source)) from None


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


def build(scenario: DynamicsScenario, speed):
    """The model of the scenario at ``speed`` (m/s)."""
    from railwear.dynamics import build_model

    fields = {k: v for k, v in scenario.model.model_dump().items() if k not in ("kind", "out_of_round", "profiles")}
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
