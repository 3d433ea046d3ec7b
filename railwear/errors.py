"""Exception types of railwear (layer 0)."""


class RailwearError(Exception):
    """Base of every error railwear raises on purpose."""


class ScenarioError(RailwearError, ValueError):
    """Bad input: a scenario field, a table or a file that cannot be used.

    The message is one line and names the field.
    """


class NumericalInstabilityError(RailwearError, ArithmeticError):
    """A solution blew up or left the resolved range.

    ``last_good`` holds the last state that passed the guard, with its time.
    """

    def __init__(self, message, last_good=None, last_time=None):
        super().__init__(message)
        self.last_good = last_good
        self.last_time = last_time


class IllPosedError(NumericalInstabilityError):
    """Growth at the grid scale: the equation is ill-posed or under-resolved."""


class ResolutionWarning(UserWarning):
    """The top of the kept spectrum grew: the grid may not resolve the solution."""
