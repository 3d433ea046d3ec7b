"""Scenarios: TOML files validated into frozen models; built-in scenarios ship with the package."""

import hashlib
import json
import tomllib
import warnings
from importlib import resources
from pathlib import Path

import tomli_w
from pydantic import ValidationError

from railwear.errors import OptionError, ScenarioError, ScenarioLayoutWarning
from railwear.textfiles import decode_text
from railwear.scenario.schema import OLD_BODY_SECTIONS, OLD_BODY_SETTINGS, Scenario, _new_layout
from railwear.scenario import bodies  # noqa: F401  (registers the built-in [body] sections)

DEFAULT = "metro"

__all__ = ["DEFAULT", "Scenario", "builtin_names", "builtin_text", "load_scenario", "parse_set",
           "scenario_hash", "set_field", "to_toml", "unset_field"]


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


_BRANCHES = {"bool", "dict", "float", "int", "list", "none", "str"}  # pydantic's names of union branches


def _parts(loc, data):
    """``(part, is_branch)`` along a pydantic error location: a key of ``data`` (the validated
    input) at that point is a field, whatever its spelling; otherwise a name that is not an
    identifier, or one of pydantic's type names, is a union branch."""
    node = data
    for part in loc:
        if isinstance(part, int):
            node = node[part] if isinstance(node, list) and -len(node) <= part < len(node) else None
            yield part, False
        elif isinstance(node, dict) and part in node:
            node = node[part]
            yield part, False
        else:
            branch = not part.isidentifier() or part in _BRANCHES
            node = node if branch else None
            yield part, branch


def _field_path(loc, data=None):
    """A pydantic error location as a dotted field with list indices, without the names of union
    branches (``speed_kmh[1]``, not ``speed_kmh.list[constrained-float].1``)."""
    out = ""
    for part, branch in _parts(loc, data):
        if isinstance(part, int):
            out += f"[{part}]"
        elif not branch:
            out += f".{part}" if out else part
    return out


def _site(loc, data=None):
    """The field an error is about: its location up to the first union branch."""
    parts = list(_parts(loc, data))
    end = next((i for i, (_, branch) in enumerate(parts) if branch), len(parts))
    return _field_path(loc[:end], data)


_MESSAGES = {"model_type": "should be a table", "model_attributes_type": "should be a table",
             "dict_type": "should be a table", "extra_forbidden": "no such field", "missing": "required"}


def _message(error):
    """Pydantic's message in plain words: no class names, no 'after validation'."""
    if error["type"] in _MESSAGES:
        return _MESSAGES[error["type"]]
    return error["msg"].removeprefix("Value error, ").replace(" after validation", "")


def _one_line(err: ValidationError, source, data=None):
    """The first error of a validation as one line naming its field (by its key in ``data``, the
    input). Of a union's branches the one that got furthest speaks (a bound broken before a type
    mismatched); branches that all mismatched the type are joined with 'or'. A refusal of the
    schema's own (:func:`~railwear.scenario.schema.refuse`) reads ``field.path: message``."""
    errors = err.errors()
    site = _site(errors[0]["loc"], data)
    if errors[0]["type"] == "field":
        return f"{source}: {site}: {errors[0]['msg']}"
    branches = [e for e in errors if _site(e["loc"], data) == site]
    rank = lambda e: (not e["type"].endswith("_type"), len(e["loc"]))  # noqa: E731
    best = max(map(rank, branches))
    chosen = [e for e in branches if rank(e) == best]
    messages = list(dict.fromkeys(_message(e) for e in chosen))
    message = messages[0] + "".join(" or " + m.removeprefix("Input should be ") for m in messages[1:])
    more = {_site(e["loc"], data) for e in errors} - {site}
    more = f" (and {len(more)} more)" if more else ""
    return f"{source}: field '{_field_path(chosen[0]['loc'], data) or 'scenario'}': {message}{more}"


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
        raise ScenarioError(_one_line(e, source, data)) from None
    except RecursionError:
        raise ScenarioError(f"{source}: nested too deeply") from None


def new_layout(data, source):
    """Plain scenario ``data`` in today's layout (:func:`~railwear.scenario.schema._new_layout`);
    a conflict between the layouts is refused in one line naming the field."""
    try:
        return _new_layout(data) if isinstance(data, dict) else data
    except ValidationError as e:
        raise ScenarioError(_one_line(e, source, data)) from None


def parse_scenario(text, source="scenario", base_dir=None):
    """Validate TOML text (or its plain data) into a :class:`Scenario`; a relative
    ``initial.file`` (or a wheel's in ``[[initial.wheels]]``) is taken from ``base_dir``."""
    data = parse_toml(text, source) if isinstance(text, str) else text
    scenario = validated(Scenario, data, source)
    if base_dir is None:
        return scenario

    def located(init):
        file = init.file
        if file and not Path(file).is_absolute():
            return init.model_copy(update={"file": str(Path(base_dir, file).resolve())})
        return init

    initial = located(scenario.initial)
    if initial.wheels is not None and any(w.file for w in initial.wheels):
        initial = initial.model_copy(update={"wheels": [located(w) for w in initial.wheels]})
    return scenario if initial is scenario.initial else scenario.model_copy(update={"initial": initial})


def scenario_text(path_or_name, names, directory, kind="scenario"):
    """``(text, source, base_dir)`` of a scenario: a path that exists as a file is read, otherwise
    the built-in of that name (``names``, in ``directory``); a folder is never a scenario."""
    name = str(path_or_name)
    path = Path(name)
    try:
        is_file, is_dir, exists = path.is_file(), path.is_dir(), path.exists()
    except OSError:  # a name too long for the file system: nothing there
        is_file = is_dir = exists = False
    if is_file:
        text = read_text(path)
        data = parse_toml(text, path.name)
        shadows = name in names and path.suffix == ""  # a file in this folder named like a built-in
        if not any(isinstance(value, dict) for value in data.values()):
            given = f"only {', '.join(data)} and no [section]" if data else "nothing"
            builtin = (f"; a file of that name in this folder is read in place of the built-in {kind} "
                       f"{name!r} (railwear show {name} prints that one)" if shadows else "")
            raise ScenarioError(f"{path.name}: not a {kind}: the file holds {given}, and the schema's defaults "
                                f"alone are no wheel anyone meant{builtin}")
        if shadows:
            warnings.warn(f"reading the file {path} in this folder, not the built-in {kind} {name!r}",
                          ShadowWarning, stacklevel=2)
        return text, path.name, path.parent
    if name in names:
        return (directory / f"{name}.toml").read_text(), name, None
    known = f"built-in {kind}s: {', '.join(names)}"
    if is_dir:
        raise ScenarioError(f"{name} is a folder, not a {kind} file; {known}")
    if exists:
        raise ScenarioError(f"{name} is not a {kind} file (not a regular file)")
    if path.suffix == ".toml" or "/" in name or "\\" in name:
        raise ScenarioError(f"{kind} file {name} does not exist")
    raise ScenarioError(f"no built-in {kind} {name!r}; {known}")


class ShadowWarning(UserWarning):
    """A scenario file named like a built-in is read in its place."""


SPEED_FIELDS = ("operation.speed_kmh", "operation.speed_m_s")  # one replaces the other


def field_table(data, path, what, create=False):
    """``(table, key)`` of the dotted field ``path`` in plain scenario ``data``; missing tables
    are made with ``create``, otherwise (or through a value) an :class:`OptionError` naming ``what``."""
    node, keys = data, path.split(".")
    if not all(k.strip() for k in keys):
        raise OptionError(f"{what} {path!r}: expected a dotted scenario field such as operation.speed_kmh")
    for key in keys[:-1]:
        if create and key not in node:
            node[key] = {}
        if not isinstance(node.get(key), dict):
            raise OptionError(f"{what} {path}: no such scenario field")
        node = node[key]
    return node, keys[-1]


def moved_field(path):
    """The field of today's layout for a dotted ``path`` of the layout before ``[body]``
    (``strategy.body`` is ``body.kind``; the body's settings and ``[disk_wheel]``, ``[vehicle]``,
    ``[wheelset_wear]`` are ``[body]``'s), with a warning when it moved."""
    section, _, name = path.partition(".")
    if path == "strategy.body":
        new = "body.kind"
    elif (section == "strategy" and name in OLD_BODY_SETTINGS) or (section in OLD_BODY_SECTIONS.values() and name):
        new = f"body.{name}"
    else:
        return path
    warnings.warn(f"{path} is {new} now (scenario layout with [body])", ScenarioLayoutWarning, stacklevel=3)
    return new


def set_field(data, path, value, what="--set", create=False):
    """Set the dotted field ``path`` of plain scenario ``data`` (a field of the layout before
    ``[body]`` at its new place); a speed field replaces the other."""
    path = moved_field(path)
    node, key = field_table(data, path, what, create)
    node[key] = value
    if path in SPEED_FIELDS:
        node.pop(SPEED_FIELDS[1 - SPEED_FIELDS.index(path)].split(".")[-1], None)


def parse_set(text):
    """``FIELD=VALUE`` as ``(field, value)``, the value a TOML value (``180``, ``"x"``, ``[1, 2]``,
    ``true``) or else a bare word taken as a string (``stepwise``)."""
    field, sep, value = text.partition("=")
    field, value = field.strip(), value.strip()
    if not sep or not field or not value:
        raise OptionError(f"--set {text!r}: expected FIELD=VALUE, e.g. operation.speed_kmh=180")
    try:
        return field, tomllib.loads(f"v = {value}")["v"]
    except (tomllib.TOMLDecodeError, RecursionError) as e:
        if value[0] in "[{\"'":
            raise OptionError(f"--set {field}: not a TOML value ({e})") from None
        return field, value


KINDS = ("strategy.kind", "body.kind", "wear.law")  # the fields that choose which others apply


def _within(data, allowed):
    """``data`` with only the keys, table by table, that ``allowed`` has."""
    return {k: _within(v, allowed[k]) if isinstance(v, dict) and isinstance(allowed[k], dict) else v
            for k, v in data.items() if k in allowed}


def unset_field(data, path, applicable):
    """Remove the dotted field or section ``path`` from plain scenario ``data`` (``--unset``), so
    that it takes its default as if the file had not given it; ``applicable`` is the scenario's
    every field with its default, to tell a field of the scenario from a misspelt one."""
    if not all(key.strip() for key in path.split(".")):
        raise OptionError(f"--unset {path!r}: expected a dotted scenario field such as track.ballast_stiffness_MN_m")
    path = moved_field(path)
    for table, said in ((data, None), (applicable, "it has its default already")):
        try:
            node, key = field_table(table, path, "--unset")
        except OptionError:
            continue
        if key in node:
            if said:
                raise OptionError(f"--unset {path}: the scenario does not set it; {said}")
            del node[key]
            return
    raise OptionError(f"--unset {path}: the scenario does not set it: no such field, or one that does not apply to it")


def load_scenario(path_or_name=None, overrides=(), unset=()):
    """A scenario from a TOML file or a built-in name (the default scenario when ``None``), with
    ``overrides`` (``FIELD=VALUE`` texts or a ``{field: value}`` mapping) set as if in the file;
    an override of a kind (:data:`KINDS`) drops the file's fields that do not apply to the new one.
    ``unset`` names fields or sections (dotted) to remove first, each taking its default as if the
    file had not given it (:func:`unset_field`); a field both unset and set is refused."""
    if isinstance(path_or_name, Scenario):
        base, source, base_dir = path_or_name, path_or_name.name, None
        data = base.model_dump(mode="python", exclude_unset=True)
    else:
        text, source, base_dir = scenario_text(DEFAULT if path_or_name is None else path_or_name,
                                               builtin_names(), _builtin_dir())
        data = new_layout(parse_toml(text, source), source)
        base = parse_scenario(data, source, base_dir)
    if not overrides and not unset:
        return base
    sets = dict(overrides.items() if isinstance(overrides, dict) else map(parse_set, overrides))
    sets = {moved_field(field): value for field, value in sets.items()}
    source = f"{source} with --set" if sets else f"{source} with --unset"
    for field in unset:
        if moved_field(field.strip()) in sets:
            raise OptionError(f"--unset {field}: also given to --set; give it one or the other")
        unset_field(data, field.strip(), base.applicable(mode="python", exclude_none=False))
    current = {field: getattr(getattr(base, field.split(".")[0]), field.split(".")[1]) for field in KINDS}
    if any(sets.get(field, value) != value for field, value in current.items()):
        kinds = {}
        for field, value in current.items():
            set_field(kinds, field, sets.get(field, value), create=True)
        data = _within(data, validated(Scenario, kinds, source).applicable(mode="python", exclude_none=False))
    for field, value in sets.items():
        if field == "initial.file" and isinstance(value, str):  # a file named on the command line
            value = str(Path(value).resolve())
        set_field(data, field, value, create=True)
    return parse_scenario(data, source, base_dir)


def to_toml(scenario: Scenario):
    """The scenario as TOML, with every default that applies to its strategy and body written out."""
    return tomli_w.dumps(scenario.applicable())


_ADDED_LATER = {"operation": ("daily_distance_km",), "initial": ("wheels",),
                "body": ("wheel_positions_m", "wheel_phases", "rolling_contact", "tangential_compliance")}


def scenario_hash(scenario: Scenario):
    """SHA-256 of the scenario's canonical JSON (hex). Fields added later, left unset
    (``_ADDED_LATER``: no effect on the run), are left out, so the hashes of earlier scenarios and
    checkpoints hold."""
    unset = {section: names for section, fields in _ADDED_LATER.items()
             if (names := {f for f in fields if getattr(getattr(scenario, section), f, 0) is None})}
    canonical = json.dumps(scenario.model_dump(mode="json", exclude=unset or None), sort_keys=True,
                           separators=(",", ":"))
    return hashlib.sha256(canonical.encode()).hexdigest()
