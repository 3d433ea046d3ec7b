"""The creep law of a model: ``"cubic"`` (Johnson-Vermeulen saturation) or ``"fastsim"``.

Under ``"fastsim"`` the kernels read FASTSIM's factor table
(``railwear.contact.fastsim_factor_table``) from the model's surface array; these helpers put it
there and select it in the parameter array.
"""

from __future__ import annotations

import numpy as np

from railwear.contact.creep_tables import fastsim_factor_table
from railwear.errors import ScenarioError


def check_creep_law(model):
    """``model.creep_law`` must be one of ``model.CREEP_LAWS``."""
    if model.creep_law not in model.CREEP_LAWS:
        raise ScenarioError(f"creep_law: must be one of {model.CREEP_LAWS}, got {model.creep_law!r}")


def law_table(model) -> np.ndarray:
    """The kernel's FASTSIM factor table for ``model`` (empty under the cubic law)."""
    return fastsim_factor_table().copy() if model.creep_law == "fastsim" else np.zeros(0)


def law_params(model, offset) -> dict:
    """``pack`` values selecting the creep law, its table at ``offset`` in the surface array."""
    return dict(law=model.CREEP_LAWS.index(model.creep_law), law_offset=offset, law_points=law_table(model).size)


def linear_slope(model) -> float:
    """Ratio of the creep law's small-creepage forces to Kalker's: 1 for the cubic law, FASTSIM's
    discretised slope (``1 + 1 / (2 ny^2)``, ``ny`` strips) for ``"fastsim"``."""
    return float(fastsim_factor_table()[0]) if model.creep_law == "fastsim" else 1.0
