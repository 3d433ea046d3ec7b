"""Strategy 1 of the paper: direct coupled integration (eq. 3) with an acceleration factor on β.

The body's dynamics and its wear surface advance together: the dynamics run a segment over the
current surface from the dynamic state where the last one ended, the segment's wear is taken off
with ``A β`` in place of ``β``, and the next segment runs over the new surface. Each simulated
second stands for ``A`` seconds of service, so normed time advances by ``A V Δt /
life_distance``. The error is first order in ``A`` (the wear of a segment acts only from the next
one on, and the dynamics lag the faster-changing surface); ``A = 1`` is the coupled system itself.

**Over a duty cycle** (``cycle``: the shares ``p_k`` of the distance, each with the body at its
segment's speed and traction torque) every segment keeps its own dynamic state, settled once by
the body's start transient and carried from update to update. An update runs every segment from
its own state over the same current surface, its wear ``Δu_k`` (with ``A β``) standing for the
service distance ``A d_k`` (``d_k`` the metres it ran, ``ΔT_k = A d_k / life_distance``), and
takes off

    Δu = Σ_k w_k Δu_k,   w_k = p_k ΔT̄ / ΔT_k,   over   ΔT̄ = Σ_k p_k ΔT_k,

the segments in proportion of distance: each ``Δu_k / ΔT_k`` is segment ``k``'s wear per
distance on the current surface, weighed by its share. A wheel in service passes through the
segments of a cycle a few kilometres long, over which the surface is frozen (it changes over
``10⁴``-``10⁵`` km), so its wear over a cycle is that sum plus the transients of the switches.
Those are left out: a real demand changes over about a second (a jerk-limited speed and torque),
much longer than the wheel's vertical and rotational dynamics take to settle, so the wheel
passes through settled states, which are what the segments hold. Each segment's carried state
is one such state, on the same surface; the surface moves per update as in a single run at
``A``, so the error stays first order in ``A``. The cost is one single run per segment. A cycle
of one segment (``w = 1``) is the single run bit for bit.
"""

from dataclasses import dataclass

import numpy as np

from railwear.errors import ScenarioError
from railwear.longterm.base import Body, Segment, Strategy
from railwear.longterm.driver import Step, drive


@dataclass(frozen=True)
class Direct(Strategy, name="direct"):
    """Strategy 1 on ``body`` with ``acceleration_factor`` ``A >= 1`` on the wear coefficient; outputs at
    ``n_save`` marks evenly spaced in normed time and in removed depth (``None``: every segment);
    ``seed`` seeds the generator of the body's start. ``cycle``: a duty cycle's ``(share, body)``
    pairs, each the body at its segment's speed and demand (shares of the distance summing to 1;
    ``body`` then only records and builds the result); empty: ``body`` runs alone."""

    body: Body
    acceleration_factor: float
    n_save: int | None = 101
    seed: int = 0
    max_steps: int = 20_000_000
    cycle: tuple = ()

    monte_carlo = False

    def __post_init__(self):
        if not (np.isfinite(self.acceleration_factor) and self.acceleration_factor >= 1):
            raise ScenarioError(f"acceleration factor must be >= 1, got {self.acceleration_factor}")
        if self.n_save is not None and (int(self.n_save) != self.n_save or self.n_save < 2):
            raise ScenarioError("n_save must be a whole number >= 2")
        if int(self.seed) != self.seed or self.seed < 0:
            raise ScenarioError(f"seed must be a whole number >= 0, got {self.seed}")
        cycle = tuple(self.cycle)
        object.__setattr__(self, "cycle", cycle)
        for i, part in enumerate(cycle):
            if not (isinstance(part, tuple) and len(part) == 2):
                raise ScenarioError(f"cycle: segment {i}: must be a (share, body) pair")
            share, body = part
            if not (isinstance(share, (int, float, np.floating)) and np.isfinite(share) and share > 0):
                raise ScenarioError(f"cycle: segment {i}: share must be > 0, got {share}")
            if not isinstance(body, Body):
                raise ScenarioError(f"cycle: segment {i}: body must be a railwear.longterm.base.Body, "
                                    f"not {type(body).__name__}")
            if type(body) is not type(self.body):
                raise ScenarioError(f"cycle: segment {i}: body must be a {type(self.body).__name__} as the run's, "
                                    f"not {type(body).__name__}")
        if cycle and abs(sum(p for p, _ in cycle) - 1) > 1e-9:
            raise ScenarioError(f"cycle: the shares of the distance must sum to 1, not {sum(p for p, _ in cycle):.12g}")

    def run(self, u0=None, until=1.0, depth_limit=None, progress=None, checkpoint=None, resume=None):
        """The result from ``u0`` until ``until`` or ``depth_limit`` (m); ``checkpoint`` is called
        at every output, ``resume`` continues from one to the same result bit for bit."""
        settings = (self.acceleration_factor,)
        if self.cycle:
            settings += (tuple((float(p), b.fingerprint_parts()) for p, b in self.cycle),)
        return drive(self, self.body, u0, until, depth_limit, settings=settings,
                     seed=self.seed,
                     n_save=self.n_save, max_steps=self.max_steps,
                     too_many="segments did not reach the end; raise the acceleration factor",
                     progress=progress, checkpoint=checkpoint, resume=resume,
                     coupled=None if self.cycle else self.acceleration_factor)

    def advance(self, body, state, until):
        """One coupled segment of the body's dynamics and its wear; over a cycle, one update of
        every segment, weighed by distance (module docstring)."""
        if self.cycle:
            return self._advance_cycle(state, until)
        segment = Segment._make(body.segment(state.u, state.carry, self.acceleration_factor, until - state.time,
                                             state.cost))
        state.carry = segment.carry
        return Step(segment.increment, segment.dT, segment.final, segment.law_volume, segment.seen)

    def _advance_cycle(self, state, until):
        """Every segment from its own carried state over ``state.u``; the carry is flat, segment
        ``k``'s entries prefixed ``s{k}_`` (checkpoints keep plain values)."""
        A = self.acceleration_factor
        if not state.carry:  # the first update: each segment settles from rest (the body's transient)
            carries = [b.couple(state.u, state.rng, A, state.cost) for _, b in self.cycle]
        else:
            carries = [{} for _ in self.cycle]
            for key, value in state.carry.items():
                k, name = key.split("_", 1)
                carries[int(k[1:])][name] = value
        parts = [Segment._make(b.segment(state.u, c, A, until - state.time, state.cost))
                 for (_, b), c in zip(self.cycle, carries)]
        dT = sum(p * s.dT for (p, _), s in zip(self.cycle, parts))
        weights = [p * dT / s.dT for (p, _), s in zip(self.cycle, parts)]
        increment = sum(w * s.increment for w, s in zip(weights, parts))
        law = sum(w * s.law_volume for w, s in zip(weights, parts))
        state.carry = {f"s{k}_{name}": value for k, s in enumerate(parts) for name, value in s.carry.items()}
        return Step(increment, dT, False, law, parts[0].seen)

    def attributes(self, state):
        attrs = {"strategy_description": "direct coupled integration", "acceleration_factor": self.acceleration_factor,
                 "steps": state.steps}
        if self.cycle:
            attrs["strategy_description"] += (f" over a duty cycle of {len(self.cycle)} segment(s), each from its own "
                                              "settled state, weighed by distance")
        return attrs
