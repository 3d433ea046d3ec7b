"""Every run says what its model was validated against, and warns (ScopeWarning, a result
attribute) when the case lies outside it: speed, braking, a polygon too short for steady creep."""

import warnings

import pytest

import railwear
from railwear.errors import ScopeWarning
from railwear.scenario import load_scenario


def run(name, sets=()):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        ds = railwear.run(load_scenario(name, list(sets)))
    return ds, [str(w.message) for w in caught if issubclass(w.category, ScopeWarning)]


def test_the_metro_case_is_inside_its_validation():
    ds, notes = run("metro")
    assert "orders 6-9" in ds.attrs["validated_against"] and notes == [] and "outside_validation" not in ds.attrs


@pytest.mark.parametrize("sets, words", [
    (["operation.speed_kmh=300"], "high-speed polygons (orders 18-26 at 250-350 km/h) are not reproduced"),
    (["contact.traction_coefficient=-0.05"], "braking over 100% of the distance"),
])
def test_a_metro_wheel_outside_its_validation_is_warned(sets, words):
    ds, notes = run("metro", sets)
    assert any(words in n for n in notes) and words in ds.attrs["outside_validation"]


def test_the_paper_scenarios_say_they_hold_against_the_paper_only():
    ds, _ = run("stable")
    assert "no field observations" in ds.attrs["validated_against"]
