"""The checkpoint observer (layer 0): a consumer may say when it wants a state.

A run calls ``checkpoint(state)`` after each saved interval. Building the state copies the run's
history (O(saves) per call), so a consumer that writes every few seconds would make a run of many
saves quadratic; :func:`wanted` asks it first."""

from __future__ import annotations

import time

__all__ = ["wanted", "Periodic"]


def wanted(checkpoint) -> bool:
    """Whether to build a state for ``checkpoint`` (a callable or ``None``) now: its ``due()``
    where it has one, else always."""
    return checkpoint is not None and (not hasattr(checkpoint, "due") or checkpoint.due())


class Periodic:
    """``write(state)`` at most every ``seconds`` of wall time, counted from creation."""

    def __init__(self, write, seconds):
        self.write, self.seconds, self.last = write, float(seconds), time.monotonic()

    def due(self) -> bool:
        return time.monotonic() - self.last >= self.seconds

    def __call__(self, state):
        if self.due():
            self.write(state)
            self.last = time.monotonic()
