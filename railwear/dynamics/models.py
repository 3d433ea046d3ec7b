"""The dynamics models, one module each, and the scenario builder ``build_model``.

- ``WheelsetModel`` (``railwear.dynamics.wheelset``), ``TableWheelsetModel``
  (``table_wheelset``), ``BogieModel`` (``bogie``), ``TableBogieModel`` (``table_bogie``),
  ``CooperriderBogie`` (``cooperrider``, the published bogie with frame roll),
  ``DiskWheelModel`` (``disk_wheel``): frozen, validated dataclasses (SI units). Each knows its
  compiled kernel (``kind``), packs its parameters into the float64 array the kernels read
  (``params``), gives its surface array, initial state and, where it has one, its linear state
  matrix.
- ``contact_constants`` lives in ``railwear.contact`` (layer 1) and ``numerical_state_matrix``
  in ``railwear.dynamics.linear``; both are re-exported here.
"""

from __future__ import annotations

from dataclasses import MISSING, fields

from railwear.contact.constants import contact_constants
from railwear.dynamics._fields import model_fields  # noqa: F401  (re-exported for railwear.dynamics.models)
from railwear.dynamics.bogie import BogieModel
from railwear.dynamics.cooperrider import CooperriderBogie
from railwear.dynamics.disk_wheel import DiskWheelModel
from railwear.dynamics.linear import numerical_state_matrix
from railwear.dynamics.table_bogie import TableBogieModel
from railwear.dynamics.table_wheelset import TableWheelsetModel
from railwear.dynamics.wheelset import WheelsetModel
from railwear.errors import ScenarioError

__all__ = [
    "BogieModel",
    "CooperriderBogie",
    "DiskWheelModel",
    "MODEL_KINDS",
    "TableBogieModel",
    "TableWheelsetModel",
    "WheelsetModel",
    "build_model",
    "contact_constants",
    "numerical_state_matrix",
]


MODEL_KINDS = {"wheelset": WheelsetModel, "disk_wheel": DiskWheelModel, "bogie": BogieModel,
               "table_wheelset": TableWheelsetModel, "table_bogie": TableBogieModel, "cooperrider": CooperriderBogie}


def build_model(kind, section):
    """A model from a scenario section: ``kind`` in ``MODEL_KINDS`` (``"cooperrider"`` is the
    published bogie, ``CooperriderBogie``, whose fields all have their published defaults but the
    speed) and a mapping of field values in SI units. Unknown or missing fields raise
    ``ScenarioError`` naming the field."""
    if kind not in MODEL_KINDS:
        raise ScenarioError(f"model: unknown model kind {kind!r}; expected one of {sorted(MODEL_KINDS)}")
    cls = MODEL_KINDS[kind]
    known = {fld.name: fld for fld in fields(cls)}
    for name in section:
        if name not in known:
            raise ScenarioError(f"{name}: not a field of the {kind} model")
    required = [n for n, fld in known.items() if fld.default is MISSING and fld.default_factory is MISSING]
    for name in required:
        if name not in section:
            raise ScenarioError(f"{name}: missing (required for the {kind} model)")
    return cls(**dict(section))
