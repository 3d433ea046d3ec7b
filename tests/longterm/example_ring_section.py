"""A new body, as a user would add one (file 2 of 2): its ``[body]`` section and builder."""

from typing import ClassVar, Literal

from example_ring_body import Ring
from railwear.scenario.schema import BodySection, Positive, body_section
from railwear.units import UM


@body_section
class RingSection(BodySection):
    """``kind = "ring"``: a ring losing ``mean_um + amplitude_um cos(order x)`` (µm per unit
    normed time), worn by the stepwise and direct strategies."""

    kind: Literal["ring"] = "ring"
    mean_um: Positive = 200.0
    amplitude_um: Positive = 50.0
    order: int = 6

    provides: ClassVar[frozenset] = frozenset({"rates", "segment"})

    def build(self, scenario, speed=None):
        return Ring(mean=self.mean_um * UM, amplitude=self.amplitude_um * UM, order=self.order)
