"""The long-term contract holds for code from outside: a fifth strategy in two files
(example_frozen_strategy.py, example_frozen_section.py) run from a scenario on both bodies, and a
new body in two files (example_ring_body.py, example_ring_section.py) run by the stepwise and
direct strategies, from Python and from a scenario."""

import importlib

import numpy as np
import pytest

import railwear
from railwear.errors import ScenarioError
from railwear.longterm.base import Strategy, check_result
from railwear.longterm.direct import Direct
from railwear.longterm.stepwise import Stepwise
from railwear.scenario import build, load_scenario, parse_scenario, to_toml
from railwear.scenario.schema import BODY_SECTIONS, STRATEGY_SECTIONS


@pytest.fixture(scope="module")
def frozen_kind():
    section = importlib.import_module("example_frozen_section")
    yield section
    Strategy.registry.pop("frozen")
    STRATEGY_SECTIONS.pop("frozen")
    build.BUILDERS.pop("frozen")


def _as(name, **strategy):
    data = load_scenario(name).applicable()
    data["strategy"] = strategy
    import tomli_w

    return parse_scenario(tomli_w.dumps(data), source=name)


def test_a_fifth_strategy_runs_from_a_scenario_and_is_one_euler_step(frozen_kind):
    """``kind = "frozen"`` on the disk wheel: the same draws as a stepwise run whose step limit
    never binds (one Euler step to the end), so the same worn wheel to the bit; the result keeps
    the contract and the scenario round-trips."""
    sc = _as("stepwise", kind="frozen")
    assert parse_scenario(to_toml(sc)) == sc
    ds = railwear.run(sc)
    assert ds.attrs["strategy"] == "frozen" and ds.sizes["time"] == 2
    one_step = railwear.run(_as("stepwise", kind="stepwise", step_limit_um=1e6))
    np.testing.assert_array_equal(ds.u.values[-1], one_step.u.values[-1])
    assert float(ds.removed_depth[-1]) == pytest.approx(1e-3, rel=1e-9)
    with pytest.raises(ScenarioError, match="step_limit_um: does not apply to kind 'frozen'"):
        _as("stepwise", kind="frozen", step_limit_um=2.0)


def test_the_fifth_strategy_runs_on_the_wheelset_too(frozen_kind):
    data = load_scenario("wheelset-wear").applicable()
    data["strategy"] = {"kind": "frozen"}
    data["solver"]["t_end"] = 0.01
    import tomli_w

    ds = railwear.run(parse_scenario(tomli_w.dumps(data)))
    assert ds.attrs["body"] == "wheelset" and ds.u.dims == ("time", "wheel", "angle", "lateral")
    np.testing.assert_allclose(ds.removed_volume.values, ds.law_volume.values, rtol=1e-12)


def test_a_new_body_is_worn_by_both_strategies_to_its_closed_form():
    """The ring loses ``(m + a cos 6x) T``: the direct strategy reproduces it to round-off and
    stops on the depth limit exactly; the stepwise one within its Monte Carlo error."""
    from example_ring_body import Ring

    ring, u0 = Ring(), np.zeros(64)
    exact = ring.rate(64)
    direct = check_result(Direct(ring, 1.0, n_save=None).run(u0, until=0.5))
    assert direct.attrs["body"] == "ring" and float(direct.stop_time) == 0.5
    np.testing.assert_allclose(u0 - direct.u.values[-1], exact * 0.5, rtol=1e-12)
    limited = Direct(ring, 1.0, n_save=5).run(u0, until=1.0, depth_limit=1e-4)
    assert float(limited.removed_depth[-1]) == pytest.approx(1e-4, rel=1e-12)
    assert float(limited.stop_time) == pytest.approx(1e-4 / exact.max(), rel=1e-12)
    step = Stepwise(ring, 2e-5, seed=1).run(u0, until=0.5)
    worn = u0 - step.u.values[-1]
    assert np.max(np.abs(worn - exact * 0.5)) < 4 * float(step.u_standard_error[-1].max())
    np.testing.assert_allclose(step.removed_volume.values, step.law_volume.values, rtol=1e-12)
    assert int(step.dominant_order) == 6


RING = """
name = "ring"

[strategy]
kind = "direct"
acceleration_factor = 1.0

[body]
kind = "ring"
order = 5

[solver]
points = 64
t_end = 0.5
depth_limit_mm = 10.0

[initial]
kind = "round"
"""


@pytest.fixture(scope="module")
def ring_kind():
    section = importlib.import_module("example_ring_section")
    yield section
    BODY_SECTIONS.pop("ring")


def test_a_new_body_runs_from_a_scenario_with_its_section(ring_kind):
    """``[body] kind = "ring"``: the direct strategy wears the closed form to round-off, the
    scenario round-trips, a field the ring has not is refused naming it, and a strategy that
    needs what the ring does not give is refused naming ``body.kind``."""
    sc = parse_scenario(RING)
    assert parse_scenario(to_toml(sc)) == sc
    ds = railwear.run(sc)
    assert ds.attrs["body"] == "ring" and float(ds.stop_time) == 0.5
    exact = ring_kind.Ring(order=5).rate(64)
    np.testing.assert_allclose(-ds.u.values[-1], exact * 0.5, rtol=1e-12)
    step = railwear.run(load_scenario(sc, ["strategy.kind=stepwise", "strategy.step_limit_um=20"]))
    assert step.attrs["strategy"] == "stepwise" and int(step.dominant_order) == 5
    with pytest.raises(ScenarioError, match="body.rail_mass_kg: does not apply to kind 'ring'"):
        parse_scenario(RING.replace("order = 5", "order = 5\nrail_mass_kg = 1.0"))
    with pytest.raises(ScenarioError, match="body.kind: the fourier strategy needs a linear model"):
        load_scenario(sc, ["strategy.kind=fourier"])
