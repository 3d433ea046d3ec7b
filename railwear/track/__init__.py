"""Vertical track dynamics: one rail on continuous or discrete supports (layer 2).

- ``rail("60E1")``, ``rail("54E1")``: standard sections (EN 13674-1, shipped data), any field
  overridable; ``Rail``, ``Support``, ``Track`` frozen, validated dataclasses;
- ``support_set("zhai-2004")``: published supports with their sources (shipped data): the
  two-layer ballasted support (ballast mass on a subgrade) and slab tracks; ``support_of(base, ...)``
  builds a ``Support`` from a base's values (``base_fields``);
- ``receptance(track, frequency_hz, position, response=None)``: the exact point or transfer
  receptance of the infinite track [m/N] (continuous: eigen-waves; discrete: Floquet waves);
- ``finite_track_receptance``: the same on a finite track of exact spans (a cross-check, and the
  convergence in length);
- ``ModalTrack(track, n_sleepers, max_frequency_hz, reference_frequency_hz)``: the time-domain
  track (modal superposition, compiled RK4); ``.run(...)`` under a moving or harmonic load, and
  the compiled ``railwear.track.modal.rhs`` / ``rail_displacement`` for a body's own loop.
"""

from railwear import _numba_cache  # noqa: F401  (first: numba caches keyed on the sources)

from railwear.track.model import (BASES, BEAMS, Rail, Support, SupportSet, Track, base_fields, default_support_set,
                                  rail, rail_names, support_of, support_set, support_set_names)
from railwear.track.receptance import load_offset, receptance  # the function, not the module, as before


def __getattr__(name):
    """The finite and the time-domain track imported on first use (PEP 562): a frequency-domain
    run does not import the modal track (compiled) with the package."""
    if name == "finite_track_receptance":
        from railwear.track import finite as module
    elif name in ("ModalTrack", "MovingLoadResult"):
        from railwear.track import modal as module
    else:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    return getattr(module, name)


__all__ = [
    "BASES",
    "BEAMS",
    "ModalTrack",
    "MovingLoadResult",
    "Rail",
    "Support",
    "SupportSet",
    "Track",
    "base_fields",
    "default_support_set",
    "finite_track_receptance",
    "load_offset",
    "rail",
    "rail_names",
    "receptance",
    "support_of",
    "support_set",
    "support_set_names",
]
