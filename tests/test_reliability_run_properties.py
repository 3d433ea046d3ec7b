"""Runs, not only validation, at valid but extreme values (issue 19): every numeric field of the
sections two cheap built-in scenarios write, one at a time, at each bound of the schema and at
1e-300, 1e300 and their negatives where the bounds allow them, run by 'railwear run' in process.

Whatever the value, the command ends in one of three ways and no other: 0 with every written
number finite (or masked, saying why) in result.nc, summary.json, summary.txt and report.html; 1
with one line saying why the run failed and its last good state kept; 2 with one line naming the
field. An exception of another kind (railwear's 'internal error') fails the test.
"""

import math
import tomllib
from typing import get_args

import numpy as np
import pytest
from annotated_types import Ge, Gt, Le, Lt
from pydantic import BaseModel
from test_nonfinite_outputs import assert_finite_file, assert_strict_summary
from test_reliability_outputs import NAN_OR_INF
from typer.testing import CliRunner

from railwear.cli import app
from railwear.scenario import builtin_text, load_scenario, to_toml

# The base of each scenario: a few saved states of a short run on a coarse grid.
BASES = {"onset": ("solver.points=64", "solver.n_save=101", "solver.t_end=0.05"),  # evolution equation
         "linear-dynamics": ("solver.n_save=11",)}  # Fourier technique on the disk wheel and rail (64 points)
TINY_AND_HUGE = (1e-300, 1e300, -1e300, -1e-300)

# Seconds each on a busy two-core machine, marked slow (-m "not slow" leaves them out; 102 s in all).
SLOW = {("onset", "solver.epsilon", 1000.0): "51 s: 12 800 ETDRK4 steps of 64 points",
        ("onset", "wear_rate.drift_rad", -1e9): "5 s",
        ("onset", "solver.points", 65536): "3 s", ("linear-dynamics", "solver.points", 65536): "24 s"}
# Found by this suite and fixed since (the refusal names the field now); none left.
KNOWN = {}


def _limits(annotation, metadata=()):
    """``(low, low open, high, high open, integer)`` of a field from its annotation and metadata."""
    low = high = None
    low_open = high_open = False
    integer = annotation is int
    for meta in [*metadata, *getattr(annotation, "__metadata__", ())]:
        for m in getattr(meta, "metadata", [meta]):
            if low is None and isinstance(m, (Ge, Gt)):
                low, low_open = (m.ge, False) if isinstance(m, Ge) else (m.gt, True)
            if high is None and isinstance(m, (Le, Lt)):
                high, high_open = (m.le, False) if isinstance(m, Le) else (m.lt, True)
    for arg in get_args(annotation):
        inner = _limits(arg)
        if low is None:
            low, low_open = inner[:2]
        if high is None:
            high, high_open = inner[2:4]
        integer = integer or inner[4]
    return low, low_open, high, high_open, integer


def _extremes(low, low_open, high, high_open, integer):
    """The values at the bounds (the nearest inside an open one), and 1e-300, 1e300 and their
    negatives where the bounds allow them."""
    if integer:
        return ([int(low) + low_open] if low is not None else []) + ([int(high) - high_open] if high is not None else [])
    values = []
    if low is not None:
        values.append(math.nextafter(low, math.inf) if low_open and low != 0 else 1e-300 if low_open else low)
    if high is not None:
        values.append(math.nextafter(high, -math.inf) if high_open else high)

    def inside(v):
        return ((low is None or (v > low if low_open else v >= low))
                and (high is None or (v < high if high_open else v <= high)))

    return sorted({float(v) for v in values} | {v for v in TINY_AND_HUGE if inside(v)})


def _numbers(data, prefix=""):
    for key, value in data.items():
        path = f"{prefix}.{key}" if prefix else key
        if isinstance(value, dict):
            yield from _numbers(value, path)
        elif isinstance(value, (int, float)) and not isinstance(value, bool):
            yield path


def _fields(sc):
    """Every field of the scenario ``sc`` by its dotted path."""
    sections = [(name, type(getattr(sc, name))) for name in type(sc).model_fields]
    return {f"{name}.{field}" for name, model in sections if isinstance(model, type) and issubclass(model, BaseModel)
            for field in model.model_fields}


FIELDS = {}


def _cases():
    cases = []
    for name, base in BASES.items():
        sc = load_scenario(name, list(base))
        FIELDS[name] = _fields(sc)
        written = tomllib.loads(builtin_text(name))  # its sections; their fields at the defaults too
        for path in _numbers(tomllib.loads(to_toml(sc))):
            section, field = path.split(".")
            if section not in written:  # a section the run does not read ([service], [wheelset])
                continue
            info = type(getattr(sc, section)).model_fields[field]
            for value in _extremes(*_limits(info.annotation, info.metadata)):
                marks = []
                if (name, path, value) in SLOW:
                    marks.append(pytest.mark.slow)
                if (name, path, value) in KNOWN:
                    marks.append(pytest.mark.xfail(strict=True, reason=KNOWN[(name, path, value)]))
                cases.append(pytest.param(name, path, value, marks=marks, id=f"{name}:{path}={value!r}"))
    return cases


@pytest.mark.parametrize("scenario, field, value", _cases())
def test_a_run_at_an_extreme_value_ends_in_one_of_three_ways(tmp_path, scenario, field, value):
    out = tmp_path / "out"
    args = ["run", scenario, "-o", str(out), "--no-figures"]
    for s in [s for s in BASES[scenario] if not s.startswith(f"{field}=")] + [f"{field}={value!r}"]:
        args += ["--set", s]
    result = CliRunner().invoke(app, args)
    assert result.exception is None or isinstance(result.exception, SystemExit), repr(result.exception)
    errors = [line for line in result.stderr.splitlines() if line.startswith("railwear: error: ")]
    if result.exit_code == 0:
        assert not errors, errors
        assert_finite_file(out / "result.nc")
        assert_strict_summary(out)
        html = (out / "report.html").read_text(encoding="utf-8")
        assert not NAN_OR_INF.search(html), NAN_OR_INF.findall(html)
    elif result.exit_code == 1:  # a failed run: why, in one line, and the last good state kept
        assert len(errors) == 1 and "internal error" not in errors[0], result.stderr
        assert "last_good_state.npy" in errors[0] and np.all(np.isfinite(np.load(out / "last_good_state.npy")))
        assert not (out / "result.nc").exists()
    else:  # bad input: one line naming a field of the scenario (this one, or one it contradicts)
        assert result.exit_code == 2 and len(errors) == 1, (result.exit_code, result.stderr)
        assert any(name in errors[0] for name in FIELDS[scenario]), errors[0]
        assert not (out / "result.nc").exists()
