"""Scenarios: TOML files validated into frozen models; built-in scenarios ship with the package."""

import hashlib
import json
import tomllib
from importlib import resources
from pathlib import Path

import tomli_w
from pydantic import ValidationError

from railwear.errors import ScenarioError
from railwear.scenario.schema import Scenario

DEFAULT = "polygonalisation"

__all__ = ["DEFAULT", "Scenario", "builtin_names", "builtin_text", "load_scenario",
           "scenario_hash", "to_toml"]


def _builtin_dir():
    return resources.files("railwear.scenario") / "builtin"


def builtin_names():
    """Names of the scenarios that ship with railwear, sorted."""
    return sorted(p.name[:-5] for p in _builtin_dir().iterdir() if p.name.endswith(".toml"))


def builtin_text(name):
    """The TOML text of a built-in scenario."""
    if name not in builtin_names():
        raise ScenarioError(f"no built-in scenario {name!r}; known: {', '.join(builtin_names())}")
    return (_builtin_dir() / f"{name}.toml").read_text()


def _one_line(err: ValidationError, source):
    first = err.errors()[0]
    field = ".".join(str(p) for p in first["loc"]) or "scenario"
    message = first["msg"].removeprefix("Value error, ")
    more = f" (and {err.error_count() - 1} more)" if err.error_count() > 1 else ""
    return f"{source}: field '{field}': {message}{more}"


def parse_scenario(text, source="scenario", base_dir=None):
    """Validate TOML text into a :class:`Scenario`; a relative ``initial.file`` is taken from ``base_dir``."""
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as e:
        raise ScenarioError(f"{source}: not valid TOML: {e}") from None
    try:
        scenario = Scenario.model_validate(data)
    except ValidationError as e:
        raise ScenarioError(_one_line(e, source)) from None
    file = scenario.initial.file
    if file and base_dir is not None and not Path(file).is_absolute():
        initial = scenario.initial.model_copy(update={"file": str(Path(base_dir, file).resolve())})
        scenario = scenario.model_copy(update={"initial": initial})
    return scenario


def load_scenario(path_or_name=None):
    """A scenario from a TOML file or a built-in name (the default scenario when ``None``)."""
    if isinstance(path_or_name, Scenario):
        return path_or_name
    name = DEFAULT if path_or_name is None else str(path_or_name)
    path = Path(name)
    if path.suffix == ".toml" or path.exists():
        if not path.is_file():
            raise ScenarioError(f"scenario file {name} does not exist")
        return parse_scenario(path.read_text(), source=path.name, base_dir=path.parent)
    return parse_scenario(builtin_text(name), source=name)


def to_toml(scenario: Scenario):
    """The scenario as TOML, with every default that applies to its strategy and body written out."""
    return tomli_w.dumps(scenario.applicable())


def scenario_hash(scenario: Scenario):
    """SHA-256 of the scenario's canonical JSON (hex)."""
    canonical = json.dumps(scenario.model_dump(mode="json"), sort_keys=True, separators=(",", ":"))
    return hashlib.sha256(canonical.encode()).hexdigest()
