"""The long-term contracts fail early: a stepped strategy or a body that lacks a member is
refused when it is defined or constructed, naming the member; lookups by name see every
built-in piece in a fresh interpreter."""

import json
import subprocess
import sys

import pytest

from railwear.longterm.base import RadiusBody, Strategy


def test_a_stepped_strategy_without_monte_carlo_or_attributes_is_refused_when_defined():
    with pytest.raises(TypeError, match="monte_carlo"):
        class NoMonteCarlo(Strategy):
            def run(self, u0=None, until=1.0, depth_limit=None, progress=None, checkpoint=None, resume=None):
                return None  # never called: the class is refused when it is defined

            def advance(self, body, state, until):
                return None

            def attributes(self, state):
                return {}

    with pytest.raises(TypeError, match="attributes"):
        class NoAttributes(Strategy):
            monte_carlo = False

            def run(self, u0=None, until=1.0, depth_limit=None, progress=None, checkpoint=None, resume=None):
                return None  # never called: the class is refused when it is defined

            def advance(self, body, state, until):
                return None
    assert "NoMonteCarlo" not in {c.__name__ for c in Strategy.registry.values()}


def test_a_body_without_a_member_fails_at_construction_naming_it():
    class Half(RadiusBody):
        def new_cost(self):
            return {}

    with pytest.raises(TypeError, match="rates"):
        Half()


def test_builtin_strategies_and_bodies_are_found_by_name_in_a_fresh_interpreter():
    """Nothing but the lookup is imported first (the registry once depended on import order)."""
    code = ("import json; from railwear.longterm.base import bodies, strategies; "
            "print(json.dumps([sorted(strategies()), {k: v.__name__ for k, v in bodies().items()}]))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    names, found = json.loads(out)
    assert names == ["direct", "fourier", "multiplier", "phenomenological", "stepwise"]
    assert found == {"disk_wheel": "DiskWheel", "vehicle_track": "VehicleTrackBody", "wheelset": "Wheelset"}
