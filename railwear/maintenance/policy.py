"""The maintenance policy file: triggers, a cut rule, the residual after turning, the last-turning
diameter (layer 4).

A policy is TOML validated like a scenario (frozen pydantic models, strict types, a physical
bound on every number, one line naming the field on a refusal); units are in the field names and
are converted once, in :meth:`PolicyFile.build`, to the SI objects of
:mod:`railwear.maintenance.turning`. Built-in policies ship in ``maintenance/policies/``, each
with its ``source``.
"""

from importlib import resources
from pathlib import Path
from typing import Annotated, Literal

from pydantic import BaseModel, Field, SerializeAsAny, field_validator, model_validator

from railwear.errors import ScenarioError
from railwear.geometry import bands
from railwear.maintenance.turning import CutRule, Policy, Residual, Triggers, Turning
from railwear.scenario import parse_toml, read_text, validated
from railwear.scenario.schema import Count, Name, Text, _Section, _section_of, refuse
from railwear.units import KM, KN, MM, UM, kmh_to_m_s

Level = Annotated[float, Field(ge=-100, le=100)]  # dB re 1 µm: beyond this a typing error
BandWavelength_mm = Annotated[float, Field(ge=3, le=5000)]  # one-third-octave band centres a wheel holds
MAX_ORDERS = 1000


def _band_centre(wavelength_mm):
    """Refuse a wavelength (mm) that names no one-third-octave band centre."""
    try:
        bands.limit_spectrum([wavelength_mm * MM], [0.0])
    except ScenarioError:
        raise ValueError(f"{wavelength_mm:g} mm is not a one-third-octave band centre (EN 15610: "
                         "..., 250, 200, 160, 125, 100 mm, ...)") from None


class TriggerSection(_Section):
    """``[trigger]``: when the wheel is turned; the first to be reached acts. ``peak_to_peak_mm``
    (radius deviation), ``order_level_db`` (dB re 1 µm, ``20 lg(A_n / √2 / 1 µm)``: one level for
    every order, or one per order of ``orders``), one-third-octave band levels (EN 15610:
    ``band_limit = "iso3095"`` or ``band_wavelength_mm`` with ``band_level_db``), and
    ``interval_km`` since the last turning, ``peak_force_kN``: the peak vertical wheel–rail force a
    wheel-impact-load detector reads, on the time-domain track at ``peak_force_speeds_kmh``
    (default: the scenario's speed; :mod:`railwear.maintenance.detectors`); the flange parameters of
    EN 15313 on a body that simulates the lateral profile (:mod:`railwear.maintenance.lateral`):
    ``flange_height_max_mm`` (Sh), ``flange_thickness_min_mm`` (Sd), ``flange_gradient_min_mm``
    (qR)."""

    peak_to_peak_mm: Annotated[float, Field(gt=0, le=10)] | None = None
    order_level_db: Level | Annotated[list[Level], Field(min_length=1, max_length=MAX_ORDERS)] | None = None
    orders: Annotated[list[Count], Field(min_length=1, max_length=MAX_ORDERS)] | None = None
    band_limit: Literal["iso3095"] | None = None
    band_wavelength_mm: Annotated[list[BandWavelength_mm], Field(min_length=1, max_length=100)] | None = None
    band_level_db: Annotated[list[Level], Field(min_length=1, max_length=100)] | None = None
    interval_km: Annotated[float, Field(ge=100, le=1e7)] | None = None
    peak_force_kN: Annotated[float, Field(ge=10, le=2000)] | None = None
    peak_force_speeds_kmh: Annotated[list[Annotated[float, Field(ge=5, le=500)]],
                                     Field(min_length=1, max_length=20)] | None = None
    flange_height_max_mm: Annotated[float, Field(gt=12, le=60)] | None = None  # above the 10 + 2 mm Sd and qR need
    flange_thickness_min_mm: Annotated[float, Field(ge=5, le=50)] | None = None
    flange_gradient_min_mm: Annotated[float, Field(gt=0, le=30)] | None = None

    @model_validator(mode="after")
    def _consistent(self):
        given = [n for n in type(self).model_fields if getattr(self, n) is not None]
        if not set(given) - {"orders", "peak_force_speeds_kmh"}:
            raise ValueError("give at least one trigger: peak_to_peak_mm, order_level_db, band_limit or "
                             "band_wavelength_mm, interval_km, peak_force_kN, flange_height_max_mm, "
                             "flange_thickness_min_mm, flange_gradient_min_mm")
        if self.peak_force_speeds_kmh is not None and self.peak_force_kN is None:
            raise refuse("peak_force_speeds_kmh", "needs peak_force_kN")
        levels = self.order_level_db
        if self.orders is not None:
            if not isinstance(levels, list) or len(levels) != len(self.orders):
                raise refuse("orders", "needs order_level_db as a list with one level per order")
            if len(set(self.orders)) != len(self.orders):
                raise refuse("orders", "an order is given twice")
        elif isinstance(levels, list):
            raise refuse("order_level_db", "a list of levels needs orders, one per level (or give one level)")
        if self.band_limit is not None and self.band_wavelength_mm is not None:
            raise refuse("band_wavelength_mm", "give band_limit or a band table, not both")
        if (self.band_wavelength_mm is None) != (self.band_level_db is None) or (
                self.band_wavelength_mm is not None and len(self.band_wavelength_mm) != len(self.band_level_db)):
            raise refuse("band_level_db", "needs band_wavelength_mm, one wavelength per level")
        if self.band_wavelength_mm is not None:
            try:
                bands.limit_spectrum([w * MM for w in self.band_wavelength_mm], self.band_level_db)
            except ScenarioError as e:
                raise refuse("band_wavelength_mm", str(e).removeprefix("limit 'limit': ")) from None
        return self

    def build(self):
        """The SI :class:`~railwear.maintenance.turning.Triggers`."""
        from railwear import forecast
        from railwear.maintenance.lateral import LIMITS, FlangeLimit

        limits = []
        if self.peak_to_peak_mm is not None:
            limits.append(forecast.peak_to_peak_limit(self.peak_to_peak_mm * MM))
        if self.order_level_db is not None:
            limits.append(forecast.order_limit(self.order_level_db, self.orders))
        if self.band_limit == "iso3095":
            limits.append(forecast.band_limit(bands.iso3095_limit()))
        elif self.band_wavelength_mm is not None:
            limits.append(forecast.band_limit(bands.limit_spectrum(
                [w * MM for w in self.band_wavelength_mm], self.band_level_db, name="the policy's band levels")))
        return Triggers(tuple(limits), None if self.interval_km is None else self.interval_km * KM,
                        None if self.peak_force_kN is None else self.peak_force_kN * KN,
                        tuple(kmh_to_m_s(v) for v in self.peak_force_speeds_kmh or ()),
                        tuple(FlangeLimit(k, getattr(self, k) * MM) for k in LIMITS if getattr(self, k) is not None))

    def given(self, names):
        """The fields of ``names`` this section gives, in its order."""
        return [n for n in type(self).model_fields if n in names and getattr(self, n) is not None]


class CutSection(_Section):
    """``[cut]``: the cut depth on the radius, ``c = max(minimum, step ⌈(ū - min u + margin) / step⌉)``:
    the deepest point of the polygon below the mean radius plus ``margin_mm``, rounded up to the
    lathe's ``step_mm``, at least ``minimum_mm``."""

    margin_mm: Annotated[float, Field(ge=0, le=10)] = 0.2
    step_mm: Annotated[float, Field(ge=0.01, le=5)] = 0.1
    minimum_mm: Annotated[float, Field(ge=0.05, le=20)] = 0.5

    def build(self):
        return CutRule(self.margin_mm * MM, self.step_mm * MM, self.minimum_mm * MM)


class ResidualSection(_Section):
    """``[residual]``: the out-of-roundness a turning leaves, chosen by ``kind``; ``add_initial``
    adds the scenario's ``[initial]`` wheel (a re-profiled wheel's roughness) to it."""

    kind: str
    add_initial: bool = True

    def build(self):
        """The SI :class:`~railwear.maintenance.turning.Residual`."""
        return Residual(self.kind)


RESIDUALS: dict = {}


def residual_section(cls):
    RESIDUALS[cls.model_fields["kind"].default] = cls
    return cls


@residual_section
class RoundResidual(ResidualSection):
    """Nothing of its own: the lathe leaves a round wheel (plus ``[initial]`` with ``add_initial``)."""

    kind: Literal["round"] = "round"


@residual_section
class SpectrumResidual(ResidualSection):
    """A given spectrum: ``amplitudes_um`` of ``orders`` with ``phases_deg`` (default 0), e.g. a
    three-jaw chuck's 3rd order, or a measured post-turning wheel's orders."""

    kind: Literal["spectrum"] = "spectrum"
    orders: Annotated[list[Count], Field(min_length=1, max_length=MAX_ORDERS)]
    amplitudes_um: Annotated[list[Annotated[float, Field(ge=0, le=1000)]], Field(min_length=1, max_length=MAX_ORDERS)]
    phases_deg: Annotated[list[Annotated[float, Field(ge=-360, le=360)]], Field(max_length=MAX_ORDERS)] | None = None

    @model_validator(mode="after")
    def _lengths(self):
        if len(set(self.orders)) != len(self.orders):
            raise refuse("orders", "an order is given twice")
        for name in ("amplitudes_um", "phases_deg"):
            values = getattr(self, name)
            if values is not None and len(values) != len(self.orders):
                raise refuse(name, f"needs one value per order: {len(values)} for {len(self.orders)} orders")
        return self

    def build(self):
        import numpy as np

        phases = np.deg2rad(self.phases_deg) if self.phases_deg is not None else np.zeros(len(self.orders))
        return Residual("spectrum", orders=tuple(self.orders), amplitudes=tuple(a * UM for a in self.amplitudes_um),
                        phases=tuple(float(p) for p in phases))


@residual_section
class InheritResidual(ResidualSection):
    """Partial inheritance: the turned wheel keeps ``fraction`` of every order of the old polygon,
    or ``fractions`` of the ``orders`` named (the others none), in phase with it."""

    kind: Literal["inherit"] = "inherit"
    fraction: Annotated[float, Field(ge=0, le=1)] | None = None
    orders: Annotated[list[Count], Field(min_length=1, max_length=MAX_ORDERS)] | None = None
    fractions: Annotated[list[Annotated[float, Field(ge=0, le=1)]], Field(min_length=1, max_length=MAX_ORDERS)] | None = None

    @model_validator(mode="after")
    def _one_way(self):
        if (self.fraction is None) == (self.orders is None):
            raise refuse("fraction", "give fraction (every order) or orders with fractions, one of the two")
        if self.orders is not None:
            if self.fractions is None or len(self.fractions) != len(self.orders):
                raise refuse("fractions", "needs one fraction per order")
            if len(set(self.orders)) != len(self.orders):
                raise refuse("orders", "an order is given twice")
        elif self.fractions is not None:
            raise refuse("fractions", "needs orders, one per fraction")
        return self

    def build(self):
        if self.orders is None:
            return Residual("inherit", fractions=(self.fraction,))
        return Residual("inherit", orders=tuple(self.orders), fractions=tuple(self.fractions))


@residual_section
class BandResidual(ResidualSection):
    """A residual in one one-third-octave band: ``level_db`` (dB re 1 µm, EN 15610) in the band
    of ``wavelength_mm`` (a band centre, e.g. the 200 mm band), shared equally in amplitude by
    the orders whose lines fall in it on the turned wheel, with phases drawn from ``seed`` and the
    turning's number."""

    kind: Literal["band"] = "band"
    wavelength_mm: BandWavelength_mm
    level_db: Level
    seed: Annotated[int, Field(ge=0, lt=2**63)] = 0

    @field_validator("wavelength_mm")
    @classmethod
    def _centre(cls, value):
        _band_centre(value)
        return value

    def build(self):
        return Residual("band", wavelength=self.wavelength_mm * MM, level=self.level_db, seed=self.seed)


class WheelSection(_Section):
    """``[wheel]``: ``last_turning_diameter_mm``, below which no turning may take the wheel: it is
    scrapped there (the new diameter is the scenario's wheel's)."""

    last_turning_diameter_mm: Annotated[float, Field(ge=100, le=4000)]


class PolicyFile(BaseModel):
    """A maintenance policy: ``name``, ``description``, ``source`` (where its numbers come from,
    or that they are an example), ``[trigger]``, ``[cut]``, ``[residual]`` and ``[wheel]``."""

    model_config = _Section.model_config

    name: Name
    description: Text = ""
    source: Annotated[Text, Field(min_length=1)]
    trigger: TriggerSection
    cut: CutSection = CutSection()
    residual: SerializeAsAny[ResidualSection] = RoundResidual()
    wheel: WheelSection

    _residual = field_validator("residual", mode="before")(_section_of(RESIDUALS, "kind", "round", "residual kind"))

    def build(self, base=None):
        """The SI :class:`~railwear.maintenance.turning.Policy`; ``base`` (m, on the grid) is the
        scenario's ``[initial]`` wheel the residual adds when ``add_initial``."""
        return Policy(self.name, self.trigger.build(),
                      Turning(self.cut.build(), self.residual.build(), base if self.residual.add_initial else None),
                      self.wheel.last_turning_diameter_mm * MM, self.source, self.description)


def _builtin_dir():
    return resources.files("railwear.maintenance") / "policies"


def builtin_policy_names():
    """Names of the policies that ship with railwear, sorted."""
    return sorted(p.name[:-5] for p in _builtin_dir().iterdir() if p.name.endswith(".toml"))


def builtin_policy_text(name):
    """The TOML text of a built-in policy."""
    if name not in builtin_policy_names():
        raise ScenarioError(f"no built-in policy {name!r}; built-in policies: {', '.join(builtin_policy_names())}")
    return (_builtin_dir() / f"{name}.toml").read_text(encoding="utf-8")


def parse_policy(text, source="policy"):
    """A :class:`PolicyFile` from TOML text; a refusal is one line naming the field."""
    return validated(PolicyFile, parse_toml(text, source), source)


def load_policy(path_or_name):
    """A policy from a TOML file, or a built-in one by name (a file of that name first; a folder
    never); a :class:`PolicyFile` is returned as it is."""
    if isinstance(path_or_name, PolicyFile):
        return path_or_name
    name = str(path_or_name)
    path = Path(name)
    try:
        is_file, is_dir = path.is_file(), path.is_dir()
    except OSError:  # a name too long for the file system: nothing there
        is_file = is_dir = False
    if is_file:
        return parse_policy(read_text(path), path.name)
    if name in builtin_policy_names():
        return parse_policy(builtin_policy_text(name), name)
    known = f"built-in policies: {', '.join(builtin_policy_names())}"
    if is_dir:
        raise ScenarioError(f"policy {name} is a folder, not a policy file; {known}")
    if path.suffix == ".toml" or "/" in name or "\\" in name:
        raise ScenarioError(f"policy file {name} does not exist")
    raise ScenarioError(f"no built-in policy {name!r}; {known}")
