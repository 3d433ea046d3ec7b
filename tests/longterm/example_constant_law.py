"""A new wear law, as a user would add one (file 1 of 2): a constant volume rate in contact."""

from dataclasses import dataclass

import numpy as np

from railwear.wear import WearLaw


@dataclass(frozen=True)
class ConstantLaw(WearLaw, name="constant"):
    """``rate`` (m³/s) removed while the wheel is in contact, whatever the contact's power."""

    rate: float

    def volume_rate_of(self, contact):
        return np.where(contact.normal_force > 0, self.rate, 0.0)
