"""Every refusal names its field (issue 19): bad values for every numeric field of every built-in
scenario, unknown and unicode keys in every table, nested and ragged tables in files, each refused
in one line naming the field by its dotted path; work beyond the stated bounds is refused naming
the field and the bound; a byte-order mark is fine."""

import tomllib
from typing import get_args

import pytest
from annotated_types import Ge, Gt
from typer.testing import CliRunner

from railwear import api
from railwear.cli import app
from railwear.errors import ScenarioError
from railwear.scenario import builtin_names, builtin_text, load_scenario, to_toml
from railwear.scenario.schema import MAX_LONGTERM_STEPS, MAX_SAVED, MAX_SAVED_VALUES

CERTAINLY_BAD = ["1e300", "-1e300", "nan", "inf", "-inf", '"text"', '["x"]', "{ a = 1 }", '{ "ключ" = 1 }']
LOW = ["-0.0", "0", "-1"]  # bad where the field's lower bound excludes them
KEYS = ["ключ", "rädius_m", '"a b"', '"é-x"', "bogus"]


def _bound(annotation, metadata=()):
    """``(lower bound, open)`` of a field's numbers and whether they are integers, from its annotation."""
    found, is_int = None, annotation is int
    for meta in [*metadata, *getattr(annotation, "__metadata__", ())]:
        for m in getattr(meta, "metadata", [meta]):
            if found is None and isinstance(m, (Ge, Gt)):
                found = (m.ge, False) if isinstance(m, Ge) else (m.gt, True)
    for arg in get_args(annotation):
        inner, inner_int = _bound(arg)
        found, is_int = found or inner, is_int or inner_int
    return found, is_int


def _refuses(value, bound, is_int):
    """Whether the TOML number ``value`` lies below ``bound`` (or is a float for an integer field)."""
    number = float(value)
    if is_int and "." in value:
        return True
    if bound is None:
        return False
    low, open_ = bound
    return number <= low if open_ else number < low


def _numbers(data, prefix=""):
    for key, value in data.items():
        path = f"{prefix}.{key}" if prefix else key
        if isinstance(value, dict):
            yield from _numbers(value, path)
        elif isinstance(value, (int, float, list)) and not isinstance(value, bool) and value != []:
            yield path, value


def _cases():
    """``(scenario, field, TOML value, what the message must name)``, each field once, from the
    first built-in it applies to."""
    seen, cases = set(), []
    for name in builtin_names():
        sc = load_scenario(name)
        data = tomllib.loads(to_toml(sc))
        fields = dict(_numbers(data))
        for section in [s for s in data if isinstance(data[s], dict)]:
            model = type(getattr(sc, section))
            fields.update({f"{section}.{f}": None for f in model.model_fields if f"{section}.{f}" not in fields})
            for key in KEYS:
                if (section, key) not in seen:
                    seen.add((section, key))
                    cases.append((name, f"{section}.{key}", "1", f"{section}.{key}"))
        for path, value in fields.items():
            *sections, field = path.split(".")  # a nested table: operation.line.top_speed_kmh
            owner = sc
            for part in sections:
                owner = getattr(owner, part)
            info = type(owner).model_fields[field]
            bound, is_int = _bound(info.annotation, info.metadata)
            numeric = value is not None or bound is not None
            if path in seen or not numeric or (value is None and field in ("file",)):
                continue
            seen.add(path)
            if isinstance(value, list) and value and all(not isinstance(v, list) for v in value):
                head = ", ".join(map(repr, value[:-1]))
                for bad in CERTAINLY_BAD + [v for v in LOW if _refuses(v, bound, is_int)]:
                    cases.append((name, path, f"[{head}{', ' if head else ''}{bad}]", f"{path}[{len(value) - 1}]"))
            for bad in CERTAINLY_BAD + [v for v in LOW if _refuses(v, bound, is_int)]:
                cases.append((name, path, bad, path))
    return cases


CASES = _cases()


@pytest.mark.parametrize("scenario, field, value, named", CASES, ids=[f"{c[0]}:{c[1]}={c[2]}" for c in CASES])
def test_a_bad_value_is_refused_naming_its_field(scenario, field, value, named):
    with pytest.raises(ScenarioError) as err:
        load_scenario(scenario, [f"{field}={value}"])
    message = str(err.value)
    assert named in message and "\n" not in message, message
    assert not any(word in message for word in ("Value error", "constrained", "list[", "Traceback")), message


@pytest.fixture
def no_run(monkeypatch):
    """A scenario that passes validation fails the test instead of running."""
    def accepted(scenario, *args, **kwargs):
        raise AssertionError(f"accepted: {scenario}")
    monkeypatch.setattr(api, "run", accepted)


def refused(args, *named):
    """Exit 2, one line ``railwear: error: ...`` naming each of ``named``, no traceback."""
    result = CliRunner().invoke(app, [str(a) for a in args])
    lines = [line for line in result.output.splitlines() if line and not line.startswith("compiling kernels")]
    assert result.exit_code == 2, (result.output, result.exception)
    assert len(lines) == 1 and lines[0].startswith("railwear: error:") and "Traceback" not in result.output, lines
    assert all(name in lines[0] for name in named), lines[0]
    return lines[0]


@pytest.mark.parametrize("scenario, field, value, named", [c for c in CASES if c[2] in ("-0.0", '{ "ключ" = 1 }')
                                                           or c[1].endswith(tuple(KEYS))][::3])
def test_the_command_line_says_the_same_in_one_line(scenario, field, value, named, no_run, tmp_path):
    refused(["run", scenario, "--set", f"{field}={value}", "-o", tmp_path / "out", "--no-figures"], named)


ONSET, STEPWISE = builtin_text("onset"), builtin_text("stepwise")
TABLE = ('[wear_rate]\nform = "table"\ncurvature_m = [-1.0, -0.5, 0.0, 0.5, 1.0]\n'
         'table_speed_kmh = [100.0, 200.0]\nrate_m = {}\n\n[solver]')


def _table(rate):
    head, tail = ONSET.split("[wear_rate]")
    return head + TABLE.format(rate) + tail.split("[solver]")[1]


ROW = "[1.0, 2.0]"
FIVE = f"[{ROW}, {ROW}, {ROW}, {ROW}, {ROW}]"
CURVATURE = "[-1.0, -0.5, 0.0, 0.5, 1.0]"


@pytest.mark.parametrize("text, named", [
    (ONSET + "\n[wheel.extra]\nx = 1\n", "wheel.extra"),
    (ONSET + '\n[[wheel."é-x"]]\nx = 1\n', "wheel.é-x"),
    (ONSET + '\n[wheel."a b"]\nx = 1\n', "wheel.a b"),
    (STEPWISE + "\n[strategy.sub]\nx = -1\n", "strategy.sub"),
    (STEPWISE + '\n[[strategy."ключ"]]\nx = -1\n', "strategy.ключ"),
    (ONSET + '\n[wear."ключ"]\nx = -1\n', "wear.ключ"),
    (ONSET.replace("[initial]", "[initial]\namplitudes_um = [1.0, [2.0]]"), "initial.amplitudes_um[1]"),
    (ONSET.replace("[initial]", '[initial]\nphases_deg = [1.0, { "ключ" = -1e300 }]'), "initial.phases_deg[1]"),
    (_table(f"[{ROW}, {ROW}, [1.0], {ROW}, {ROW}]"), "wear_rate.rate_m[2]"),
    (_table(f"[{ROW}, {ROW}, [1.0, 2.0, 3.0], {ROW}, {ROW}]"), "wear_rate.rate_m[2]"),
    (_table(f"[{ROW}, {ROW}, 3.0, {ROW}, {ROW}]"), "wear_rate.rate_m[2]"),
    (_table(f"[{ROW}, {ROW}, {ROW}]"), "wear_rate.rate_m"),
    (_table(f"[{ROW}, {ROW}, [1.0, 1e300], {ROW}, {ROW}]"), "wear_rate.rate_m[2][1]"),
    (_table(f"[{ROW}, {ROW}, [1.0, -0.0], {ROW}, [nan, 1.0]]"), "wear_rate.rate_m[4][0]"),
    (_table(FIVE).replace(CURVATURE, "[-1.0, 0.5, 0.0, 0.5, 1.0]"), "wear_rate.curvature_m"),
    (_table(f"[{ROW}, {ROW}]").replace(CURVATURE, "[-1.0, 1.0]"), "wear_rate.curvature_m"),
    (_table(FIVE).replace("[100.0, 200.0]", "[200.0, 100.0]"), "wear_rate.table_speed_kmh"),
])
def test_a_bad_nested_or_ragged_table_in_a_file_names_its_field(text, named, tmp_path, no_run):
    path = tmp_path / "bad.toml"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(ScenarioError) as err:
        load_scenario(path)
    assert named in str(err.value) and "\n" not in str(err.value), str(err.value)
    refused(["run", path, "-o", tmp_path / "out", "--no-figures"], named)


def test_a_well_formed_table_is_accepted():
    from railwear.scenario import build, parse_scenario

    sc = parse_scenario(_table(FIVE).replace("190.0", "150.0"))
    assert build.wear_rate(sc).rate.shape == (5, 2)


def test_a_byte_order_mark_is_fine(tmp_path):
    path = tmp_path / "bom.toml"
    path.write_bytes(b"\xef\xbb\xbf" + ONSET.encode())
    assert load_scenario(path) == load_scenario("onset")
    bad = tmp_path / "bom-bad.toml"
    bad.write_bytes(b"\xef\xbb\xbf" + ONSET.replace("radius_m = 0.46", "radius_m = -0.0").encode())
    with pytest.raises(ScenarioError, match="field 'wheel.radius_m'"):
        load_scenario(bad)


@pytest.mark.parametrize("sets, named", [
    (["solver.n_save=100000", "solver.points=16", "initial.highest_order=4"], ("solver.n_save", f"{MAX_SAVED}")),
    ([f"solver.n_save={MAX_SAVED}", "solver.points=4096"],
     ("solver.n_save", f"{MAX_SAVED_VALUES:.0e}", f"at most {MAX_SAVED_VALUES // 4096}")),
    (["strategy.step_limit_um=1e-300"], ("strategy.step_limit_um", f"{MAX_LONGTERM_STEPS:.0e}", "at least 0.01 um")),
    (["strategy.step_limit_um=0.009"], ("strategy.step_limit_um", f"{MAX_LONGTERM_STEPS:.0e}")),
    (["strategy.step_limit_um=0.5", "solver.depth_limit_mm=60"], ("strategy.step_limit_um", "60 mm")),
    (["solver.points=16"], ("initial.highest_order", "at most 7")),
])
def test_work_beyond_its_bound_is_refused_naming_the_field_and_the_bound(sets, named, no_run, tmp_path):
    args = [a for s in sets for a in ("--set", s)]
    refused(["run", "stepwise", *args, "-o", tmp_path / "out", "--no-figures"], *named)


def test_work_at_its_bound_is_accepted():
    assert load_scenario("stepwise", ["strategy.step_limit_um=0.01"]).strategy.step_limit_um == 0.01
    sc = load_scenario("onset", [f"solver.n_save={MAX_SAVED}", f"solver.points={MAX_SAVED_VALUES // MAX_SAVED}"])
    assert sc.solver.n_save * sc.solver.points == MAX_SAVED_VALUES
