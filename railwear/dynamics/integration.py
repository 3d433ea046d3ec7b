"""``Integrator``: the options of the compiled integration loop as one object, and its result.

``railwear.dynamics.integrators.integrate`` takes 17 positional arguments; ``Integrator`` names
them, checks them once and returns an ``IntegrationResult`` with named fields:

    integrator = Integrator(method="dop853", rtol=1e-9, atol=1e-11)
    run = integrator.run(model.kind, model.params(), model.surface(), model.initial_state(), 0.0, 2.0,
                         t_eval=np.linspace(0.0, 2.0, 201)).check("hunting wheelset")
    run.y_out[-1], run.stats.rhs_evaluations

The methods, error control, events and switch cuts are those of ``integrators`` (Dormand-Prince
5(4), Dormand-Prince 8(5,3), Rosenbrock 2(3); Hairer, Norsett & Wanner, Solving ODE I, II.4-II.10;
Shampine & Reichelt 1997). The same options give the same numbers as ``integrate`` bit for bit.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from railwear.dynamics import integrators as _integ
from railwear.errors import NumericalInstabilityError, ScenarioError

__all__ = ["IntegrationResult", "IntegrationStats", "Integrator"]

_EPS = np.finfo(float).eps
_NO_INTERMEDIATE_OUTPUT = np.iinfo(np.int64).max  # "every n steps" that never comes


@dataclass(frozen=True)
class IntegrationStats:
    """Counters of a run (``integrators.STAT_*``); ``a + b`` adds two runs' counters."""

    rhs_evaluations: int
    accepted_steps: int
    rejected_steps: int
    jacobian_evaluations: int
    events: int

    @classmethod
    def from_array(cls, stats) -> IntegrationStats:
        s = [int(v) for v in stats]
        return cls(s[_integ.STAT_NFEV], s[_integ.STAT_NACCEPT], s[_integ.STAT_NREJECT], s[_integ.STAT_NJAC],
                   s[_integ.STAT_NEVENTS])

    def __add__(self, other: IntegrationStats) -> IntegrationStats:
        return IntegrationStats(*(a + b for a, b in zip(vars(self).values(), vars(other).values())))


@dataclass(frozen=True, eq=False)
class IntegrationResult:
    """What one ``Integrator.run`` gives.

    ``status``: ``integrators.STATUS_*`` (``success`` when ``STATUS_OK``), ``message`` says why
    not; ``t`` [s], ``y``: the last accepted time and state; ``stats``: ``IntegrationStats``;
    ``t_out``, ``y_out``: the output times and states (rows); ``event_t``, ``event_y``,
    ``event_direction``: the located events (+1 when the event function turns positive, e.g.
    contact regained; -1 contact lost).
    """

    status: int
    t: float
    y: np.ndarray
    stats: IntegrationStats
    t_out: np.ndarray
    y_out: np.ndarray
    event_t: np.ndarray
    event_y: np.ndarray
    event_direction: np.ndarray
    message: str

    @property
    def success(self) -> bool:
        return self.status == _integ.STATUS_OK

    def check(self, what: str) -> IntegrationResult:
        """``self`` if the run succeeded, else ``NumericalInstabilityError`` naming ``what``, with
        the last good state and time."""
        if not self.success:
            raise NumericalInstabilityError(f"{what}: {self.message} at t = {self.t:.6g} s",
                                            last_good=self.y.copy(), last_time=float(self.t))
        return self


@dataclass(frozen=True)
class Integrator:
    """Options of the compiled integrator (``railwear.dynamics.integrators.integrate``).

    ``method``: ``"dopri5"``, ``"dop853"`` or ``"rosenbrock"``; ``rtol`` [-] and ``atol`` (units
    of the states) in the weighted RMS norm ``|e_i| / (atol + rtol max(|y_i|, |y_new_i|))``;
    ``max_steps``: step budget (status ``STATUS_MAX_STEPS``); ``first_step`` [s], 0: chosen by
    Hairer, Norsett & Wanner's starting-step algorithm; ``max_step`` [s]; ``max_norm``: status
    ``STATUS_BLOW_UP`` when any ``|y_i|`` exceeds it; ``events``: locate sign changes of the
    model's event function (``kernels.event``, the disk wheel's contact loss) and end the step
    there; ``output_every``: without ``t_eval``, output at ``t0``, every that many accepted steps
    and ``t_end`` (``None``: ``t0`` and ``t_end`` only); ``cut_at_switches``: retry a rejected
    step across a flange switch up to it (``False`` only to measure what that saves).

    ``run(kind, params, surface, y0, t0, t_end, *, t_eval=None, energy=None)`` integrates the
    model ``kind`` (``kernels.KIND_*``, with its parameter and surface arrays, e.g.
    ``model.params()``, ``model.surface()``) from ``y0`` at ``t0`` to ``t_end`` [s] and returns an
    ``IntegrationResult``. ``t_eval``: ascending output times in ``[t0, t_end]`` (dense output).
    ``energy``: a float64 array, one value per wheel cell, to which the run adds the frictional
    energy [J] each cell received (disk wheel; in place). Bad options raise ``ScenarioError``.
    """

    method: str = "dopri5"
    rtol: float = 1e-8
    atol: float = 1e-10
    max_steps: int = 10_000_000
    first_step: float = 0.0
    max_step: float = math.inf
    max_norm: float = 1e6
    events: bool = False
    output_every: int | None = None
    cut_at_switches: bool = True

    def __post_init__(self):
        if self.method not in _integ.METHODS:
            raise ScenarioError(f"method: must be one of {sorted(_integ.METHODS)}, got {self.method!r}")
        rtol, atol = float(self.rtol), float(self.atol)
        if not (100.0 * _EPS <= rtol < 1.0):
            raise ScenarioError(
                f"rtol: cannot be met in double precision or is meaningless; need 2.2e-14 <= rtol < 1, got {rtol!r}"
            )
        if not (atol > 0.0 and math.isfinite(atol)):
            raise ScenarioError(f"atol: must be a positive finite number, got {atol!r}")
        if int(self.max_steps) < 1:
            raise ScenarioError(f"max_steps: must be at least 1, got {self.max_steps!r}")
        if not (float(self.first_step) >= 0.0 and math.isfinite(self.first_step)):
            raise ScenarioError(f"first_step: must be 0 (automatic) or a positive time [s], got {self.first_step!r}")
        if not (float(self.max_step) > 0.0):
            raise ScenarioError(f"max_step: must be positive, got {self.max_step!r}")
        if not (float(self.max_norm) > 0.0):
            raise ScenarioError(f"max_norm: must be positive, got {self.max_norm!r}")
        if self.output_every is not None and not (int(self.output_every) == self.output_every >= 1):
            raise ScenarioError(f"output_every: must be a positive number of steps, got {self.output_every!r}")
        # plain types, so that every run meets the same compiled specialisation
        for name, kind in (("rtol", float), ("atol", float), ("max_steps", int), ("first_step", float),
                           ("max_step", float), ("max_norm", float), ("events", bool), ("cut_at_switches", bool)):
            object.__setattr__(self, name, kind(getattr(self, name)))
        if self.output_every is not None:
            object.__setattr__(self, "output_every", int(self.output_every))

    @property
    def method_id(self) -> int:
        """The method's ``integrators.METHOD_*`` number."""
        return _integ.METHODS[self.method]

    def run(self, kind, params, surface, y0, t0, t_end, *, t_eval=None, energy=None, clock=None) -> IntegrationResult:
        """Integrate; see the class docstring. ``clock`` (a float64 array of one element) receives
        the time of each accepted step while the compiled loop runs (``integrators.integrate``)."""
        y0 = np.ascontiguousarray(y0, dtype=float)
        if y0.ndim != 1:
            raise ScenarioError(f"y0: must be a 1-D state, got shape {y0.shape}")
        t_eval = np.zeros(0) if t_eval is None else np.ascontiguousarray(t_eval, dtype=float)
        if t_eval.size and self.output_every is not None:
            raise ScenarioError("output_every: give either t_eval or output_every, not both")
        if energy is None:
            energy = np.zeros(0)
        elif not (isinstance(energy, np.ndarray) and energy.dtype == np.float64 and energy.ndim == 1
                  and energy.flags.c_contiguous and energy.flags.writeable):
            raise ScenarioError("energy: must be a writeable 1-D float64 array (the run adds to it in place)")
        every = _NO_INTERMEDIATE_OUTPUT if self.output_every is None else self.output_every
        # the switch cuts are the compiled default: pass the flag only to turn them off, so that
        # the usual call meets the specialisation already compiled for callers of ``integrate``
        extra = () if self.cut_at_switches else (False,)
        if clock is not None:
            if not (isinstance(clock, np.ndarray) and clock.dtype == np.float64 and clock.shape == (1,)
                    and clock.flags.writeable):
                raise ScenarioError("clock: must be a writeable float64 array of one element")
            extra = (self.cut_at_switches, clock)
        ts, ys, n_out, status, t_last, y_last, stats, ev_t, ev_y, ev_dir = _integ.integrate(
            int(kind), params, surface, y0, float(t0), float(t_end), self.rtol, self.atol, self.method_id,
            self.first_step, self.max_step, self.max_steps, t_eval, every, self.events, self.max_norm, energy, *extra)
        return IntegrationResult(status=int(status), t=float(t_last), y=y_last, stats=IntegrationStats.from_array(stats),
                                 t_out=ts[:n_out], y_out=ys[:n_out], event_t=ev_t, event_y=ev_y,
                                 event_direction=ev_dir, message="" if status == _integ.STATUS_OK else self._message(status))

    def _message(self, status) -> str:
        return {
            _integ.STATUS_MAX_STEPS: f"max_steps = {self.max_steps} reached",
            _integ.STATUS_STEP_TOO_SMALL:
                "the step size fell to round-off (tolerance cannot be met or the solution is singular)",
            _integ.STATUS_BLOW_UP: f"a state exceeded max_norm = {self.max_norm:g}",
        }[status]
