"""ETDRK4 time stepping of an :class:`~railwear.pde.equation.EvolutionEquation`, with its guards.

Each output interval ``t_end / (n_save - 1)`` is taken in equal steps per row (the compiled loop
of :mod:`railwear.pde.etdrk4`; a callable ``h`` takes the Python loop with one step for all
rows). Around that:

- step control: the interval is taken again with half the steps; ``|u - u_half| / 15``
  (Richardson, order 4) over the out-of-round deviation estimates its error; a row over
  ``rtol · interval / t_end`` repeats it with twice the steps, one 32 times under halves them;
- guards: a non-finite value or an amplitude 10⁶ times the start's repeats the interval with half
  the step and ``S`` recomputed, up to ``max_halvings`` times (then
  :class:`~railwear.errors.NumericalInstabilityError`); growth at the top of the spectrum raises
  :class:`~railwear.errors.IllPosedError`;
- depth limit: a row stops where its most worn spot has lost ``depth_limit`` (m);
- a checkpoint after every interval, from which a resumed run is bit for bit the uninterrupted one.

On the compiled path the rows of a batch are independent: a row that fails its Richardson check
or its guard takes the interval again alone (the others keep their result), and the ETDRK4
weights are kept per row and step count, so every row of a batch is bit for bit the solve of that
row alone, and a batch costs at most what its rows cost apart. Two things stay shared: the guard's
blow-up bound (10⁶ times the largest start amplitude of the batch, the same for rows that start
alike) and the batch's stop on an ill-posed row.
"""

import hashlib
import math
import sys
import warnings
from dataclasses import dataclass

import numpy as np

from railwear.checkpoints import wanted
from railwear.errors import IllPosedError, NumericalInstabilityError, ResolutionWarning, ScenarioError
from railwear.pde.etdrk4 import OK, ETDCoefficients, advance_compiled, advance_python, etdrk4_coefficients

TAIL_GROWTH = 1e3  # growth of the top of the spectrum, over its start, that counts as ill-posed
_FIELDS = ("E", "E2", "Q", "f1", "f2", "f3")  # the ETDRK4 weights kept per row
CHUNK_COPIES = 64  # step counts x rows per call of the compiled loop (see _chunks)


@dataclass(frozen=True)
class EvolutionCheckpoint:
    """Everything needed to continue a solve bit for bit after output interval ``intervals``.

    ``fingerprint`` identifies the problem (initial state, speeds, ``h``, parameters); the rest is
    the loop's state: spectra saved so far with their times, the present spectra, the rows still
    running and the stop times of the others, the steps per interval of each row, the halvings
    spent and the stabilisation ``S`` in force.
    """

    fingerprint: str
    intervals: int
    steps: np.ndarray
    halvings: int
    stabilisation: np.ndarray
    spectra: np.ndarray
    active: np.ndarray
    stop_time: np.ndarray
    saved: np.ndarray
    times: np.ndarray
    tail_peak: np.ndarray


@dataclass(frozen=True)
class EvolutionRun:
    """What a solve returns: output ``times`` (normed), the spectra ``saved`` there (time, batch,
    n // 2 + 1), each row's ``stop_time`` and last ``time_step``, the stabilisation ``S`` in force
    at the end (rad² per unit time) and ``spectral_tail``, the largest share of the top quarter of
    the kept orders in the largest amplitude met per row."""

    times: np.ndarray
    saved: np.ndarray
    stop_time: np.ndarray
    time_step: np.ndarray
    stabilisation: np.ndarray
    spectral_tail: np.ndarray


def _richardson_error(v, v_half, n):
    """Per row: ``|u - u_half|_2 / 15`` over the out-of-round part ``|u - mean u|_2`` (floor 1 nm rms)."""
    diff = np.fft.irfft(v - v_half, n, axis=-1)
    dev = np.fft.irfft(np.concatenate([np.zeros_like(v[:, :1]), v[:, 1:]], axis=1), n, axis=-1)
    scale = np.maximum(np.sqrt(np.mean(dev**2, axis=-1)), 1e-9)
    return np.sqrt(np.mean(diff**2, axis=-1)) / 15 / scale


def _chunks(row_steps, active):
    """The ``active`` rows sorted by step count and cut into chunks whose distinct counts times
    rows stay within :data:`CHUNK_COPIES` (the rows the loop's re-gathers copy): 64 rows of one
    count go in one call, 64 of different counts in 8 calls of 8 (measured on 64 speeds of the
    Fig. 11 case: a third less time than one call per count, chunks of 8 and 16 alike)."""
    rows = np.flatnonzero(active)
    rows = rows[np.argsort(row_steps[rows], kind="stable")]
    chunks, start, counts = [], 0, 1
    for i in range(1, rows.size):
        counts += row_steps[rows[i]] != row_steps[rows[i - 1]]
        if counts * (i - start + 1) > CHUNK_COPIES:
            chunks.append(rows[start:i])
            start, counts = i, 1
    chunks.append(rows[start:])
    return chunks


def _tail(equation, v):
    """Largest amplitude per row in the top quarter of the kept orders, and overall."""
    amp = np.abs(v[:, 1 : equation.kept + 1])
    top = amp[:, int(0.75 * equation.kept) :]
    return top.max(axis=1), amp.max(axis=1)


def _outside_pde():
    """``stacklevel`` of the first caller outside railwear.pde, for warnings."""
    frame, level = sys._getframe(1), 1
    while frame is not None and frame.f_globals.get("__name__", "").startswith("railwear.pde"):
        frame, level = frame.f_back, level + 1
    return level


@dataclass(frozen=True)
class ETDRK4Solver:
    """Options of the loop (see :func:`railwear.pde.solve_evolution` for each): a fixed ``dt`` or
    the step control's ``rtol``, ``n_save`` output times, the split's ``stabilisation`` ``S``,
    ``depth_limit`` (m), ``tail_tolerance``, ``max_halvings`` and ``resolution_tolerance``."""

    dt: float | None = None
    n_save: int = 101
    stabilisation: float | None = None
    depth_limit: float | None = None
    tail_tolerance: float = 1e-3
    max_halvings: int = 6
    rtol: float | None = 1e-4
    resolution_tolerance: float = 3e-5

    def __post_init__(self):
        if int(self.n_save) < 2:
            raise ScenarioError("n_save must be at least 2")
        if self.depth_limit is not None and not self.depth_limit > 0:
            raise ScenarioError(f"depth_limit must be > 0 (m), got {self.depth_limit}")
        if self.dt is not None and not (np.isfinite(self.dt) and self.dt > 0):
            raise ScenarioError(f"dt must be > 0, got {self.dt}")
        if self.dt is None and self.rtol is not None and not self.rtol > 0:
            raise ScenarioError(f"rtol must be > 0, got {self.rtol}")

    def fingerprint(self, equation, t_end):
        """Identifies the problem and the options a checkpoint belongs to."""
        eq = equation
        odd = (tuple(eq.drift), tuple(eq.dispersion)) if np.any(eq.drift) or np.any(eq.dispersion) else None
        parameters = (t_end, eq.epsilon, eq.nu, self.dt, self.n_save, eq.dealias, self.stabilisation,
                      self.depth_limit, self.tail_tolerance, self.max_halvings, self.rtol, odd)
        digest = hashlib.sha256()
        digest.update(np.ascontiguousarray(eq.u0).tobytes())
        digest.update(np.ascontiguousarray(eq.speeds).tobytes())
        digest.update(eq.fingerprint_bytes())
        name = getattr(getattr(eq.h, "func", None), "__qualname__", None) or repr(eq.h)
        digest.update(repr((name,) + parameters).encode())
        return digest.hexdigest()

    def solve(self, equation, t_end, *, progress=None, checkpoint=None, resume=None):
        """Advance ``equation`` over normed time ``[0, t_end]``; returns an :class:`EvolutionRun`.

        ``progress(fraction)`` and ``checkpoint(EvolutionCheckpoint)`` are called after each
        output interval; ``resume`` continues from a checkpoint of the same problem.
        """
        if not np.isfinite(t_end) or t_end < 0:
            raise ScenarioError(f"t_end must be finite and >= 0, got {t_end}")
        if t_end == 0:
            raise ScenarioError("t_end must be > 0")
        loop = _Loop(self, equation, t_end)
        if resume is not None:
            if resume.fingerprint != loop.fingerprint:
                raise ScenarioError("resume: the checkpoint belongs to another problem")
            loop.restore(resume)
        while loop.intervals < self.n_save - 1:
            if not loop.step_interval():
                continue
            if not np.any(loop.active):
                break
            if wanted(checkpoint):
                checkpoint(loop.checkpoint())
            if progress is not None:
                progress(loop.intervals / (self.n_save - 1))
        if progress is not None:
            progress(1.0)
        return loop.result()


class _Loop:
    """The state of one solve between output intervals, and one interval's step."""

    def __init__(self, solver, equation, t_end):
        self.solver, self.eq, self.t_end = solver, equation, t_end
        eq = equation
        self.fingerprint = solver.fingerprint(eq, t_end)
        # C-ordered arrays throughout: the compiled loop is typed (and compiled) once per layout
        self.u_start = np.ascontiguousarray(eq.u0)
        v = np.ascontiguousarray(np.fft.rfft(eq.u0, axis=-1))
        if eq.ill_posed(v):
            raise IllPosedError(
                "h decreases with u_xx at the start and neither epsilon nor nu regularises it: "
                "the equation is ill-posed", last_good=eq.u0, last_time=0.0)
        self.restabilise(v)
        self.interval = interval = t_end / (solver.n_save - 1)
        self.rtol = solver.rtol if solver.dt is None else None
        if solver.dt is None:
            # Each row its own step: the largest growth rate met sets σ Δt <= 0.25.
            steps = np.ceil(interval * eq.growth_bound(v) / 0.25)
            steps = np.maximum(steps, math.ceil(interval / (t_end / 200) * (1 - 1e-12)))
        else:
            steps = np.full(len(eq.speeds), math.ceil(interval / solver.dt * (1 - 1e-12)))
        steps = np.maximum(steps, 1).astype(np.int64)
        if not eq.compiled:
            steps[:] = steps.max()
        self.tail_start, self.amp_start = _tail(eq, v)
        self.tail_ref = np.maximum(self.tail_start, solver.tail_tolerance * self.amp_start)
        self.tail_peak = self.tail_start / np.maximum(self.amp_start, 1e-300)
        # A million times the largest out-of-round mode at the start, or than 1 nm of amplitude.
        self.blowup = 1e6 * max(float(np.max(np.abs(v[:, 1:]))), 0.5e-9 * eq.n)
        self.depth = float(solver.depth_limit) if solver.depth_limit is not None else 0.0
        if self.rtol is not None:
            steps = steps + steps % 2  # even, so that half the steps is exact
            self.local_tolerance = self.rtol * interval / t_end  # errors of the intervals add up to about rtol
        self.steps = steps
        self.v = v
        self.active = np.ones(len(eq.speeds), dtype=bool)
        self.stop_time = np.full(len(eq.speeds), np.nan)
        self.saved, self.times = [v.copy()], [0.0]
        self.halvings = np.zeros(len(eq.speeds), dtype=np.int64)  # per row
        self.intervals = 0

    def restabilise(self, v, S=None, rows=None):
        """Set ``S`` per row (given, fixed, or the largest slope met at ``v``) and drop the weights;
        with ``rows`` (a mask) only those rows change."""
        if S is not None:
            S = np.asarray(S, float)
        elif self.solver.stabilisation is not None:
            S = np.full(len(self.eq.speeds), float(self.solver.stabilisation))
        else:
            S = np.maximum(self.eq.max_slope(v), 0.0)
        if rows is None:
            self.weights = {}
        else:
            S = np.where(rows, S, self.S)
            self.weights = {key: w for key, w in self.weights.items() if not rows[key[0]]}
            for _, held in self.slots.values():
                held[rows] = 0
        self.S = S
        self.L = self.eq.linear(S)
        self.terms = tuple(map(np.ascontiguousarray, self.eq.compiled_terms(S))) if self.eq.compiled else None
        self.multipliers = (np.ascontiguousarray(self.eq.m_in), np.ascontiguousarray(self.eq.m_out))
        if rows is None:
            self.slots = {}

    def restore(self, c):
        self.intervals, self.steps = c.intervals, c.steps.copy()
        self.halvings = np.full(len(self.steps), int(c.halvings))
        self.v, self.active, self.stop_time = c.spectra.copy(), c.active.copy(), c.stop_time.copy()
        self.saved, self.times = list(c.saved), list(c.times)
        self.tail_peak = c.tail_peak.copy()
        self.restabilise(self.v, c.stabilisation)

    def checkpoint(self):
        # The checkpoint's format holds one count of halvings: the largest of the rows' (a
        # resumed run gives it to every row, so it can only stop sooner at max_halvings).
        return EvolutionCheckpoint(self.fingerprint, self.intervals, self.steps.copy(), int(self.halvings.max()),
                                   self.S.copy(), self.v.copy(), self.active.copy(),
                                   self.stop_time.copy(), np.array(self.saved), np.array(self.times),
                                   self.tail_peak.copy())

    def _weights(self, row_steps, rows, slot):
        """The ETDRK4 weights with row ``b`` in ``row_steps[b]`` steps per interval, right for the
        ``rows`` (a mask). Each row's weights are computed once per step count (and ``S``) and
        copied into the arrays of ``slot`` (one set for the full and one for the half steps)."""
        if slot not in self.slots:
            shape, dtype = self.L.shape, (float if not np.iscomplexobj(self.L) or not np.any(self.L.imag) else complex)
            self.slots[slot] = (ETDCoefficients(np.ones(shape[0]), *(np.zeros(shape, dtype) for _ in range(6))),
                                np.zeros(shape[0], np.int64))
        co, held = self.slots[slot]
        change = np.flatnonzero(rows & (held != row_steps))
        missing = np.array([b for b in change if (b, int(row_steps[b])) not in self.weights], dtype=np.int64)
        odd = np.any(self.L[missing].imag != 0, axis=1) if np.iscomplexobj(self.L) else np.zeros(missing.size, bool)
        for group in (missing[~odd], missing[odd]):  # a row without drift takes the real weights, as alone
            if group.size:
                new = etdrk4_coefficients(self.L[group], self.interval / row_steps[group])
                for i, b in enumerate(group):
                    self.weights[b, int(row_steps[b])] = tuple(getattr(new, f)[i] for f in _FIELDS)
        for b in change:
            for name, value in zip(_FIELDS, self.weights[b, int(row_steps[b])]):
                getattr(co, name)[b] = value
            co.dt[b] = self.interval / row_steps[b]
            held[b] = row_steps[b]
        return co

    def _advance(self, v, row_steps, t0, active, stop_time, slot):
        """Advance ``v`` in place over one interval in ``row_steps`` per row; returns the status.

        The compiled loop takes the rows in the chunks of :func:`_chunks`: it gathers its running
        rows anew whenever one is done, so one call on a whole batch of different step counts
        would copy the batch once per row (a cost that grows as the batch size squared), while a
        chunk still shares its transforms."""
        if not self.eq.compiled:
            co = self._weights(row_steps, np.ones_like(active), slot)
            status, _ = advance_python(v, co, lambda w: self.eq.nonlinear(w, self.S), int(row_steps[0]), t0,
                                       active, stop_time, self.u_start, self.depth, self.blowup)
            return status
        co = self._weights(row_steps, active, slot)
        for chunk in _chunks(row_steps, active):
            running = np.zeros_like(active)
            running[chunk] = True
            status, _ = advance_compiled(
                v, self.eq.n, co.E, co.E2, co.Q, co.f1, co.f2, co.f3, *self.multipliers,
                *self.terms, row_steps, co.dt, t0, running, stop_time, self.u_start, self.depth, self.blowup)
            active[chunk] = running[chunk]
            if status != OK:
                return status
        return OK

    def _attempt(self, v_start, stop_start, rows, row_steps, t0, slot):
        """The ``rows`` (a mask) over the interval from ``v_start``: ``(v, active, stop_time,
        status per row)``. Where the batch's guard fails, the rows are taken again one by one to
        find which failed (compiled path; the Python loop's status is every row's)."""
        v, active, stop = v_start.copy(), rows.copy(), stop_start.copy()
        status = self._advance(v, row_steps, t0, active, stop, slot)
        out = np.full(len(rows), OK)
        if status == OK:
            return v, active, stop, out
        if not self.eq.compiled or np.count_nonzero(rows) == 1:
            out[rows] = status
            return v, active, stop, out
        for b in np.flatnonzero(rows):
            one = np.zeros_like(rows)
            one[b] = True
            vb, ab, sb = v_start.copy(), one.copy(), stop_start.copy()
            out[b] = self._advance(vb, row_steps, t0, ab, sb, slot)
            v[b], active[b], stop[b] = vb[b], ab[b], sb[b]
        return v, active, stop, out

    def step_interval(self):
        """Take the next output interval, each row again with other steps until it passes its
        checks (only the rows that failed); ``True`` when done."""
        eq, n, t0 = self.eq, self.eq.n, self.intervals * self.interval
        v_start, active_start, stop_start = self.v.copy(), self.active.copy(), self.stop_time.copy()
        todo = active_start.copy()
        while np.any(todo):
            v, active, stop, status = self._attempt(v_start, stop_start, todo, self.steps, t0, "full")
            failed = todo & (status != OK)
            ok = todo & ~failed
            refine = coarsen = np.zeros_like(todo)
            if self.rtol is not None and np.any(ok):
                v_half, _, _, status_half = self._attempt(v_start, stop_start, ok, self.steps // 2, t0, "half")
                error = np.zeros(len(todo))
                error[ok] = _richardson_error(v[ok], v_half[ok], n)
                refine = ok & ((error > self.local_tolerance) | (status_half != OK))
                coarsen = ok & ~refine & (error < self.local_tolerance / 32) & (self.steps % 4 == 0)
            if not eq.compiled:  # the Python loop: one step count for all rows, all retake together
                if np.any(failed) or np.any(refine):
                    failed, refine = (todo, refine & False) if np.any(failed) else (failed, todo)
                coarsen = np.full_like(todo, bool(np.any(ok)) and bool(np.all(coarsen[ok])))
            accept = todo & ~failed & ~refine
            self.v[accept], self.active[accept], self.stop_time[accept] = v[accept], active[accept], stop[accept]
            self.steps = np.where(coarsen, self.steps // 2, self.steps)
            if np.any(refine):
                self.steps = np.where(refine, 2 * self.steps, self.steps)
                if self.steps.max() > 2**24:
                    raise NumericalInstabilityError(
                        f"the step-size control cannot meet rtol = {self.rtol:g} near T = {t0:.4g}",
                        last_good=np.fft.irfft(v_start, n, axis=-1), last_time=t0)
            if np.any(failed):
                self.halvings[failed] += 1
                if np.any(self.halvings > self.solver.max_halvings):
                    raise NumericalInstabilityError(
                        f"the solution blew up near T = {t0:.4g} even with the step cut to "
                        f"{self.interval / self.steps[failed].max():.3g}",
                        last_good=np.fft.irfft(v_start, n, axis=-1), last_time=t0)
                again = failed if eq.compiled else np.ones_like(failed)
                self.steps = np.where(again, 2 * self.steps, self.steps)
                self.restabilise(v_start, rows=again if eq.compiled else None)
            todo = failed | refine
        tail, amp = _tail(eq, self.v)
        bad = (tail > self.solver.tail_tolerance * amp) & (tail > TAIL_GROWTH * np.maximum(self.tail_ref, 1e-300))
        self.tail_peak = np.maximum(self.tail_peak, tail / np.maximum(amp, 1e-300))
        if np.any(bad):
            raise IllPosedError(
                f"growth at the grid scale near T = {t0 + self.interval:.4g}: the equation is ill-posed "
                "or under-resolved (raise epsilon or nu, or the number of points)",
                last_good=np.fft.irfft(v_start, n, axis=-1), last_time=t0)
        self.intervals += 1
        self.saved.append(self.v.copy())
        self.times.append(float(np.nanmax(self.stop_time)) if not np.any(self.active)
                          else self.intervals * self.interval)
        return True

    def result(self):
        n = self.eq.n
        start_ratio = self.tail_start / np.maximum(self.amp_start, 1e-300)
        coarse = (self.tail_peak > self.solver.resolution_tolerance) & (self.tail_peak > 10 * start_ratio)
        if np.any(coarse):
            warnings.warn(
                f"the top quarter of the kept orders reached {self.tail_peak.max():.2g} of the largest "
                f"amplitude: {n} points may not resolve this run; compare with {2 * n}",
                ResolutionWarning, stacklevel=_outside_pde())
        stop = np.where(np.isnan(self.stop_time), self.times[-1], self.stop_time)
        return EvolutionRun(np.array(self.times), np.array(self.saved), stop, self.interval / self.steps,
                            self.S, self.tail_peak)
