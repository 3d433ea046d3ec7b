"""Flange parameters (EN 15313) of S1002, of a uniformly worn S1002, and in the wheelset's result."""

import numpy as np
import pytest

from railwear.errors import ScenarioError
from railwear.geometry import circular_profile, load_profile, worn_profile
from railwear.geometry.flange import flange_parameters


def test_new_s1002_has_its_nominal_flange_within_0_1_mm():
    """EN 13715 designation h28 e32.5: Sh 28 mm, Sd 32.5 mm; qR of the new profile about 10.8 mm."""
    f = flange_parameters(load_profile("S1002"))
    assert f.height == pytest.approx(0.028, abs=1e-4)
    assert f.thickness == pytest.approx(0.0325, abs=1e-4)
    assert f.gradient == pytest.approx(0.0108, abs=1e-4)


def test_a_tread_worn_evenly_raises_the_flange_by_the_depth_and_keeps_its_thickness():
    """A depth d removed evenly from y = -45 mm outwards (the flank below Sd's height and the tread,
    not the tip): Sh grows by d, Sd and qR are unchanged (the flank moves down with the tape circle)."""
    new = load_profile("S1002")
    d = 0.5e-3
    worn = worn_profile(new, lambda y: np.where(y > -0.045, -d, 0.0))
    a, b = flange_parameters(new), flange_parameters(worn)
    assert b.height - a.height == pytest.approx(d, abs=1e-9)
    assert b.thickness == pytest.approx(a.thickness, abs=1e-9)
    assert b.gradient == pytest.approx(a.gradient, abs=1e-9)


def test_a_rail_or_a_profile_without_a_flange_is_refused():
    with pytest.raises(ScenarioError, match="wheel"):
        flange_parameters(load_profile("UIC60"))
    with pytest.raises(ScenarioError, match="must reach"):
        flange_parameters(circular_profile(0.5, kind="wheel"))
