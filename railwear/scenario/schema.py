"""The scenario schema: frozen pydantic models with physical bounds; units in the field names."""

from typing import Annotated, ClassVar, Literal

from pydantic import (BaseModel, ConfigDict, Field, SerializeAsAny, ValidationError, field_validator,
                      model_validator)

from railwear.units import GPA, UG, kmh_to_m_s

Positive = Annotated[float, Field(gt=0, allow_inf_nan=False)]
NonNegative = Annotated[float, Field(ge=0, allow_inf_nan=False)]
Finite = Annotated[float, Field(allow_inf_nan=False)]


class _Section(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True)


class Wheel(_Section):
    radius_m: Positive = 0.46
    unsprung_mass_kg: Positive = 1000.0
    static_load_kN: Positive = 80.0


class Contact(_Section):
    youngs_modulus_GPa: Positive = 210.0
    poisson: Annotated[float, Field(ge=0, lt=0.5)] = 0.28
    rail_head_radius_m: Positive = 0.3
    friction_coefficient: Annotated[float, Field(gt=0, le=2)] = 0.3
    traction_coefficient: Annotated[float, Field(gt=0, le=1)] = 0.05
    load_scatter: Annotated[float, Field(ge=0.01, le=1)] = 0.2


class WearSection(_Section):
    """``[wear]``: the wear law named by ``law`` with its own fields (a field of another law is an
    error), and the lateral ``band_width_mm`` the disk wheel's tread wear spreads over (default the
    Hertz ``2b``). A new law is one :class:`~railwear.wear.WearLaw` plus a section registered here
    with :func:`wear_section`; its ``build()`` returns the law in SI units."""

    law: str
    band_width_mm: Positive | None = None

    def build(self):
        """The :class:`~railwear.wear.WearLaw` of the section."""
        raise NotImplementedError


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
    specific_wear_ug_per_J: Positive = 5.3
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


def _section_of(registry, key, default, what):
    """A before-validator: a TOML table validated by the class registered under its ``key``; a
    field the class does not have is named as not applying to it."""
    def pick(value):
        if isinstance(value, BaseModel):
            return value
        if not isinstance(value, dict):
            raise ValueError(f"must be a table, not {type(value).__name__}")
        name = value.get(key, default)
        if not isinstance(name, str) or name not in registry:
            raise ValueError(f"{key}: unknown {what} {name!r}; known: {', '.join(sorted(registry))}")
        try:
            return registry[name].model_validate(value)
        except ValidationError as e:
            extra = [err["loc"][0] for err in e.errors() if err["type"] == "extra_forbidden"]
            if extra:
                raise ValueError(f"{extra[0]}: does not apply to {key} {name!r}") from None
            raise
    return pick


class Operation(_Section):
    speed_kmh: Positive | list[Positive] | None = None
    speed_m_s: Positive | list[Positive] | None = None
    life_distance_km: Positive = 50000.0

    @model_validator(mode="after")
    def _one_speed(self):
        if (self.speed_kmh is None) == (self.speed_m_s is None):
            raise ValueError("give exactly one of speed_kmh and speed_m_s")
        for name in ("speed_kmh", "speed_m_s"):
            value = getattr(self, name)
            if isinstance(value, list) and (not value or sorted(set(value)) != value):
                raise ValueError(f"{name} must list distinct speeds in increasing order")
        return self

    @property
    def speeds(self):
        """Speed or speeds in m/s; a list makes a batch."""
        if self.speed_kmh is not None:
            v = self.speed_kmh
            return kmh_to_m_s(v)
        return self.speed_m_s


class WearRate(_Section):
    """``h``: the physical disk-contact form, a cubic in ``u_xx``, or a table; plus the odd terms
    ``drift_rad u_x + dispersion_rad3 u_xxx`` (per unit normed life: order ``n`` travels round the
    wheel at ``-(drift_rad - dispersion_rad3 n²)`` rad), each one value or one per ``table_speed_kmh``."""

    form: Literal["disk_contact", "cubic", "table"] = "disk_contact"
    c0: Finite = 0.0
    c1: Finite = 0.0
    c3: Finite = 0.0
    curvature_m: list[Finite] | None = None
    table_speed_kmh: list[Positive] | None = None
    rate_m: list[Finite] | list[list[Finite]] | None = None
    drift_rad: Finite | list[Finite] = 0.0
    dispersion_rad3: Finite | list[Finite] = 0.0

    @model_validator(mode="after")
    def _table_given(self):
        if self.form == "table" and (self.curvature_m is None or self.rate_m is None):
            raise ValueError("form 'table' needs curvature_m and rate_m")
        for name in ("drift_rad", "dispersion_rad3"):
            value = getattr(self, name)
            if isinstance(value, list) and len(value) != len(self.table_speed_kmh or []):
                raise ValueError(f"{name}: a list needs one value per table_speed_kmh")
        return self


class Solver(_Section):
    points: Annotated[int, Field(ge=16, le=65536)] = 512
    epsilon: NonNegative = 1e-4
    nu: NonNegative = 1e-3
    t_end: Positive = 1.0
    depth_limit_mm: Positive | None = 1.0
    n_save: Annotated[int, Field(ge=2, le=100000)] = 101
    dealias: bool = True
    dt: Positive | None = None

    @field_validator("points")
    @classmethod
    def _even(cls, v):
        if v % 2:
            raise ValueError("must be even")
        return v


class Initial(_Section):
    kind: Literal["random", "harmonics", "measured", "round"] = "random"
    rms_um: NonNegative = 40.0
    lowest_order: Annotated[int, Field(ge=1)] = 2
    highest_order: Annotated[int, Field(ge=1)] = 16
    seed: Annotated[int, Field(ge=0)] = 1
    orders: list[Annotated[int, Field(ge=1)]] | None = None
    amplitudes_um: list[Finite] | None = None
    phases_deg: list[Finite] | None = None
    file: str | None = None

    @model_validator(mode="after")
    def _complete(self):
        if self.kind == "harmonics" and (self.orders is None or self.amplitudes_um is None):
            raise ValueError("kind 'harmonics' needs orders and amplitudes_um")
        if self.kind == "measured" and not self.file:
            raise ValueError("kind 'measured' needs file (a CSV of angle and deviation)")
        if self.lowest_order > self.highest_order:
            raise ValueError("lowest_order must not exceed highest_order")
        return self


class StrategySection(_Section):
    """``[strategy]``: the long-term strategy named by ``kind`` with its own fields (a field of
    another kind is an error) on the ``body`` (``"disk_wheel"``: ``[disk_wheel]``; ``"wheelset"``:
    ``[wheelset_wear]``). A new strategy registers its section with :func:`strategy_section` and
    its builder with :func:`railwear.scenario.build.builds`."""

    kind: str
    body: Literal["disk_wheel", "wheelset"] = "disk_wheel"
    bodies: ClassVar[tuple] = ("disk_wheel",)
    disk_wheel_only: ClassVar[tuple] = ()

    @model_validator(mode="after")
    def _body(self):
        if self.body not in self.bodies:
            raise ValueError(f"body {self.body!r} takes kind {' or '.join(repr(k) for k in _kinds_of(self.body))}, "
                             f"not {self.kind!r}")
        for name in self.disk_wheel_only:
            if self.body != "disk_wheel" and name in self.model_fields_set:
                raise ValueError(f"{name}: applies to body 'disk_wheel' only, not {self.body!r}")
        return self


STRATEGY_SECTIONS: dict = {}


def strategy_section(cls):
    """Register a ``[strategy]`` section class under the default of its ``kind`` field."""
    STRATEGY_SECTIONS[cls.model_fields["kind"].default] = cls
    return cls


def _kinds_of(body):
    return [k for k, c in STRATEGY_SECTIONS.items() if body in c.bodies]


Revolutions = Annotated[int, Field(ge=0, le=100000)]


@strategy_section
class PhenomenologicalSection(StrategySection):
    """The evolution equation (paper eq. 4) with the ``h`` of ``[wear_rate]`` and the
    regularisation of ``[solver]``."""

    kind: Literal["phenomenological"] = "phenomenological"


@strategy_section
class FourierSection(StrategySection):
    """The Fourier technique on the linearised disk wheel of ``[disk_wheel]`` (one speed)."""

    kind: Literal["fourier"] = "fourier"


@strategy_section
class StepwiseSection(StrategySection):
    """Stepwise frozen geometry: ``step_limit_um`` the largest change of ``u``
    (``step_limit_on = "u"``) or of its shape ``u - mean(u)`` (``"shape"``) per long-term step,
    taken by ``scheme`` (``"euler"``, or ``"adams-bashforth"``: second order at the same cost per
    step), ``samples`` draws of phase and speed (from ``[service]``, seeded by ``service.seed``);
    on the disk wheel each of ``revolutions`` after ``transient_revolutions``."""

    kind: Literal["stepwise"] = "stepwise"
    bodies: ClassVar[tuple] = ("disk_wheel", "wheelset")
    disk_wheel_only: ClassVar[tuple] = ("revolutions", "transient_revolutions")
    step_limit_um: Positive = 10.0
    step_limit_on: Literal["u", "shape"] = "u"
    scheme: Literal["euler", "adams-bashforth"] = "euler"
    samples: Annotated[int, Field(ge=2, le=100000)] = 8
    revolutions: Annotated[int, Field(ge=1, le=100000)] = 4
    transient_revolutions: Revolutions = 4


@strategy_section
class DirectSection(StrategySection):
    """Direct coupled integration: ``acceleration_factor`` on the wear coefficient (>= 1); on the
    disk wheel the surface updated ``updates_per_revolution`` times a revolution after
    ``transient_revolutions`` without wear."""

    kind: Literal["direct"] = "direct"
    bodies: ClassVar[tuple] = ("disk_wheel", "wheelset")
    disk_wheel_only: ClassVar[tuple] = ("updates_per_revolution", "transient_revolutions")
    acceleration_factor: Annotated[float, Field(ge=1, le=1e9, allow_inf_nan=False)] = 100.0
    updates_per_revolution: Annotated[int, Field(ge=1, le=1000)] = 1
    transient_revolutions: Revolutions = 4


class DiskWheel(_Section):
    """Vertical and rotational dynamics of the disk wheel (paper Fig. 5), for the Fourier strategy.

    The wheel mass is ``wheel.unsprung_mass_kg``; radius, load, contact and traction come from
    ``[wheel]`` and ``[contact]``. A rail mass on pads gives the P2 resonance.
    """

    wheel_inertia_kg_m2: Positive = 80.0
    primary_stiffness_N_m: NonNegative = 1.2e6
    primary_damping_N_s_m: NonNegative = 2e4
    sprung_mass_kg: Positive | None = None
    rail_mass_kg: Positive | None = 150.0
    pad_stiffness_N_m: Positive = 1e8
    pad_damping_N_s_m: NonNegative = 6e4


class Wheelset(_Section):
    """A suspended wheelset on straight track, for hunting (critical-speed) maps.

    The rolling radius is ``wheel.radius_m``; Kalker's coefficients come from the Hertz patch of
    ``[contact]`` at the wheel load. Defaults: the Cooperrider wheelset (mass, yaw inertia, half
    gauge) on stiff primary springs.
    """

    mass_kg: Positive = 1022.0
    yaw_inertia_kg_m2: Positive = 678.0
    lateral_stiffness_N_m: NonNegative = 1.823e6
    yaw_stiffness_N_m_rad: NonNegative = 3.646e6
    half_gauge_m: Positive = 0.7163
    conicity: Positive = 0.05


class WheelsetWear(_Section):
    """Long-term wear of the wheelset on real profiles (``[strategy] body = "wheelset"``): the
    worn lateral profile over distance and the angular pattern at the end.

    The suspension is ``[wheelset]`` (mass, yaw inertia, stiffnesses; its conicity and half gauge
    are not used: the contact table of the profiles gives the geometry), the speed
    ``operation.speed_kmh`` (one), friction and elasticity ``[contact]``, the nominal rolling
    radius ``wheel.radius_m``, the axle load twice ``wheel.static_load_kN``, the energy law
    ``[wear]``, one unit of normed time ``operation.life_distance_km``, the run to
    ``solver.t_end`` or ``solver.depth_limit_mm``, the seed ``service.seed``. Stepwise:
    ``strategy.step_limit_um`` per step on the lateral profile, ``strategy.samples`` random starts
    of ``seconds_per_sample_s`` each; direct: ``strategy.acceleration_factor``, the profile and
    the contact table updated every ``update_interval_s`` of simulated time. Example::

        [strategy]
        kind = "stepwise"
        body = "wheelset"
        step_limit_um = 1.0
        samples = 2

        [wheelset_wear]
        wheel_profile = "S1002"
        rail_profile = "UIC60"
        seconds_per_sample_s = 1.0

    ``wheel_profile``/``rail_profile`` a built-in name (S1002, UIC60) or a SIMPACK profile file;
    ``shift_max_mm``/``shift_step_mm`` the table's lateral shifts; ``lateral_min_mm``,
    ``lateral_max_mm``, ``lateral_cells`` and ``angle_cells`` the wear surface on the wheel
    profile; ``transient_s`` run before wear is gathered; each run starts from rest at a random
    lateral offset between ``offset_min_mm`` and ``offset_max_mm`` (random sign);
    ``output_rate_Hz`` the output times of the dynamics per simulated second.
    """

    wheel_profile: str = "S1002"
    rail_profile: str = "UIC60"
    shift_max_mm: Annotated[float, Field(gt=0, le=50, allow_inf_nan=False)] = 10.0
    shift_step_mm: Annotated[float, Field(gt=0, le=10, allow_inf_nan=False)] = 0.1
    lateral_min_mm: Finite = -50.0
    lateral_max_mm: Finite = 40.0
    lateral_cells: Annotated[int, Field(ge=2, le=10000)] = 180
    angle_cells: Annotated[int, Field(ge=4, le=100000)] = 64
    transient_s: NonNegative = 3.0
    offset_min_mm: NonNegative = 1.0
    offset_max_mm: NonNegative = 3.0
    output_rate_Hz: Positive = 2000.0
    footprint: Literal["hertz", "uniform"] = "hertz"
    seconds_per_sample_s: Positive = 2.0
    update_interval_s: Positive = 0.5

    @model_validator(mode="after")
    def _ranges(self):
        if not self.lateral_min_mm < self.lateral_max_mm:
            raise ValueError("lateral_min_mm must be below lateral_max_mm")
        if self.offset_min_mm > self.offset_max_mm:
            raise ValueError("offset_min_mm must not exceed offset_max_mm")
        if self.shift_step_mm > self.shift_max_mm:
            raise ValueError("shift_step_mm must not exceed shift_max_mm")
        return self


class Service(_Section):
    """Scatter of the service conditions, for forecasts: speed peaks with weights, load, friction."""

    speed_kmh: list[Positive] | None = None
    speed_weights: list[Annotated[float, Field(ge=0, allow_inf_nan=False)]] | None = None
    speed_scatter_kmh: NonNegative = 0.0
    load_scatter: Annotated[float, Field(ge=0, lt=0.5)] = 0.0
    friction_range: list[Positive] | None = None
    samples: Annotated[int, Field(ge=1, le=100000)] = 64
    seed: Annotated[int, Field(ge=0)] = 0

    @model_validator(mode="after")
    def _distribution(self):
        if self.speed_weights is not None:
            if self.speed_kmh is None or len(self.speed_weights) != len(self.speed_kmh):
                raise ValueError("speed_weights needs one weight per speed_kmh peak")
            if abs(sum(self.speed_weights) - 1) > 1e-9:
                raise ValueError(f"the speed distribution must sum to 1, not {sum(self.speed_weights):g}")
        if self.friction_range is not None and (len(self.friction_range) != 2
                                                or self.friction_range[0] > self.friction_range[1]):
            raise ValueError("friction_range must be [low, high]")
        return self


class Scenario(_Section):
    """A whole railwear run: wheel, contact, wear, operation, h, solver and initial state."""

    name: str = "unnamed"
    description: str = ""
    wheel: Wheel = Wheel()
    contact: Contact = Contact()
    wear: SerializeAsAny[WearSection] = Wear()
    operation: Operation = Operation(speed_kmh=220.0)
    wear_rate: WearRate = WearRate()
    solver: Solver = Solver()
    initial: Initial = Initial()
    service: Service = Service()
    strategy: SerializeAsAny[StrategySection] = PhenomenologicalSection()
    disk_wheel: DiskWheel = DiskWheel()
    wheelset: Wheelset = Wheelset()
    wheelset_wear: WheelsetWear = WheelsetWear()

    _wear = field_validator("wear", mode="before")(_section_of(WEAR_SECTIONS, "law", "energy", "wear law"))
    _strategy = field_validator("strategy", mode="before")(
        _section_of(STRATEGY_SECTIONS, "kind", "phenomenological", "strategy kind"))

    @model_validator(mode="after")
    def _applies(self):
        for section, names, applies, to in self._only_for():
            given = getattr(self, section).model_fields_set & set(names or type(getattr(self, section)).model_fields)
            if given and not applies:
                raise ValueError(f"{section}.{sorted(given)[0]}: applies to {to} only")
        return self

    def _only_for(self):
        """(section, fields or None for all, whether they apply, to what)."""
        kind, body = self.strategy.kind, self.strategy.body
        return (("solver", ("epsilon", "nu", "dealias", "dt"), kind == "phenomenological", "the phenomenological strategy"),
                ("wear_rate", None, kind == "phenomenological", "the phenomenological strategy"),
                ("disk_wheel", None, body == "disk_wheel", "body 'disk_wheel'"),
                ("wheelset_wear", None, body == "wheelset", "body 'wheelset'"))

    def applicable(self, **dump):
        """The scenario as plain data (``model_dump`` options ``dump``; default JSON types without
        ``None``) without the fields that do not apply to its strategy and body."""
        data = self.model_dump(**{"mode": "json", "exclude_none": True, **dump})
        if self.strategy.body != "disk_wheel":
            for name in self.strategy.disk_wheel_only:
                data["strategy"].pop(name)
        for section, names, applies, _ in self._only_for():
            if not applies:
                for name in names or list(data[section]):
                    data[section].pop(name, None)
                if not data[section]:
                    data.pop(section)
        return data
