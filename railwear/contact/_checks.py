"""Input checks shared by the contact modules: one-line ScenarioError messages naming the argument."""

import numpy as np

from railwear.errors import ScenarioError


def as_float_array(value, name):
    """Return ``value`` as a float array; non-numeric or non-finite input raises ScenarioError."""
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise ScenarioError(f"{name} must be a number or an array of numbers") from None
    if not np.all(np.isfinite(arr)):
        raise ScenarioError(f"{name} must be finite")
    return arr


def positive(value, name):
    """A strictly positive quantity (semi-axis, curvature, modulus)."""
    arr = as_float_array(value, name)
    if np.any(arr <= 0.0):
        raise ScenarioError(f"{name} must be > 0, got {np.min(arr):g}")
    return arr


def non_negative(value, name):
    """A quantity that may be zero but not negative (normal force, friction coefficient)."""
    arr = as_float_array(value, name)
    if np.any(arr < 0.0):
        raise ScenarioError(f"{name} must be >= 0, got {np.min(arr):g}")
    return arr


def poisson_ratio(value, name="poisson"):
    """Poisson's ratio in [0, 0.5)."""
    arr = as_float_array(value, name)
    if np.any(arr < 0.0) or np.any(arr >= 0.5):
        bad = arr[(arr < 0.0) | (arr >= 0.5)].flat[0]
        raise ScenarioError(f"{name} must lie in [0, 0.5), got {bad:g}")
    return arr


def scalar_or_array(arr):
    """Unwrap 0-d arrays to numpy scalars so scalar input gives scalar output."""
    arr = np.asarray(arr)
    return arr[()] if arr.ndim == 0 else arr
