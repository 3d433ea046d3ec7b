"""The wheel's lateral profile between turnings, for flange triggers and a turning that restores the
design profile (layer 4).

Between turnings the profile is the design profile ``z_0(y)`` (m, radius over the new wheel's tape
circle, :mod:`railwear.geometry.profiles`) worn by a depth that grows in proportion to the
distance ``a`` run since the turning:

    z(y, a) = z_0(y) - g w'(y) a

``w'(y)`` (m of depth per m run) is the fed depth (mean round the wheel and over both wheels) of a
wheelset-wear run of the scenario at its own conditions, divided by the distance it ran
(:func:`profile_wear`); ``g`` the growth multiplier of the plan. Holding the pattern of that run
over a whole segment is an assumption: the contact table is not rebuilt from the worn profile as
the run itself does, and the rate is the one of the new diameter. The flange parameters Sh, Sd and
qR (EN 15313, :func:`~railwear.geometry.flange.flange_parameters`) are measured on ``z(y, a)``.

A turning restores the design profile: the radius cut below the tape circle of the worn wheel is
its depth relative to the tape circle, ``max_y (z_0 - z) - (z_0(0) - z(0))``
(:func:`~railwear.geometry.flange.restoring_depth`), added to the polygon's depth in the cut rule.
"""

from dataclasses import dataclass, replace

import numpy as np

from railwear.errors import ScenarioError
from railwear.geometry import worn_profile
from railwear.geometry.flange import FlangeParameters, flange_parameters, restoring_depth
from railwear.units import KM, MM

BODIES = ("wheelset",)  # the bodies that simulate the lateral profile
SCAN = 64  # equal scan steps over a segment for a flange trigger
BISECTIONS = 40  # then halvings of the step: a segment of 10^6 km located to 10^-5 km

# name in the policy, FlangeParameters field, sense of the limit, long name
LIMITS = {"flange_height_max_mm": ("height", +1, "flange height Sh"),
          "flange_thickness_min_mm": ("thickness", -1, "flange thickness Sd"),
          "flange_gradient_min_mm": ("gradient", -1, "flange gradient qR")}


@dataclass(frozen=True)
class FlangeLimit:
    """A flange trigger ``key`` of :data:`LIMITS` (its policy field) at ``value`` (m): the
    parameter at or above a maximum, or at or below a minimum."""

    key: str
    value: float

    def __post_init__(self):
        if self.key not in LIMITS:
            raise ScenarioError(f"flange trigger {self.key!r}: one of {', '.join(LIMITS)}")

    @property
    def name(self):
        _, sense, label = LIMITS[self.key]
        return f"{label} {'>=' if sense > 0 else '<='} {self.value / MM:g} mm"

    def reached(self, parameters):
        field, sense, _ = LIMITS[self.key]
        return sense * (getattr(parameters, field) - self.value) >= 0


@dataclass(frozen=True, eq=False)
class ProfileWear:
    """The lateral profile of a wheel between turnings: the ``design`` profile (a
    :class:`~railwear.geometry.Profile`) and the depth removed per metre run ``rate`` (m/m) at the
    lateral positions ``lateral`` (m; none outside them), ``source`` how the rate was obtained."""

    design: object
    lateral: np.ndarray
    rate: np.ndarray
    source: str = ""

    def __post_init__(self):
        lateral, rate = (np.array(v, float) for v in (self.lateral, self.rate))
        if lateral.ndim != 1 or lateral.shape != rate.shape or lateral.size < 2 or np.any(np.diff(lateral) <= 0):
            raise ScenarioError("profile wear: the depth rate needs one value per increasing lateral position")
        if not np.all(np.isfinite(rate)):
            raise ScenarioError("profile wear: the depth rate must be finite")
        for name, v in (("lateral", lateral), ("rate", rate)):
            v.flags.writeable = False
            object.__setattr__(self, name, v)

    def scaled(self, multiplier):
        """The same wheel wearing ``multiplier`` times as fast."""
        return replace(self, rate=multiplier * self.rate)

    @property
    def tape_rate(self):
        """Depth per metre run at the tape circle ``y = 0`` (m/m): the diameter's wear."""
        return float(np.interp(0.0, self.lateral, self.rate, left=0.0, right=0.0))

    def profile(self, age):
        """The profile after ``age`` (m) run since the design profile was cut."""
        depth = np.interp(self.design.y, self.lateral, self.rate * age, left=0.0, right=0.0)
        return worn_profile(self.design, -depth)

    def flange(self, age) -> FlangeParameters:
        """Sh, Sd, qR (m) after ``age`` (m)."""
        return flange_parameters(self.profile(age))

    def cut(self, age):
        """The radius (m) a turning cuts below the worn tape circle after ``age`` (m) to restore the
        design profile: ``max_y (z_0 - z) - (z_0(0) - z(0))``."""
        return restoring_depth(self.design, self.profile(age)) - self.tape_rate * age

    def distance(self, limits, age, within):
        """The distance (m) beyond ``age`` at which the first of ``limits`` (:class:`FlangeLimit`)
        is reached, or ``inf`` if not within ``within`` (m): a scan of :data:`SCAN` equal steps
        (each parameter assumed monotone within a step), the crossing located by bisection. A
        profile whose flange can no longer be measured has reached every limit."""
        if not limits or not within > 0:
            return np.inf if not limits else (0.0 if self._reached(limits, age) else np.inf)
        if self._reached(limits, age):
            return 0.0
        grid = np.linspace(0.0, within, SCAN + 1)
        for lo, hi in zip(grid[:-1], grid[1:]):
            if self._reached(limits, age + hi):
                for _ in range(BISECTIONS):
                    mid = 0.5 * (lo + hi)
                    lo, hi = (lo, mid) if self._reached(limits, age + mid) else (mid, hi)
                return float(hi)
        return np.inf

    def _reached(self, limits, age):
        try:
            parameters = self.flange(age)
        except ScenarioError:  # the flange is worn past measuring: past every limit
            return True
        return any(limit.reached(parameters) for limit in limits)

    def which(self, limits, age):
        """The name of the first of ``limits`` reached after ``age`` (m)."""
        try:
            parameters = self.flange(age)
        except ScenarioError:
            return limits[0].name
        return next((limit.name for limit in limits if limit.reached(parameters)), limits[0].name)


def profile_wear(scenario, progress=None):
    """The :class:`ProfileWear` of ``scenario`` (a wheelset body): its wheelset-wear run as the
    scenario sets it (strategy, distance), the fed depth at the end over the distance run."""
    from railwear.api import run

    if scenario.body.kind not in BODIES:
        raise ScenarioError(f"body.kind: {scenario.body.kind!r} does not simulate the lateral profile; flange "
                            f"triggers need {' or '.join(repr(b) for b in BODIES)}")
    ds = run(scenario, progress=progress)
    distance = float(ds.distance.values[-1]) * KM
    if not distance > 0:
        raise ScenarioError("solver.t_end: the wheelset-wear run gives no distance to take a wear rate over")
    depth = ds.worn_depth.isel(time=-1).mean("wheel").values
    return ProfileWear(scenario.body.profile("wheel"), ds.lateral.values, depth / distance,
                       f"the wheelset-wear run of {scenario.name}: {distance / KM:,.0f} km at "
                       f"{float(ds.speed_kmh):g} km/h ({scenario.strategy.kind}), its fed depth held over each segment")
