"""The track: a rail (``Rail``), its support (``Support``) and how they are put together (``Track``).

All values SI. A discrete track (``sleeper_spacing`` set) takes the support per rail seat
(N/m, kg, N s/m); a continuous track takes it per metre of rail (N/m², kg/m, N s/m²).
"""

from __future__ import annotations

import math
import tomllib
from dataclasses import dataclass, fields, replace
from importlib import resources

import numpy as np

from railwear.errors import ScenarioError

__all__ = ["BASES", "BEAMS", "Rail", "Support", "SupportSet", "Track", "base_fields", "default_support_set", "rail",
           "rail_names", "support_of", "support_set", "support_set_names"]

BEAMS = ("euler", "timoshenko")


def _require(obj, name, low=0.0, strict=True, allow_inf=False):
    """``obj.name`` must be a number above ``low`` (at least ``low`` if not ``strict``)."""
    value = getattr(obj, name)
    try:
        value = float(value)
    except (TypeError, ValueError):
        raise ScenarioError(f"{name}: must be a number, got {value!r}") from None
    ok = value > low if strict else value >= low
    if not ok or math.isnan(value) or (math.isinf(value) and not allow_inf):
        bound = "positive" if (strict and low == 0.0) else f">= {low}"
        raise ScenarioError(f"{name}: must be {bound}{'' if allow_inf else ' and finite'}, got {value!r}")
    object.__setattr__(obj, name, value)


@dataclass(frozen=True)
class Rail:
    """One rail as a beam in vertical bending.

    ``mass_per_metre`` m [kg/m], ``area`` A [m²], ``second_moment`` I [m⁴] (about the horizontal
    axis), ``youngs_modulus`` E and ``shear_modulus`` G [Pa], ``shear_coefficient`` κ [-] (Timoshenko
    shear area κA), ``loss_factor`` η [-] of the rail steel (E and G become E(1+iη), G(1+iη)).
    Rotary inertia per metre is ρI = m I / A. Standard sections: ``rail("60E1")``.
    """

    mass_per_metre: float
    area: float
    second_moment: float
    youngs_modulus: float = 210e9
    shear_modulus: float = 80.77e9
    shear_coefficient: float = 0.4
    loss_factor: float = 0.0
    name: str = "custom"
    source: str = ""

    def __post_init__(self):
        for name in ("mass_per_metre", "area", "second_moment", "youngs_modulus", "shear_modulus", "shear_coefficient"):
            _require(self, name)
        _require(self, "loss_factor", strict=False)

    @property
    def bending_stiffness(self) -> complex:
        """E I (1 + iη) [N m²]."""
        return self.youngs_modulus * self.second_moment * (1.0 + 1j * self.loss_factor)

    @property
    def shear_stiffness(self) -> complex:
        """κ G A (1 + iη) [N]."""
        return self.shear_coefficient * self.shear_modulus * self.area * (1.0 + 1j * self.loss_factor)

    @property
    def rotary_inertia(self) -> float:
        """ρ I = m I / A [kg m]."""
        return self.mass_per_metre * self.second_moment / self.area


def _rail_table() -> dict:
    with resources.files("railwear.track").joinpath("data", "rails.toml").open("rb") as fh:
        return tomllib.load(fh)


def rail_names() -> tuple[str, ...]:
    """The shipped rail sections (``railwear/track/data/rails.toml``)."""
    return tuple(_rail_table())


def rail(name: str = "60E1", **overrides) -> Rail:
    """A standard rail section from the shipped data (EN 13674-1; the file names its sources),
    with any field overridden: ``rail("60E1", loss_factor=0.02)``. "UIC60"/"UIC54" are aliases."""
    table = _rail_table()
    key = str(name).upper()
    aliases = {entry.get("also_known_as", "").upper(): k for k, entry in table.items()}
    key = aliases.get(key, key)
    if key not in table:
        raise ScenarioError(f"rail: unknown section {name!r} (known: {', '.join(table)})")
    entry = {k: v for k, v in table[key].items() if k != "also_known_as"}
    known = {f.name for f in fields(Rail)}
    unknown = sorted(set(overrides) - known)
    if unknown:
        raise ScenarioError(f"{unknown[0]}: not a field of Rail (fields: {', '.join(sorted(known))})")
    return Rail(name=key, **{**entry, **overrides})


@dataclass(frozen=True)
class Support:
    """Rail support per rail seat: a chain of springs and masses from the rail down to rigid ground.

    ``pad`` (the rail pad, or a slab track's fastener) carries the rail on the ``sleeper_mass``
    (half a sleeper, or a slab's share per rail seat); the ``ballast`` spring (or a slab's CA-mortar
    layer) carries the sleeper on the ``ballast_mass``, which sits on the ``subgrade`` spring:

        rail -- pad -- M_s -- ballast -- M_b -- subgrade -- ground

    ``ballast_stiffness = inf`` (the default) puts the pad on a rigid base; ``subgrade_stiffness =
    inf`` (the default) the ballast on rigid ground, where a ballast mass cannot move (so it must
    then be 0). Per rail seat for a discrete track [N/m, N s/m, kg], per metre for a continuous one
    [N/m², N s/m², kg/m]. Each spring has a viscous coefficient and a loss factor, used together:
    ``k* = k (1 + iη) + iωc``. Dynamic stiffness of the support seen by the rail, from the bottom up
    (a spring in series with what lies below it, a mass beside it):

        k_g = k_f* - M_b ω²,   k_b' = k_b* k_g / (k_b* + k_g)   (k_b' = k_b* on rigid ground)
        k_s = k_p* (k_b' - M_s ω²) / (k_p* + k_b' - M_s ω²)

    (Knothe & Grassie 1993 for the pad, sleeper and ballast; the ballast mass on a subgrade as in
    Zhai, Wang & Lin, JSV 270 (2004) 673.) Published sets: :func:`support_set`.
    """

    pad_stiffness: float
    pad_damping: float = 0.0
    pad_loss_factor: float = 0.0
    sleeper_mass: float = 0.0
    ballast_stiffness: float = math.inf
    ballast_damping: float = 0.0
    ballast_loss_factor: float = 0.0
    ballast_mass: float = 0.0
    subgrade_stiffness: float = math.inf
    subgrade_damping: float = 0.0
    subgrade_loss_factor: float = 0.0

    def __post_init__(self):
        _require(self, "pad_stiffness")
        _require(self, "ballast_stiffness", allow_inf=True)
        _require(self, "subgrade_stiffness", allow_inf=True)
        for name in ("pad_damping", "pad_loss_factor", "sleeper_mass", "ballast_damping", "ballast_loss_factor",
                     "ballast_mass", "subgrade_damping", "subgrade_loss_factor"):
            _require(self, name, strict=False)
        if self.rigid_base and not self.rigid_ground:
            raise ScenarioError("subgrade_stiffness: a subgrade needs a ballast spring above it "
                                f"(ballast_stiffness is inf), got {self.subgrade_stiffness!r}")
        if self.rigid_ground and self.ballast_mass > 0:
            raise ScenarioError(f"ballast_mass: moves only on a subgrade spring (subgrade_stiffness is inf), "
                                f"got {self.ballast_mass!r}")

    @property
    def rigid_base(self) -> bool:
        """The pad on a rigid base (no sleeper motion)."""
        return math.isinf(self.ballast_stiffness)

    @property
    def rigid_ground(self) -> bool:
        """The ballast spring on rigid ground (no ballast mass, no subgrade)."""
        return math.isinf(self.subgrade_stiffness)

    def stiffness(self, omega) -> np.ndarray:
        """Complex dynamic stiffness of the support at angular frequencies ``omega`` [rad/s]:
        force per displacement of the rail [N/m, or N/m² per metre]."""
        w = np.asarray(omega, dtype=float)
        pad = self.pad_stiffness * (1.0 + 1j * self.pad_loss_factor) + 1j * w * self.pad_damping
        if self.rigid_base:
            return pad
        if self.rigid_ground:
            below = (self.ballast_stiffness * (1.0 + 1j * self.ballast_loss_factor) + 1j * w * self.ballast_damping
                     - self.sleeper_mass * w**2)
        else:
            ballast = self.ballast_stiffness * (1.0 + 1j * self.ballast_loss_factor) + 1j * w * self.ballast_damping
            ground = (self.subgrade_stiffness * (1.0 + 1j * self.subgrade_loss_factor) + 1j * w * self.subgrade_damping
                      - self.ballast_mass * w**2)
            below = ballast * ground / (ballast + ground) - self.sleeper_mass * w**2
        return pad * below / (pad + below)

    def scaled(self, factor: float) -> Support:
        """Every stiffness, damping and mass times ``factor`` (loss factors kept): per rail seat
        to per metre with ``1 / spacing``."""
        return replace(
            self,
            pad_stiffness=self.pad_stiffness * factor,
            pad_damping=self.pad_damping * factor,
            sleeper_mass=self.sleeper_mass * factor,
            ballast_stiffness=self.ballast_stiffness * factor,
            ballast_damping=self.ballast_damping * factor,
            ballast_mass=self.ballast_mass * factor,
            subgrade_stiffness=self.subgrade_stiffness * factor,
            subgrade_damping=self.subgrade_damping * factor,
        )


BASES = ("ballast", "ballast_subgrade", "slab", "rigid")
# The names a support set uses for each base, as the Support fields they fill.
_SET_FIELDS = {
    "ballast": ("pad_stiffness", "pad_damping", "pad_loss_factor", "sleeper_mass", "ballast_stiffness",
                "ballast_damping", "ballast_loss_factor"),
    "ballast_subgrade": ("pad_stiffness", "pad_damping", "pad_loss_factor", "sleeper_mass", "ballast_stiffness",
                         "ballast_damping", "ballast_loss_factor", "ballast_mass", "subgrade_stiffness",
                         "subgrade_damping", "subgrade_loss_factor"),
    "slab": ("pad_stiffness", "pad_damping", "pad_loss_factor", "slab_mass", "mortar_stiffness", "mortar_damping",
             "mortar_loss_factor"),
    "rigid": ("pad_stiffness", "pad_damping", "pad_loss_factor"),
}
# A slab track is the same chain: the slab's share per rail seat on the CA-mortar layer on rigid ground.
SLAB_AS_SUPPORT = {"slab_mass": "sleeper_mass", "mortar_stiffness": "ballast_stiffness",
                   "mortar_damping": "ballast_damping", "mortar_loss_factor": "ballast_loss_factor"}


def base_fields(base: str) -> tuple[str, ...]:
    """The support values (names as in the support sets, SI) that apply to ``base``:
    "ballast" (pad, sleeper, ballast), "ballast_subgrade" (and the ballast mass on a subgrade),
    "slab" (fastener as the pad, slab mass, CA mortar) or "rigid" (pad only)."""
    if base not in _SET_FIELDS:
        raise ScenarioError(f"base: must be one of {', '.join(BASES)}, got {base!r}")
    return _SET_FIELDS[base]


def support_of(base: str, **values) -> Support:
    """The :class:`Support` of ``base`` from its values (names of :func:`base_fields`, SI);
    a value of another base is refused naming it."""
    allowed = base_fields(base)
    for name in values:
        if name not in allowed:
            raise ScenarioError(f"{name}: does not apply to base {base!r} (it takes {', '.join(allowed)})")
    return Support(**{SLAB_AS_SUPPORT.get(k, k): float(v) for k, v in values.items()})


@dataclass(frozen=True)
class SupportSet:
    """A published support set (``railwear/track/data/supports.toml``): its ``base``, the values
    per rail seat (names of :func:`base_fields`, SI), the ``sleeper_spacing`` [m], the ``source``
    and ``notes`` (what was assumed or derived)."""

    name: str
    base: str
    values: dict
    sleeper_spacing: float
    source: str
    notes: str = ""

    @property
    def support(self) -> Support:
        return support_of(self.base, **self.values)


def _support_table() -> dict:
    with resources.files("railwear.track").joinpath("data", "supports.toml").open("rb") as fh:
        return tomllib.load(fh)


def support_set_names() -> tuple[str, ...]:
    """The shipped support sets (``railwear/track/data/supports.toml``)."""
    return tuple(_support_table())


def support_set(name: str) -> SupportSet:
    """A shipped support set by name: ``support_set("zhai-2004").support`` is the two-layer
    ballasted support of Zhai, Wang & Lin (2004); the file names each set's source."""
    table = _support_table()
    if name not in table:
        raise ScenarioError(f"preset: unknown support set {name!r} (known: {', '.join(table)})")
    entry = dict(table[name])
    meta = {k: entry.pop(k) for k in ("base", "sleeper_spacing", "source", "notes", "default_for") if k in entry}
    base_fields(meta["base"])
    return SupportSet(name, meta["base"], entry, float(meta["sleeper_spacing"]), meta["source"], meta.get("notes", ""))


def default_support_set(base: str) -> SupportSet | None:
    """The set a base takes its values from when none is named: the entry marked
    ``default_for`` that base, or None (the bases "ballast" and "rigid" keep the values they had)."""
    base_fields(base)
    for name, entry in _support_table().items():
        if entry.get("default_for") == base:
            return support_set(name)
    return None


@dataclass(frozen=True)
class Track:
    """A rail on its support: continuous (``sleeper_spacing=None``, support per metre) or on
    discrete supports at ``sleeper_spacing`` L [m] (support per rail seat). ``beam``: "euler"
    (Euler-Bernoulli) or "timoshenko" (shear and rotary inertia)."""

    rail: Rail
    support: Support
    sleeper_spacing: float | None = None
    beam: str = "timoshenko"

    def __post_init__(self):
        if not isinstance(self.rail, Rail):
            raise ScenarioError(f"rail: must be a Rail (railwear.track.rail('60E1')), got {type(self.rail).__name__}")
        if not isinstance(self.support, Support):
            raise ScenarioError(f"support: must be a Support, got {type(self.support).__name__}")
        if self.beam not in BEAMS:
            raise ScenarioError(f"beam: must be one of {', '.join(BEAMS)}, got {self.beam!r}")
        if self.sleeper_spacing is not None:
            _require(self, "sleeper_spacing")

    @property
    def discrete(self) -> bool:
        return self.sleeper_spacing is not None

    def smeared(self) -> Track:
        """The continuous track with the discrete supports spread evenly (per metre = per seat / L)."""
        if not self.discrete:
            return self
        return replace(self, support=self.support.scaled(1.0 / self.sleeper_spacing), sleeper_spacing=None)

    def pinned_pinned_frequency(self) -> float:
        """Frequency [Hz] of the rail bending between supports at spacing L with nodes at the
        supports (wavenumber π/L), undamped. Euler: ``(π / 2L²) sqrt(EI/m)``; Timoshenko: the lower
        root of ``(m ω² - κGA k²)(ρI ω² - EI k² - κGA) = (κGA k)²`` with ``k = π/L``."""
        if not self.discrete:
            raise ScenarioError("sleeper_spacing: a continuous track has no pinned-pinned frequency")
        r = self.rail
        k = math.pi / self.sleeper_spacing
        EI, m = r.youngs_modulus * r.second_moment, r.mass_per_metre
        if self.beam == "euler":
            return k**2 * math.sqrt(EI / m) / (2.0 * math.pi)
        S, J = r.shear_coefficient * r.shear_modulus * r.area, r.rotary_inertia
        # m J W² - (m (EI k² + S) + J S k²) W + EI S k⁴ = 0 with W = ω²
        a, b, c = m * J, m * (EI * k**2 + S) + J * S * k**2, EI * S * k**4
        W = 2.0 * c / (b + math.sqrt(b * b - 4.0 * a * c))  # smaller root, free of cancellation
        return math.sqrt(W) / (2.0 * math.pi)
