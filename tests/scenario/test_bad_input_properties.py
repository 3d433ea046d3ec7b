"""Property tests (hypothesis) of the input edge: built-in scenarios, measured wheels and options,
each mutated so that it is certainly bad, give exit status 2, one line that names the field (or
the file and line), no traceback and no file in the output folder.

``RAILWEAR_FUZZ_EXAMPLES`` sets the examples per test (default 300, about ten seconds for all);
run ``RAILWEAR_FUZZ_EXAMPLES=2000 pytest tests/scenario/test_bad_input_properties.py`` locally.
"""

import os
import tempfile
import tomllib
from pathlib import Path

import numpy as np
import tomli_w
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from typer.testing import CliRunner

from railwear.cli import app
from railwear.scenario import builtin_names, builtin_text, dynamics

EXAMPLES = int(os.environ.get("RAILWEAR_FUZZ_EXAMPLES", "300"))
SETTINGS = settings(max_examples=EXAMPLES, deadline=None, derandomize="RAILWEAR_FUZZ_EXAMPLES" not in os.environ,
                    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
SCENARIOS = {name: builtin_text(name) for name in builtin_names()}
DYNAMICS = {name: (dynamics._builtin_dir() / f"{name}.toml").read_text() for name in dynamics.builtin_names()}


def refused(args, out, *named):
    """Exit 2, one line naming each of ``named`` (a tuple: one of them), no traceback, nothing in ``out``."""
    result = CliRunner().invoke(app, [str(a) for a in args])
    result_lines = [line for line in result.output.splitlines() if not line.startswith("compiling kernels")]
    text = result.output
    assert result.exit_code == 2, (args, text, result.exception)
    assert "Traceback" not in text and len(result_lines) == 1, text
    for name in named:
        assert any(n in text for n in ((name,) if isinstance(name, str) else name)), (name, text)
    assert not out.exists() or not any(p.is_file() for p in out.rglob("*")), list(out.rglob("*"))


def _leaves(data, path=()):
    """``(path, value)`` of every value in a TOML document (lists as one value)."""
    for key, value in data.items():
        if isinstance(value, dict):
            yield from _leaves(value, path + (key,))
        else:
            yield path + (key,), value


NESTED = "@@nested {}@@"  # written into the text as that many nested brackets


def _bad_value(value):
    """Values that no field of ``value``'s type accepts: the wrong type, outside every bound (every
    number has bounds below 1e300 in magnitude), not finite, a control character, nested deeply."""
    nested = st.integers(600, 3000).map(lambda d: NESTED.format(d))
    if isinstance(value, bool):
        return st.sampled_from([1, 0.0, "yes", [True]]) | nested
    if isinstance(value, (int, float)):
        return st.sampled_from([True, False, "1", 1e300, -1e300, float("nan"), float("inf"), -float("inf"),
                                {"value": value}]) | nested  # not [value]: a one-speed batch is fine
    if isinstance(value, str):
        return st.sampled_from(["\x00", "a\x00b", "\x07", "x\x1b[31m"]).map(lambda c: value + c) | st.sampled_from([1, 2.5, True, [value]])
    if isinstance(value, list) and value and all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in value):
        return st.tuples(st.integers(0, len(value) - 1), st.sampled_from([True, "1", 1e300, -1e300, float("nan")])).map(
            lambda iv: [iv[1] if i == iv[0] else v for i, v in enumerate(value)])
    return st.sampled_from([True, "\x00", 1e300])


@st.composite
def bad_scenario(draw, texts):
    """``(name, toml text, what the message must name)`` for one mutation of a built-in scenario."""
    name = draw(st.sampled_from(sorted(texts)))
    text = texts[name]
    how = draw(st.sampled_from(["value", "value", "value", "extra", "bytes"]))
    if how == "bytes":  # a byte that is no UTF-8, somewhere in the file
        data = text.encode()
        at = draw(st.integers(0, len(data)))
        byte = draw(st.sampled_from([b"\xe9", b"\xff", b"\xc3", b"\x80"]))
        line = data[:at].count(b"\n") + 1
        return name, data[:at] + byte + data[at:], [f"line {line}", "UTF-8"]
    data = tomllib.loads(text)
    if how == "extra":
        sections = [k for k, v in data.items() if isinstance(v, dict)] + [None]
        section = draw(st.sampled_from(sections))
        key = draw(st.from_regex(r"[a-z]{3,10}_[a-z]{1,4}", fullmatch=True))
        target = data if section is None else data[section]
        if key in target:
            key += "_x"
        target[key] = 1.0
        return name, tomli_w.dumps(data).encode(), [key]
    path, value = draw(st.sampled_from(list(_leaves(data))))
    bad = draw(_bad_value(value))
    node = data
    for key in path[:-1]:
        node = node[key]
    node[path[-1]] = bad
    try:
        out = tomli_w.dumps(data)
    except (TypeError, ValueError):  # what TOML cannot hold (NaN inside some forms): a bracket run instead
        bad = NESTED.format(1000)
        node[path[-1]] = bad
        out = tomli_w.dumps(data)
    if isinstance(bad, str) and bad.startswith("@@nested"):
        depth = int(bad.split()[1].rstrip("@"))
        fields = tuple(p for p in path if isinstance(p, str))
        return name, out.replace(f'"{bad}"', "[" * depth + "]" * depth).encode(), [("nested too deeply", fields[-1])]
    return name, out.encode(), [path[-1]]


def _check_scenario(case, command):
    name, data, named = case
    with tempfile.TemporaryDirectory() as tmp:
        path, out = Path(tmp) / f"{name}.toml", Path(tmp) / "out"
        path.write_bytes(data)
        refused([command, path, "-o", out], out, *named)


@SETTINGS
@given(bad_scenario(SCENARIOS))
def test_a_mutated_builtin_scenario_is_refused_naming_the_field(case):
    _check_scenario(case, "run")


@SETTINGS
@given(bad_scenario(DYNAMICS))
def test_a_mutated_dynamics_scenario_is_refused_naming_the_field(case):
    _check_scenario(case, "simulate")


def _wheel_lines():
    angles = np.arange(0.0, 360.0, 5.0)
    return ["angle_deg,deviation_um"] + [f"{a:g},{20 * np.cos(np.radians(4 * a)):.4f}" for a in angles]


BAD_NUMBERS = ["1_0", "0x10", "inf", "-inf", "nan", "", " ", "1e999", "\u0661", "1..2", "--1", "1e", ".", "+",
               "1 2", "١٢", "½", "1e5e5", "0b1", "\u00a01", "1j", "True", "1%"]


@st.composite
def bad_wheel(draw):
    """``(csv bytes, [what the message must name])`` for one mutation of a good measured wheel."""
    lines = _wheel_lines()
    row = draw(st.integers(1, len(lines) - 1))
    number = row + 1  # file lines start at 1 and the header is line 1
    angle, deviation = lines[row].split(",")
    how = draw(st.sampled_from(["number", "number", "comma", "angle", "deviation", "order", "bytes", "header"]))
    if how == "number":
        column = draw(st.integers(1, 2))
        cell = draw(st.sampled_from(BAD_NUMBERS) | st.text(min_size=1, max_size=6).filter(
            lambda t: any(c not in "0123456789.eE+-" for c in t) and "," not in t and "\n" not in t
            and "\r" not in t and '"' not in t and t.strip() and not t.lstrip().startswith("#")))
        lines[row] = f"{cell},{deviation}" if column == 1 else f"{angle},{cell}"
        named = [f"line {number}"]
        if cell.strip() and "\x00" not in cell:
            named.append(f"column {column}")
    elif how == "comma":  # a decimal comma in a comma-separated file
        lines[row] = f"{angle},{deviation.replace('.', ',')}" if "." in deviation else f"{angle},{deviation},5"
        named = [f"line {number}"]
    elif how == "angle":
        lines[row] = f"{draw(st.sampled_from([-5, -0.001, 360.5, 400, 1e6]))},{deviation}"  # 360 closes the turn
        named = []  # an angle out of turn may show first as an order fault elsewhere: the file is named
    elif how == "deviation":
        lines[row] = f"{angle},{draw(st.sampled_from([5e4 + 1, -2e6, 1e300]))}"
        named = [f"line {number}", "column 2"]
    elif how == "order":
        other = draw(st.integers(1, len(lines) - 1).filter(lambda r: r != row))
        lines[row], lines[other] = lines[other], lines[row]
        named = []
    elif how == "bytes":
        data = "\n".join(lines).encode()
        at = data.index(lines[row].encode())
        return data[:at] + b"\xe9" + data[at:], [f"line {number}", "UTF-8"]
    else:
        lines[0] = draw(st.sampled_from(["angle,deviation", "theta_deg,deviation_um", "angle_deg,dev_um",
                                         "deviation_um", "", "angle_deg;deviation_um"]))
        named = []
    return ("\n".join(lines) + "\n").encode(), named


@SETTINGS
@given(bad_wheel())
def test_a_mutated_measured_wheel_is_refused_naming_file_and_line(case):
    data, named = case
    with tempfile.TemporaryDirectory() as tmp:
        path, out = Path(tmp) / "wheel.csv", Path(tmp) / "out"
        path.write_bytes(data)
        refused(["forecast", path, "--scenario", "forecast", "-o", out], out, "wheel.csv", *named)


BAD_TEXT = st.text(min_size=1, max_size=12).filter(lambda t: any(c not in "0123456789.eE+-,: " for c in t))
BAD_RANGE = st.sampled_from(["nan", "inf", "1_0", "", ":", "1:2", "1:2:0", "2:1:1", "1:1e9:1e-6", "1,,2", "1:2:-1",
                             "1e999", "0x1"]) | BAD_TEXT


@st.composite
def bad_option(draw):
    """``(arguments, option name)`` of one command with one option certainly bad."""
    command = draw(st.sampled_from(["forecast", "stability", "sweep", "run", "hunting-map"]))
    if command == "forecast":
        option, value = draw(st.sampled_from([
            ("--samples", draw(st.integers(max_value=0) | st.integers(min_value=100001))),
            ("--seed", draw(st.integers(max_value=-1))),
            ("--limit", draw(st.sampled_from(["0mm", "-1mm", "infmm", "nanmm", "1_0mm", "2m", "3", "mm", "1e999um"]) | BAD_TEXT)),
            ("--horizon-km", draw(st.sampled_from(["0", "-1", "inf", "nan", "1e300"]))),
            ("--angle-unit", draw(st.sampled_from(["grad", "DEG", "", "turn"]))),
            ("--deviation-unit", draw(st.sampled_from(["nm", "inch", "", "MM"])))]))
        return ["forecast", "WHEEL", "--scenario", "forecast", option, str(value)], (option, option.lstrip("-").replace("-", "_"))
    if command == "stability":
        option = draw(st.sampled_from(["--speeds", "--orders"]))
        return ["stability", "onset", option, draw(BAD_RANGE)], option
    if command == "hunting-map":
        option = draw(st.sampled_from(["--conicity", "--yaw-stiffness"]))
        return ["hunting-map", option, draw(BAD_RANGE)], option
    if command == "run":
        return ["run", "onset", "--checkpoint-every", draw(st.sampled_from(["-1", "nan", "inf", "-0.5"]))], "--checkpoint-every"
    option, value = draw(st.sampled_from([
        ("--vary", "operation.speed_kmh=" + draw(BAD_RANGE)),
        ("--vary", draw(st.sampled_from(["nosuch.field=1,2", "wheel=1,2", "name=1,2", "=1", "wheel.radius_m"]))),
        ("--samples", str(draw(st.integers(max_value=0)))),
        ("--seed", str(draw(st.integers(max_value=-1))))]))
    args = ["sweep", "onset", option, value]
    if option != "--vary":
        args += ["--vary", "operation.speed_kmh=100,200"] + (["--samples", "2"] if option == "--seed" else [])
    return args, "--vary" if option == "--vary" else option


@SETTINGS
@given(bad_option())
def test_a_bad_option_exits_2_naming_it(case):
    args, name = case
    with tempfile.TemporaryDirectory() as tmp:
        wheel, out = Path(tmp) / "wheel.csv", Path(tmp) / "out"
        wheel.write_text("\n".join(_wheel_lines()) + "\n")
        args = [str(wheel) if a == "WHEEL" else a for a in args]
        refused([*args, "-o", out], out, name)
