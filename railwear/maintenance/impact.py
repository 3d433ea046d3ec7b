"""The dynamic wheel load a wheel-impact-load detector sees (issue 24, item 4; layer 4).

A wheel shape ``u(x)`` (a result's radius deviation, a measured wheel, or the scenario's initial
wheel) rolls at each speed of a list over the time-domain track of the vehicle–track case: the
rigid-rail disk wheel (:class:`~railwear.dynamics.DiskWheelModel`: wheel mass, primary suspension
to the bogie frame's share, Hertz contact ``N = k_H δ^(3/2)`` that lets go at ``δ <= 0``, Kalker
creep under the traction torque) on the discretely supported ring track
(:class:`~railwear.track.modal.RingTrack`: rail modes, pads, sleepers, ballast, so the sleeper
passing is in), wheel and track in the compiled RK4 loop of
:class:`~railwear.dynamics.disk_wheel_track.WheelOnRing`. Each run starts at rest under the static
load, runs ``transient`` seconds (whole revolutions) and records ``revolutions`` more at every
step. The same run with the round wheel gives the sleeper passing alone, and the difference of
the two is the force the shape adds, whose amplitude per polygon order ``n`` (at ``f = n Ω / 2π``,
``Ω`` the wheel's angular speed) is set beside the linear model's, ``|N̂_n| = |H̄(nΩ)| |ū_n|``
(``H̄`` the bay-averaged coupled transfer of
:meth:`~railwear.longterm.vehicle_track.VehicleTrackModel.contact_force_transfer`, ``ū_n`` the
harmonic of the patch-filtered deviation the contact reads). With several wheels on the rail
(``wheel_positions``, a bogie ``(0, 2.5)``), the shaped wheel leads and the others follow it round
(:class:`~railwear.dynamics.wheels_track.WheelsOnRing`, one compiled loop): the peak and least
force at every wheel beside the round bogie's.

:class:`DynamicLoad` holds the inputs (SI), :func:`dynamic_load` returns the ``xarray.Dataset``;
:func:`wheel_load` builds the inputs from a scenario and a wheel file; :func:`report`, :func:`write`
and the figures give what ``railwear load`` writes. :data:`DETECTORS` is the table of published
detector thresholds with their sources.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np
import xarray as xr

from railwear.errors import OptionError, ScenarioError
from railwear.units import KN, MM, UM, kmh_to_m_s, m_s_to_kmh

__all__ = ["Detector", "DETECTORS", "DynamicLoad", "dynamic_load", "peak_forces", "wheel_load", "report", "write",
           "peak_figure", "trace_figure"]

KIP = 4448.2216152605  # N per kip (1000 lbf)
UNITS = {"kN": KN, "kip": KIP}


@dataclass(frozen=True)
class Detector:
    """A published wheel-impact-load-detector threshold: the peak vertical force ``value`` in
    ``unit`` ('kN' or 'kip') above which ``who`` acts as ``action`` says, from ``source``."""

    name: str
    who: str
    value: float
    unit: str
    action: str
    source: str

    @property
    def threshold(self) -> float:
        """The threshold in newtons."""
        return self.value * UNITS[self.unit]


# The thresholds a planner compares with, each as its source gives it (kips converted at the edge).
DETECTORS = (
    Detector("network-rail", "Network Rail", 200.0, "kN", "acts on the vehicle (four levels of action above 200 kN)",
             "Network Rail NR/SP/TRK/0133, Control of Wheel Impact Forces (2006): action when vertical wheel-rail "
             "forces exceed 200 kN"),
    Detector("trafikverket", "Trafikverket", 350.0, "kN", "stops the train for inspection",
             "Trafikverket's alarm limit of 350 kN (BVS 1586.68; Chalmers report 'Towards improved regulations and "
             "procedures for damaged wheels - Assessment of wheel impact load detectors', 2024)"),
    Detector("na-shop", "North American advisory", 80.0, "kip", "replace the wheel when in a repair shop",
             "FRA Safety Advisory 2023-04, 88 FR 62623 (12 September 2023): wheels above 80 kips replaced in a shop"),
    Detector("na-service", "North American advisory", 90.0, "kip", "replace the wheel wherever found in service",
             "FRA Safety Advisory 2023-04, 88 FR 62623 (12 September 2023): wheels above 90 kips replaced in service"),
)

STABLE_STEP = 2.4  # |λ| dt of the fastest mode the step keeps (RK4's real-axis limit is 2.78; WheelOnRing takes 2.5)
SPEED_KMH = (1.0, 400.0)  # the speeds a user may ask for
LARGEST_SHAPE = 10 * MM  # a deviation beyond this from the mean radius is no polygon of a wheel in service


def _check(name, value, low, high, integer=False):
    """Refuse ``value`` outside ``[low, high]`` (or not an integer where one is asked), naming ``name``."""
    bad = (not isinstance(value, (int, float, np.integer, np.floating)) or isinstance(value, bool)
           or not math.isfinite(value) or not low <= value <= high or (integer and int(value) != value))
    if bad:
        kind = "an integer" if integer else "a number"
        raise ScenarioError(f"{name}: must be {kind} in [{low:g}, {high:g}], got {value!r}")


@dataclass(frozen=True, eq=False)
class DynamicLoad:
    """The inputs of :func:`dynamic_load` (SI).

    ``case``: the :class:`~railwear.longterm.vehicle_track.VehicleCase` (wheel, suspension,
    contact and a discretely supported track; no flexible wheelset modes, which the time-domain
    track does not carry). ``deviation``: the radius deviation ``u`` [m] at the angles
    ``2π j / n`` (its mean is removed: the mean radius does not load the rail). ``speeds`` [m/s].
    The ring track: ``ring_sleepers`` bays, rail modes to ``ring_max_frequency_hz``.
    ``revolutions`` recorded after ``transient`` [s] (rounded up to whole revolutions);
    ``max_step`` [s] the RK4 step at most (smaller where the track's fastest mode asks for it);
    ``trace_samples`` the samples per revolution of the stored force trace (the peak and the
    spectrum use every step); the run starts with the wheel ``start_position`` [m] past a sleeper
    and the angle ``start_angle`` [rad] of ``u`` in contact. ``bay_positions``: the offsets the
    linear model averages over. ``wheel``: what the shape is, in words. ``wheel_positions``: the
    wheels on the rail, m behind the shaped wheel (0, then increasing; the others round); the
    ring must be at least twice their span."""

    case: object
    deviation: np.ndarray
    speeds: tuple
    ring_sleepers: int = 32
    ring_max_frequency_hz: float = 3000.0
    revolutions: int = 8
    transient: float = 1.0
    max_step: float = 1e-4
    trace_samples: int = 256
    start_position: float = 0.0
    start_angle: float = 0.0
    bay_positions: int = 8
    wheel: str = field(default="a wheel")
    wheel_positions: tuple = (0.0,)

    def __post_init__(self):
        from railwear.longterm.vehicle_track import VehicleCase

        if not isinstance(self.case, VehicleCase):
            raise ScenarioError("case: must be a railwear.longterm.vehicle_track.VehicleCase")
        if self.case.wheel_modes:
            raise ScenarioError("case.wheel_modes: the time-domain track carries no flexible wheelset modes; the "
                                "dynamic load is the rigid wheelset's")
        if not self.case.track.discrete:
            raise ScenarioError("track.support: the time-domain ring track needs discrete supports (sleepers)")
        u = np.array(self.deviation, dtype=float)
        if u.ndim != 1 or not 8 <= u.size <= 2**16 or not np.all(np.isfinite(u)):
            raise ScenarioError("deviation: must be 8 to 65536 finite radius deviations [m] round the wheel")
        u = u - u.mean()
        if np.max(np.abs(u)) > LARGEST_SHAPE:
            raise ScenarioError(f"deviation: {np.max(np.abs(u)) / MM:.3g} mm from the mean radius is more than "
                                f"{LARGEST_SHAPE / MM:g} mm: not the out-of-roundness of a wheel in service (metres?)")
        u.setflags(write=False)
        object.__setattr__(self, "deviation", u)
        speeds = np.atleast_1d(np.asarray(self.speeds, dtype=float))
        low, high = kmh_to_m_s(SPEED_KMH[0]), kmh_to_m_s(SPEED_KMH[1])
        if speeds.ndim != 1 or not 1 <= speeds.size <= 100 or not np.all(np.isfinite(speeds)):
            raise ScenarioError(f"speeds: must be 1 to 100 finite speeds [m/s], got {self.speeds!r}")
        if np.any((speeds < low) | (speeds > high)):
            raise ScenarioError(f"speeds: must lie in {SPEED_KMH[0]:g}-{SPEED_KMH[1]:g} km/h, got "
                                f"{', '.join(f'{v:g}' for v in m_s_to_kmh(speeds))} km/h")
        if np.unique(speeds).size != speeds.size:
            raise ScenarioError("speeds: a speed is given twice")
        object.__setattr__(self, "speeds", tuple(float(v) for v in np.sort(speeds)))
        _check("ring_sleepers", self.ring_sleepers, 8, 1024, integer=True)
        _check("ring_max_frequency_hz", self.ring_max_frequency_hz, 200.0, 2e4)
        _check("revolutions", self.revolutions, 1, 1000, integer=True)
        _check("transient", self.transient, 0.0, 60.0)
        _check("max_step", self.max_step, 1e-7, 1e-3)
        _check("trace_samples", self.trace_samples, 16, 4096, integer=True)
        _check("start_position", self.start_position, -1e6, 1e6)
        _check("start_angle", self.start_angle, -1e3, 1e3)
        _check("bay_positions", self.bay_positions, 1, 256, integer=True)
        x = np.atleast_1d(np.asarray(self.wheel_positions, float))
        if x.ndim != 1 or not 1 <= x.size <= 8 or not np.all(np.isfinite(x)) or x[0] != 0 or np.any(np.diff(x) <= 0):
            raise ScenarioError(f"wheel_positions: 1 to 8 wheels' distances behind the shaped wheel (m), 0 then "
                                f"increasing, got {self.wheel_positions!r}")
        length = int(self.ring_sleepers) * self.case.track.sleeper_spacing
        if 2 * x[-1] > length * (1 + 1e-9):
            raise ScenarioError(f"ring_sleepers: a ring of {int(self.ring_sleepers)} bays ({length:g} m) is shorter than "
                                f"twice the wheels' span ({x[-1]:g} m): round it the last wheel would run just ahead of "
                                f"the first; take at least {math.ceil(2 * x[-1] / self.case.track.sleeper_spacing)} bays")
        object.__setattr__(self, "wheel_positions", tuple(float(v) for v in x))

    def ring(self):
        """The :class:`~railwear.track.modal.RingTrack` the wheel runs on."""
        from railwear.longterm.vehicle_track_body import ring_for

        return ring_for(self.case.track, int(self.ring_sleepers), float(self.ring_max_frequency_hz))


def filtered_harmonics(model, u, oversample=4):
    """Amplitudes ``|ū_n|`` [m], ``n = 0 .. size/2``, of the deviation the contact reads: ``u``
    (piecewise linear between its points) averaged over the patch, as the compiled contact does
    (``kernels.patch_average``), sampled at ``oversample`` times its points."""
    from railwear.dynamics import kernels
    from railwear.longterm.disk_wheel import surface

    surf, n = surface(u), u.size
    half = model.patch_half_length / model.radius
    x = 2 * np.pi * np.arange(oversample * n) / (oversample * n)
    ubar = np.array([kernels.patch_average(surf, n, float(a), half) for a in x])
    return 2 * np.abs(np.fft.rfft(ubar))[: n // 2 + 1] / x.size


def _intervals(mask):
    """``(start, stop)`` index pairs of the runs of True in ``mask``."""
    edges = np.diff(np.concatenate([[0], mask.astype(np.int8), [0]]))
    return list(zip(np.flatnonzero(edges == 1), np.flatnonzero(edges == -1)))


def _speed_run(inputs, ring, speed, with_round=True):
    """The polygon and the round wheel at ``speed`` [m/s]: ``(records, round_records, model, dt,
    steps per revolution, the record's start time)``, every step of ``revolutions`` recorded, rows
    ``(steps, wheels, 8)`` (the shaped wheel first; without ``with_round``, the round wheel is not
    run and its records are the polygon's)."""
    from railwear.dynamics.disk_wheel_track import WheelOnRing
    from railwear.dynamics.wheels_track import WheelsOnRing
    from railwear.longterm.disk_wheel import start_lift, wheel_turn

    u, a0 = inputs.deviation, float(inputs.start_angle)
    base = inputs.case.wheel(speed)
    shaped = replace(base, radius_deviation=u, initial_angle=a0, initial_lift=start_lift(base, u, a0))
    round_wheel = replace(base, initial_angle=a0)
    bogie = len(inputs.wheel_positions) > 1
    if bogie:  # every wheel's surface on the shape's grid
        round_wheel = replace(round_wheel, radius_deviation=np.zeros(u.size))
    turn = wheel_turn(base)
    rate = WheelOnRing(base, ring, 1e-12).fastest_rate()
    step = min(float(inputs.max_step), STABLE_STEP / rate)
    per = int(inputs.trace_samples) * math.ceil(turn / (int(inputs.trace_samples) * step) - 1e-9)
    dt = turn / per
    settle = per * math.ceil(float(inputs.transient) / turn - 1e-9)
    t0, x0 = settle * dt, float(inputs.start_position)
    out = []
    runs = (shaped, round_wheel) if with_round else (shaped,)
    for model in runs if np.any(u) else (round_wheel,):  # a round wheel runs once
        if bogie:
            dyn = WheelsOnRing(model, ring, dt, positions=inputs.wheel_positions)
            models = [model] + [round_wheel] * (dyn.n_wheels - 1)
            p, surf = [m.params() for m in models], [m.surface() for m in models]
            y = dyn.static_state(x0, [m.initial_lift for m in models], models)
        else:
            dyn = WheelOnRing(model, ring, dt)
            p, surf = model.params(), model.surface()
            y = dyn.static_state(x0, model.initial_lift)
        if settle:
            y, _ = dyn.run(y, 0.0, settle, x0, p, surf)
        _, records = dyn.run(y, t0, int(inputs.revolutions) * per, x0 + speed * t0, p, surf, every=1)
        out.append(records[:-1].reshape(-1, len(inputs.wheel_positions), records.shape[-1]))  # whole revolutions
    return out[0], out[-1], shaped, dt, per, t0


def _loss(force, angle, position, spacing, revolutions):
    """Contact loss over a record: ``(fraction of the time, losses per revolution, the wheel angle
    [rad] and the offset past a sleeper [m] at the middle of the longest loss)``; NaN where none."""
    lost = force <= 0.0
    runs = _intervals(lost)
    if not runs:
        return 0.0, 0.0, np.nan, np.nan
    start, stop = max(runs, key=lambda r: r[1] - r[0])
    mid = (start + stop - 1) // 2
    return float(lost.mean()), len(runs) / revolutions, float(angle[mid] % (2 * np.pi)), float(position[mid] % spacing)


def dynamic_load(inputs: DynamicLoad, progress=None) -> xr.Dataset:
    """The vertical wheel–rail force of ``inputs``' wheel at each of its speeds on the time-domain
    track (module docstring): its history, peak, minimum, contact loss, the dynamic increment over
    the static load, the force per polygon order against the linear model's, and the round wheel's
    sleeper passing, as an ``xarray.Dataset`` (SI, CF units). ``progress(fraction)`` after each speed."""
    from railwear import __version__
    from railwear.api import speed_coordinates
    from railwear.longterm.vehicle_track import VehicleTrackModel

    if not isinstance(inputs, DynamicLoad):
        raise ScenarioError("inputs: must be a DynamicLoad")
    ring, u, case = inputs.ring(), inputs.deviation, inputs.case
    speeds, revs, m = np.array(inputs.speeds), int(inputs.revolutions), int(inputs.trace_samples)
    orders = np.arange(1, min(u.size, m) // 2 + 1)
    spacing = case.track.sleeper_spacing
    first = case.wheel(speeds[0])
    ubar = filtered_harmonics(first, u)[orders]
    load = first.static_load
    k_s, k_o, k_t = speeds.size, orders.size, revs * m
    scalar = {name: np.full(k_s, np.nan) for name in (
        "peak", "minimum", "peak_angle", "loss", "losses", "loss_angle", "loss_offset", "round_peak", "round_minimum",
        "step", "omega")}
    per_order = {name: np.full((k_s, k_o), np.nan) for name in ("simulated", "linear", "phase")}
    trace = {name: np.full((k_s, k_t), np.nan) for name in ("force", "round", "time", "angle", "offset", "deviation")}
    wheels = {name: np.full((k_s, len(inputs.wheel_positions)), np.nan) for name in ("peak", "minimum", "round_peak")}
    for i, v in enumerate(speeds):
        every_wheel, round_wheels, model, dt, per, t0 = _speed_run(inputs, ring, v)
        wheels["peak"][i], wheels["minimum"][i] = every_wheel[:, :, 1].max(0), every_wheel[:, :, 1].min(0)
        wheels["round_peak"][i] = round_wheels[:, :, 1].max(0)
        rec, flat = every_wheel[:, 0], round_wheels[:, 0]
        force, angle = rec[:, 1], rec[:, 4]
        j = int(np.argmax(force))
        s = scalar
        s["peak"][i], s["minimum"][i], s["peak_angle"][i] = force[j], force.min(), angle[j] % (2 * np.pi)
        s["loss"][i], s["losses"][i], s["loss_angle"][i], s["loss_offset"][i] = _loss(force, angle, rec[:, 7], spacing,
                                                                                      revs)
        s["round_peak"][i], s["round_minimum"][i], s["step"][i] = flat[:, 1].max(), flat[:, 1].min(), dt
        omega = v * (1 + model.steady_creepage()) / model.radius
        s["omega"][i] = omega
        spectrum = np.fft.rfft(force - flat[:, 1]) * 2 / force.size
        line = spectrum[orders * revs]
        linear = VehicleTrackModel(case.wheel(v), case.track, int(inputs.bay_positions)).contact_force_transfer(
            orders * omega)
        per_order["simulated"][i], per_order["phase"][i] = np.abs(line), np.angle(line)
        per_order["linear"][i] = np.abs(linear) * ubar
        every = per // m
        trace["force"][i], trace["round"][i] = force[::every], flat[::every, 1]
        trace["time"][i], trace["angle"][i] = rec[::every, 0] - t0, angle[::every] % (2 * np.pi)
        trace["offset"][i] = rec[::every, 7] % spacing
        trace["deviation"][i] = np.interp(trace["angle"][i], 2 * np.pi * np.arange(u.size + 1) / u.size, np.append(u, u[0]))
        if progress is not None:
            progress((i + 1) / k_s)
    s = scalar
    undefined = {"undefined_because": "the wheel kept contact at this speed"}
    thresholds = np.array([d.threshold for d in DETECTORS])
    sp, so, st = ("speed",), ("speed", "order"), ("speed", "sample")
    ds = xr.Dataset(
        {
            "radius_deviation": (("angle",), u, {"units": "m", "long_name": "radius deviation of the wheel (mean removed)"}),
            "deviation_amplitude": (("order",), np.abs(np.fft.rfft(u))[orders] * 2 / u.size,
                                    {"units": "m", "long_name": "harmonic amplitude of the radius deviation"}),
            "filtered_deviation_amplitude": (("order",), ubar, {
                "units": "m", "long_name": "harmonic amplitude of the deviation averaged over the contact patch"}),
            "static_load": ((), load, {"units": "N", "long_name": "static wheel load"}),
            "peak_force": (sp, s["peak"], {"units": "N", "long_name": "peak vertical wheel-rail force"}),
            "minimum_force": (sp, s["minimum"], {"units": "N", "long_name": "least vertical wheel-rail force"}),
            "dynamic_increment": (sp, s["peak"] - load, {"units": "N", "long_name": "peak force less the static load"}),
            "dynamic_factor": (sp, s["peak"] / load, {"units": "1", "long_name": "peak force over the static load"}),
            "peak_angle": (sp, s["peak_angle"], {"units": "rad", "long_name": "wheel angle in contact at the peak force"}),
            "contact_loss_fraction": (sp, s["loss"], {"units": "1", "long_name": "fraction of the time without contact"}),
            "contact_loss_per_revolution": (sp, s["losses"], {"units": "1", "long_name": "losses of contact per revolution"}),
            "contact_loss_angle": (sp, s["loss_angle"], {
                "units": "rad", "long_name": "wheel angle at the middle of the longest loss of contact", **undefined}),
            "contact_loss_offset": (sp, s["loss_offset"], {
                "units": "m", "long_name": "wheel past a sleeper at the middle of the longest loss of contact", **undefined}),
            "round_peak_force": (sp, s["round_peak"], {"units": "N", "long_name": "peak force of the round wheel"}),
            "round_minimum_force": (sp, s["round_minimum"], {"units": "N", "long_name": "least force of the round wheel"}),
            "sleeper_ripple": (sp, (s["round_peak"] - s["round_minimum"]) / 2, {
                "units": "N", "long_name": "half the peak-to-peak force of the round wheel: the sleeper passing"}),
            "sleeper_passing_frequency": (sp, speeds / spacing, {"units": "Hz", "long_name": "sleeper-passing frequency"}),
            "wheel_rotation_frequency": (sp, s["omega"] / (2 * np.pi), {"units": "Hz", "long_name": "wheel revolutions per second"}),
            "time_step": (sp, s["step"], {"units": "s", "long_name": "RK4 step"}),
            "order_force_amplitude": (so, per_order["simulated"], {
                "units": "N", "long_name": "amplitude of the force the shape adds (less the round wheel's), per order"}),
            "order_force_phase": (so, per_order["phase"], {
                "units": "rad", "long_name": "phase of that force per order at the record's start"}),
            "linear_force_amplitude": (so, per_order["linear"], {
                "units": "N", "long_name": "linear model per order: |bay-averaged coupled transfer| x filtered amplitude"}),
            "force": (st, trace["force"], {"units": "N", "long_name": "vertical wheel-rail force"}),
            "round_force": (st, trace["round"], {"units": "N", "long_name": "vertical wheel-rail force of the round wheel"}),
            "time": (st, trace["time"], {"units": "s", "long_name": "time from the start of the record"}),
            "contact_angle": (st, trace["angle"], {"units": "rad", "long_name": "wheel angle in contact"}),
            "bay_offset": (st, trace["offset"], {"units": "m", "long_name": "wheel past the last sleeper"}),
            "deviation_in_contact": (st, trace["deviation"], {
                "units": "m", "long_name": "radius deviation at the wheel angle in contact"}),
            "threshold": (("detector",), thresholds, {"units": "N", "long_name": "detector threshold on the peak force"}),
            "flagged": (("speed", "detector"), (s["peak"][:, None] > thresholds[None, :]).astype(np.int8), {
                "units": "1", "long_name": "1: the peak force exceeds the detector's threshold"}),
            "detector_who": (("detector",), np.array([d.who for d in DETECTORS]), {"long_name": "who acts"}),
            "detector_action": (("detector",), np.array([d.action for d in DETECTORS]), {"long_name": "what they do"}),
            "detector_source": (("detector",), np.array([d.source for d in DETECTORS]), {"long_name": "source"}),
        },
        coords={
            "order": ("order", orders, {"units": "1", "long_name": "polygon order"}),
            "angle": ("angle", 2 * np.pi * np.arange(u.size) / u.size, {"units": "rad", "long_name": "wheel angle"}),
            "sample": ("sample", np.arange(k_t), {"long_name": f"sample of the record, {m} per revolution"}),
            "detector": ("detector", [d.name for d in DETECTORS], {"long_name": "wheel-impact-load detector threshold"}),
        },
        attrs={"title": "railwear: dynamic wheel load", "wheel": inputs.wheel, "revolutions": revs,
               "transient_s": float(inputs.transient), "ring_sleepers": int(inputs.ring_sleepers),
               "ring_max_frequency_hz": float(inputs.ring_max_frequency_hz), "sleeper_spacing_m": spacing,
               "bay_positions": int(inputs.bay_positions), "start_position_m": float(inputs.start_position),
               "start_angle_rad": float(inputs.start_angle), "railwear_version": __version__, "Conventions": "CF-1.10",
               "linear_model": "the bay-averaged coupled transfer N/u of the vehicle-track model (Fourier technique) "
                               "times the patch-filtered harmonic; the simulated amplitude is the force less the round "
                               "wheel's, at the line n times the wheel's rotation frequency over whole revolutions"})
    if len(inputs.wheel_positions) > 1:
        sw = ("speed", "wheel")
        ds = ds.assign({
            "wheel_peak_force": (sw, wheels["peak"], {"units": "N", "long_name": "peak vertical force at each wheel"}),
            "wheel_minimum_force": (sw, wheels["minimum"], {"units": "N", "long_name": "least vertical force at each wheel"}),
            "wheel_round_peak_force": (sw, wheels["round_peak"], {
                "units": "N", "long_name": "peak vertical force at each wheel with every wheel round"})})
        ds = ds.assign_coords(wheel_position=("wheel", np.array(inputs.wheel_positions), {
            "units": "m", "long_name": "wheel behind the shaped one on the same rail (the others round)"}))
    ds = speed_coordinates(ds, speeds, "speed")
    return ds.assign_coords(frequency=(so, orders[None, :] * s["omega"][:, None] / (2 * np.pi),
                                       {"units": "Hz", "long_name": "frequency of the order"}))


def peak_forces(inputs: DynamicLoad, speeds=None, ring=None) -> np.ndarray:
    """The peak vertical force [N] of ``inputs``' wheel at each of ``speeds`` [m/s] (default its
    own), the same run as :func:`dynamic_load`'s (so the same peak) without the round wheel, the
    spectrum or the trace: what a detector reads, at one time-domain run per speed."""
    ring = inputs.ring() if ring is None else ring
    speeds = inputs.speeds if speeds is None else speeds
    return np.array([float(_speed_run(inputs, ring, float(v), with_round=False)[0][:, 0, 1].max()) for v in speeds])


# ---- from a scenario and a wheel file ---------------------------------------------------------

DIAMETER_MATCH = 0.01  # a wheel file's diameter within 1 % of the scenario's wheel is that wheel


def shape_from_result(path, scenario, field="--result"):
    """``(u, words)``: the radius deviation [m] at the end of a ``railwear run`` result file, and
    what it is. A result of another wheel diameter (more than 1 %) or of several runs is refused."""
    from railwear import results

    path = Path(path)
    if not path.is_file():
        raise OptionError(f"{field}: {path} does not exist")
    try:
        ds = results.read_netcdf(path)
    except (OSError, ValueError) as e:
        raise OptionError(f"{field}: {path.name} is not a railwear result ({e})") from None
    if "u" not in ds or "angle" not in ds.u.dims:
        raise OptionError(f"{field}: {path.name} holds no radius deviation u over the angle (a result.nc of railwear run)")
    u = ds.u.isel(time=-1) if "time" in ds.u.dims else ds.u
    if u.dims != ("angle",):
        extra = [d for d in u.dims if d != "angle"]
        raise OptionError(f"{field}: {path.name} holds a run per {', '.join(extra)}; give the result of one run")
    radius = float(ds.nominal_radius) if "nominal_radius" in ds else None
    if radius is not None and not abs(radius - scenario.wheel.radius_m) <= DIAMETER_MATCH * scenario.wheel.radius_m:
        raise OptionError(f"{field}: the result's wheel is {2 * radius / MM:g} mm, the scenario's "
                          f"{2 * scenario.wheel.radius_m / MM:g} mm (wheel.radius_m = {scenario.wheel.radius_m:g}): "
                          "give the scenario of that wheel")
    at = f" after {float(ds.distance[-1]):,.0f} km" if "distance" in ds.coords and "time" in ds.u.dims else ""
    values = np.asarray(u.values, float)
    return values, (f"{path.name} ({ds.attrs.get('scenario_name', 'a run')}{at}, "
                    f"{np.ptp(values) / UM:.1f} um peak to peak)")


def shape_from_file(path, scenario, points, angle_unit=None, deviation_unit=None, nominal_diameter=None,
                    field="--wheel"):
    """``(u, words)``: a measured wheel (:func:`railwear.measured.read_measured`) on ``points``
    angles; ``nominal_diameter`` [m] for absolute columns, checked against the scenario's wheel."""
    from railwear.forecast import check_diameter
    from railwear.geometry.roundness import resample_measured
    from railwear.measured import read_measured

    if nominal_diameter is not None:
        check_diameter(nominal_diameter, scenario)
    angle, deviation = read_measured(path, angle_unit, deviation_unit, field=field, nominal_diameter=nominal_diameter)
    u = resample_measured(angle, deviation, points)
    return u, f"{Path(path).name} (measured, {np.ptp(u) / UM:.1f} um peak to peak)"


def check_body(sc, what="the dynamic wheel load"):
    """``sc`` if its body can run on the time-domain track, else a one-line refusal naming the field."""
    if sc.body.kind != "vehicle_track":
        raise ScenarioError(f"body.kind: {what} runs a vehicle_track body (the wheel on the time-domain track), "
                            f"not {sc.body.kind!r}")
    if sc.body.wheel_mode_frequencies_hz:
        raise ScenarioError("body.wheel_mode_frequencies_hz: the time-domain track carries no flexible wheelset "
                            f"modes; remove them (--unset body.wheel_mode_frequencies_hz ...) for {what}")
    return sc


def wheel_load(scenario=None, speeds_kmh=(40.0, 70.0, 120.0), wheel=None, result=None, revolutions=8, transient=1.0,
               angle_unit=None, deviation_unit=None, nominal_diameter=None, progress=None) -> xr.Dataset:
    """:func:`dynamic_load` of a scenario (file, built-in name or Scenario; its body must be a
    ``vehicle_track``) at ``speeds_kmh``: the wheel of the measured file ``wheel``, or at the end of
    the result file ``result``, or else the scenario's ``[initial]`` wheel; ``revolutions`` recorded
    after ``transient`` seconds. The scenario's name, TOML and hash go into the attributes."""
    from railwear.scenario import build, load_scenario, scenario_hash, to_toml

    sc = check_body(load_scenario(scenario))
    if wheel is not None and result is not None:
        raise OptionError("--wheel, --result: give one wheel, a measured file or a result")
    if result is not None:
        u, words = shape_from_result(result, sc)
    elif wheel is not None:
        u, words = shape_from_file(wheel, sc, sc.solver.points, angle_unit, deviation_unit, nominal_diameter)
    else:
        u = build.initial_state(sc, "railwear load (the shaped wheel leads, the others round)")
        words = f"the scenario's initial wheel ({sc.initial.kind}, {np.ptp(u) / UM:.1f} um peak to peak)"
    try:
        inputs = DynamicLoad(sc.body.case(sc), u, tuple(kmh_to_m_s(np.atleast_1d(np.asarray(speeds_kmh, float)))),
                             sc.track.ring_sleepers, sc.track.ring_max_frequency_hz, revolutions=revolutions,
                             transient=transient, bay_positions=sc.track.bay_positions, wheel=words,
                             wheel_positions=tuple(sc.body.wheel_positions_m or (0.0,)))
    except ScenarioError as e:  # the scenario's names for DynamicLoad's
        for name, field in (("ring_sleepers", "track.ring_sleepers"), ("wheel_positions", "body.wheel_positions_m")):
            if str(e).startswith(f"{name}:"):
                raise ScenarioError(field + str(e)[len(name):]) from None
        raise
    ds = dynamic_load(inputs, progress)
    ds.attrs.update({"title": f"railwear: {sc.name}, dynamic wheel load", "scenario_name": sc.name,
                     "scenario": to_toml(sc), "scenario_hash": scenario_hash(sc)})
    return ds


# ---- what railwear load writes ----------------------------------------------------------------

THRESHOLD_COLOURS = ("C4", "C1", "C5", "C6")
TEXT, TABLE, NETCDF, PEAK_FIGURE, TRACE_FIGURE = "load.txt", "load.csv", "load.nc", "load-peak.png", "load-trace.png"
HTML = "load.html"


def _kn(x):
    return f"{x / KN:.1f}"


def _flagged_by(ds, i):
    """The detectors whose threshold the peak at speed index ``i`` exceeds, in words."""
    names = [f"{ds.detector_who.values[d]} {ds.threshold.values[d] / KN:.0f} kN"
             for d in range(ds.sizes["detector"]) if ds.flagged.values[i, d]]
    return ", ".join(names) if names else "none"


def table_rows(ds):
    """One row per speed: what a planner reads (forces in kN)."""
    rows = []
    for i, kmh in enumerate(ds.speed_kmh.values):
        p = ds.isel(speed=i)
        rows.append({"speed_kmh": float(kmh), "peak_force_kN": float(p.peak_force) / KN,
                     "minimum_force_kN": float(p.minimum_force) / KN,
                     "dynamic_increment_kN": float(p.dynamic_increment) / KN, "dynamic_factor": float(p.dynamic_factor),
                     "contact_loss_fraction": float(p.contact_loss_fraction),
                     "sleeper_ripple_kN": float(p.sleeper_ripple) / KN,
                     "largest_order": int(p.order[int(np.argmax(p.order_force_amplitude.values))]),
                     "largest_order_force_kN": float(p.order_force_amplitude.max()) / KN, "flagged_by": _flagged_by(ds, i)})
    return rows


def _wheels_lines(ds):
    """With several wheels on the rail: the peak at each wheel per speed, beside the round bogie's."""
    if "wheel_peak_force" not in ds:
        return []
    x = ds.wheel_position.values
    lines = ["", f"wheels on the rail at {', '.join(f'{v:g}' for v in x)} m, the shaped wheel first, the others round:",
             f"  {'speed':>5}  peak force at each wheel, kN (every wheel round)"]
    for i, kmh in enumerate(ds.speed_kmh.values):
        peaks = ", ".join(f"{a / KN:.1f} ({b / KN:.1f})" for a, b in zip(ds.wheel_peak_force.values[i],
                                                                       ds.wheel_round_peak_force.values[i]))
        lines.append(f"  {kmh:5g}  {peaks}")
    return lines


def report(ds):
    """The dynamic load in words: the wheel, the track, per speed the peak against the detector
    thresholds, the contact loss and the sleeper passing, then the thresholds with their sources."""
    a = ds.attrs
    w = float(ds.static_load)
    lines = [f"dynamic wheel load of {a.get('scenario_name', 'a wheel')}: {a['wheel']}",
             f"static load {_kn(w)} kN; the wheel on the ring track of {a['ring_sleepers']} sleeper bays of "
             f"{a['sleeper_spacing_m']:g} m (rail modes to {a['ring_max_frequency_hz']:g} Hz), {a['revolutions']} "
             f"revolutions recorded after {a['transient_s']:g} s at each speed", "",
             f"  {'speed':>5}  {'peak':>5}  {'increment':<14}  {'least':>5}  {'contact lost (the longest loss)':<40}  "
             f"{'sleeper':>9}  {'largest':>7}  flagged by",
             f"  {'km/h':>5}  {'kN':>5}  {'kN (x W)':<14}  {'kN':>5}  {'time, wheel angle, past a sleeper':<40}  "
             f"{'ripple kN':>9}  {'order: kN'}"]
    for i, row in enumerate(table_rows(ds)):
        p = ds.isel(speed=i)
        lost = "-"
        if row["contact_loss_fraction"] > 0:
            lost = (f"{100 * row['contact_loss_fraction']:.2g} %, {np.degrees(float(p.contact_loss_angle)):.0f} deg, "
                    f"{float(p.contact_loss_offset) / MM:.0f} mm past a sleeper")
        increment = f"{row['dynamic_increment_kN']:.1f} (x{row['dynamic_factor']:.2f})"
        lines.append(f"  {row['speed_kmh']:5g}  {row['peak_force_kN']:5.1f}  {increment:<14}  "
                     f"{row['minimum_force_kN']:5.1f}  {lost:<40}  {row['sleeper_ripple_kN']:9.2f}  "
                     f"{row['largest_order']:5d}: {row['largest_order_force_kN']:<5.1f}  {row['flagged_by']}")
    lines += _wheels_lines(ds)
    peak = ds.peak_force.values
    j = int(np.argmax(peak))
    low = int(np.argmin(ds.threshold.values))
    kmh = ds.speed_kmh.values
    span = f"{kmh.min():g}-{kmh.max():g} km/h" if kmh.size > 1 else f"{kmh[0]:g} km/h"
    lines.append("")
    if ds.flagged.values.any():
        flagged = kmh[ds.flagged.values.any(axis=1)]
        lines.append(f"a detector flags this wheel at {', '.join(f'{v:g}' for v in flagged)} km/h; the highest peak is "
                     f"{_kn(peak[j])} kN at {kmh[j]:g} km/h")
    else:
        lines.append(f"no detector flags this wheel at {span}: the highest peak, {_kn(peak[j])} kN at {kmh[j]:g} km/h, "
                     f"is {peak[j] / ds.threshold.values[low]:.0%} of the lowest threshold "
                     f"({ds.detector_who.values[low]}, {ds.threshold.values[low] / KN:.0f} kN)")
    lost = ds.contact_loss_fraction.values > 0
    lines.append(f"the wheel loses contact at {', '.join(f'{v:g}' for v in kmh[lost])} km/h" if lost.any() else
                 f"the wheel keeps contact at every speed (least force {_kn(ds.minimum_force.values.min())} kN)")
    lines += ["", "detector thresholds on the peak vertical force:"]
    for d in range(ds.sizes["detector"]):
        lines.append(f"  {ds.threshold.values[d] / KN:5.0f} kN  {ds.detector_who.values[d]}: "
                     f"{ds.detector_action.values[d]} ({ds.detector_source.values[d]})")
    return "\n".join(lines) + "\n"


def peak_figure(ds, label=None, others=()):
    """The peak and the least force (kN) over the speed, with the static load, the round wheel's
    peak (the sleeper passing alone) and the detector thresholds as lines; ``label`` names the
    wheel, ``others`` are ``(label, dataset)`` of other wheels whose peak and least force are drawn
    beside (hollow markers)."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(8, 5.5), layout="constrained")
    ax = fig.subplots()
    kmh = ds.speed_kmh.values
    named = f", {label}" if label else ""
    ax.plot(kmh, ds.peak_force.values / KN, "o-", color="C3", label=f"peak force{named}")
    ax.plot(kmh, ds.minimum_force.values / KN, "v-", color="C0", label=f"least force{named} (0: contact lost)")
    if "wheel_peak_force" in ds:
        for a in range(1, ds.sizes["wheel"]):
            ax.plot(kmh, ds.wheel_peak_force.values[:, a] / KN, "s-", color=("C2", "C8", "C9", "C7")[(a - 1) % 4], ms=5,
                    label=f"peak force, round wheel {ds.wheel_position.values[a]:g} m behind")
    for other, o in others:
        ax.plot(o.speed_kmh.values, o.peak_force.values / KN, "o--", color="C3", mfc="none", label=f"peak force, {other}")
        ax.plot(o.speed_kmh.values, o.minimum_force.values / KN, "v--", color="C0", mfc="none",
                label=f"least force, {other}")
    ax.plot(kmh, ds.round_peak_force.values / KN, ":", color="0.3", label="round wheel's peak (sleeper passing)")
    ax.axhline(float(ds.static_load) / KN, color="k", lw=0.8, label=f"static load {float(ds.static_load) / KN:.1f} kN")
    styles = ("--", "-.", (0, (5, 2, 1, 2)), (0, (1, 1)))
    for d in range(ds.sizes["detector"]):
        ax.axhline(ds.threshold.values[d] / KN, color=THRESHOLD_COLOURS[d % len(THRESHOLD_COLOURS)],
                   ls=styles[d % len(styles)], lw=1.2,
                   label=f"{ds.detector_who.values[d]}, {ds.threshold.values[d] / KN:.0f} kN")  # actions: load.txt
    top = max([ds.threshold.values.max(), np.nanmax(ds.peak_force.values)]
              + [np.nanmax(o.peak_force.values) for _, o in others]) / KN
    ax.set_ylim(0, 1.08 * top)
    if kmh.size == 1:
        ax.set_xlim(kmh[0] - 10, kmh[0] + 10)
    if kmh.size <= 15:
        ax.set_xticks(kmh, [f"{v:g}" for v in kmh])  # the speeds that ran, not a scale's round numbers
    ax.set(xlabel="speed (km/h)", ylabel="vertical wheel-rail force (kN)",
           title=f"{ds.attrs.get('scenario_name', 'wheel')}: peak force against wheel-impact-load detector thresholds")
    ax.legend(fontsize="small", loc="upper center", bbox_to_anchor=(0.5, -0.13), ncol=2)
    ax.grid(alpha=0.3)
    return fig


def trace_figure(ds, speed_kmh=None):
    """The force (kN) over the last recorded revolution at ``speed_kmh`` (default: the speed of the
    highest peak), the round wheel's and the static load; below, the radius deviation (µm) in
    contact at the same instants."""
    from matplotlib.figure import Figure

    i = int(np.argmax(ds.peak_force.values)) if speed_kmh is None else int(np.argmin(np.abs(ds.speed_kmh.values - speed_kmh)))
    p = ds.isel(speed=i)
    m = int(ds.sizes["sample"] // ds.attrs["revolutions"])
    last = slice(ds.sizes["sample"] - m, None)
    t = (p.time.values[last] - p.time.values[last][0]) * 1e3
    fig = Figure(figsize=(8, 5.5), layout="constrained")
    top, bottom = fig.subplots(2, 1, sharex=True, height_ratios=(3, 1.3))
    top.plot(t, p.force.values[last] / KN, color="C3", lw=1.2, label="force of the wheel")
    top.plot(t, p.round_force.values[last] / KN, color="0.4", lw=1, ls=":", label="round wheel (sleeper passing)")
    top.axhline(float(ds.static_load) / KN, color="k", lw=0.8, label="static load")
    lost = p.force.values[last] <= 0
    if lost.any():
        top.plot(t[lost], np.zeros(lost.sum()), "|", color="C0", ms=8, label="contact lost")
    top.set(ylabel="vertical force (kN)", title=f"{ds.attrs.get('scenario_name', 'wheel')} at {float(p.speed_kmh):g} km/h: "
            f"one revolution, peak {float(p.peak_force) / KN:.1f} kN")
    top.legend(fontsize="small", loc="upper right", ncol=2)
    top.set_ylim(min(0.0, np.nanmin(p.force.values[last]) / KN), 1.25 * np.nanmax(p.force.values[last]) / KN)
    top.grid(alpha=0.3)
    bottom.plot(t, p.deviation_in_contact.values[last] / UM, color="C2", lw=1)
    bottom.set(xlabel="time in the revolution (ms)", ylabel="deviation in contact (µm)")
    bottom.grid(alpha=0.3)
    return fig


def draw_figures(ds, directory, fmt="png", dpi=120):
    """``load-peak.png`` and ``load-trace.png`` (and their PDF or SVG) in ``directory``; returns the paths."""
    from railwear import plots

    directory = Path(directory)
    return [plots.save(peak_figure(ds), directory / PEAK_FIGURE, fmt, dpi),
            plots.save(trace_figure(ds), directory / TRACE_FIGURE, fmt, dpi)]


def html_report(ds, path, figures=()):
    """``load.html``: the text, the table per speed, the detector thresholds with their sources,
    the figures embedded and the scenario, in one file; returns its path."""
    from railwear import report as pages

    rows = table_rows(ds)
    keys = list(rows[0])
    cells = [[f"{r[k]:.4g}" if isinstance(r[k], float) else str(r[k]) for k in keys] for r in rows]
    detectors = [(f"{ds.threshold.values[d] / KN:.0f}", str(ds.detector_who.values[d]), str(ds.detector_action.values[d]),
                  str(ds.detector_source.values[d])) for d in range(ds.sizes["detector"])]
    blocks = [("p", f"wheel: {ds.attrs['wheel']}"), ("h2", "Summary"), ("pre", report(ds)),
              ("h2", f"Per speed (as {TABLE})"), ("table", (keys, cells)),
              ("h2", "Detector thresholds"), ("table", (("threshold (kN)", "who", "action", "source"), detectors))]
    title = f"railwear load: {ds.attrs.get('scenario_name', 'a wheel')}, dynamic wheel load"
    return pages.write_page(path, title, blocks, figures, scenario=ds.attrs.get("scenario", ""))


def write(ds, directory, fmt="png", dpi=120, figures=True):
    """``load.nc``, ``load.txt``, ``load.csv``, (with ``figures``) ``load-peak.png`` and
    ``load-trace.png``, and ``load.html`` (all of it in one file) in ``directory``, each written
    atomically; returns their paths."""
    from railwear import results
    from railwear.maintenance.outputs import _csv

    directory = Path(directory)
    paths = [results.write_netcdf(ds, directory / NETCDF), results.write_text(report(ds), directory / TEXT),
             results.write_text(_csv(table_rows(ds)), directory / TABLE)]
    drawn = draw_figures(ds, directory, fmt, dpi) if figures else []
    paths += drawn
    paths.append(html_report(ds, directory / HTML, drawn))
    return paths
