"""The scenario schema: frozen pydantic models with physical bounds; units in the field names.

Every number a user types has a lower and an upper bound: a value outside what a railway wheel
can be (a 1e-30 m wheel, a 1e300 N/m spring) would otherwise run into a division by zero, an
overflow or a run that never ends. Types are strict: ``true`` is not a number, ``2.0`` not a count.
"""

import warnings
from abc import abstractmethod
from typing import Annotated, ClassVar, Literal

from pydantic import (AfterValidator, BaseModel, ConfigDict, Field, SerializeAsAny, ValidationError,
                      field_validator, model_serializer, model_validator)
from pydantic_core import PydanticCustomError

from railwear.errors import ScenarioError, ScenarioLayoutWarning
from railwear.units import GPA, KN, MN, UG, kmh_to_m_s

Positive = Annotated[float, Field(gt=0, allow_inf_nan=False)]
NonNegative = Annotated[float, Field(ge=0, allow_inf_nan=False)]
Finite = Annotated[float, Field(allow_inf_nan=False)]

SPEED_KMH = (1.0, 1000.0)  # walking pace to above the wheel-rail record (575 km/h)
Speed_kmh = Annotated[float, Field(ge=SPEED_KMH[0], le=SPEED_KMH[1])]
Speed_m_s = Annotated[float, Field(ge=kmh_to_m_s(SPEED_KMH[0]), le=kmh_to_m_s(SPEED_KMH[1]))]
Stiffness = Annotated[float, Field(ge=0, le=1e11)]  # N/m: above a rigid steel contact (~1e9)
Damping = Annotated[float, Field(ge=0, le=1e8)]  # N s/m: far above any rail pad or damper
Mass = Annotated[float, Field(ge=1, le=1e5)]  # kg: a roller-rig wheel to a locomotive bogie
Coefficient = Annotated[float, Field(ge=-1e9, le=1e9)]  # h's terms (m per unit life): 1e9 overflows nothing
Count = Annotated[int, Field(ge=1, le=32768)]  # polygon orders: half the finest grid
MAX_LIST = 10000  # per-speed tables, batches and harmonics: more is a mistake, not a study
MAX_STEPS = 10**6  # fixed time steps of one run: beyond this it does not end in a working day
MAX_SAVED = 10000  # saved states of one run (solver.n_save): a figure shows a few hundred
MAX_SAVED_VALUES = 2 * 10**7  # n_save x points: 160 MB of float64 per saved field
MAX_LONGTERM_STEPS = 10**5  # stepwise steps to the depth limit: each runs the dynamics (0.1-1 s)
WORN_MM = 100.0  # the most a run can wear off (mm; a wheel has ~40 mm to lose): steps without a depth limit


def refuse(field, message):
    """A validation error located at ``field`` (a name, or a tuple of names and indices, below
    the model that raises it); shown as ``section.field: message``."""
    loc = field if isinstance(field, tuple) else (field,)
    error = PydanticCustomError("field", "{message}", {"message": message})
    return ValidationError.from_exception_data("scenario", [{"type": error, "loc": loc, "input": None}])


def _increasing(values):
    """Whether ``values`` (a list) are distinct and in increasing order."""
    return bool(values) and sorted(set(values)) == list(values)


def _printable(text, allowed=""):
    bad = [c for c in text if (ord(c) < 32 or ord(c) == 127) and c not in allowed]
    if bad:
        raise ValueError(f"must not contain control characters (U+{ord(bad[0]):04X})")
    return text


Name = Annotated[str, Field(max_length=200), AfterValidator(_printable)]
Text = Annotated[str, Field(max_length=10000), AfterValidator(lambda t: _printable(t, "\t\n\r"))]
PathText = Annotated[str, Field(min_length=1, max_length=4096), AfterValidator(_printable)]


class _Section(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True, strict=True, allow_inf_nan=False)


class Wheel(_Section):
    """The wheel: a radius from a scaled roller rig's (5 cm) to twice a locomotive's, a load up to
    five times a heavy-haul wheel's (200 kN)."""

    radius_m: Annotated[float, Field(ge=0.05, le=2.0)] = 0.46
    unsprung_mass_kg: Mass = 1000.0
    static_load_kN: Annotated[float, Field(ge=0.01, le=1000)] = 80.0


class Contact(_Section):
    youngs_modulus_GPa: Annotated[float, Field(ge=1, le=1000)] = 210.0  # polymers to carbides
    poisson: Annotated[float, Field(ge=0, lt=0.5)] = 0.28
    rail_head_radius_m: Annotated[float, Field(ge=0.01, le=100)] = 0.3  # 100 m: a flat head
    friction_coefficient: Annotated[float, Field(gt=0, le=2)] = 0.3
    traction_coefficient: Annotated[float, Field(ge=-1, le=1)] = 0.05  # signed: > 0 traction, < 0 braking
    load_scatter: Annotated[float, Field(ge=0.01, le=1)] = 0.2


class WearSection(_Section):
    """``[wear]``: the wear law named by ``law`` with its own fields (a field of another law is an
    error), and the lateral ``band_width_mm`` the disk wheel's tread wear spreads over (default the
    Hertz ``2b``). A new law is one :class:`~railwear.wear.WearLaw` plus a section registered here
    with :func:`wear_section`; its ``build()`` returns the law in SI units."""

    law: str
    band_width_mm: Annotated[float, Field(gt=0, le=1000)] | None = None

    @abstractmethod
    def build(self):
        """The :class:`~railwear.wear.WearLaw` of the section."""


WEAR_SECTIONS: dict = {}


def wear_section(cls):
    """Register a ``[wear]`` section class under the default of its ``law`` field."""
    WEAR_SECTIONS[cls.model_fields["law"].default] = cls
    return cls


@wear_section
class Wear(WearSection):
    """The energy law (paper eq. 2a): ``specific_wear_ug_per_J`` of steel removed per joule of
    frictional energy (5.3 µg/J, Braghin et al. 2006's mild regime as used in the paper) at
    ``density_kg_m3``."""

    law: Literal["energy"] = "energy"
    specific_wear_ug_per_J: Annotated[float, Field(gt=0, le=1e5)] = 5.3
    density_kg_m3: Annotated[float, Field(ge=1000, le=25000, allow_inf_nan=False)] = 7850.0

    def build(self):
        from railwear.wear import EnergyLaw

        return EnergyLaw(self.specific_wear_ug_per_J * UG, self.density_kg_m3)


@wear_section
class ArchardWear(WearSection):
    """Archard's law ``V = k N s / H``: ``coefficient`` k (1; 1e-4 mild to 1e-2 severe for
    rail steels) and ``hardness_GPa`` H (3 GPa, wheel steel)."""

    law: Literal["archard"] = "archard"
    coefficient: Annotated[float, Field(gt=0, le=1, allow_inf_nan=False)] = 1e-4
    hardness_GPa: Annotated[float, Field(gt=0, le=20, allow_inf_nan=False)] = 3.0

    def build(self):
        from railwear.wear import Archard

        return Archard(self.coefficient, self.hardness_GPa * GPA)


@wear_section
class USFDWear(WearSection):
    """The USFD Tγ/A wear function (Braghin, Lewis, Dwyer-Joyce & Bruni 2006): ``convention``
    ``"continuous"`` or ``"as_printed"`` (see :class:`railwear.wear.USFD`), at ``density_kg_m3``."""

    law: Literal["usfd"] = "usfd"
    convention: Literal["continuous", "as_printed"] = "continuous"
    density_kg_m3: Annotated[float, Field(ge=1000, le=25000, allow_inf_nan=False)] = 7850.0

    def build(self):
        from railwear.wear import USFD

        return USFD(self.convention, self.density_kg_m3)


@wear_section
class HardeningWear(WearSection):
    """Work hardening on the energy law (paper eq. 2 with an internal state per cell, see
    :class:`railwear.wear.Hardening`): ``specific_wear_ug_per_J`` at ``density_kg_m3``, the state
    rising to ``saturation`` under ``power_scale_W_m2`` with ``time_constant_s`` (the wear
    coefficient falls to β / (1 + z)); ``state_scale_um`` the micrometres one unit of the state
    counts for in a stepwise step limit. Disk wheel only."""

    law: Literal["hardening"] = "hardening"
    specific_wear_ug_per_J: Annotated[float, Field(gt=0, le=1e4, allow_inf_nan=False)] = 5.3
    density_kg_m3: Annotated[float, Field(ge=1000, le=25000, allow_inf_nan=False)] = 7850.0
    saturation: Annotated[float, Field(ge=0, le=100, allow_inf_nan=False)] = 1.0
    power_scale_W_m2: Annotated[float, Field(gt=0, le=1e12, allow_inf_nan=False)] = 1e6
    time_constant_s: Annotated[float, Field(gt=0, le=1e9, allow_inf_nan=False)] = 3600.0
    state_scale_um: Annotated[float, Field(gt=0, le=1e6, allow_inf_nan=False)] = 10.0

    def build(self):
        from railwear.wear import Hardening

        return Hardening(self.specific_wear_ug_per_J * UG, self.density_kg_m3, self.saturation,
                         self.power_scale_W_m2, self.time_constant_s)


def _section_of(registry, key, default, what):
    """A before-validator: a TOML table validated by the class registered under its ``key``; a
    field the class does not have is named as not applying to it."""
    def pick(value):
        if isinstance(value, BaseModel):
            return value
        value = {} if value is None else value  # the default section of the default kind
        if not isinstance(value, dict):
            raise ValueError(f"must be a table, not {type(value).__name__}")
        name = value.get(key, default)
        if not isinstance(name, str) or name not in registry:
            raise refuse(key, f"unknown {what} {name!r}; known: {', '.join(sorted(registry))}")
        try:
            return registry[name].model_validate(value)
        except ValidationError as e:
            extra = [err["loc"][0] for err in e.errors() if err["type"] == "extra_forbidden"]
            if extra:
                raise refuse(extra[0], f"does not apply to {key} {name!r}") from None
            raise
    return pick


class DutySegmentSection(_Section):
    """One segment of ``[[operation.cycle]]``: its ``share`` of the distance, ``speed_kmh`` and
    signed ``traction_coefficient`` (creep force over wheel load: > 0 traction, < 0 braking)."""

    share: Annotated[float, Field(gt=0, le=1)]
    speed_kmh: Speed_kmh
    traction_coefficient: Annotated[float, Field(gt=-1, lt=1)]


class LineSection(_Section):
    """``[operation.line]``: a stopping service whose distance-weighted segments are derived
    (:func:`railwear.longterm.duty.line_cycle`): stations ``station_spacing_km`` apart,
    ``top_speed_kmh``, ``acceleration_m_s2`` and ``braking_m_s2``, for a ``"motor"`` wheel
    (traction and electric braking; ``motored_share`` of the train's weight on motor wheels) or a
    ``"trailer"`` wheel (disc braking through the contact); ``rotating_allowance`` ρ, the running
    ``resistance`` per weight, ``bins`` speed bins per acceleration and braking phase."""

    station_spacing_km: Annotated[float, Field(ge=0.1, le=1000)]
    top_speed_kmh: Speed_kmh
    acceleration_m_s2: Annotated[float, Field(gt=0, le=5)] = 1.0
    braking_m_s2: Annotated[float, Field(gt=0, le=5)] = 1.0
    wheel: Literal["motor", "trailer"] = "motor"
    motored_share: Annotated[float, Field(gt=0, le=1)] = 1.0
    rotating_allowance: Annotated[float, Field(ge=0, le=0.5)] = 0.08
    resistance: Annotated[float, Field(ge=0, le=0.05)] = 0.002
    bins: Annotated[int, Field(ge=1, le=100)] = 4


class Operation(_Section):
    """Speed (one, or a list for a batch) and the distance of one unit of normed life; or a duty
    cycle instead of the speed: segments ``[[operation.cycle]]`` or a ``[operation.line]`` to
    derive them from (their demands then replace ``contact.traction_coefficient``)."""

    speed_kmh: Speed_kmh | Annotated[list[Speed_kmh], Field(max_length=MAX_LIST)] | None = None
    speed_m_s: Speed_m_s | Annotated[list[Speed_m_s], Field(max_length=MAX_LIST)] | None = None
    life_distance_km: Annotated[float, Field(ge=1e-3, le=1e8)] = 50000.0  # a metre to 40 wheel lives
    # the wheel's mean daily mileage in service: distances to a limit are also said in months
    daily_distance_km: Annotated[float, Field(gt=0.0, le=5000.0)] | None = None
    cycle: Annotated[list[DutySegmentSection], Field(min_length=1, max_length=MAX_LIST)] | None = None
    line: LineSection | None = None

    @model_validator(mode="after")
    def _one_speed(self):
        if self.cycle is not None and self.line is not None:
            raise refuse("line", "give a cycle or a line, not both")
        speeds = [n for n in ("speed_kmh", "speed_m_s") if getattr(self, n) is not None]
        if self.cycle is not None or self.line is not None:
            if speeds:
                raise refuse(speeds[0], f"the duty {'cycle' if self.line is None else 'line'} gives the speeds; leave it out")
            if self.cycle is not None and abs(sum(s.share for s in self.cycle) - 1) > 1e-9:
                raise refuse("cycle", f"the shares of the distance must sum to 1, not {sum(s.share for s in self.cycle):.12g}")
            return self
        if len(speeds) != 1:
            raise ValueError("give exactly one of speed_kmh and speed_m_s (or a cycle or a line)")
        for name in ("speed_kmh", "speed_m_s"):
            value = getattr(self, name)
            if isinstance(value, list) and not _increasing(value):
                raise refuse(name, "must list distinct speeds in increasing order")
        return self

    def duty(self):
        """The :class:`~railwear.longterm.duty.DutyCycle` of ``cycle`` or ``line`` (SI), or ``None``."""
        from railwear.longterm.duty import DutyCycle, DutySegment, line_cycle

        if self.cycle is not None:
            return DutyCycle(tuple(DutySegment(s.share, kmh_to_m_s(s.speed_kmh), s.traction_coefficient)
                                   for s in self.cycle))
        if self.line is not None:
            n = self.line
            return line_cycle(n.station_spacing_km * 1e3, kmh_to_m_s(n.top_speed_kmh), n.acceleration_m_s2,
                              n.braking_m_s2, n.wheel, n.motored_share, n.rotating_allowance, n.resistance, n.bins)
        return None

    @property
    def speeds(self):
        """Speed or speeds in m/s; a list makes a batch; a duty cycle's mean speed (distance over time)."""
        if self.speed_kmh is not None:
            v = self.speed_kmh
            return kmh_to_m_s(v)
        if self.speed_m_s is None:
            return self.duty().mean_speed
        return self.speed_m_s


class WearRate(_Section):
    """``h``: the physical disk-contact form, a cubic in ``u_xx``, or a table; plus the odd terms
    ``drift_rad u_x + dispersion_rad3 u_xxx`` (per unit normed life: order ``n`` travels round the
    wheel at ``-(drift_rad - dispersion_rad3 n²)`` rad), each one value or one per ``table_speed_kmh``."""

    form: Literal["disk_contact", "cubic", "table"] = "disk_contact"
    c0: Coefficient = 0.0
    c1: Coefficient = 0.0
    c3: Coefficient = 0.0
    curvature_m: Annotated[list[Annotated[float, Field(ge=-10, le=10)]], Field(min_length=1, max_length=MAX_LIST)] | None = None
    table_speed_kmh: Annotated[list[Speed_kmh], Field(min_length=1, max_length=MAX_LIST)] | None = None
    rate_m: Annotated[list[Coefficient | Annotated[list[Coefficient], Field(max_length=MAX_LIST)]],
                      Field(min_length=1, max_length=MAX_LIST)] | None = None
    drift_rad: Coefficient | list[Coefficient] = 0.0
    dispersion_rad3: Coefficient | list[Coefficient] = 0.0

    @model_validator(mode="after")
    def _table_given(self):
        if self.form == "table":
            if self.curvature_m is None or self.rate_m is None:
                raise refuse("curvature_m" if self.curvature_m is None else "rate_m",
                             "form 'table' needs curvature_m and rate_m")
            self._table_shape()
        for name in ("drift_rad", "dispersion_rad3"):
            value = getattr(self, name)
            if isinstance(value, list) and (self.table_speed_kmh is None or len(value) != len(self.table_speed_kmh)):
                raise refuse(name, "a list needs table_speed_kmh and one value per table speed")
        return self

    def _table_shape(self):
        """``rate_m``: one entry per ``curvature_m`` value (at least 4, increasing for the
        spline), each a number, or with ``table_speed_kmh`` a row of one number per table speed."""
        curvature, speeds, rate = self.curvature_m, self.table_speed_kmh, self.rate_m
        if len(curvature) < 4:
            raise refuse("curvature_m", f"needs at least 4 values for the spline, not {len(curvature)}")
        if not _increasing(curvature):
            raise refuse("curvature_m", "must list distinct values in increasing order")
        if speeds is not None and not _increasing(speeds):
            raise refuse("table_speed_kmh", "must list distinct speeds in increasing order")
        if len(rate) != len(curvature):
            raise refuse("rate_m", f"expected one entry per curvature_m value ({len(curvature)}), not {len(rate)}")
        for i, row in enumerate(rate):
            if speeds is None and isinstance(row, list):
                raise refuse(("rate_m", i), "expected a number (rows of one value per speed need table_speed_kmh)")
            if speeds is not None and (not isinstance(row, list) or len(row) != len(speeds)):
                given = len(row) if isinstance(row, list) else "a number"
                raise refuse(("rate_m", i), f"expected a row of {len(speeds)} values, one per table_speed_kmh, not {given}")


class Solver(_Section):
    points: Annotated[int, Field(ge=16, le=65536)] = 512
    epsilon: Annotated[float, Field(ge=0, le=1e3)] = 1e-4
    nu: Annotated[float, Field(ge=0, le=1e3)] = 1e-3
    t_end: Annotated[float, Field(gt=0, le=1e3)] = 1.0  # normed lives
    depth_limit_mm: Annotated[float, Field(ge=1e-6, le=100)] | None = 1.0  # a wheel has ~40 mm to lose
    peak_to_peak_limit_mm: Annotated[float, Field(ge=1e-4, le=10)] | None = None  # out of round: 0.1-0.6 mm
    n_save: Annotated[int, Field(ge=2, le=MAX_SAVED)] = 101
    dealias: bool = True
    dt: Annotated[float, Field(gt=0, le=1e3)] | None = None

    @field_validator("points")
    @classmethod
    def _even(cls, v):
        if v % 2:
            raise ValueError("must be even")
        return v

    @model_validator(mode="after")
    def _steps(self):
        """A guard on the work, not on the clock: a fixed ``dt`` may not take more than
        :data:`MAX_STEPS` steps to ``t_end``, the saved states not hold more than
        :data:`MAX_SAVED_VALUES` values."""
        if self.dt is not None and self.t_end / self.dt > MAX_STEPS:
            raise refuse("dt", f"t_end / dt = {self.t_end / self.dt:.3g} steps, more than {MAX_STEPS:.0e}")
        if self.n_save * self.points > MAX_SAVED_VALUES:
            raise refuse("n_save", f"n_save x points = {self.n_save * self.points:.3g} saved values, more than "
                                   f"{MAX_SAVED_VALUES:.0e}: at most {MAX_SAVED_VALUES // self.points} "
                                   f"at {self.points} points")
        return self


class InitialWheel(_Section):
    """One wheel's starting radius deviation: ``kind`` random (``rms_um`` over orders
    ``lowest_order..highest_order``, amplitude ∝ ``n^-amplitude_slope``, ``seed``), harmonics
    (``orders``, ``amplitudes_um``, ``phases_deg``), measured (``file``) or round."""

    kind: Literal["random", "harmonics", "measured", "round"] = "random"
    rms_um: Annotated[float, Field(ge=0, le=1e4)] = 40.0  # 10 mm out of round is long past scrap
    lowest_order: Count = 2
    highest_order: Count = 16
    seed: Annotated[int, Field(ge=0, lt=2**64)] = 1
    amplitude_slope: Annotated[float, Field(ge=0, le=4)] = 0.0  # kind "random": amplitude of order n ∝ n^-slope
    orders: Annotated[list[Count], Field(max_length=MAX_LIST)] | None = None
    amplitudes_um: Annotated[list[Annotated[float, Field(ge=-1e4, le=1e4)]], Field(max_length=MAX_LIST)] | None = None
    phases_deg: Annotated[list[Annotated[float, Field(ge=-360, le=360)]], Field(max_length=MAX_LIST)] | None = None
    file: PathText | None = None

    @model_validator(mode="after")
    def _complete(self):
        if self.kind == "harmonics" and (self.orders is None or self.amplitudes_um is None):
            raise refuse("orders" if self.orders is None else "amplitudes_um",
                         "kind 'harmonics' needs orders and amplitudes_um")
        if self.kind == "measured" and not self.file:
            raise refuse("file", "kind 'measured' needs file (a CSV of angle and deviation)")
        if self.lowest_order > self.highest_order:
            raise refuse("lowest_order", f"must not exceed highest_order ({self.highest_order})")
        for name in ("amplitudes_um", "phases_deg"):
            values = getattr(self, name)
            if self.kind == "harmonics" and values is not None and len(values) != len(self.orders):
                raise refuse(name, f"needs one value per order ({len(self.orders)}), not {len(values)}")
        return self


class Initial(InitialWheel):
    """``[initial]``: the wheel's starting surface (:class:`InitialWheel`'s fields); with several
    wheels on the rail (``body.wheel_positions_m``) all but the first start round, or ``wheels``
    gives each its own: one ``[[initial.wheels]]`` per wheel, in the order of the positions, and
    then none of the fields above."""

    wheels: Annotated[list[InitialWheel], Field(min_length=2, max_length=MAX_LIST)] | None = None

    @model_validator(mode="after")
    def _one_way(self):
        given = sorted(self.model_fields_set - {"wheels"})
        if self.wheels is not None and given:
            raise refuse(given[0], "the wheels' surfaces are given per wheel in [[initial.wheels]]: leave it out here")
        return self

    @property
    def surfaces(self) -> tuple:
        """Each wheel's :class:`InitialWheel` (``wheels``), or this section alone."""
        return tuple(self.wheels) if self.wheels is not None else (self,)


PER_WHEEL_STRATEGIES = ("fourier", "stepwise", "direct")  # those that run [[initial.wheels]]
OPTIONAL_PARTS = ("solver.dealias", "solver.dt", "solver.epsilon", "solver.nu", "wear_rate",
                  "solver.peak_to_peak_limit_mm", "track")  # read by some strategies or bodies only
EQUATION = frozenset({"solver.dealias", "solver.dt", "solver.epsilon", "solver.nu"})  # the evolution equation's
NEEDS = {"rates": "frozen-geometry wear rates", "segment": "a coupled segment of dynamics and wear",
         "linear_model": "a linear model"}  # what a strategy can ask of a body


class StrategySection(_Section):
    """``[strategy]``: the long-term strategy named by ``kind`` with its own fields (a field of
    another kind is an error). ``needs`` is what it asks of the ``[body]`` (a key of
    :data:`NEEDS`, ``None``: nothing, as the evolution equation of ``[wear_rate]``);
    ``reads`` which of the :data:`OPTIONAL_PARTS` it reads; ``batches_speeds`` whether a list of
    speeds runs as one batch; ``runs_cycles`` whether it runs an ``[operation]`` duty cycle
    (:meth:`cycle_refusal` names a field of its own that keeps it from one). A new strategy registers its
    section with :func:`strategy_section` and its builder with :func:`railwear.scenario.build.builds`."""

    kind: str
    needs: ClassVar[str | None] = None
    validated_against: ClassVar[str] = ""  # a strategy that needs no body says what its model holds against
    reads: ClassVar[frozenset] = frozenset()
    batches_speeds: ClassVar[bool] = False
    runs_cycles: ClassVar[bool] = False

    def cycle_refusal(self):
        """``(field, reason)`` of a setting of this section that cannot run a duty cycle, or ``None``."""
        return None


STRATEGY_SECTIONS: dict = {}


def strategy_section(cls):
    """Register a ``[strategy]`` section class under the default of its ``kind`` field."""
    if cls.needs is not None and cls.needs not in NEEDS:
        raise TypeError(f"strategy section {cls.__name__}: needs must be None or one of {', '.join(NEEDS)}")
    STRATEGY_SECTIONS[cls.model_fields["kind"].default] = cls
    return cls


@strategy_section
class PhenomenologicalSection(StrategySection):
    """The evolution equation (paper eq. 4) with the ``h`` of ``[wear_rate]`` and the
    regularisation of ``[solver]``."""

    kind: Literal["phenomenological"] = "phenomenological"
    reads: ClassVar[frozenset] = EQUATION | {"wear_rate"}
    validated_against: ClassVar[str] = ("the paper's evolution equation (its Figs 9-11: smoothing, onset, "
                                        "polygonalisation), qualitatively; no field observations")
    batches_speeds: ClassVar[bool] = True


@strategy_section
class FourierSection(StrategySection):
    """The Fourier technique (one speed) on the body's linear model."""

    kind: Literal["fourier"] = "fourier"
    needs: ClassVar[str] = "linear_model"
    reads: ClassVar[frozenset] = frozenset({"solver.peak_to_peak_limit_mm"})
    runs_cycles: ClassVar[bool] = True


@strategy_section
class MultiplierSection(StrategySection):
    """The multiplier law (one speed): the Fourier technique's rate per order exact in ETDRK4's
    linear part, plus ``local`` = ``"load"`` (the contact's load nonlinearity: creep stiffness,
    saturation, contact loss) or ``"none"``, on the body's linear model. ``grid_points``: the
    surface grid of a direct run to compare with (filters the rates as that grid does).
    ``[solver] epsilon`` and ``nu`` default to 0 here. Over a duty cycle (``local = "none"``) the
    rates are the cycle's distance-weighted Fourier rates."""

    kind: Literal["multiplier"] = "multiplier"
    needs: ClassVar[str] = "linear_model"
    reads: ClassVar[frozenset] = EQUATION | {"solver.peak_to_peak_limit_mm"}
    runs_cycles: ClassVar[bool] = True
    local: Literal["load", "none"] = "load"
    grid_points: Annotated[int, Field(ge=2, le=65536)] | None = None

    def cycle_refusal(self):
        if self.local == "load":
            return "local", ("the load nonlinearity is one per segment (its load transfer, contact and table depend on "
                             "the segment's speed and demand), and the solver takes one; over a duty cycle use "
                             "local = \"none\" (the cycle's averaged Fourier rates)")
        return None


@strategy_section
class StepwiseSection(StrategySection):
    """Stepwise frozen geometry: ``step_limit_um`` the largest change of ``u``
    (``step_limit_on = "u"``) or of its shape ``u - mean(u)`` (``"shape"``) per long-term step,
    taken by ``scheme`` (``"euler"``, or ``"adams-bashforth"``: second order at the same cost per
    step); the body's frozen-geometry rates are drawn as ``[body]`` says, over a duty cycle each
    draw from a segment with the probability of its share of the distance."""

    kind: Literal["stepwise"] = "stepwise"
    needs: ClassVar[str] = "rates"
    runs_cycles: ClassVar[bool] = True
    step_limit_um: Annotated[float, Field(gt=0, le=1e6)] = 10.0
    step_limit_on: Literal["u", "shape"] = "u"
    scheme: Literal["euler", "adams-bashforth"] = "euler"


@strategy_section
class DirectSection(StrategySection):
    """Direct coupled integration: ``acceleration_factor`` on the wear coefficient (>= 1); the
    body's coupled segments as ``[body]`` says; over a duty cycle every segment from its own
    settled state, weighed by distance (:mod:`railwear.longterm.direct`)."""

    kind: Literal["direct"] = "direct"
    needs: ClassVar[str] = "segment"
    runs_cycles: ClassVar[bool] = True
    acceleration_factor: Annotated[float, Field(ge=1, le=1e9, allow_inf_nan=False)] = 100.0


class BodySection(_Section):
    """``[body]``: what wears, named by ``kind``, with its own fields (a field of another kind is
    an error). A body section says what it ``provides`` (keys of :data:`NEEDS`), which of its
    fields serve only some needs (``serves``: field -> needs; other fields always apply), which
    other sections it reads (``sections``, e.g. ``("track",)``), whether it starts from its new
    state rather than ``[initial]`` (``starts_new``) and whether the direct strategy saves after
    every segment (``saves_every_segment``), whether it carries ``contact.traction_coefficient``
    (``longitudinal_demand``). A new body registers its section with
    :func:`body_section`; ``build(scenario, speed)`` returns the
    :class:`~railwear.longterm.base.Body` and ``linear_model(scenario, speed)`` the linear model
    with its wear band (m)."""

    kind: str
    provides: ClassVar[frozenset] = frozenset()
    serves: ClassVar[dict] = {}
    sections: ClassVar[tuple] = ()
    starts_new: ClassVar[bool] = False
    saves_every_segment: ClassVar[bool] = False
    longitudinal_demand: ClassVar[bool] = True
    label: ClassVar[str] = ""
    validated_against: ClassVar[str] = ""

    def scope(self, scenario, ds):
        """Why this run lies outside what the body's model was validated against (texts; none:
        inside). ``ds`` is the run's result."""
        return []

    def build(self, scenario, speed=None):
        """The long-term body at ``speed`` (m/s; default the service mean); a section that
        provides neither rates nor segments has none and is refused naming ``body.kind``."""
        raise ScenarioError(f"body.kind: body {self.kind!r} gives no {NEEDS['rates']} or {NEEDS['segment']}")

    def linear_model(self, scenario, speed):
        """``(model, band_width)``: the linearisable model at ``speed`` (m/s) and its wear band (m);
        a section that does not provide one is refused naming ``body.kind``."""
        raise ScenarioError(f"body.kind: body {self.kind!r} gives no {NEEDS['linear_model']}")

    def growth_map(self, scenario, speeds, orders):
        """Fourier growth rate (1/km) over ``speeds`` (m/s) x ``orders`` on :meth:`linear_model`."""
        from railwear.longterm.fourier import stability_map

        band = self.linear_model(scenario, speeds[0])[1]
        return stability_map(lambda v: self.linear_model(scenario, v)[0], speeds, orders, scenario.wear.build(), band)


BODY_SECTIONS: dict = {}


def body_section(cls):
    """Register a ``[body]`` section class under the default of its ``kind`` field."""
    unknown = sorted(set(cls.provides) - set(NEEDS)) + sorted(
        n for needs in cls.serves.values() for n in needs if n not in NEEDS)
    if unknown:
        raise TypeError(f"body section {cls.__name__}: {unknown[0]!r} is not one of {', '.join(NEEDS)}")
    BODY_SECTIONS[cls.model_fields["kind"].default] = cls
    return cls


# [track] fields that apply to some bases only, and the scenario field of a support set's value (SI).
TRACK_BASE_FIELDS = {
    "ballast": ("sleeper_mass_kg", "ballast_stiffness_MN_m", "ballast_damping_kN_s_m", "ballast_loss_factor"),
    "ballast_subgrade": ("sleeper_mass_kg", "ballast_stiffness_MN_m", "ballast_damping_kN_s_m", "ballast_loss_factor",
                         "ballast_mass_kg", "subgrade_stiffness_MN_m", "subgrade_damping_kN_s_m",
                         "subgrade_loss_factor"),
    "slab": ("slab_mass_kg", "mortar_stiffness_MN_m", "mortar_damping_kN_s_m", "mortar_loss_factor"),
    "rigid": (),
}
_BASE_ONLY = frozenset(name for names in TRACK_BASE_FIELDS.values() for name in names)
_TRACK_UNITS = (("_MN_m", MN), ("_kN_s_m", KN), ("_kg", 1.0), ("_m", 1.0))  # suffix, SI per field unit


def track_field(key):
    """``(field, SI per unit)`` of a support set's value ``key`` (``railwear.track.base_fields``):
    ``pad_stiffness`` is ``pad_stiffness_MN_m`` in MN/m, ``slab_mass`` ``slab_mass_kg``."""
    suffix = {"stiffness": "_MN_m", "damping": "_kN_s_m", "mass": "_kg", "spacing": "_m"}.get(key.rsplit("_", 1)[-1], "")
    return key + suffix, dict(_TRACK_UNITS).get(suffix, 1.0)


# [track]'s default support (SI): the shipped set zhai-2004-no-subgrade (railwear/track/data/supports.toml),
# written out so that the schema loads without the track physics; tests/track hold them equal
_TRACK = {"pad_stiffness": 65e6, "pad_damping": 75e3, "sleeper_mass": 125.5, "ballast_stiffness": 137.75e6,
          "ballast_damping": 58.8e3}


class TrackSection(_Section):
    """``[track]``: one rail (``rail`` a shipped section, ``beam`` its theory, ``rail_loss_factor``)
    on its support per rail seat at ``sleeper_spacing_m`` (``support = "continuous"`` spreads it
    evenly over the spacing), for body ``"vehicle_track"``. ``base`` is what carries the pads:

    - ``"ballast"``: half a sleeper (``sleeper_mass_kg``) on a ballast spring on rigid ground;
    - ``"ballast_subgrade"``: the two-layer ballasted support, the ballast a mass (``ballast_mass_kg``)
      on a subgrade spring (``subgrade_*``);
    - ``"slab"``: the pads are the fasteners, on a slab (``slab_mass_kg``, its share per rail seat)
      on a CA-mortar layer (``mortar_*``) on rigid ground;
    - ``"rigid"``: the pads on a rigid base.

    A field of another base is refused naming it. ``preset`` names a shipped support set
    (``railwear.track.support_set_names()``; data and sources in ``railwear/track/data/supports.toml``):
    it sets ``base`` and the support values and spacing the file does not give. ``base =
    "ballast_subgrade"`` or ``"slab"`` without a preset takes the set marked default for it (Zhai,
    Wang & Lin 2004; a CRTS slab of Shock Vib. 2019, 2015465); ``"ballast"`` and ``"rigid"`` keep the
    defaults below (Zhai, Wang & Lin, JSV 270 (2004) 673, without the ballast mass and subgrade, with
    a 60E1 rail). Springs carry a viscous coefficient and a loss factor together. ``bay_positions``:
    the wheel's offsets past a sleeper the Fourier technique averages over; ``ring_sleepers`` and
    ``ring_max_frequency_hz``: the time-domain track of the stepwise and direct strategies (a ring of
    that many bays, rail modes to that frequency, the rest as residual flexibility; 1 % of the
    receptance to about 250 Hz at 3 kHz, see docs/vehicle_track_time.md; bases "ballast", "slab" and
    "rigid")."""

    rail: Literal["60E1", "54E1", "UIC60", "UIC54"] = "60E1"
    beam: Literal["euler", "timoshenko"] = "timoshenko"
    rail_loss_factor: Annotated[float, Field(ge=0, le=1)] = 0.02
    support: Literal["discrete", "continuous"] = "discrete"
    sleeper_spacing_m: Annotated[float, Field(ge=0.3, le=1.5)] = 0.6
    pad_stiffness_MN_m: Annotated[float, Field(ge=1, le=1e4)] = _TRACK["pad_stiffness"] / 1e6  # soft pads to stiff EVA
    pad_damping_kN_s_m: Annotated[float, Field(ge=0, le=1e4)] = _TRACK["pad_damping"] / 1e3
    pad_loss_factor: Annotated[float, Field(ge=0, le=2)] = 0.0
    sleeper_mass_kg: Annotated[float, Field(ge=0, le=2000)] = _TRACK["sleeper_mass"]  # half a sleeper
    base: Literal["ballast", "ballast_subgrade", "slab", "rigid"] = "ballast"
    preset: Name | None = None
    ballast_stiffness_MN_m: Annotated[float, Field(ge=1, le=1e5)] = _TRACK["ballast_stiffness"] / 1e6
    ballast_damping_kN_s_m: Annotated[float, Field(ge=0, le=1e4)] = _TRACK["ballast_damping"] / 1e3
    ballast_loss_factor: Annotated[float, Field(ge=0, le=2)] = 0.0
    ballast_mass_kg: Annotated[float, Field(ge=0, le=1e4)] | None = None  # under one rail seat
    subgrade_stiffness_MN_m: Annotated[float, Field(ge=1, le=1e5)] | None = None
    subgrade_damping_kN_s_m: Annotated[float, Field(ge=0, le=1e4)] | None = None
    subgrade_loss_factor: Annotated[float, Field(ge=0, le=2)] = 0.0
    slab_mass_kg: Annotated[float, Field(ge=1, le=1e4)] | None = None  # the slab's share per rail seat
    mortar_stiffness_MN_m: Annotated[float, Field(ge=1, le=1e5)] | None = None
    mortar_damping_kN_s_m: Annotated[float, Field(ge=0, le=1e4)] | None = None
    mortar_loss_factor: Annotated[float, Field(ge=0, le=2)] = 0.0
    bay_positions: Annotated[int, Field(ge=1, le=256)] = 8
    ring_sleepers: Annotated[int, Field(ge=8, le=1024)] = 32
    ring_max_frequency_hz: Annotated[float, Field(ge=200, le=20000)] = 3000.0

    @model_validator(mode="after")
    def _base(self):
        given, chosen = self.model_fields_set, None
        if self.preset is not None or self.base in ("ballast_subgrade", "slab"):
            from railwear.track.model import default_support_set, support_set, support_set_names

            if self.preset is None:
                chosen = default_support_set(self.base)
            elif self.preset not in support_set_names():
                raise refuse("preset", f"must be one of {', '.join(support_set_names())}, got {self.preset!r}")
            else:
                chosen = support_set(self.preset)
                if "base" in given and self.base != chosen.base:
                    raise refuse("base", f"is {self.base!r}, but preset {self.preset!r} is a {chosen.base!r} set")
                object.__setattr__(self, "base", chosen.base)
        wrong = sorted((given & _BASE_ONLY) - set(TRACK_BASE_FIELDS[self.base]))
        if wrong:
            raise refuse(wrong[0], f"does not apply to base {self.base!r}")
        if chosen is not None:
            for key, value in {**chosen.values, "sleeper_spacing": chosen.sleeper_spacing}.items():
                name, unit = track_field(key)
                if name not in given:
                    object.__setattr__(self, name, value / unit)
        return self

    @model_serializer(mode="wrap")
    def _applicable(self, handler):
        """Only the fields of the chosen base (and ``preset`` when one is named), so that a scenario
        reads back as written and the files of the bases before the new ones keep their text and hash."""
        data = handler(self)
        if isinstance(data, dict):
            for name in _BASE_ONLY.difference(TRACK_BASE_FIELDS[self.base]) | ({"preset"} if self.preset is None else set()):
                data.pop(name, None)
        return data

    def support_values(self) -> dict:
        """The support values of the base (``railwear.track.base_fields``), SI."""
        from railwear.track.model import base_fields

        out = {}
        for key in base_fields(self.base):
            name, unit = track_field(key)
            out[key] = getattr(self, name) * unit
        return out


class WheelsetSuspension(_Section):
    """A suspended wheelset on straight track, for hunting (critical-speed) maps.

    The rolling radius is ``wheel.radius_m``; Kalker's coefficients come from the Hertz patch of
    ``[contact]`` at the wheel load. Defaults: the Cooperrider wheelset (mass, yaw inertia, half
    gauge) on stiff primary springs.
    """

    mass_kg: Annotated[float, Field(ge=10, le=1e5)] = 1022.0
    yaw_inertia_kg_m2: Annotated[float, Field(ge=1, le=1e5)] = 678.0
    lateral_stiffness_N_m: Stiffness = 1.823e6
    yaw_stiffness_N_m_rad: Stiffness = 3.646e6
    half_gauge_m: Annotated[float, Field(ge=0.15, le=1.5)] = 0.7163  # 300 mm gauge to twice broad gauge
    conicity: Annotated[float, Field(gt=0, le=1)] = 0.05


class Service(_Section):
    """Scatter of the service conditions, for forecasts: speed peaks with weights, load, friction."""

    speed_kmh: Annotated[list[Speed_kmh], Field(min_length=1, max_length=MAX_LIST)] | None = None
    speed_weights: Annotated[list[Annotated[float, Field(ge=0, le=1)]], Field(max_length=MAX_LIST)] | None = None
    speed_scatter_kmh: Annotated[float, Field(ge=0, le=SPEED_KMH[1])] = 0.0
    load_scatter: Annotated[float, Field(ge=0, lt=0.5)] = 0.0
    friction_range: list[Annotated[float, Field(gt=0, le=2)]] | None = None
    samples: Annotated[int, Field(ge=1, le=100000)] = 64
    seed: Annotated[int, Field(ge=0, lt=2**64)] = 0

    @model_validator(mode="after")
    def _distribution(self):
        if self.speed_weights is not None:
            if self.speed_kmh is None or len(self.speed_weights) != len(self.speed_kmh):
                peaks = len(self.speed_kmh or ())
                raise refuse("speed_weights", f"needs one weight per speed_kmh peak: {len(self.speed_weights)} "
                                              f"weight(s), {peaks} peak(s)")
            if abs(sum(self.speed_weights) - 1) > 1e-9:
                raise ValueError(f"the speed distribution must sum to 1, not {sum(self.speed_weights):g} "
                                 "(speed_weights)")
        if self.friction_range is not None and (len(self.friction_range) != 2
                                                or self.friction_range[0] > self.friction_range[1]):
            raise refuse("friction_range", "must be [low, high]")
        return self


OLD_BODY_SECTIONS = {"disk_wheel": "disk_wheel", "vehicle_track": "vehicle", "wheelset": "wheelset_wear"}
OLD_BODY_SETTINGS = ("samples", "revolutions", "transient_revolutions", "updates_per_revolution")
EQUATION_DEFAULTS = {"multiplier": {"epsilon": 0.0, "nu": 0.0}}  # [solver] defaults that differ by strategy


def _strategy_defaults(data):
    """``[solver]`` defaults of the strategy (:data:`EQUATION_DEFAULTS`) written into plain
    ``data``, so that the scenario's text says what runs and round-trips to the same problem."""
    strategy, solver = data.get("strategy"), data.get("solver", {})
    kind = strategy.get("kind") if isinstance(strategy, dict) else None
    if isinstance(kind, str) and kind in EQUATION_DEFAULTS and isinstance(solver, dict):
        data["solver"] = {**EQUATION_DEFAULTS[kind], **solver}
    return data


def _new_layout(data):
    """Plain scenario ``data`` in the layout before ``[body]`` (``[strategy] body`` with the body
    settings under ``[strategy]``, and ``[disk_wheel]``, ``[vehicle]`` or ``[wheelset_wear]``)
    moved to ``[body]``, with a :class:`~railwear.errors.ScenarioLayoutWarning` saying so."""
    strategy = data.get("strategy") if isinstance(data.get("strategy"), dict) else {}
    old = [f"[{k}]" for k in OLD_BODY_SECTIONS.values() if k in data] + [
        f"strategy.{k}" for k in ("body",) + OLD_BODY_SETTINGS if k in strategy]
    if not old or not isinstance(data.get("body", {}), dict):
        return data
    data, strategy, body = dict(data), dict(strategy), dict(data.get("body", {}))
    kind = strategy.pop("body", body.get("kind", "disk_wheel"))
    if body.get("kind", kind) != kind:
        raise refuse(("strategy", "body"), f"is body.kind now, which says {body['kind']!r}; give it once")
    moved = {name: strategy.pop(name) for name in OLD_BODY_SETTINGS if name in strategy}
    section = OLD_BODY_SECTIONS.get(kind) if isinstance(kind, str) else None
    for name, owner in OLD_BODY_SECTIONS.items():
        if owner in data and owner != section:
            raise refuse((owner,), f"applies to body {name!r} only (now [body] kind = {name!r})")
    if section in data:
        if not isinstance(data[section], dict):
            raise refuse((section,), "should be a table")
        moved.update(data.pop(section))
    for name, value in moved.items():
        if name in body:
            raise refuse(("body", name), f"given twice: here and in the layout before [body] ({', '.join(old)})")
        body[name] = value
    if "strategy" in data:
        data["strategy"] = strategy
    data["body"] = {"kind": kind, **body}
    warnings.warn(f"scenario layout before [body]: {', '.join(old)} read as [body] kind = {kind!r} "
                  "(railwear show NAME prints the new layout)", ScenarioLayoutWarning, stacklevel=2)
    return data


class Scenario(_Section):
    """A whole railwear run: wheel, contact, wear, operation, h, solver, initial state, the
    strategy and the body it wears."""

    name: Name = "unnamed"
    description: Text = ""
    wheel: Wheel = Wheel()
    contact: Contact = Contact()
    wear: SerializeAsAny[WearSection] = Wear()
    operation: Operation = Operation(speed_kmh=220.0)
    wear_rate: WearRate = WearRate()
    solver: Solver = Solver()
    initial: Initial = Initial()
    service: Service = Service()
    strategy: SerializeAsAny[StrategySection] = PhenomenologicalSection()
    body: SerializeAsAny[BodySection] = Field(default=None, validate_default=True)
    wheelset: WheelsetSuspension = WheelsetSuspension()
    track: TrackSection = TrackSection()

    _wear = field_validator("wear", mode="before")(_section_of(WEAR_SECTIONS, "law", "energy", "wear law"))
    _strategy = field_validator("strategy", mode="before")(
        _section_of(STRATEGY_SECTIONS, "kind", "phenomenological", "strategy kind"))
    _body = field_validator("body", mode="before")(_section_of(BODY_SECTIONS, "kind", "disk_wheel", "body kind"))

    @model_validator(mode="before")
    @classmethod
    def _layout(cls, data):
        if not isinstance(data, dict):
            return data
        return _strategy_defaults(_new_layout(data))

    @model_validator(mode="after")
    def _applies(self):
        need, body = self.strategy.needs, self.body
        if need is not None and need not in body.provides:
            able = [k for k, c in BODY_SECTIONS.items() if need in c.provides]
            raise refuse(("body", "kind"), f"the {self.strategy.kind} strategy needs {NEEDS[need]}, which body "
                                           f"{body.kind!r} does not give; bodies that do: {', '.join(able)}")
        for name in sorted(body.model_fields_set):
            serves = body.serves.get(name)
            if serves is not None and need not in serves:
                kinds = [k for k, c in STRATEGY_SECTIONS.items() if c.needs in serves]
                raise refuse(("body", name), f"applies to the {' and '.join(kinds)} "
                                             f"strateg{'ies' if len(kinds) > 1 else 'y'} only, not {self.strategy.kind!r}")
        for section, names, applies, to in self._only_for():
            given = getattr(self, section).model_fields_set & set(names or type(getattr(self, section)).model_fields)
            if given and not applies:
                raise refuse((section, sorted(given)[0]), f"applies to {to} only")
        self._duty()
        self._orders_on_grid()
        self._stepwise_steps()
        return self

    def _duty(self):
        """A duty cycle runs with a strategy that runs one (:attr:`StrategySection.runs_cycles`)
        and carries the demand itself; every demand stays below adhesion, ``|f| < μ``."""
        op = self.operation
        given = "cycle" if op.cycle is not None else "line" if op.line is not None else None
        mu = self.contact.friction_coefficient
        if given is None:
            f = self.contact.traction_coefficient
            if self.body.longitudinal_demand and abs(f) >= mu:
                raise refuse(("contact", "traction_coefficient"), f"|{f:g}| needs more than the adhesion limit: "
                                                                  f"must be below friction_coefficient = {mu:g}")
            return
        demands = [abs(s.traction_coefficient) for s in op.cycle] if op.cycle is not None else \
            [float(max(abs(op.duty().demands)))]
        if max(demands) >= mu:
            where = ("operation", "cycle", demands.index(max(demands)), "traction_coefficient") if op.cycle is not None \
                else ("operation", "line", "acceleration_m_s2" if op.line.acceleration_m_s2 >= op.line.braking_m_s2
                      else "braking_m_s2")
            raise refuse(where, f"a demand of {max(demands):.3g} x the wheel load needs more than the adhesion limit "
                                f"(contact.friction_coefficient = {mu:g})")
        if not self.strategy.runs_cycles:
            able = [k for k, c in STRATEGY_SECTIONS.items() if c.runs_cycles]
            raise refuse(("operation", given), f"the {self.strategy.kind} strategy runs one operating point; a duty "
                                               f"cycle runs with the {' or '.join(able)} strategy")
        if not self.body.longitudinal_demand:
            raise refuse(("operation", given), f"body {self.body.kind!r} carries no longitudinal demand to cycle")
        refusal = self.strategy.cycle_refusal()
        if refusal is not None:
            raise refuse(("strategy", refusal[0]), refusal[1])
        if self.strategy.needs == "rates" and self.service.speed_kmh is not None:
            raise refuse(("service", "speed_kmh"), f"operation.{given} gives the speeds the draws take; leave it out")
        if "traction_coefficient" in self.contact.model_fields_set:
            raise refuse(("contact", "traction_coefficient"), f"operation.{given} gives the demand per segment; "
                                                              "leave it out")

    def _orders_on_grid(self):
        """The initial orders resolved on ``solver.points``: below the Nyquist order ``points / 2``."""
        self._initial_wheels()
        if self.body.starts_new:
            return
        points = self.solver.points
        top = points // 2 - 1
        per_wheel = self.initial.wheels is not None
        for k, init in enumerate(self.initial.surfaces):
            at = ("initial", "wheels", k) if per_wheel else ("initial",)
            if init.kind == "random" and init.highest_order > top:
                raise refuse(at + ("highest_order",), f"must be at most {top} on solver.points = {points}")
            for i, order in enumerate(init.orders or ()):
                if init.kind == "harmonics" and order > top:
                    raise refuse(at + ("orders", i), f"must be at most {top} on solver.points = {points}")

    def _initial_wheels(self):
        """``[[initial.wheels]]``: one per wheel of ``body.wheel_positions_m``, under a strategy
        that carries each wheel's surface (:data:`PER_WHEEL_STRATEGIES`)."""
        wheels = self.initial.wheels
        if wheels is None:
            return
        positions = getattr(self.body, "wheel_positions_m", None) or ()
        if len(positions) < 2:
            raise refuse(("initial", "wheels"), "one surface per wheel needs several wheels on the rail "
                                                "(body.wheel_positions_m); one wheel takes the fields of [initial]")
        if len(wheels) != len(positions):
            raise refuse(("initial", "wheels"), f"one [[initial.wheels]] per wheel of body.wheel_positions_m "
                                                f"({len(positions)}), in their order, not {len(wheels)}")
        if self.strategy.kind not in PER_WHEEL_STRATEGIES:
            raise refuse(("initial", "wheels"), f"the {self.strategy.kind} strategy runs the wheels in one growing "
                                                f"combination; a surface per wheel runs with the "
                                                f"{', '.join(PER_WHEEL_STRATEGIES)} strategies")

    def _stepwise_steps(self):
        """A guard on the work of a step limit: at most :data:`MAX_LONGTERM_STEPS` steps of
        ``strategy.step_limit_um`` to ``solver.depth_limit_mm`` (without one, to :data:`WORN_MM`)."""
        step = getattr(self.strategy, "step_limit_um", None)
        if step is None:
            return
        depth = self.solver.depth_limit_mm or WORN_MM
        steps = depth * 1e3 / step
        if steps > MAX_LONGTERM_STEPS:
            raise refuse(("strategy", "step_limit_um"), f"{depth:g} mm to wear in steps of {step:g} um is {steps:.3g} "
                         f"steps, more than {MAX_LONGTERM_STEPS:.0e}: at least {depth * 1e3 / MAX_LONGTERM_STEPS:g} um")

    def _only_for(self):
        """(section, fields or None for all, whether they apply, to what) of the parts of a
        scenario that only some strategies (:attr:`StrategySection.reads`) or bodies
        (:attr:`BodySection.sections`) read."""
        out = []
        for part in OPTIONAL_PARTS:
            section, _, name = part.partition(".")
            kinds = [k for k, c in STRATEGY_SECTIONS.items() if part in c.reads]
            bodies = [f"body {k!r}" for k, c in BODY_SECTIONS.items() if part in c.sections]
            to = [f"the {' and '.join(kinds)} strateg{'ies' if len(kinds) > 1 else 'y'}"] if kinds else []
            applies = part in self.strategy.reads or part in self.body.sections
            out.append((section, (name,) if name else None, applies, " and ".join(to + bodies)))
        return tuple(out)

    def applicable(self, **dump):
        """The scenario as plain data (``model_dump`` options ``dump``; default JSON types without
        ``None``) without the fields that do not apply to its strategy and body."""
        data = self.model_dump(**{"mode": "json", "exclude_none": True, **dump})
        if self.operation.cycle is not None or self.operation.line is not None:
            data["contact"].pop("traction_coefficient", None)  # the duty cycle's segments carry the demand
        if self.initial.wheels is not None:  # each wheel's surface in [[initial.wheels]], none of [initial]'s own
            data["initial"] = {"wheels": data["initial"]["wheels"]}
        for name, serves in self.body.serves.items():
            if self.strategy.needs not in serves:
                data["body"].pop(name, None)
        for section, names, applies, _ in self._only_for():
            if not applies:
                for name in names or list(data[section]):
                    data[section].pop(name, None)
                if not data[section]:
                    data.pop(section)
        return data
