"""Strategies 1 and 3 from scenario files: the built-in scenarios, the command line, bad input."""

import numpy as np
import pytest
from typer.testing import CliRunner

import railwear
from railwear.cli import app
from railwear.errors import ScenarioError
from railwear.scenario import builtin_text, parse_scenario


def edited(name, old, new):
    text = builtin_text(name)
    assert old in text
    return parse_scenario(text.replace(old, new), source=f"{name}.toml")


def test_builtin_stepwise_and_direct_agree_on_the_p2_order():
    step, direct = railwear.run("stepwise"), railwear.run("direct")
    assert step.attrs["strategy"] == "stepwise" and direct.attrs["strategy"] == "direct"
    for ds in (step, direct):
        assert float(ds.removed_depth[-1]) == pytest.approx(1e-3, rel=1e-9)
        # the order passing the P2 resonance (47 Hz) at 70 km/h: n V / (2 pi R0) just above it
        assert int(ds.dominant_order) == 8
    # the same wheel in service near 70 km/h: the same life to 1 mm within a percent
    assert float(step.stop_time) == pytest.approx(float(direct.stop_time), rel=1e-2)
    assert np.all(step.u_standard_error.values >= 0)


@pytest.mark.parametrize("old, new, field", [
    ("step_limit_um = 25.0", "step_limit_um = 0.0", "strategy.step_limit_um"),
    ("step_limit_um = 25.0", "step_limit_um = -5.0", "strategy.step_limit_um"),
    ("speed_weights = [0.25, 0.5, 0.25]", "speed_weights = [0.25, 0.5, 0.3]", "service"),
    ("samples = 2", "samples = 1", "body.samples"),
])
def test_bad_stepwise_input_is_refused_before_any_run(old, new, field):
    with pytest.raises(ScenarioError, match=field.replace(".", r"\.")):
        edited("stepwise", old, new)


def test_an_acceleration_factor_below_one_is_refused():
    with pytest.raises(ScenarioError, match=r"strategy\.acceleration_factor"):
        edited("direct", "acceleration_factor = 20000.0", "acceleration_factor = 0.5")


def test_direct_takes_one_speed():
    from railwear.scenario import build

    sc = edited("direct", "speed_kmh = 70.0", "speed_kmh = [60.0, 70.0]")
    with pytest.raises(ScenarioError, match="one speed"):
        build.strategy(sc)


def test_cli_runs_the_stepwise_scenario(tmp_path):
    result = CliRunner().invoke(app, ["run", "stepwise", "-o", str(tmp_path)])
    assert result.exit_code == 0, result.output
    assert (tmp_path / "summary.txt").read_text().count("dominant order 8") == 1


def test_fit_writes_a_phenomenological_scenario_that_runs(tmp_path):
    """Strategy 4 end to end: frozen-geometry statistics at two speeds, the fitted table in a
    scenario, and the evolution equation run from it to 1 mm."""
    from railwear.pde import Table
    from railwear.scenario import build, load_scenario

    result = CliRunner().invoke(app, ["fit", "stepwise", "--speeds", "60,80", "-o", str(tmp_path)])
    assert result.exit_code == 0, result.output
    sc = load_scenario(tmp_path / "fitted-h.toml")
    assert sc.strategy.kind == "phenomenological" and sc.wear_rate.form == "table"
    h = build.wear_rate(sc)
    assert isinstance(h, Table) and h.rate.shape == (33, 2)
    np.testing.assert_allclose(h.speed * 3.6, [60.0, 80.0])
    ds = railwear.run(sc)
    assert float(ds.removed_depth[-1]) == pytest.approx(1e-3, rel=1e-9)
    # wear everywhere: the table's rates are negative over the fitted range
    assert np.all(h.rate < 0)
