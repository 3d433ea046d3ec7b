"""Summary lines that hold at the edges (issue 22, item 2): a wheel worn round, a stable wheel, an
eccentric one, an order grown from round-off, a rate within its standard error, a limit the wheel
starts past; summary.json stays strict JSON throughout."""

import json
import re

import numpy as np
import pytest
import xarray as xr
from typer.testing import CliRunner

import railwear
from railwear import results
from railwear.cli import app

NAN = re.compile(r"\b(nan|inf)\b|xnan|-0%|order-1 polygon|\b1 maxima\b", flags=re.I)


def lines_of(name, *sets):
    """The summary lines of a built-in run with ``--set`` fields, checked strict: no NaN in the
    JSON, none of the broken wordings in the text."""
    ds = railwear.run(railwear.load_scenario(name, list(sets)))
    s = results.summary(ds)
    json.loads(json.dumps(s, allow_nan=False), parse_constant=lambda c: pytest.fail(f"summary holds {c}"))
    text = results.summary_text(s)
    assert not NAN.search(text), NAN.findall(text)
    return s["runs"][0], text


# case: (scenario and fields, words the summary must say, words it must not say)
CASES = {
    "worn round": (("stable", "initial.kind=round"),
                   ["round at the end", "no dominant order, no maxima", "round at the start"],
                   ["maxima,", "dominant order 1", "polygon"]),
    "stable": (("stable",), ["5 maxima, dominant order 2", "order-2 polygon", "-0.24% per 10 000 km"], []),
    "eccentric": (("stable", "initial.kind=harmonics", "initial.orders=[1]", "initial.amplitudes_um=[20]"),
                  ["1 maximum, dominant order 1 (eccentricity)", "eccentricity (order 1): once per revolution",
                   "-0.050% per 10 000 km"], ["polygon"]),
    "order from round-off": (("onset",),
                             ["dominant order 1 (eccentricity)", "fastest order present at the start 4",
                              "+132% per 10 000 km)",
                              "growth per 10 000 km not meaningful: order 1 grew from round-off (2.4e-21 m at the "
                              "start, under 1e-9 of the largest amplitude then)"],
                             ["+518%"]),
    "metro (README)": (("metro",), ["order-8 polygon: wavelength 330 mm on the tread, passing at 58.9 Hz, +20% per "
                                    "10 000 km", "out-of-roundness limit 0.1 mm peak to peak: reached after 173,878 km"],
                       []),
}


@pytest.mark.parametrize("case", list(CASES))
def test_summary_line_at_the_edge(case):
    fields, said, unsaid = CASES[case]
    run, text = lines_of(*fields)
    for words in said:
        assert words in text, (words, text)
    for words in unsaid:
        assert words not in text, (words, text)


def test_a_round_wheel_has_no_dominant_order_in_the_json():
    run, _ = lines_of("stable", "initial.kind=round")
    assert run["round"] and run["round_at_start"]
    assert "dominant_order" not in run and "maxima" not in run
    assert {"dominant_order", "maxima"} <= set(run["undefined"])
    assert "round at the end" in run["undefined_because"]["dominant_order"]


def test_a_rate_from_round_off_is_left_out_with_its_reason():
    run, _ = lines_of("onset")
    assert "dominant_growth_per_10000_km" not in run
    assert run["undefined_because"]["dominant_growth_per_10000_km"].startswith("not meaningful: order 1 grew from round-off")
    assert run["leading_growth_per_10000_km"] == pytest.approx(1.3169, abs=1e-4)


def _fitted(rate, error, start=(1e-5, 1e-5)):
    """A run of two orders whose first has the fitted ``rate`` and ``error`` (per unit time)."""
    order = [1, 2]
    return xr.Dataset({"growth_rate": ("order", [rate, 0.0]), "growth_rate_error": ("order", [error, 0.0]),
                       "amplitude_initial": ("order", list(start))}, coords={"order": order})


@pytest.mark.parametrize("rate, error, start, note", [
    (0.5, 0.1, (1e-5, 1e-5), None),
    (0.5, 0.5, (1e-5, 1e-5), "undefined: the standard error of its rate (0.5) is as large as the rate (0.5)"),
    (-0.2, 0.3, (1e-5, 1e-5), "undefined: the standard error"),
    (0.5, 0.1, (1e-15, 1e-5), "not meaningful: order 1 grew from round-off (1e-15 m"),
    (0.5, 0.1, (0.0, 1e-5), "not meaningful: order 1 grew from round-off (0 m"),
    (np.nan, np.nan, (1e-5, 1e-5), "undefined: no fitted rate"),
])
def test_growth_note(rate, error, start, note):
    said = results.growth_note(_fitted(rate, error, start), 1)
    assert said is None if note is None else said.startswith(note), said


@pytest.mark.parametrize("fraction, text", [
    (0.2, "+20%"), (1.3169, "+132%"), (0.0466, "+4.7%"), (-0.0024, "-0.24%"), (-0.000499, "-0.050%"),
    (0.0, "0%"), (-1e-7, "-0.000010%"), (5.18, "+518%"), (0.096, "+9.6%"), (0.0996, "+10%"),
])
def test_percent_never_prints_minus_zero(fraction, text):
    assert results.percent(fraction) == text


@pytest.mark.parametrize("count, text", [(0, "0 maxima"), (1, "1 maximum"), (8, "8 maxima")])
def test_plural(count, text):
    assert results.plural(count, "maximum", "maxima") == text


def test_a_limit_passed_at_the_start_is_refused_naming_the_field(tmp_path):
    """Limit reached at 0 km: the run is refused before it starts (exit 2), naming the field."""
    done = CliRunner().invoke(app, ["run", "metro", "-o", str(tmp_path), "--set", "solver.peak_to_peak_limit_mm=0.01"])
    assert done.exit_code == 2
    assert "solver.peak_to_peak_limit_mm: the wheel starts 0.04419 mm out of round, above the limit 0.01 mm" in done.stderr
