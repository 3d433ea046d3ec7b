"""Strategy 3 of the paper: stepwise frozen geometry (section "Solution strategies", Fig. 7).

With the body's wear state ``u`` frozen, the body's dynamics give the Monte Carlo wear rate
``r`` per unit normed time with its standard error ``s`` (random phases, starts and speeds; see
the body). The state is then advanced over a long-term step

    u ← u - r ΔT,   ΔT = step_limit / max_j |r_j|,

so no cell of what the limit looks at changes by more than ``step_limit`` (m); repeat. With
``limit_on="shape"`` the limit applies to the change without its uniform part (the dynamics see
only the shape: a uniformly smaller wheel only lowers the axle), so the uniform wear, which
dominates, need not shorten the steps. This is the forward Euler method in the long-term time on
the Monte Carlo rate: first order in ``step_limit``. ``scheme="adams-bashforth"`` takes the
second-order Adams-Bashforth step for unequal steps instead,

    u ← u - ΔT ((1 + ω/2) r - (ω/2) r_prev),   ω = ΔT / ΔT_prev,

at the same cost per step (one set of draws), so the same error allows far larger steps (the first
step is Euler's). The standard error is carried along, ``var += (w s ΔT)²`` summed over the rates
used with weights ``w``, as the run's error estimate.
"""

from dataclasses import dataclass

import numpy as np

from railwear.errors import ScenarioError
from railwear.longterm.base import Body, Rates, Strategy
from railwear.longterm.driver import Step, drive

SCHEMES = ("euler", "adams-bashforth")


@dataclass(frozen=True)
class Stepwise(Strategy, name="stepwise"):
    """Strategy 3 on ``body``: frozen-geometry rates extrapolated over steps of at most
    ``step_limit`` (m) change of what the body's limit looks at (``limit_on`` ``"u"`` or
    ``"shape"``), by ``scheme`` ``"euler"`` or ``"adams-bashforth"`` (second order); ``seed``
    seeds the run's one generator."""

    body: Body
    step_limit: float
    seed: int = 0
    limit_on: str = "u"
    scheme: str = "euler"
    max_steps: int = 100_000

    monte_carlo = True

    def __post_init__(self):
        if not (np.isfinite(self.step_limit) and self.step_limit > 0):
            raise ScenarioError(f"step_limit must be > 0 (m), got {self.step_limit}")
        if self.limit_on not in ("u", "shape"):
            raise ScenarioError(f"limit_on must be 'u' or 'shape', not {self.limit_on!r}")
        if self.scheme not in SCHEMES:
            raise ScenarioError(f"scheme must be one of {', '.join(SCHEMES)}, not {self.scheme!r}")
        if int(self.seed) != self.seed or self.seed < 0:
            raise ScenarioError(f"seed must be a whole number >= 0, got {self.seed}")

    def run(self, u0=None, until=1.0, depth_limit=None, progress=None, checkpoint=None, resume=None):
        """The result from ``u0`` until ``until`` or ``depth_limit`` (m); ``checkpoint`` is called
        after every step, ``resume`` continues from one to the same result bit for bit."""
        return drive(self, self.body, u0, until, depth_limit, settings=(self.step_limit, self.limit_on, self.scheme),
                     seed=self.seed, max_steps=self.max_steps, too_many="steps did not reach the end; raise step_limit",
                     progress=progress, checkpoint=checkpoint, resume=resume)

    def advance(self, body, state, until):
        """One step: the rates over the frozen state, the step size, the scheme's weights."""
        rate, error, law_rate, seen = Rates._make(body.rates(state.u, state.rng, state.cost))
        top = np.max(np.abs(body.limited(rate, self.limit_on)))
        dT = self.step_limit / top if top > 0 else np.inf
        if state.time + dT >= until:
            dT = until - state.time
        last_rate, last_error, last_dT, last_law = state.previous or (np.zeros_like(rate), np.zeros_like(error), 0.0, 0.0)
        # a step cut short at the depth keeps these weights, so the crossing stays exact (third order)
        half = dT / last_dT / 2 if self.scheme != "euler" and last_dT > 0 else 0.0
        step_rate = (1 + half) * rate - half * last_rate
        law = (1 + half) * law_rate - half * last_law
        return Step(step_rate * dT, dT, dT == until - state.time, law * dT, seen, (error, last_error),
                    (1 + half, half), (rate, error, dT, law_rate))

    def attributes(self, state):
        return {"strategy_description": "stepwise frozen geometry", "steps": state.steps,
                "step_limit_m": self.step_limit, "step_limit_on": self.limit_on, "scheme": self.scheme}

