"""The public entry points: a scenario in, an ``xarray.Dataset`` out (layer 4)."""

from railwear.scenario import load_scenario, scenario_hash, to_toml
from railwear.scenario import build

__all__ = ["load_scenario", "run"]


def run(scenario=None, progress=None, checkpoint_path=None, checkpoint_every=30.0, resume_path=None):
    """Run a scenario (a :class:`~railwear.scenario.schema.Scenario`, a file or a built-in name).

    Returns the solution with its spectrum, the resolved scenario as TOML, its hash and the
    package version in the attributes. ``progress`` is called with the fraction done. With
    ``checkpoint_path`` the state is saved there at most every ``checkpoint_every`` seconds of
    wall time; ``resume_path`` continues from such a file (the scenario is then taken from it when
    ``scenario`` is None) to the same result, bit for bit, as an uninterrupted run.
    """
    import time

    from railwear import __version__, results
    from railwear.errors import ScenarioError
    from railwear.scenario import parse_scenario

    resume = None
    if resume_path is not None:
        resume, toml, digest = results.read_checkpoint(resume_path)
        scenario = parse_scenario(toml, source=str(resume_path)) if scenario is None else load_scenario(scenario)
        if scenario_hash(scenario) != digest:
            raise ScenarioError(f"resume: {resume_path} was written for another scenario")
    scenario = load_scenario(scenario)
    save = None
    if checkpoint_path is not None:
        toml, digest, last = to_toml(scenario), scenario_hash(scenario), [time.monotonic()]

        def save(state):
            if time.monotonic() - last[0] >= checkpoint_every:
                results.write_checkpoint(checkpoint_path, state, toml, digest)
                last[0] = time.monotonic()

    solver = scenario.solver
    strategy = build.strategy(scenario)
    depth = None if solver.depth_limit_mm is None else solver.depth_limit_mm * 1e-3
    ds = strategy.run(build.initial_state(scenario), until=solver.t_end, depth_limit=depth,
                      progress=progress, checkpoint=save, resume=resume)
    life_km = scenario.operation.life_distance_km
    ds = ds.assign_coords(distance=("time", ds.time.values * life_km,
                                    {"units": "km", "long_name": "distance run"}))
    ds.attrs.update({
        "title": f"railwear: {scenario.name}",
        "scenario_name": scenario.name,
        "scenario": to_toml(scenario),
        "scenario_hash": scenario_hash(scenario),
        "railwear_version": __version__,
        "strategy": scenario.strategy.kind,
        "Conventions": "CF-1.10",
        "life_distance_km": life_km,
    })
    return ds
