"""Exception types of railwear (layer 0).

Bad input of every kind is a :class:`ScenarioError` (exit status 2 from the command line, one
line); its subclasses say which kind of input it was.
"""

from railwear.units import MM


class RailwearError(Exception):
    """Base of every error railwear raises on purpose."""


class ScenarioError(RailwearError, ValueError):
    """Bad input: a scenario field, a table or a file that cannot be used.

    The message is one line and names the field.
    """


def start_past_limit(field, out_of_round, limit, wheel="the wheel"):
    """The refusal of a start ``out_of_round`` (m, peak to peak) at or past the peak-to-peak
    ``limit`` (m), the run's stop at 0 km: one line naming ``field``, ``wheel`` and the excess
    ``out_of_round - limit`` (mm; a start within round-off of the limit prints as the limit at 4
    digits, the excess says it is over)."""
    excess = out_of_round - limit
    where = "at the limit" if excess == 0 else "above the limit"
    by = "" if excess == 0 else f" by {excess / MM:.3g} mm"
    return ScenarioError(f"{field}: {wheel} starts {out_of_round / MM:.4g} mm out of round, {where} {limit / MM:.4g} "
                         f"mm{by}: the limit is reached at 0 km, before the run starts")


class MeasuredFileError(ScenarioError):
    """A measured-wheel file that cannot be used; the message names the file, line and column."""


class OptionError(ScenarioError):
    """A command-line option or API argument out of its range; the message names it."""


class CheckpointError(ScenarioError):
    """A checkpoint file that is not one railwear wrote for this run, or is damaged."""


class NumericalInstabilityError(RailwearError, ArithmeticError):
    """A solution blew up or left the resolved range.

    ``last_good`` holds the last state that passed the guard, with its time.
    """

    def __init__(self, message, last_good=None, last_time=None):
        super().__init__(message)
        self.last_good = last_good
        self.last_time = last_time


class ModelRangeError(NumericalInstabilityError):
    """The model left the range where it holds (the wheel gained radius as a whole, say): its
    numbers are not written; ``last_good`` holds the last state inside the range."""


class IllPosedError(NumericalInstabilityError):
    """Growth at the grid scale: the equation is ill-posed or under-resolved."""


class ResolutionWarning(UserWarning):
    """The top of the kept spectrum grew: the grid may not resolve the solution."""


class ScopeWarning(UserWarning):
    """A run that lies outside what its model was validated against (the message says how)."""


class ScenarioLayoutWarning(UserWarning):
    """A scenario written in an earlier layout was read in today's (the message says what moved)."""
