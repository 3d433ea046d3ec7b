"""A fifth strategy, as a user would add one (file 2 of 2): its ``[strategy]`` section and builder."""

from typing import ClassVar, Literal

from example_frozen_strategy import Frozen
from railwear.scenario import build
from railwear.scenario.schema import StrategySection, strategy_section


@strategy_section
class FrozenSection(StrategySection):
    """``kind = "frozen"``: the start's rate over ``samples`` draws, on either body."""

    kind: Literal["frozen"] = "frozen"
    bodies: ClassVar[tuple] = ("disk_wheel", "wheelset")
    samples: int = 8


@build.builds("frozen")
def frozen(scenario):
    return Frozen(build.body(scenario), seed=scenario.service.seed)
