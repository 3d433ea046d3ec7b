"""Strategy 1 of the paper: direct coupled integration (eq. 3) with an acceleration factor on β.

The body's dynamics and its wear surface advance together: the dynamics run a segment over the
current surface from the dynamic state where the last one ended, the segment's wear is taken off
with ``A β`` in place of ``β``, and the next segment runs over the new surface. Each simulated
second stands for ``A`` seconds of service, so normed time advances by ``A V Δt /
life_distance``. The error is first order in ``A`` (the wear of a segment acts only from the next
one on, and the dynamics lag the faster-changing surface); ``A = 1`` is the coupled system itself.
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
    ``seed`` seeds the generator of the body's start."""

    body: Body
    acceleration_factor: float
    n_save: int | None = 101
    seed: int = 0
    max_steps: int = 20_000_000

    monte_carlo = False

    def __post_init__(self):
        if not (np.isfinite(self.acceleration_factor) and self.acceleration_factor >= 1):
            raise ScenarioError(f"acceleration factor must be >= 1, got {self.acceleration_factor}")
        if self.n_save is not None and (int(self.n_save) != self.n_save or self.n_save < 2):
            raise ScenarioError("n_save must be a whole number >= 2")
        if int(self.seed) != self.seed or self.seed < 0:
            raise ScenarioError(f"seed must be a whole number >= 0, got {self.seed}")

    def run(self, u0=None, until=1.0, depth_limit=None, progress=None, checkpoint=None, resume=None):
        """The result from ``u0`` until ``until`` or ``depth_limit`` (m); ``checkpoint`` is called
        at every output, ``resume`` continues from one to the same result bit for bit."""
        return drive(self, self.body, u0, until, depth_limit, settings=(self.acceleration_factor,),
                     seed=self.seed,
                     n_save=self.n_save, max_steps=self.max_steps,
                     too_many="segments did not reach the end; raise the acceleration factor",
                     progress=progress, checkpoint=checkpoint, resume=resume, coupled=self.acceleration_factor)

    def advance(self, body, state, until):
        """One coupled segment of the body's dynamics and its wear."""
        segment = Segment._make(body.segment(state.u, state.carry, self.acceleration_factor, until - state.time,
                                             state.cost))
        state.carry = segment.carry
        return Step(segment.increment, segment.dT, segment.final, segment.law_volume, segment.seen)

    def attributes(self, state):
        return {"strategy_description": "direct coupled integration", "acceleration_factor": self.acceleration_factor,
                "steps": state.steps}

