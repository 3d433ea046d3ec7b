"""``simulate(model, t_end)``: run a dynamics model with the compiled integrators into an xarray Dataset."""

from __future__ import annotations

import logging
import math
import threading

import numpy as np
import xarray as xr

from railwear.dynamics import integrators as integ
from railwear.dynamics import kernels as k
from railwear.dynamics._fields import model_fields
from railwear.dynamics.integration import Integrator
from railwear.dynamics.bogie import BogieModel
from railwear.dynamics.cooperrider import CooperriderBogie
from railwear.dynamics.disk_wheel import DiskWheelModel
from railwear.dynamics.table_bogie import TableBogieModel
from railwear.dynamics.table_wheelset import TableWheelsetModel
from railwear.dynamics.wheelset import WheelsetModel
from railwear.errors import ScenarioError

__all__ = ["simulate", "METHODS"]

METHODS = integ.METHODS  # name -> method id, kept with the integrators
_log = logging.getLogger("railwear.dynamics")
POLL_S = 0.2  # how often the progress of a run in one compiled piece is read [s of wall time]


class _Clock:
    """The progress of one compiled run, read from its clock (``integrators.integrate`` writes
    each accepted step's time there without the GIL) by a thread every :data:`POLL_S` seconds,
    which calls ``progress(fraction)`` when the fraction has grown. Reading changes no number."""

    def __init__(self, progress, t_end):
        self.progress, self.t_end = progress, t_end
        self.clock = np.zeros(1)
        self.stop = threading.Event()
        self.shown = -1.0
        self.thread = threading.Thread(target=self._poll, name="railwear-progress", daemon=True)

    def fraction(self):
        return min(max(float(self.clock[0]) / self.t_end, 0.0), 1.0)

    def _poll(self):
        try:
            while not self.stop.wait(POLL_S):
                f = self.fraction()
                if self.shown < f < 1.0:
                    self.shown = f
                    self.progress(f)
        except BaseException as e:  # noqa: BLE001  (raised again in the caller's thread)
            self.error = e

    def __enter__(self):
        self.error = None
        self.thread.start()
        return self.clock

    def __exit__(self, *exc):
        self.stop.set()
        self.thread.join()
        if self.error is not None and exc[0] is None:
            raise self.error


def _options(model, t_end, method, rtol, atol, t_eval, output_every, n_output, max_steps, max_step, max_norm):
    """``t_end``, the ``Integrator`` (which checks the tolerances and limits) and the output times."""
    try:
        t_end = float(t_end)
    except (TypeError, ValueError):
        raise ScenarioError(f"t_end: must be a number of seconds, got {t_end!r}") from None
    if not (t_end > 0.0 and math.isfinite(t_end)):
        raise ScenarioError(f"t_end: must be a positive finite time [s], got {t_end!r}")
    if t_eval is not None and output_every is not None:
        raise ScenarioError("output_every: give either t_eval or output_every, not both")
    integrator = Integrator(method=method, rtol=rtol, atol=model.default_atol if atol is None else atol,
                            max_steps=max_steps, max_step=max_step, max_norm=max_norm,
                            events=model.kind == k.KIND_DISK_WHEEL, output_every=output_every)
    if output_every is not None:
        return t_end, integrator, np.zeros(0)
    if t_eval is None:
        if int(n_output) != n_output or n_output < 1:
            raise ScenarioError(f"n_output: must be a positive whole number, got {n_output!r}")
        t_eval = np.linspace(0.0, t_end, int(n_output))
    t_eval = np.asarray(t_eval, dtype=float)
    if t_eval.ndim != 1 or t_eval.size == 0 or np.any(np.diff(t_eval) <= 0.0):
        raise ScenarioError("t_eval: must be a non-empty, strictly increasing 1-D array of times [s]")
    if t_eval[0] < 0.0 or t_eval[-1] > t_end:
        raise ScenarioError(f"t_eval: times must lie in [0, t_end = {t_end}] s")
    return t_end, integrator, t_eval


def simulate(
    model,
    t_end,
    *,
    method="dopri5",
    rtol=1e-8,
    atol=None,
    t_eval=None,
    output_every=None,
    n_output=1001,
    max_steps=10_000_000,
    max_step=math.inf,
    max_norm=1e6,
    initial_state=None,
    progress=None,
    chunks=None,
    cell_energy=False,
) -> xr.Dataset:
    """Integrate ``model`` (``WheelsetModel``, ``TableWheelsetModel``, ``DiskWheelModel``,
    ``BogieModel`` or ``TableBogieModel``) over ``[0, t_end]`` seconds.

    Output at ``t_eval`` (dense output; default ``n_output`` equidistant times) or every
    ``output_every`` accepted steps. ``method``: ``"dopri5"`` (explicit, default), ``"dop853"`` or
    ``"rosenbrock"`` (linearly implicit, for stiff creep). Returns a Dataset with the states and
    the contact quantities; every variable has CF ``units`` and ``long_name``.
    Raises ``ScenarioError`` for bad options and ``NumericalInstabilityError`` if the solution
    blows up (any state above ``max_norm``), the step size underflows or ``max_steps`` is hit.
    ``initial_state`` (length ``model.n_states``) replaces the model's initial state, e.g. to
    continue a run at another speed. ``progress(fraction)`` is called as the run goes: read from
    the compiled loop's clock by a thread every ``POLL_S`` seconds (the numbers are those of a run
    without it, bit for bit) and with 1.0 at the end. For long runs, ``chunks`` splits the
    interval into that many compiled runs (each restarting its step-size control), with a log
    line on the ``railwear.dynamics`` logger and the ``progress`` call after each instead. ``cell_energy=True`` (disk wheel with a radius
    deviation grid) adds ``frictional_energy``: the frictional energy [J] each cell of the grid
    received over the run, spread uniformly over the patch as it passes (paper Figs 3 and 7).
    """
    if not isinstance(model, (WheelsetModel, DiskWheelModel, BogieModel, TableWheelsetModel, TableBogieModel,
                              CooperriderBogie)):
        raise ScenarioError(f"model: expected one of the railwear.dynamics models, got {type(model).__name__}")
    t_end, integrator, t_eval = _options(
        model, t_end, method, rtol, atol, t_eval, output_every, n_output, max_steps, max_step, max_norm
    )
    polled = chunks is None and progress is not None  # one compiled run, its clock read meanwhile
    if chunks is None:
        chunks = 1
    if int(chunks) != chunks or chunks < 1:
        raise ScenarioError(f"chunks: must be a positive whole number, got {chunks!r}")
    p = model.params()
    surf = model.surface()
    y = model.initial_state() if initial_state is None else _initial_state(model, initial_state, p, surf)
    energy = None
    if cell_energy:
        if model.kind != k.KIND_DISK_WHEEL or model.n_cells() == 0:
            raise ScenarioError("cell_energy: needs a disk wheel with a radius_deviation grid")
        energy = np.zeros(model.n_cells())
    bounds = np.linspace(0.0, t_end, int(chunks) + 1)
    parts_t, parts_y, parts_ev_t, parts_ev_dir = [], [], [], []
    stats = None
    for i in range(int(chunks)):
        t0, t1 = bounds[i], bounds[i + 1]
        if t_eval.size:
            lo = 0 if i == 0 else np.searchsorted(t_eval, t0, side="right")
            segment_eval = t_eval[lo:np.searchsorted(t_eval, t1, side="right")]
            if segment_eval.size == 0:
                segment_eval = np.array([t1])  # keep dense mode; this point is dropped below
                drop_all = True
            else:
                drop_all = False
        else:
            segment_eval, drop_all = None, False
        if polled:
            with _Clock(progress, t_end) as clock:
                run = integrator.run(model.kind, p, surf, y, t0, t1, t_eval=segment_eval, energy=energy, clock=clock)
        else:
            run = integrator.run(model.kind, p, surf, y, t0, t1, t_eval=segment_eval, energy=energy)
        stats = run.stats if stats is None else stats + run.stats
        run.check(type(model).__name__)
        first = 1 if (i > 0 and not t_eval.size) else 0  # every-n mode repeats the segment start
        if not drop_all:
            parts_t.append(run.t_out[first:].copy())
            parts_y.append(run.y_out[first:].copy())
        parts_ev_t.append(run.event_t.copy())
        parts_ev_dir.append(run.event_direction.copy())
        y = run.y.copy()
        if chunks > 1:
            _log.info("%s: t = %.4g of %.4g s, %d right-hand sides", type(model).__name__, t1, t_end,
                      stats.rhs_evaluations)
        if progress is not None:
            progress(float(t1 / t_end))
    ts, ys = np.concatenate(parts_t), np.concatenate(parts_y)
    ev_t, ev_dir = np.concatenate(parts_ev_t), np.concatenate(parts_ev_dir)
    if isinstance(model, WheelsetModel):
        ds = _wheelset_dataset(model, ts, ys, p, surf)
    elif isinstance(model, (BogieModel, TableBogieModel, CooperriderBogie)):
        ds = _bogie_dataset(model, ts, ys, p, surf)
    elif isinstance(model, TableWheelsetModel):
        ds = _table_wheelset_dataset(model, ts, ys, p, surf)
    else:
        ds = _disk_wheel_dataset(model, ts, ys, p, surf, ev_t, ev_dir)
        if cell_energy:
            angles = 2.0 * np.pi * np.arange(energy.size) / energy.size
            ds = ds.assign_coords(cell_angle=_var("cell_angle", angles, "rad", "angle of the wheel cell centre"))
            ds["frictional_energy"] = _var("cell_angle", energy, "J",
                                           "frictional energy dissipated in the contact while over the cell")
    ds.attrs.update(
        {
            "model": type(model).__name__,
            "method": method,
            "rtol": integrator.rtol,
            "atol": integrator.atol,
            "rhs_evaluations": stats.rhs_evaluations,
            "accepted_steps": stats.accepted_steps,
            "rejected_steps": stats.rejected_steps,
            "jacobian_evaluations": stats.jacobian_evaluations,
        }
    )
    for name, value in model_fields(model).items():
        ds.attrs[f"model_{name}"] = value
    return ds


def _initial_state(model, initial_state, p, surf):
    y0 = np.array(initial_state, dtype=float)
    if y0.shape != (model.n_states,) or not np.all(np.isfinite(y0)):
        raise ScenarioError(f"initial_state: must be {model.n_states} finite numbers, got shape {y0.shape}")
    if model.kind == k.KIND_DISK_WHEEL and k.event(model.kind, 0.0, y0, p, surf) <= 0.0:
        raise ScenarioError("initial_state: the wheel starts above the rail (no contact)")
    return y0


def _var(dims, data, units, long_name):
    return xr.Variable(dims, data, {"units": units, "long_name": long_name})


def _wheelset_variables(model, ts, ys, out):
    """States and the per-wheel creep quantities shared by the wheelset models (output columns
    0-6 of each wheel, left at 0 and right at 8)."""
    per_wheel = lambda j: np.stack([out[:, j], out[:, 8 + j]], axis=1)  # noqa: E731
    tw = ("time", "wheel")
    return {
        "lateral_displacement": _var("time", ys[:, 0], "m", "lateral displacement of the wheelset"),
        "yaw_angle": _var("time", ys[:, 1], "rad", "yaw angle of the wheelset"),
        "lateral_velocity": _var("time", ys[:, 2], "m s-1", "lateral velocity of the wheelset"),
        "yaw_rate": _var("time", ys[:, 3], "rad s-1", "yaw rate of the wheelset"),
        "distance": _var("time", model.speed * ts, "m", "distance travelled"),
        "longitudinal_creepage": _var(tw, per_wheel(0), "1", "longitudinal creepage"),
        "lateral_creepage": _var(tw, per_wheel(1), "1", "lateral creepage"),
        "spin_creepage": _var(tw, per_wheel(2), "m-1", "spin creepage"),
        "longitudinal_creep_force": _var(tw, per_wheel(3), "N", "longitudinal creep force on the wheel"),
        "lateral_creep_force": _var(tw, per_wheel(4), "N", "lateral creep force on the wheel"),
        "spin_creep_moment": _var(tw, per_wheel(5), "N m", "spin creep moment on the wheel"),
        "frictional_power": _var(tw, per_wheel(6), "W", "frictional power in the contact"),
    }, {
        "time": _var("time", ts, "s", "time"),
        "wheel": xr.Variable("wheel", np.array(["left", "right"]), {"long_name": "wheel of the wheelset"}),
    }


def _wheelset_dataset(model, ts, ys, p, surf):
    out = k.outputs(model.kind, ts, ys, p, surf, k.WS_N_OUTPUTS)
    data, coords = _wheelset_variables(model, ts, ys, out)
    if model.n_states > 4:
        data["spin_deviation"] = _var("time", ys[:, 4], "rad s-1", "axle angular velocity minus V / r0")
    data.update({
        "contact_lateral_position": _var(("time", "wheel"), np.stack([out[:, 7], out[:, 15]], axis=1), "m",
                                         "lateral contact position on the tread, towards the flange"),
        "contact_angle": _var("time", out[:, 17], "rad", "angle of the contact point on the wheel"),
        "flange_force": _var("time", out[:, 16], "N", "lateral flange force on the wheelset"),
        "track_lateral_alignment": _var("time", out[:, 18], "m", "lateral position of the track centre line"),
    })
    return xr.Dataset(data, coords=coords)


def _table_wheelset_dataset(model, ts, ys, p, surf):
    out = k.outputs(model.kind, ts, ys, p, surf, k.TW_N_OUTPUTS)
    data, coords = _wheelset_variables(model, ts, ys, out)
    data.update({
        "normal_force": _var(("time", "wheel"), np.stack([out[:, 7], out[:, 15]], axis=1), "N",
                             "normal contact force from the contact table"),
        "rolling_radius_difference": _var("time", out[:, 16], "m", "rolling radius difference left - right"),
        "contact_lateral_position": _var(("time", "wheel"), out[:, 17:19], "m",
                                         "contact point on the wheel profile (profile coordinate)"),
        "contact_angle": _var("time", out[:, 19], "rad", "angle of the contact point on the wheel"),
    })
    return xr.Dataset(data, coords=coords)


def _disk_wheel_dataset(model, ts, ys, p, surf, ev_t, ev_dir):
    out = k.outputs(model.kind, ts, ys, p, surf, k.DW_N_OUTPUTS)
    data = {
        "rotation_deviation": _var("time", ys[:, 0], "rad", "wheel rotation angle minus V t / R0"),
        "angular_velocity": _var("time", ys[:, 1], "rad s-1", "angular velocity of the wheel"),
        "wheel_displacement": _var("time", ys[:, 2], "m", "vertical displacement of the wheel, upward"),
        "wheel_velocity": _var("time", ys[:, 3], "m s-1", "vertical velocity of the wheel"),
        "sprung_displacement": _var("time", ys[:, 4], "m", "vertical displacement of the sprung mass"),
        "sprung_velocity": _var("time", ys[:, 5], "m s-1", "vertical velocity of the sprung mass"),
        "rail_displacement": _var("time", ys[:, 6], "m", "vertical displacement of the rail, upward"),
        "rail_velocity": _var("time", ys[:, 7], "m s-1", "vertical velocity of the rail"),
        "normal_force": _var("time", out[:, 0], "N", "wheel-rail normal force"),
        "creepage": _var("time", out[:, 1], "1", "longitudinal creepage"),
        "creep_force": _var("time", out[:, 2], "N", "longitudinal creep force on the wheel"),
        "frictional_power": _var("time", out[:, 3], "W", "frictional power in the contact"),
        "contact_angle": _var("time", out[:, 4], "rad", "angle of the contact point on the wheel"),
        "radius_deviation_at_contact": _var("time", out[:, 5], "m", "radius deviation averaged over the contact patch"),
        "approach": _var("time", out[:, 6], "m", "Hertzian approach of wheel and rail"),
        "event_time": _var("event", np.asarray(ev_t, dtype=float), "s", "time of contact loss or regain"),
        "event_direction": _var("event", np.asarray(ev_dir, dtype=np.int64), "1", "+1 contact regained, -1 contact lost"),
    }
    return xr.Dataset(data, coords={"time": _var("time", ts, "s", "time")})


def _bogie_dataset(model, ts, ys, p, surf):
    out = k.outputs(model.kind, ts, ys, p, surf, k.BG_N_OUTPUTS)
    tw = ("time", "wheelset")
    both = lambda j: np.stack([out[:, j], out[:, 5 + j]], axis=1)  # noqa: E731
    n = model.n_states // 2  # 6, or 7 with the frame's roll
    data = {
        "lateral_displacement": _var(tw, ys[:, [0, 2]], "m", "lateral displacement of the wheelset"),
        "yaw_angle": _var(tw, ys[:, [1, 3]], "rad", "yaw angle of the wheelset"),
        "lateral_velocity": _var(tw, ys[:, [n, n + 2]], "m s-1", "lateral velocity of the wheelset"),
        "yaw_rate": _var(tw, ys[:, [n + 1, n + 3]], "rad s-1", "yaw rate of the wheelset"),
        "frame_lateral_displacement": _var("time", ys[:, 4], "m", "lateral displacement of the bogie frame"),
        "frame_yaw_angle": _var("time", ys[:, 5], "rad", "yaw angle of the bogie frame"),
        "frame_lateral_velocity": _var("time", ys[:, n + 4], "m s-1", "lateral velocity of the bogie frame"),
        "frame_yaw_rate": _var("time", ys[:, n + 5], "rad s-1", "yaw rate of the bogie frame"),
        "distance": _var("time", model.speed * ts, "m", "distance travelled"),
        "frictional_power_left": _var(tw, both(0), "W", "frictional power in the left wheel's contact"),
        "frictional_power_right": _var(tw, both(1), "W", "frictional power in the right wheel's contact"),
    }
    if n == 7:
        data["frame_roll_angle"] = _var("time", ys[:, 6], "rad", "roll angle of the bogie frame")
        data["frame_roll_rate"] = _var("time", ys[:, 13], "rad s-1", "roll rate of the bogie frame")
    if model.kind == k.KIND_TABLE_BOGIE:
        data["normal_force_lateral"] = _var(tw, both(2), "N", "lateral component of the normal forces on the wheelset")
    else:
        data["flange_force"] = _var(tw, both(2), "N", "lateral flange force on the wheelset")
    coords = {
        "time": _var("time", ts, "s", "time"),
        "wheelset": xr.Variable("wheelset", np.array(["front", "rear"]), {"long_name": "wheelset of the bogie"}),
    }
    return xr.Dataset(data, coords=coords)
