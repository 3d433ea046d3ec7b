"""Distance to the out-of-roundness limit also in months of service where the scenario gives a daily
mileage (``[operation] daily_distance_km``; issue 22)."""

import pytest

import railwear
from railwear import results
from railwear.errors import ScenarioError
from railwear.scenario import scenario_hash


def test_the_limit_in_months_at_the_scenario_s_daily_mileage():
    ds = railwear.run(railwear.load_scenario("metro", ["operation.daily_distance_km=600",
                                                      "solver.peak_to_peak_limit_mm=0.05"]))
    run = results.summary(ds)["runs"][0]
    assert run["limit_months"] == pytest.approx(run["limit_distance_km"] / 600 / (365.25 / 12), rel=1e-12)
    text = results.summary_text(results.summary(ds))
    assert f"{run['limit_months']:.1f} months at 600 km a day" in text


def test_without_a_daily_mileage_no_months_and_the_built_in_is_the_same_scenario():
    scenario = railwear.load_scenario("metro")
    assert scenario.operation.daily_distance_km is None
    assert scenario_hash(scenario) == "81ff3b9629ebc6e8ba258436b5ba02648541e629e1dbd215ab8aa5accb3a451c"
    with pytest.raises(ScenarioError, match="daily_distance_km"):
        railwear.load_scenario("metro", ["operation.daily_distance_km=0"])
