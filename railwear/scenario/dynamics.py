"""Short-time dynamics scenarios: one model of ``railwear.dynamics`` run at one or more speeds.

A TOML file with a ``[model]`` section (``kind`` and the model's fields in SI units, as
:func:`railwear.dynamics.build_model` takes them; for the disk wheel an out-of-round wheel may be
given as ``out_of_round = {orders = [...], amplitudes_um = [...], points = 512}``) and a
``[run]`` section. Built-in ones ship in ``builtin_dynamics/`` (``railwear simulate NAME``).
"""

import tomllib
from importlib import resources
from pathlib import Path
from typing import Annotated, Literal

import numpy as np
from pydantic import BaseModel, ConfigDict, Field, ValidationError

from railwear.errors import ScenarioError
from railwear.scenario import _one_line

Positive = Annotated[float, Field(gt=0, allow_inf_nan=False)]


class OutOfRound(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True)

    orders: list[Annotated[int, Field(ge=1)]]
    amplitudes_um: list[Annotated[float, Field(allow_inf_nan=False)]]
    points: Annotated[int, Field(ge=8, le=65536)] = 512


class ModelSection(BaseModel):
    """``kind`` and the model's own fields (checked by ``build_model``, which names a wrong one)."""

    model_config = ConfigDict(extra="allow", frozen=True)

    kind: Literal["wheelset", "disk_wheel", "cooperrider"]
    out_of_round: OutOfRound | None = None


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


def build(scenario: DynamicsScenario, speed):
    """The model of the scenario at ``speed`` (m/s)."""
    from railwear.dynamics import BogieModel, build_model

    fields = {k: v for k, v in scenario.model.model_dump().items() if k not in ("kind", "out_of_round")}
    if scenario.model.kind == "cooperrider":
        return BogieModel.cooperrider(speed, **fields)
    ring = scenario.model.out_of_round
    if ring is not None:
        if scenario.model.kind != "disk_wheel":
            raise ScenarioError("model.out_of_round: only the disk wheel has a radius deviation")
        if len(ring.orders) != len(ring.amplitudes_um):
            raise ScenarioError("model.out_of_round: one amplitude per order")
        x = 2 * np.pi * np.arange(ring.points) / ring.points
        fields["radius_deviation"] = sum(a * 1e-6 * np.cos(n * x) for n, a in zip(ring.orders, ring.amplitudes_um))
    fields["speed"] = speed
    return build_model(scenario.model.kind, fields)
