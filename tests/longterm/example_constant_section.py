"""A new wear law, as a user would add one (file 2 of 2): its ``[wear]`` section and builder."""

from typing import Literal

from example_constant_law import ConstantLaw
from railwear.scenario.schema import Positive, WearSection, wear_section
from railwear.units import MM3


@wear_section
class ConstantWear(WearSection):
    """``law = "constant"``: ``rate_mm3_per_s`` removed while in contact."""

    law: Literal["constant"] = "constant"
    rate_mm3_per_s: Positive = 1e-3

    def build(self):
        return ConstantLaw(self.rate_mm3_per_s * MM3)
