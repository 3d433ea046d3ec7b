"""Nonlinear critical speed by ramping the speed down from a large limit cycle.

Above the linear critical speed a hunting motion settles on a limit cycle. Stepping the speed
down and continuing each run from the last state of the previous one follows the branch of stable
limit cycles to its lower end (a fold where the Hopf bifurcation is subcritical); below it the
motion dies out. The lowest speed with a sustained cycle is the nonlinear critical speed. Ramping
up instead would stay on the stable centred solution up to the linear critical speed.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from railwear.dynamics.simulation import simulate

__all__ = ["RampDown", "ramp_down", "settle"]


@dataclass(frozen=True)
class RampDown:
    """Result of ``ramp_down``: speeds [m/s], cycle amplitudes [m] (max |lateral displacement|
    of the first wheelset over the last window) and the nonlinear critical speed (``nan`` if no
    sustained cycle was found at the first speed or the cycle survives to the last), with a state
    on the cycle at the lowest speed that sustained one (``None`` if none did)."""

    speeds: np.ndarray
    amplitudes: np.ndarray
    nonlinear_critical_speed: float
    cycle_state: np.ndarray | None = None


def _amplitude(ds):
    """Max |lateral displacement| of the first wheelset over the run [m]."""
    y = ds.lateral_displacement
    if "wheelset" in y.dims:
        y = y.isel(wheelset=0)
    return float(np.max(np.abs(y.values)))


def _last_state(ds):
    """The state vector at the end of a run, rebuilt from the Dataset's variables."""
    last = ds.isel(time=-1)
    if "wheelset" in ds.dims:
        lat, yaw = last.lateral_displacement.values, last.yaw_angle.values
        vlat, vyaw = last.lateral_velocity.values, last.yaw_rate.values
        roll = [float(last.frame_roll_angle)] if "frame_roll_angle" in ds else []
        roll_rate = [float(last.frame_roll_rate)] if roll else []
        return np.array([lat[0], yaw[0], lat[1], yaw[1], float(last.frame_lateral_displacement),
                         float(last.frame_yaw_angle)] + roll + [vlat[0], vyaw[0], vlat[1], vyaw[1],
                         float(last.frame_lateral_velocity), float(last.frame_yaw_rate)] + roll_rate)
    spin = [float(last.spin_deviation)] if "spin_deviation" in ds else []
    return np.array([float(last.lateral_displacement), float(last.yaw_angle), float(last.lateral_velocity),
                     float(last.yaw_rate)] + spin)


def settle(model, state=None, window=1.0, max_time=30.0, collapse=1e-4, tol=1e-3, rtol=1e-8, n_output=501):
    """Run ``model`` in windows of ``window`` seconds until the motion has died out (amplitude
    below ``collapse`` [m]) or settled on a cycle (two window amplitudes agree to ``tol``), at
    most ``max_time`` seconds. Returns ``(sustained, amplitude, last_state)``; a motion still
    shrinking at ``max_time`` counts as not sustained."""
    previous = None
    elapsed = 0.0
    while True:
        ds = simulate(model, window, rtol=rtol, n_output=n_output, initial_state=state)
        state = _last_state(ds)
        amplitude = _amplitude(ds)
        elapsed += window
        if amplitude < collapse:
            return False, amplitude, state
        if previous is not None and abs(amplitude - previous) <= tol * amplitude:
            return True, amplitude, state
        if elapsed >= max_time:
            return amplitude > previous, amplitude, state
        previous = amplitude


def ramp_down(model, speeds, window=1.0, max_time=30.0, collapse=1e-4, tol=1e-3, rtol=1e-8) -> RampDown:
    """Follow the hunting limit cycle of ``model`` (wheelset or bogie) down the descending
    ``speeds`` [m/s]. At each speed ``settle`` runs from the last state of the previous speed
    (the first from the model's initial state: make it large) until the cycle has settled or
    died out. The branch ends at the first speed without a sustained cycle."""
    speeds = np.asarray(speeds, dtype=float)
    if speeds.ndim != 1 or speeds.size < 2 or np.any(np.diff(speeds) >= 0.0):
        raise ValueError("speeds must be a strictly decreasing sequence of at least two speeds")
    state = None
    cycle_state = None
    visited, amplitudes = [], []
    critical = float("nan")
    for v in speeds:
        sustained, amplitude, state = settle(dataclasses.replace(model, speed=float(v)), state, window, max_time,
                                             collapse, tol, rtol)
        visited.append(float(v))
        amplitudes.append(amplitude)
        if not sustained:
            critical = visited[-2] if len(visited) > 1 else float("nan")
            break
        cycle_state = state.copy()
    return RampDown(np.array(visited), np.array(amplitudes), critical, cycle_state)
