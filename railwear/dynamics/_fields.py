"""Validation and packing of the dynamics models' fields (shared by every model).

Bad values raise ``railwear.errors.ScenarioError`` with a one-line message naming the field;
``pack`` fills a kernel's parameter array from the fields by the index constants of
``railwear.dynamics.kernels``.
"""

from __future__ import annotations

import math
from dataclasses import fields

import numpy as np

from railwear.dynamics import kernels as k
from railwear.errors import ScenarioError


def number(model, name):
    value = getattr(model, name)
    try:
        value = float(value)
    except (TypeError, ValueError):
        raise ScenarioError(f"{name}: must be a number, got {value!r}") from None
    if math.isnan(value):
        raise ScenarioError(f"{name}: must be a number, got nan")
    return value


def check(model, positive=(), nonnegative=(), finite=()):
    """Validate fields: ``positive`` > 0 and finite, ``nonnegative`` >= 0 (may be inf), ``finite``."""
    for name in positive:
        value = number(model, name)
        if not (value > 0.0 and math.isfinite(value)):
            raise ScenarioError(f"{name}: must be a positive finite number, got {value!r}")
    for name in nonnegative:
        value = number(model, name)
        if value < 0.0:
            raise ScenarioError(f"{name}: must not be negative, got {value!r}")
    for name in finite:
        value = number(model, name)
        if not math.isfinite(value):
            raise ScenarioError(f"{name}: must be finite, got {value!r}")


def pack(model, prefix, size, speed=None, **derived):
    """Parameter array of ``model`` for its kernel: field ``name`` goes to ``kernels.<prefix>NAME``,
    as do the ``derived`` values. The friction coefficient goes to ``<prefix>FRICTION``; every
    index must be filled."""
    p = np.full(size, np.nan)
    for name, value in derived.items():
        p[getattr(k, prefix + name.upper())] = value
    for fld in fields(model):
        name = "FRICTION" if fld.name == "friction_coefficient" else fld.name.upper()
        index = getattr(k, prefix + name, None)
        if index is not None:
            p[index] = getattr(model, fld.name)
    if speed is not None:
        p[getattr(k, prefix + "SPEED")] = speed
    if np.isnan(p).any():
        raise RuntimeError(f"{type(model).__name__}: kernel parameter(s) {np.flatnonzero(np.isnan(p))} not set")
    return p



def model_fields(model) -> dict:
    """The model's scalar fields as plain values for result attributes (``None`` as "none");
    arrays, tuples and tables are left out, except a contact table's profile names."""
    out = {}
    for fld in fields(model):
        value = getattr(model, fld.name)
        if value is None:
            out[fld.name] = "none"
        elif isinstance(value, (bool, np.bool_)):
            out[fld.name] = int(value)
        elif isinstance(value, (int, float, str, np.integer, np.floating)):
            out[fld.name] = value
        elif fld.name == "table":
            attrs = getattr(value, "attrs", {})
            out["table_profiles"] = f"{attrs.get('wheel_profile', '?')}/{attrs.get('rail_profile', '?')}"
    return out
