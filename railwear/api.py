"""The public entry points: a scenario in, an ``xarray.Dataset`` out (layer 4)."""

from railwear.scenario import load_scenario, scenario_hash, to_toml
from railwear.scenario import build
from railwear.checkpoints import Periodic

__all__ = ["load_scenario", "run", "simulate", "speed_coordinates"]

SPEED_KMH_DECIMALS = 6  # km/h written beside m/s: 100 km/h reads 100, not 99.99999999999999


def speed_coordinates(ds, speed_m_s=None, dim=None):
    """``ds`` with the speed convention of every file railwear writes: ``speed`` in m s-1 as the
    coordinate and ``speed_kmh`` in km h-1 beside it, on the same dimensions. ``speed_m_s`` (on
    ``dim``, or a scalar) is given where ``ds`` has no ``speed`` yet."""
    import numpy as np

    from railwear.units import m_s_to_kmh

    if speed_m_s is not None:
        ds = ds.assign_coords(speed=((dim,) if dim else (), np.asarray(speed_m_s, float),
                                     {"units": "m s-1", "long_name": "vehicle speed"}))
    if "speed" not in ds.coords:
        return ds
    speed = ds.coords["speed"]
    if speed.attrs.get("units") != "m s-1":
        raise ValueError(f"speed: expected a coordinate in m s-1, got {speed.attrs.get('units')!r}")
    kmh = np.round(m_s_to_kmh(np.asarray(speed.values, float)), SPEED_KMH_DECIMALS)
    return ds.assign_coords(speed_kmh=(speed.dims, kmh, {"units": "km h-1", "long_name": "vehicle speed"}))


def demand_attributes(scenario):
    """The longitudinal demand a run states: the signed mean creep force over the wheel load
    (distance-weighted over a duty cycle; > 0 traction, < 0 braking), the share of the distance
    run braking and the cycle in words; nothing for a body that carries no demand."""
    if not scenario.body.longitudinal_demand:
        return {}
    duty = scenario.operation.duty()
    if duty is None:
        f = scenario.contact.traction_coefficient
        kind = "traction" if f > 0 else "braking" if f < 0 else "no longitudinal demand"
        return {"mean_traction_coefficient": f, "braking_share": float(f < 0),
                "duty_cycle": f"one operating point: creep force {f:+.4g} x wheel load ({kind})"}
    return {"mean_traction_coefficient": duty.mean_traction_coefficient, "braking_share": duty.braking_share,
            "duty_cycle": duty.describe()}


def run(scenario=None, progress=None, checkpoint_path=None, checkpoint_every=30.0, resume_path=None):
    """Run a scenario (a :class:`~railwear.scenario.schema.Scenario`, a file or a built-in name).

    Returns the solution with its spectrum (with ``[body] kind = "wheelset"``: the worn
    lateral profile over distance and the angular pattern, from the new profile), the resolved
    scenario as TOML, its hash and the package version in the attributes. ``progress`` is called with the fraction done. With
    ``checkpoint_path`` the state is saved there at most every ``checkpoint_every`` seconds of
    wall time; ``resume_path`` continues from such a file (the scenario is then taken from it when
    ``scenario`` is None) to the same result, bit for bit, as an uninterrupted run.
    """
    from railwear import __version__, results
    from railwear.errors import ScenarioError
    from railwear.longterm.base import check_result
    from railwear.units import MM
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
        toml, digest = to_toml(scenario), scenario_hash(scenario)
        save = Periodic(lambda state: results.write_checkpoint(checkpoint_path, state, toml, digest), checkpoint_every)

    solver = scenario.solver
    strategy = build.strategy(scenario)
    depth = None if solver.depth_limit_mm is None else solver.depth_limit_mm * MM
    ds = strategy.run(build.initial_wear(scenario), until=solver.t_end, depth_limit=depth,
                      progress=progress, checkpoint=save, resume=resume)
    ds.attrs.update({
        "title": f"railwear: {scenario.name}",
        "scenario_name": scenario.name,
        "scenario": to_toml(scenario),
        "scenario_hash": scenario_hash(scenario),
        "railwear_version": __version__,
        "Conventions": "CF-1.10",
        "life_distance_km": scenario.operation.life_distance_km,
    })
    ds["nominal_radius"] = ((), scenario.wheel.radius_m, {"units": "m", "long_name": "nominal rolling radius"})
    ds = results.with_wheel_regime(ds)  # the wheel's regime, from growth per distance (docs/outputs.md)
    ds.attrs.update(demand_attributes(scenario))
    ds.attrs["validated_against"] = scenario.strategy.validated_against or scenario.body.validated_against
    outside = [] if scenario.strategy.needs is None else scenario.body.scope(scenario, ds)
    if outside:
        import warnings

        from railwear.errors import ScopeWarning

        ds.attrs["outside_validation"] = "; ".join(outside)
        for note in outside:
            warnings.warn(f"outside what the model was validated against: {note}", ScopeWarning, stacklevel=2)
    return check_result(speed_coordinates(ds))


def simulate(scenario, progress=None):
    """Run a dynamics scenario (:mod:`railwear.scenario.dynamics`) at each of its speeds.

    Wheelset and disk wheel: the time histories over (``speed``, ``time``). The bogie: the
    limit-cycle amplitude of a ramp down over the speeds, with its Hopf point and nonlinear
    critical speed (m/s) in the attributes.
    """
    import numpy as np
    import xarray as xr

    from railwear import __version__
    from railwear.dynamics import critical_speed
    from railwear.dynamics import simulate as run_model
    from railwear.dynamics.bifurcation import ramp_down
    from railwear.scenario import dynamics
    from railwear.units import kmh_to_m_s, m_s_to_kmh

    if not isinstance(scenario, dynamics.DynamicsScenario):
        scenario = dynamics.load_dynamics_scenario(scenario)
    speeds = kmh_to_m_s(np.array(scenario.run.speeds_kmh))
    attrs = {"scenario_name": scenario.name, "railwear_version": __version__,
             "title": f"railwear: {scenario.name}"}
    if scenario.model.kind == "cooperrider":
        descending = np.sort(speeds)[::-1]
        branch = ramp_down(dynamics.build(scenario, descending[0]), descending)
        hopf = critical_speed(dynamics.build(scenario, descending[0]))
        ds = xr.Dataset(
            {"amplitude": ("speed", branch.amplitudes, {"units": "m", "long_name": "limit-cycle amplitude of the leading wheelset"})},
            coords={"speed": ("speed", branch.speeds, {"units": "m s-1", "long_name": "vehicle speed"})})
        attrs.update(hopf_speed=float(hopf), nonlinear_critical_speed=float(branch.nonlinear_critical_speed))
    else:
        runs = []
        for i, v in enumerate(speeds):
            # progress inside each run, read from the compiled loop (the numbers of a run without)
            inside = lambda f, i=i: progress((i + f) / speeds.size) if progress is not None else None  # noqa: E731
            runs.append(run_model(dynamics.build(scenario, v), scenario.run.duration_s,
                                  n_output=scenario.run.n_output, progress=inside))
        ds = xr.concat(runs, dim="speed", combine_attrs="drop_conflicts").assign_coords(
            speed=("speed", speeds, {"units": "m s-1", "long_name": "vehicle speed"}))
        if scenario.model.kind == "wheelset":
            attrs["linear_critical_speed_kmh"] = m_s_to_kmh(float(critical_speed(dynamics.build(scenario, speeds[0]))))
    ds.attrs.update(attrs)
    return speed_coordinates(ds)
