"""Analyses of a scenario besides a run: the stability map, strategy 4's fit of ``h`` and the
paper's frozen-geometry figures (layer 4). Each builds the models with :mod:`railwear.scenario.build`
and calls one solver; ``railwear stability``, ``railwear fit`` and ``railwear figure`` print and
write what these return.
"""

from typing import Any, NamedTuple

import numpy as np

from railwear.errors import ScenarioError
from railwear.units import UM, kmh_to_m_s, m_s_to_kmh

FIGURES = ("wear-surface", "teeth", "fitted-h")  # paper Figs 4, 7 and 8
WEAR_SURFACE_CELLS = (60, 720)  # Fig. 4's angle cells: panels longer than the patch, and fine enough for it
TEETH_DRAWS = 48  # Fig. 7's Monte Carlo draws of speed and phase from the [service] distribution
FIT_SCALES = (0.5, 1.0, 1.5, 2.0)  # build.fitted_h's default scales of the initial wheel
FIT_DEFAULT = "stepwise"  # the built-in disk-wheel scenario of the frozen-geometry strategies
SPEEDS_KMH = tuple(range(20, 301, 10))  # the stability map's default speeds (km/h)
ORDERS = tuple(range(1, 31))  # and polygon orders


def _speeds_m_s(speeds_kmh, field="speeds_kmh"):
    v = np.atleast_1d(np.asarray(speeds_kmh, float))
    if v.ndim != 1 or v.size == 0 or not np.all(np.isfinite(v)) or v.min() <= 0:
        raise ScenarioError(f"{field}: expected speeds > 0 (km/h), got {speeds_kmh!r}")
    return kmh_to_m_s(v)


def stability(scenario=None, speeds_kmh=SPEEDS_KMH, orders=ORDERS, amplitude=None):
    """Growth rate over speed × polygon order; the ``speed`` coordinate is in m/s.

    With a strategy on the body's linear model (Fourier, multiplier) from the transfer functions
    of its body, the disk wheel or the wheel on the track (per km run),
    else from the evolution equation's dispersion relation (per unit normed time) with the slope
    frozen at the crest of ``amplitude`` (m; default the scenario's initial rms, 0 the round
    wheel; the Fourier technique ignores it). Attributes: ``scenario_name``, ``scenario_hash``
    and ``source``, a label for people.
    """
    from railwear.api import speed_coordinates
    from railwear.scenario import build, load_scenario, scenario_hash

    v = _speeds_m_s(speeds_kmh)
    n = np.atleast_1d(np.asarray(orders, float))
    if n.ndim != 1 or n.size == 0 or not np.all(n == np.round(n)) or n.min() < 1:
        raise ScenarioError(f"orders: expected whole numbers >= 1, got {orders!r}")
    if amplitude is not None and not amplitude >= 0:
        raise ScenarioError(f"amplitude: must be >= 0 (m), got {amplitude!r}")
    sc = load_scenario(scenario)
    duty = sc.operation.duty()
    if sc.strategy.needs == "linear_model" and duty is not None:
        ds = _cycle_map(sc, duty, v, n.astype(int))
        label = (f"{sc.body.label} (Fourier technique), the duty cycle's demands at each speed: mean creep "
                 f"force {duty.mean_traction_coefficient:+.3f} x load, braking {duty.braking_share:.0%}")
    elif sc.strategy.needs == "linear_model":
        ds = sc.body.growth_map(sc, v, n.astype(int))
        f = sc.contact.traction_coefficient
        label = f"{sc.body.label} (Fourier technique), creep force {f:+.3g} x load"
    else:
        from railwear.pde import stability_map

        a = sc.initial.rms_um * UM if amplitude is None else float(amplitude)
        ds = stability_map(build.wear_rate(sc), v, n, sc.solver.epsilon, sc.solver.nu, a)
        label = f"evolution equation, crest amplitude {a / UM:g} µm"
    if getattr(sc.body, "several_wheels", False):
        positions = ", ".join(f"{x:g}" for x in sc.body.wheel_positions_m)
        label += f"; the fastest combination of the wheels at {positions} m"
    ds.attrs.update(scenario_name=sc.name, scenario_hash=scenario_hash(sc), source=label)
    return speed_coordinates(ds)


def _cycle_map(sc, duty, speeds, orders):
    """The body's growth map (1/km) at each speed averaged over the duty cycle's demands by their
    shares of the distance (the per-metre mean, as :class:`~railwear.longterm.fourier.FourierCycle`
    takes it at one speed); one map per distinct demand."""
    from railwear.scenario import build

    weights = {}
    for share, demand in zip(duty.shares, duty.demands):
        weights[float(demand)] = weights.get(float(demand), 0.0) + float(share)
    maps = [(w, sc.body.growth_map(build.at_demand(sc, f), speeds, orders)) for f, w in weights.items()]
    ds = maps[0][1]
    ds["growth_rate"] = sum(w * m.growth_rate for w, m in maps).assign_attrs(ds.growth_rate.attrs)
    ds.attrs.update(mean_traction_coefficient=duty.mean_traction_coefficient, braking_share=duty.braking_share)
    return ds


class FitResult(NamedTuple):
    """Strategy 4's fit: the frozen-geometry statistics, the fitted ``h``
    (:class:`railwear.longterm.fitting.Fit`) and the scenario that runs with it."""

    statistics: Any
    fit: Any
    scenario: Any


def fit(scenario=None, speeds_kmh=None):
    """Fit ``h(u_xx, v)`` to frozen-geometry statistics of a disk-wheel scenario (default the
    built-in 'stepwise') at ``speeds_kmh`` (default the ``[service]`` peaks, paper Fig. 8); the
    returned scenario has it as its ``[wear_rate]`` table and the phenomenological strategy."""
    from railwear.scenario import build, load_scenario

    v = None if speeds_kmh is None else _speeds_m_s(speeds_kmh)
    sc = load_scenario(FIT_DEFAULT if scenario is None else scenario)
    stats, fitted = build.fitted_h(sc, v)
    return FitResult(stats, fitted, build.with_fitted_h(sc, fitted))


def _rigid_h(sc):
    """The scenario's disk_contact ``h`` (the rigid disk wheel's), or None for another form or law."""
    from railwear.scenario import build

    if sc.wear_rate.form != "disk_contact":
        return None
    try:
        return build.wear_rate(sc)
    except ScenarioError:  # derived for the energy law only
        return None


def _turning_speed(sc, speed):
    """The speed (m/s, a multiple of 10 km/h above ``speed``) at which the rigid disk wheel's crest
    curvature ``u_c`` (``DiskContact.crest_curvature``) reaches half the most negative curvature of
    Fig. 8's geometries: there the derived ``h`` has its falling branch inside the sampled range."""
    from railwear.longterm.fitting import curvature
    from railwear.pde import DiskContact
    from railwear.scenario import build

    h = _rigid_h(sc)
    if not isinstance(h, DiskContact):
        return 2 * speed
    deepest = 0.5 * float(np.min(curvature(build.initial_state(sc) * FIT_SCALES[-1])))
    v = h.wheel_radius * np.sqrt((h.static_load - h.saturation_load) / (h.unsprung_mass * -deepest))
    return kmh_to_m_s(max(10 * np.ceil(m_s_to_kmh(v) / 10), 10 * np.ceil(m_s_to_kmh(speed) / 10) + 10))


class PaperFigure(NamedTuple):
    """A figure and what it shows: the wear-intensity Dataset ('teeth'), the
    :class:`~railwear.geometry.wear_surface.WearSurface` ('wear-surface') or the statistics and
    the fit ('fitted-h')."""

    data: Any
    figure: Any


def figure(name, scenario=None):
    """One of the paper's frozen-geometry figures at the mean service speed of a disk-wheel
    scenario (default the built-in 'stepwise'): 'wear-surface' (Fig. 4, the depth of 12 turns with
    the Hertz patch against the cells), 'teeth' (Fig. 7, 12 turns) or 'fitted-h' (Fig. 8)."""
    from railwear import plots
    from railwear.scenario import build, load_scenario

    if name not in FIGURES:
        raise ScenarioError(f"figure: unknown name {name!r}; use wear-surface, teeth or fitted-h")
    sc = load_scenario(FIT_DEFAULT if scenario is None else scenario)
    speed = build.service_speeds(sc).mean
    if name == "fitted-h":
        speeds = [speed, _turning_speed(sc, speed)]
        data = build.fitted_h(sc, speeds, scales=FIT_SCALES)
        reference = _rigid_h(sc)
        return PaperFigure(data, plots.fitted_relation(*data, reference=reference))
    model, beta, band = build.disk_wheel_model(sc, speed), build.wear_law(sc).beta, build.band_width(sc)
    if beta is None:
        raise ScenarioError(f"wear.law: the paper's frozen-geometry figures use the energy law, not {sc.wear.law!r}")
    u0 = build.initial_state(sc)
    if name == "teeth":
        from railwear.longterm.disk_wheel import wear_intensity

        data = wear_intensity(model, u0, beta, band, turns=12)
        rng = np.random.default_rng(sc.service.seed)
        speeds = build.service_speeds(sc).sample(rng, TEETH_DRAWS)
        phases = rng.uniform(0.0, 2 * np.pi, TEETH_DRAWS)
        teeth = [wear_intensity(build.disk_wheel_model(sc, v), u0, beta, band, turns=3, phase=p).tooth_depth.values[1]
                 for v, p in zip(speeds, phases)]  # the second pass: whole, after the start
        data = data.assign(
            sample_tooth_depth=("sample", np.array(teeth), {"units": "m", "long_name": "depth of one whole pass per draw"}),
            sample_speed=("sample", speeds, {"units": "m s-1", "long_name": "drawn speed"}),
            sample_phase=("sample", phases, {"units": "rad", "long_name": "drawn starting contact angle"}))
        data.attrs["patch_half_length"] = model.patch_half_length
        return PaperFigure(data, plots.wear_intensity(data))
    from railwear.geometry.wear_surface import WearSurface
    from railwear.longterm.disk_wheel import surface_wear

    b = band / 2
    grids = []
    for n_angle in WEAR_SURFACE_CELLS:
        surface = WearSurface(model.radius, n_angle, np.linspace(-2 * b, 2 * b, 17))
        grids.append(surface_wear(model, u0, beta, surface, turns=12, per_turn=720, lateral_half_axis=b)[0])
    title = f"{sc.name}: depth worn in 12 turns at {m_s_to_kmh(speed):g} km/h (wear not accelerated)"
    return PaperFigure(grids[-1], plots.wear_surface(grids[-1], title, (model.patch_half_length, b), grids[0]))


TRACK_FREQUENCIES_HZ = (10.0, 3000.0, 600)  # the receptance's default log-spaced band (low, high, points)


def _coupled_resonances(model, low=20.0, high=150.0, points=2601):
    """The peaks [Hz] of the bay-averaged ``|N/ū|`` between ``low`` and ``high`` Hz, lowest first, on
    the grid of :func:`~railwear.longterm.vehicle_track.p2_frequency` (its value where there is one
    peak); the largest value on the grid where there is none inside it."""
    f = np.linspace(low, high, points)
    h = np.abs(model.contact_force_transfer(2 * np.pi * f))
    inside = np.flatnonzero((h[1:-1] > h[:-2]) & (h[1:-1] >= h[2:])) + 1
    return [float(x) for x in f[inside]] or [float(f[np.argmax(h)])]


def track_receptance(scenario=None, frequencies_hz=None):
    """The vertical rail receptance of a ``[body] kind = "vehicle_track"`` scenario's ``[track]`` over
    ``frequencies_hz`` (default 10-3000 Hz, log-spaced): magnitude (m N-1) and phase (deg) at
    midspan and above a sleeper, the bay-averaged normal-force transfer ``|N/ū|`` (N m-1) of the
    ``[body]`` wheel on it at the operation speed, and the pinned-pinned (discrete track) and
    P2 frequencies (Hz). The P2 is the lowest peak of ``|N/ū|`` over 20-150 Hz (the wheel and the
    track bouncing together); where the support has more than one (a ballast mass on a subgrade:
    the wheel, rail and sleepers with and against the ballast), the attribute
    ``coupled_resonances_hz`` lists them all."""
    import xarray as xr

    from railwear.longterm.vehicle_track import VehicleTrackModel
    from railwear.scenario import build, load_scenario, scenario_hash
    from railwear.track import receptance

    sc = load_scenario(scenario)
    if "track" not in sc.body.sections:
        raise ScenarioError(f"body.kind: the track receptance needs a body on [track] (vehicle_track), "
                            f"not {sc.body.kind!r}")
    f = np.geomspace(*TRACK_FREQUENCIES_HZ[:2], TRACK_FREQUENCIES_HZ[2]) if frequencies_hz is None else \
        np.atleast_1d(np.asarray(frequencies_hz, float))
    if f.ndim != 1 or f.size < 2 or not np.all(np.isfinite(f)) or f.min() <= 0 or f.max() > 1e5:
        raise ScenarioError(f"frequencies_hz: expected at least two frequencies in (0, 1e5] Hz, got {frequencies_hz!r}")
    case = sc.body.case(sc)
    track = case.track
    positions = ["midspan", "sleeper"] if track.discrete else ["continuous"]
    alpha = np.array([receptance(track, f, p if track.discrete else 0.0) for p in positions])
    model = VehicleTrackModel(case.wheel(build.one_speed(sc)), track, sc.track.bay_positions, case.wheel_modes)
    force = model.contact_force_transfer(2 * np.pi * f)
    peaks = _coupled_resonances(model)
    ds = xr.Dataset(
        {"receptance_magnitude": (("position", "frequency"), np.abs(alpha),
                                  {"units": "m N-1", "long_name": "vertical point receptance of the rail"}),
         "receptance_phase": (("position", "frequency"), np.degrees(np.angle(alpha)),
                              {"units": "degree", "long_name": "phase of the receptance"}),
         "contact_force_transfer": (("frequency",), np.abs(force),
                                    {"units": "N m-1", "long_name": "normal force per radius deviation, bay averaged"}),
         "p2_frequency": ((), peaks[0], {"units": "Hz", "long_name": "P2 resonance of wheel and track"})},
        coords={"frequency": ("frequency", f, {"units": "Hz", "long_name": "frequency"}),
                "position": ("position", positions, {"long_name": "load position in the bay"})},
        attrs={"scenario_name": sc.name, "scenario_hash": scenario_hash(sc), "source": "track receptance",
               "track": f"{sc.track.rail} ({sc.track.beam}), {sc.track.support} support"
                        + (f" at {sc.track.sleeper_spacing_m:g} m" if track.discrete else "")
                        + ("" if sc.track.base == "ballast" and sc.track.preset is None else
                           f", base {sc.track.base}" + (f" ({sc.track.preset})" if sc.track.preset else ""))})
    if len(peaks) > 1:
        ds.attrs["coupled_resonances_hz"] = np.array(peaks)
    if track.discrete:
        ds["pinned_pinned_frequency"] = ((), track.pinned_pinned_frequency(),
                                         {"units": "Hz", "long_name": "pinned-pinned frequency of the rail"})
    return ds
