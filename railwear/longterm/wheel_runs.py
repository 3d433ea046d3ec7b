"""Disk-wheel runs shared by strategies 1 and 3: the compiled dynamics over whole revolutions with
the frictional energy swept onto the wheel cells, and its conversion to a wear depth.

The dynamics are :class:`railwear.dynamics.DiskWheelModel` on the compiled integrator
(``railwear.dynamics.integrators.integrate``, Dormand-Prince 5(4) with contact-loss events). The
energy ``E_j`` (J) a cell of the ``u`` grid received becomes the depth (paper eq. 2a with the
energy law, the patch spread ``χ`` uniform over the cells it sweeps):

    Δu_j = -β E_j / (R0 Δx w),   Δx = 2π / n,

``β`` (m³/J) the energy law's volume per frictional energy and ``w`` (m) the lateral width of the
wear band: the volume removed equals ``β`` times the frictional energy, to round-off.
"""

import hashlib
import json
import math
from dataclasses import dataclass

import numpy as np

from railwear.dynamics import integrators as integ
from railwear.errors import NumericalInstabilityError, ScenarioError


def surface(u):
    """``u`` (m) at the nodes ``2π j / n`` followed by its cumulative trapezoidal integral: the
    part of the dynamics' surface array the contact filter reads (a model's full array, with its
    creep curve, is ``DiskWheelModel.surface_for``)."""
    u = np.asarray(u, float)
    dx = 2.0 * math.pi / u.size
    return np.concatenate([u, [0.0], np.cumsum(0.5 * dx * (u + np.roll(u, -1)))])


@dataclass(frozen=True)
class Integration:
    """Options of the compiled integrator: relative and absolute tolerance (m-scale states)."""

    rtol: float = 1e-7
    atol: float = 1e-13
    max_steps: int = 50_000_000

    def __post_init__(self):
        if not 1e-13 <= self.rtol < 1:
            raise ScenarioError(f"rtol must lie in [1e-13, 1), got {self.rtol}")
        if not self.atol > 0:
            raise ScenarioError(f"atol must be > 0, got {self.atol}")


@dataclass(frozen=True)
class WheelWear:
    """What both strategies wear: a :class:`~railwear.dynamics.DiskWheelModel`, the energy law's
    ``beta`` (m³/J), the lateral ``band_width`` (m) of the wear and the ``life_distance`` (m) of
    one unit of normed time."""

    model: object
    beta: float
    band_width: float
    life_distance: float

    def __post_init__(self):
        for name in ("beta", "band_width", "life_distance"):
            if not (np.isfinite(getattr(self, name)) and getattr(self, name) > 0):
                raise ScenarioError(f"{name} must be finite and > 0")


def advance(model, p, surf, y, t0, t1, energy, options: Integration):
    """Integrate the disk wheel ``model`` (its parameter array ``p`` and surface ``surf``) from
    state ``y`` at ``t0`` to ``t1`` (s), adding the frictional energy (J) per cell to ``energy``
    (an empty array: none). Returns ``(y_end, rhs_evaluations)``."""
    out = integ.integrate(model.kind, p, surf, np.asarray(y, float), float(t0), float(t1), options.rtol,
                          options.atol, integ.METHOD_DOPRI5, 0.0, math.inf, options.max_steps,
                          np.zeros(0), 1_000_000_000, True, 1e6, energy)
    status, t_last, y_last, stats = out[3], out[4], out[5], out[6]
    if status != integ.STATUS_OK:
        raise NumericalInstabilityError(
            f"disk wheel at {model.speed:g} m/s: integration failed (status {status}) at t = {t_last:.6g} s",
            last_good=y_last.copy(), last_time=float(t_last))
    return y_last.copy(), int(stats[integ.STAT_NFEV])


def wheel_turn(model):
    """Time of one wheel revolution in steady rolling (s): ``2π R0 / (V (1 + ξ))``."""
    return 2.0 * math.pi * model.radius / (model.speed * (1.0 + model.steady_creepage()))


def start_lift(model, u, angle):
    """Lift (m) that starts the wheel at its static approach over ``u`` at contact ``angle`` (rad):
    the patch mean of ``u`` there (the contact filter of the dynamics)."""
    from railwear.dynamics import kernels

    return float(kernels.patch_average(surface(u), u.size, float(angle), model.patch_half_length / model.radius))


def depth_per_energy(model, n_cells, beta, band_width):
    """Depth (m) per joule a cell receives: ``β / (R0 Δx w)``."""
    return beta / (model.radius * (2.0 * math.pi / n_cells) * band_width)


def checked_start(u0, until, depth_limit):
    """``u0`` as a float array after the checks every strategy run makes before it starts."""
    u0 = np.asarray(u0, float)
    if u0.ndim != 1 or u0.size < 4:
        raise ScenarioError("u0 must be 1-D with at least 4 angles")
    if not until > 0:
        raise ScenarioError("until must be > 0 (normed time)")
    if depth_limit is not None and not depth_limit > 0:
        raise ScenarioError("depth_limit must be > 0 (m)")
    return u0


def result(saved, times, revolutions, rhs_evaluations, speed, attrs, extra=None):
    """The strategy interface's Dataset: ``u`` over (time [normed], angle), the stop time, the
    cost in revolutions and right-hand sides, ``speed`` (m/s), plus ``extra`` variables."""
    import xarray as xr

    saved = np.asarray(saved)
    n = saved.shape[1]
    data = {"u": (("time", "angle"), saved, {"units": "m", "long_name": "radius deviation from the nominal radius"}),
            "stop_time": ((), float(times[-1]), {"units": "1", "long_name": "normed time at which the run stopped"}),
            "cost_revolutions": ((), revolutions, {"units": "1", "long_name": "wheel revolutions simulated"}),
            "cost_rhs_evaluations": ((), rhs_evaluations,
                                     {"units": "1", "long_name": "right-hand sides of the dynamics evaluated"})}
    data.update(extra or {})
    return xr.Dataset(
        data,
        coords={"time": ("time", np.asarray(times, float), {"units": "1", "long_name": "normed life time"}),
                "angle": ("angle", 2 * np.pi * np.arange(n) / n, {"units": "rad", "long_name": "angle round the wheel"}),
                "speed": ((), float(speed), {"units": "m s-1", "long_name": "vehicle speed (mean of the service)"})},
        attrs=attrs)


def fingerprint(*parts):
    """SHA-256 of arrays and plain values, to tie a checkpoint to its problem."""
    digest = hashlib.sha256()
    for part in parts:
        if isinstance(part, np.ndarray):
            digest.update(np.ascontiguousarray(part, dtype=float).tobytes())
        else:
            digest.update(repr(part).encode())
    return digest.hexdigest()


def rng_state_text(rng):
    """The state of a ``numpy.random.Generator`` as JSON text (it holds 128-bit integers)."""
    return json.dumps(rng.bit_generator.state)


def rng_from_text(text):
    """A generator continuing from :func:`rng_state_text`."""
    state = json.loads(str(text))
    bit_generator = getattr(np.random, state["bit_generator"])()
    bit_generator.state = state
    return np.random.Generator(bit_generator)


def stop_fraction(removed, increment, depth_limit):
    """Largest ``f`` in [0, 1] with ``max_j(removed_j + f increment_j) <= depth_limit`` (m): the
    part of a linear wear increment that brings the most worn spot exactly to the limit."""
    if depth_limit is None or np.max(removed + increment) < depth_limit:
        return 1.0
    room = depth_limit - removed
    with np.errstate(divide="ignore", invalid="ignore"):
        f = np.where(increment > 0, room / increment, np.inf)
    return float(np.clip(np.min(f), 0.0, 1.0))


def fraction_done(T, until, removed, depth_limit):
    """Progress of a run at normed time ``T``: the larger of ``T / until`` and the most worn
    spot's ``max(removed) / depth_limit`` (``removed`` in m), at most 1."""
    done = T / until
    if depth_limit is not None:
        done = max(done, float(np.max(removed)) / depth_limit)
    return min(done, 1.0)


def checkpoint_from_fields(fields):
    """The checkpoint of strategy 1 or 3 (disk wheel or wheelset) from the plain fields of its
    ``.npz`` file (``None`` when the fields belong to none): the class is told by its field names."""
    from dataclasses import fields as dataclass_fields

    from railwear.longterm.direct import DirectCheckpoint
    from railwear.longterm.stepwise import StepwiseCheckpoint
    from railwear.longterm.wheelset_wear import WheelsetCheckpoint

    plain = {"str": str, "int": int, "float": float}
    for cls in (StepwiseCheckpoint, DirectCheckpoint, WheelsetCheckpoint):
        names = {f.name: getattr(f.type, "__name__", f.type) for f in dataclass_fields(cls)}
        if set(fields) == set(names):
            return cls(**{k: plain[names[k]](v) if names[k] in plain else np.asarray(v) for k, v in fields.items()})
    return None
