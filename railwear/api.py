"""The public entry points: a scenario in, an ``xarray.Dataset`` out (layer 4)."""

import numpy as np

from railwear.longterm.phenomenological import Phenomenological
from railwear.scenario import load_scenario, scenario_hash, to_toml
from railwear.scenario import build

__all__ = ["load_scenario", "run"]


def run(scenario=None, progress=None):
    """Run a scenario (a :class:`~railwear.scenario.schema.Scenario`, a file or a built-in name).

    Returns the solution with its spectrum, the resolved scenario as TOML, its hash and the
    package version in the attributes. ``progress`` is called with the fraction done.
    """
    from railwear import __version__

    scenario = load_scenario(scenario)
    solver = scenario.solver
    speeds = scenario.operation.speeds
    strategy = Phenomenological(
        build.wear_rate(scenario), np.asarray(speeds, float), solver.epsilon, solver.nu,
        options={"n_save": solver.n_save, "dealias": solver.dealias, "dt": solver.dt})
    depth = None if solver.depth_limit_mm is None else solver.depth_limit_mm * 1e-3
    ds = strategy.run(build.initial_state(scenario), until=solver.t_end, depth_limit=depth,
                      progress=progress)
    life_km = scenario.operation.life_distance_km
    ds = ds.assign_coords(distance=("time", ds.time.values * life_km,
                                    {"units": "km", "long_name": "distance run"}))
    ds.attrs.update({
        "title": f"railwear: {scenario.name}",
        "scenario_name": scenario.name,
        "scenario": to_toml(scenario),
        "scenario_hash": scenario_hash(scenario),
        "railwear_version": __version__,
        "strategy": "phenomenological evolution equation (paper eq. 4)",
        "Conventions": "CF-1.10",
        "life_distance_km": life_km,
    })
    return ds
