"""The one long-term loop (layer 3): steps of a strategy on a body until the end or the depth.

:func:`drive` owns what every stepped run shares: the seeded generator, the depth limit (a step
that would pass it is cut so the most worn spot lands on it exactly), the end time, the save
marks, the Monte Carlo variance, the wear law's volume, and the observers (progress and
checkpoint, called at every save, in the pattern of py-pde's trackers). A strategy supplies one
``advance(body, state, until)`` returning a :class:`Step`; the body supplies the physics.
"""

import time as _time
from dataclasses import dataclass

import numpy as np

from railwear.checkpoints import wanted
from railwear.errors import ScenarioError
from railwear.longterm.base import (Checkpoint, WearState, checked_run, cost_variables, fingerprint, fraction_done,
                                    plain_value, rng_from_text, rng_state_text, stop_fraction, stop_time)

LIMIT_SLACK = 1 - 1e-12  # the depth counts as reached within round-off


@dataclass(frozen=True)
class Step:
    """One long-term step: the wear ``increment`` over ``dT`` (normed time), ``final`` when
    ``dT`` is exactly what is left to ``until``, the law's volume (m³), the body's record of the
    runs, and for Monte Carlo steps the standard ``errors`` with their ``weights`` (the
    variance grows by ``Σ (w s dT)²``) and the rate kept for the next step."""

    increment: np.ndarray
    dT: float
    final: bool
    law_volume: float
    seen: object = None
    errors: tuple = ()
    weights: tuple = ()
    previous: tuple = ()


def drive(strategy, body, u0, until, depth_limit, *, settings=(), seed=0, n_save=None, max_steps=100_000,
          too_many="steps did not reach the end", progress=None, checkpoint=None, resume=None, coupled=None):
    """Run ``strategy.advance`` on ``body`` from ``u0`` to normed time ``until`` or the removed
    ``depth_limit`` (m); saves after every step (``n_save`` None) or at ``n_save`` marks evenly
    spaced in time and in depth. ``settings``: the strategy's own values that identify its
    problem (for checkpoints); ``seed`` the generator's; ``max_steps`` and ``too_many`` the bound
    on the steps and what to say past it; ``progress(fraction)``, ``checkpoint(Checkpoint)`` the
    observers and ``resume`` a :class:`~railwear.longterm.base.Checkpoint` to continue from;
    ``coupled`` the acceleration factor of a coupled run (its carry is started once). Returns the
    body's result Dataset with the contract's attributes."""
    started = _time.perf_counter()
    checked_run(until, depth_limit)
    u_start = body.start(u0)
    key = fingerprint(strategy.name, *settings, seed, n_save, np.zeros(0) if u0 is None else np.asarray(u0, float),
                      until, depth_limit, *body.fingerprint_parts())
    time_marks = None if n_save is None else np.linspace(0.0, until, n_save)
    depth_marks = None if n_save is None or depth_limit is None else np.linspace(0.0, depth_limit, n_save)
    if resume is None:
        state = _start(body, u_start, seed, coupled)
        cost_variables(state.cost)  # an unknown counter fails before the run, not after it
    else:
        state = _restore(body, resume, strategy.name, key, u_start)

    def reached():
        return depth_limit is not None and np.max(body.removed(state.u, u_start)) >= depth_limit * LIMIT_SLACK

    while state.time < until and not reached():
        if state.steps >= max_steps:
            raise ScenarioError(f"{strategy.name}: {max_steps} {too_many}")
        step = strategy.advance(body, state, until)
        frac = stop_fraction(body.removed(state.u, u_start), body.removal(step.increment), depth_limit)
        frac_time = 1.0 if step.final else (until - state.time) / step.dT
        if frac_time <= min(frac, 1.0):
            share, state.time = frac_time, until
        else:
            share, state.time = frac, state.time + frac * step.dT
        state.u = body.apply(state.u, share * step.increment if share != 1.0 else step.increment)
        if step.errors:
            dT = share * step.dT
            for w, e in zip(step.weights, step.errors):
                state.variance = state.variance + (w * e * dT) ** 2
        state.law_volume += share * step.law_volume
        state.previous = step.previous
        state.steps += 1
        body.update(state.u, state.cost)
        done = state.time >= until or reached()
        due = n_save is None or state.time >= time_marks[min(state.mark, n_save - 1)]
        if depth_marks is not None:
            due = due or np.max(body.removed(state.u, u_start)) >= depth_marks[min(state.mark, n_save - 1)]
        if not (due or done):
            continue
        _save(body, state, step.seen, u_start)
        if n_save is not None:
            removed = np.max(body.removed(state.u, u_start))
            while state.mark < n_save and (state.time >= time_marks[state.mark] or (
                    depth_marks is not None and removed >= depth_marks[state.mark])):
                state.mark += 1
        if wanted(checkpoint):  # before the progress: a fraction reported is a fraction saved
            checkpoint(_snapshot(strategy.name, key, state))
        if progress is not None:
            progress(fraction_done(state.time, until, body.removed(state.u, u_start), depth_limit))
    saved = state.saved
    errors = saved.pop("_error")
    times = saved.pop("_time")
    removed = np.array(saved.pop("_removed"), float)
    errors = errors if strategy.monte_carlo else None
    ds = body.result(saved, times, state.cost, errors, strategy.attributes(state))
    ds["removed_depth"] = ("time", removed, {"units": "m", "long_name": "largest depth lost since the start "
                                                                   "(most worn spot)"})
    ds["stop_time"] = stop_time(times)
    ds = ds.assign(cost_variables(state.cost))
    ds.attrs.update(strategy=strategy.name, body=body.name, scenario_hash=ds.attrs.get("scenario_hash", ""),
                    wall_seconds=_time.perf_counter() - started)
    return ds


def _start(body, u_start, seed, coupled):
    rng = np.random.default_rng(seed)
    cost = body.new_cost()
    body.update(u_start, cost)
    state = WearState(0.0, 0, u_start.copy(), np.zeros(0), 0.0, (), {}, 1, cost, {}, rng)
    state.variance = np.zeros(body.error_shape(u_start))
    _save(body, state, None, u_start)
    if coupled is not None:
        state.carry = body.couple(state.u, rng, coupled, cost)
    return state


def _save(body, state, seen, u_start):
    record = body.record(state.u, seen, state.law_volume)
    record["_time"] = state.time
    record["_error"] = np.sqrt(state.variance)
    record["_removed"] = max(float(np.max(body.removed(state.u, u_start))), 0.0)  # round-off below the start: 0
    for k, v in record.items():
        state.saved.setdefault(k, []).append(v)


def _snapshot(kind, key, state):
    """The :class:`Checkpoint` of a run's state (copies)."""
    fields = {"time": state.time, "steps": state.steps, "u": state.u.copy(), "variance": state.variance.copy(),
              "law_volume": state.law_volume, "mark": state.mark, "rng_state": rng_state_text(state.rng),
              "previous_count": len(state.previous)}
    fields.update({f"previous_{i}": np.array(v, float) for i, v in enumerate(state.previous)})
    fields.update({f"carry_{k}": np.array(v) for k, v in state.carry.items()})
    fields.update({f"cost_{k}": v for k, v in state.cost.items()})
    fields.update({f"saved_{k}": np.array(v) for k, v in state.saved.items()})
    return Checkpoint(kind, key, fields)


def _restore(body, resume, kind, key, u_start):
    """The :class:`WearState` of a checkpoint of this problem."""
    resume.check(kind, key, body.label)
    f = resume.fields
    try:
        previous = tuple(plain_value(f[f"previous_{i}"]) for i in range(int(f["previous_count"])))
        state = WearState(
            float(f["time"]), int(f["steps"]), np.array(f["u"], float), np.array(f["variance"], float),
            float(f["law_volume"]), previous,
            {k[len("carry_"):]: plain_value(v) for k, v in f.items() if k.startswith("carry_")}, int(f["mark"]),
            {k[len("cost_"):]: plain_value(v) for k, v in f.items() if k.startswith("cost_")},
            {k[len("saved_"):]: list(np.asarray(v)) for k, v in f.items() if k.startswith("saved_")},
            rng_from_text(f["rng_state"]))
    except (KeyError, TypeError, ValueError):
        raise ScenarioError("resume: the checkpoint lacks fields of this strategy") from None
    if state.u.shape != u_start.shape:
        raise ScenarioError(f"resume: the checkpoint's wear state has shape {state.u.shape}, not {u_start.shape}")
    body.update(state.u, None)
    return state

