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


def _field_path(loc):
    """A pydantic error location as a dotted field with list indices, without the names of union
    branches (``speed_kmh[1]``, not ``speed_kmh.list[constrained-float].1``)."""
    out = ""
    for part in loc:
        if isinstance(part, int):
            out += f"[{part}]"
        elif part.isidentifier():
            out += f".{part}" if out else part
    return out


def _one_line(err: ValidationError, source):
    """The first error of a validation as one line naming its field; a union's type mismatches
    give way to the branch that says what is wrong with the value."""
    errors = sorted(err.errors(), key=lambda e: e["type"].endswith("_type") and len(err.errors()) > 1)
    first = errors[0]
    field = _field_path(first["loc"])
    message = first["msg"].removeprefix("Value error, ")
    fields = {_field_path(e["loc"]) for e in errors} - {_field_path(first["loc"])}
    more = f" (and {len(fields)} more)" if fields else ""
    return f"{source}: field '{field or 'scenario'}': {message}{more}"


def decode_text(data: bytes, source, error=ScenarioError):
    """UTF-8 text of a file (a byte-order mark is dropped); anything else is refused (``error``)
    naming the line and column of the first bad byte."""
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError as e:
        line = data.count(b"\n", 0, e.start) + 1
        column = e.start - (data.rfind(b"\n", 0, e.start) + 1) + 1
        raise error(f"{source}: line {line}, column {column}: not UTF-8 text "
                            f"(byte 0x{data[e.start]:02x}); save the file as UTF-8") from None


def read_text(path, source=None):
    """The UTF-8 text of the file ``path`` (see :func:`decode_text`); a missing file is refused."""
    path = Path(path)
    source = source or path.name
    if not path.is_file():
        raise ScenarioError(f"{source}: file {path} does not exist")
    try:
        return decode_text(path.read_bytes(), source)
    except OSError as e:
        raise ScenarioError(f"{source}: cannot be read ({e.strerror})") from None


def parse_toml(text, source):
    """A TOML document as plain data; bad TOML, or arrays nested past Python's stack, refused."""
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as e:
        raise ScenarioError(f"{source}: not valid TOML: {e}") from None
    except RecursionError:
        raise ScenarioError(f"{source}: not valid TOML: arrays or tables nested too deeply") from None


def validated(model, data, source):
    """``model`` validated from plain ``data``; a failure is one line naming the field."""
    try:
        return model.model_validate(data)
    except ValidationError as e:
        raise ScenarioError(_one_line(e, source)) from None
    except RecursionError:
        raise ScenarioError(f"{source}: nested too deeply") from None


def parse_scenario(text, source="scenario", base_dir=None):
    """Validate TOML text into a :class:`Scenario`; a relative ``initial.file`` is taken from ``base_dir``."""
    scenario = validated(Scenario, parse_toml(text, source), source)
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
        return parse_scenario(read_text(path), source=path.name, base_dir=path.parent)
    return parse_scenario(builtin_text(name), source=name)


def to_toml(scenario: Scenario):
    """The scenario as TOML, with every default that applies to its strategy and body written out."""
    return tomli_w.dumps(scenario.applicable())


def scenario_hash(scenario: Scenario):
    """SHA-256 of the scenario's canonical JSON (hex)."""
    canonical = json.dumps(scenario.model_dump(mode="json"), sort_keys=True, separators=(",", ":"))
    return hashlib.sha256(canonical.encode()).hexdigest()
