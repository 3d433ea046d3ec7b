"""A fifth strategy, as a user would add one (file 2 of 2): its ``[strategy]`` section and builder."""

from typing import ClassVar, Literal

from example_frozen_strategy import Frozen
from railwear.scenario import build
from railwear.scenario.schema import StrategySection, strategy_section


@strategy_section
class FrozenSection(StrategySection):
    """``kind = "frozen"``: the start's rate, drawn as ``[body]`` says, on any body that gives
    frozen-geometry rates."""

    kind: Literal["frozen"] = "frozen"
    needs: ClassVar[str] = "rates"


@build.builds("frozen")
def frozen(scenario):
    return Frozen(build.body(scenario), seed=scenario.service.seed)
