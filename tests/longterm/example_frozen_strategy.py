"""A fifth strategy, as a user would add one (file 1 of 2): the frozen-geometry rate of the start,
extrapolated to the end in one step, on any body."""

from dataclasses import dataclass

from railwear.longterm.base import Body, Strategy
from railwear.longterm.driver import Step, drive


@dataclass(frozen=True)
class Frozen(Strategy, name="frozen"):
    """The body's Monte Carlo rate over the starting state, applied unchanged until ``until``."""

    body: Body
    seed: int = 0

    monte_carlo = True

    def run(self, u0=None, until=1.0, depth_limit=None, progress=None, checkpoint=None, resume=None):
        return drive(self, self.body, u0, until, depth_limit, seed=self.seed, progress=progress,
                     checkpoint=checkpoint, resume=resume)

    def advance(self, body, state, until):
        rate, error, law, seen = body.rates(state.u, state.rng, state.cost)
        dT = until - state.time
        return Step(rate * dT, dT, True, law * dT, seen, (error,), (1.0,))

    def attributes(self, state):
        return {"strategy_description": "frozen start rate", "steps": state.steps}
