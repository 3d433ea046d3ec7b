"""The multiplier's refusal of a start at or over the peak-to-peak limit, worded as the Fourier
technique's (tests/longterm/test_fourier_limit_start.py): the excess named, the limit reached at
0 km. A start within round-off of 0.1 mm prints as 0.1 mm at 4 digits, so before the excess was
named it read "0.1 against 0.1". One ulp of a number in [2^-14, 2^-13) m (0.1 mm is one) is
2^-66 m = 1.36e-17 mm."""

import dataclasses
import subprocess
import sys

import numpy as np
import pytest

from railwear.errors import ScenarioError
from railwear.geometry import roundness
from railwear.pde.multiplier import solve_multiplier
from railwear.scenario import build, load_scenario
from railwear.units import MM

AT = r"at the limit 0\.1 mm: the limit is reached at 0 km, before the run starts$"
OVER = r"above the limit 0\.1 mm by 1\.36e-17 mm: the limit is reached at 0 km, before the run starts$"


def test_the_pde_stop_names_the_excess():
    """50 um of order 8 (0.1 mm peak to peak to round-off) against a limit equal to it and one ulp under it."""
    u0 = roundness.harmonics(32, [8], np.array([50e-6]))
    start = np.ptp(u0)
    assert abs(start - 0.1 * MM) < 1e-18
    rate = np.zeros(17)
    with pytest.raises(ScenarioError, match=r"^peak_to_peak_limit: the wheel starts 0\.1 mm out of round, " + AT):
        solve_multiplier(u0, 1.0, rate, peak_to_peak_limit=start)
    with pytest.raises(ScenarioError, match=r"^peak_to_peak_limit: the wheel starts 0\.1 mm out of round, " + OVER):
        solve_multiplier(u0, 1.0, rate, peak_to_peak_limit=np.nextafter(start, 0.0))


def test_the_multiplier_strategy_names_the_excess():
    """The metro multiplier, its start rescaled to 0.1 mm peak to peak, against a limit equal to it
    and one ulp under it."""
    scenario = load_scenario("metro", ["strategy.kind=multiplier"])
    technique = build.strategy(scenario)
    u0 = build.initial_wear(scenario)
    u0 = u0 * (0.1 * MM / np.ptp(u0))
    start = np.ptp(u0)
    assert abs(start - 0.1 * MM) < 1e-18
    field = r"^solver\.peak_to_peak_limit_mm: the wheel starts 0\.1 mm out of round, "
    with pytest.raises(ScenarioError, match=field + AT):
        dataclasses.replace(technique, peak_to_peak_limit=start).run(u0)
    with pytest.raises(ScenarioError, match=field + OVER):
        dataclasses.replace(technique, peak_to_peak_limit=np.nextafter(start, 0.0)).run(u0)


def test_railwear_run_says_by_how_much_the_start_is_over(tmp_path):
    """The metro start (44.19 um peak to peak) against 0.04 mm, in a fresh interpreter: exit 2, one
    line naming the field and the excess, no result written."""
    done = subprocess.run([sys.executable, "-m", "railwear", "run", "metro", "--set", "strategy.kind=multiplier",
                           "--set", "solver.peak_to_peak_limit_mm=0.04", "-o", str(tmp_path / "out")],
                          capture_output=True, text=True, timeout=120)
    assert done.returncode == 2 and "Traceback" not in done.stderr
    assert done.stderr.strip().count("\n") == 0
    assert ("solver.peak_to_peak_limit_mm: the wheel starts 0.04419 mm out of round, above the limit 0.04 mm by "
            "0.00419 mm: the limit is reached at 0 km, before the run starts") in done.stderr
    assert not (tmp_path / "out" / "result.nc").exists()
