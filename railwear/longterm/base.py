"""The long-term contract (layer 3): strategies, bodies, checkpoints and the one result shape.

**Strategy.** A subclass of :class:`Strategy` registered by ``name``; ``run(u0, until,
depth_limit, progress, checkpoint, resume)`` advances the wear state from ``u0`` (m; ``None``: the
body's new state) to normed time ``until`` or until the most worn spot has lost ``depth_limit``
(m) and returns a result (below). Strategies that take steps hand them to
:func:`railwear.longterm.driver.drive`: each step (``advance``) turns the state at ``T`` into the
state at ``T + ΔT`` and says what it cost; the driver owns the loop, the depth limit, the saves,
progress, checkpoints and the seeded generator.

**Body.** What wears and how its dynamics are run (the disk wheel, the wheelset): see
:class:`Body`. A body knows its wear variable ``u``, its frozen-geometry wear rates with their
standard errors, its coupled advance, its removed depth, its extra result variables and figures.

**Checkpoint.** :class:`Checkpoint`: the strategy's ``kind``, a format ``version``, the problem's
fingerprint and plain fields (numbers, text, arrays). A resume needs the fields the strategy
wrote; anything else is refused in one line.

**Result.** An ``xarray.Dataset`` with ``u`` (m) over (``time``[, batch], ``angle``[,
``lateral``]); coordinates ``time`` (normed life), ``distance`` (km) and ``speed`` (m s-1);
``removed_depth`` (m, most worn spot, over ``time``[, batch]), ``stop_time`` and ``cost_*``;
attributes ``strategy`` (registry name), ``body`` and ``scenario_hash`` (empty outside a
scenario). A body adds variables and never renames these. Cost is counted in what the
strategy spends: wheel revolutions or seconds simulated and right-hand sides evaluated.
"""

import hashlib
import json
from abc import ABC, abstractmethod
from dataclasses import dataclass, field
from typing import Any, NamedTuple

import numpy as np

from railwear.errors import ScenarioError
from railwear.registry import Registered
from railwear.units import KM

MANDATORY = ("u", "removed_depth", "stop_time")
COSTS = {  # the cost counters of every strategy and body, one vocabulary: name -> (units, long name)
    "revolutions": ("1", "wheel revolutions simulated"),
    "rhs_evaluations": ("1", "right-hand sides of the dynamics evaluated"),
    "seconds": ("s", "seconds of dynamics simulated"),
    "tables": ("1", "contact tables computed"),
    "draws": ("1", "Monte Carlo draws"),
    "transfer_evaluations": ("1", "orders of the transfer function evaluated"),
    "time_steps": ("1", "ETDRK4 steps at the final step size"),
}
COORDINATES = ("time", "distance", "speed")
ATTRIBUTES = ("strategy", "body", "scenario_hash")


class Strategy(Registered, ABC):
    """A long-term strategy; subclasses register with ``class X(Strategy, name="x")``.

    Rules for a new strategy:

    1. Register a ``name`` (``class X(Strategy, name="x")``): the result's ``strategy``
       attribute and the checkpoint's kind.
    2. ``run(u0, until, depth_limit, progress, checkpoint, resume)`` returns the result (the
       contract in this module's docstring).
    3. A stepped strategy defines ``advance(body, state, until)`` returning a
       :class:`~railwear.longterm.driver.Step` from the body's :class:`Rates` or
       :class:`Segment`, and hands its loop to :func:`~railwear.longterm.driver.drive`.
    4. It then also declares ``monte_carlo`` (``True`` when its steps carry standard errors)
       and ``attributes(state)`` (a dict for the result). A stepped strategy without them is
       refused when its class is defined, naming the member.
    5. Its scenario section (:class:`~railwear.scenario.schema.StrategySection`) says what it
       ``needs`` of a body; its builder is registered with ``build.builds("x")``.
    """

    registry: dict = {}
    monte_carlo: bool
    checkpoint_format: str = "driven"  # its checkpoint's fields: "driven" (drive's loop) or "evolution" (the PDE solver's)

    def __init_subclass__(cls, **kwargs):
        super().__init_subclass__(**kwargs)
        if callable(getattr(cls, "advance", None)):
            if not isinstance(getattr(cls, "monte_carlo", None), bool):
                raise TypeError(f"strategy {cls.__name__}: a stepped strategy (with advance) declares "
                                "monte_carlo = True or False")
            if not callable(getattr(cls, "attributes", None)):
                raise TypeError(f"strategy {cls.__name__}: a stepped strategy (with advance) defines "
                                "attributes(state), the dict of the result's attributes")

    @abstractmethod
    def run(self, u0=None, until=1.0, depth_limit=None, progress=None, checkpoint=None, resume=None):
        """The result Dataset of the run (the contract in this module's docstring)."""


def _imported(registry, package, modules):
    """``registry`` with the built-in ``modules`` of ``package`` imported: a lookup by name does not
    depend on what the process imported before (a resume in a fresh shell)."""
    from importlib import import_module

    for module in modules:
        import_module(f"{package}.{module}")
    return registry


BUILTIN_STRATEGIES = ("direct", "fourier", "multiplier", "phenomenological", "stepwise")
BUILTIN_BODIES = ("disk_wheel", "disk_wheel_state", "vehicle_track_body", "wheelset_wear")


def strategies():
    """The registry of strategies, with every built-in one imported."""
    return _imported(Strategy.registry, "railwear.longterm", BUILTIN_STRATEGIES)


def bodies():
    """The registry of bodies, with every built-in one imported."""
    return _imported(Body.registry, "railwear.longterm", BUILTIN_BODIES)


class Rates(NamedTuple):
    """Frozen-geometry wear of a body (:meth:`Body.rates`): ``rate`` per unit normed time in the
    layout of an increment, ``error`` its Monte Carlo standard error on what the variance is kept
    on, ``law_rate`` the wear law's volume (m³ per unit normed time), ``seen`` the body's record
    of the runs."""

    rate: Any
    error: Any
    law_rate: float
    seen: Any = None


class Segment(NamedTuple):
    """One coupled segment of a body (:meth:`Body.segment`): the wear ``increment`` over ``dT``
    (normed time), ``final`` when ``dT`` is exactly what remained, the law's volume (m³), the
    body's record ``seen`` and the ``carry`` the next segment starts from."""

    increment: Any
    dT: float
    final: bool
    law_volume: float
    seen: Any
    carry: dict


class Body(Registered, ABC):
    """What a stepped strategy wears; subclasses register with ``class X(Body, name="x")`` and
    the result's ``body`` attribute is that name. ``u`` is the body's wear variable (an array;
    for the disk wheel the radius deviation, m, for the wheelset the removed depth of both
    wheels, m). Abstract members left out fail when the body is constructed, naming them.

    Rules for a new body:

    1. Register a ``name``; set ``label`` (words for messages).
    2. Say what wears: ``start``, ``removed``, ``removal``, ``apply``, ``error_shape`` (or
       inherit :class:`RadiusBody` for a radius deviation over the angle).
    3. Give frozen-geometry :class:`Rates` (for the stepwise strategy) and/or coupled
       :class:`Segment` s after ``couple`` (for the direct one); a body without one of them
       raises ``NotImplementedError`` there, and its scenario section leaves it out of
       ``provides``.
    4. ``record`` what an output keeps and build the ``result`` Dataset from the records: ``u``
       over ``time`` and ``angle`` with :func:`time_coordinates` and the body's own variables
       (:func:`railwear.longterm.spectra.describe` adds the spectra of a radius); the driver adds
       ``removed_depth`` (from ``removed``), ``stop_time`` and the ``cost_*`` of the counters,
       named from :data:`COSTS`.
    5. ``fingerprint_parts`` names everything that makes its problem, for checkpoints.
    6. From a scenario: a ``[body]`` section registered with
       :func:`railwear.scenario.schema.body_section` whose ``build(scenario, speed)`` returns it.
    """

    registry: dict = {}
    label: str = ""

    @abstractmethod
    def start(self, u0):
        """The wear variable at the start from the user's ``u0`` (``None``: new)."""

    @abstractmethod
    def removed(self, u, u_start):
        """Depth (m) lost since the start, on the cells the depth limit looks at."""

    @abstractmethod
    def removal(self, increment):
        """What a wear ``increment`` adds to :meth:`removed`."""

    @abstractmethod
    def apply(self, u, increment):
        """``u`` after the wear ``increment`` (same layout as a rate times a step)."""

    def update(self, u, cost):
        """Called after every change of ``u``: rebuild what the dynamics see of it."""

    @abstractmethod
    def error_shape(self, u):
        """Shape of what the Monte Carlo variance is kept on."""

    @abstractmethod
    def new_cost(self):
        """The cost counters of a new run (a dict of zeros, named from :data:`COSTS`)."""

    @abstractmethod
    def rates(self, u, rng, cost):
        """Frozen-geometry wear over ``u``, the :class:`Rates`; the cost is added to ``cost``."""

    def limited(self, rate, on="u"):
        """The part of ``rate`` whose largest magnitude the step limit bounds (``"u"`` or
        ``"shape"``: without the uniform part)."""
        return rate if on == "u" else rate - rate.mean()

    @abstractmethod
    def couple(self, u, rng, acceleration, cost):
        """The carry (dict of plain values and arrays) of a coupled run started over ``u``."""

    @abstractmethod
    def segment(self, u, carry, acceleration, remaining, cost):
        """One coupled :class:`Segment` from ``carry``, at most the ``remaining`` normed time."""

    @abstractmethod
    def record(self, u, seen, law_volume):
        """Plain values saved at an output (a dict of arrays and numbers): of the wear variable
        ``u``, the body's record ``seen`` of the last runs and the law's volume so far (m³)."""

    @abstractmethod
    def result(self, records, times, cost, error, attrs):
        """The result Dataset from the saved ``records`` (dict of lists), normed ``times``, the
        ``cost`` dict and the saved standard errors (``None`` without Monte Carlo): ``u`` over
        ``time`` and ``angle`` with the coordinates (:func:`time_coordinates`) and the body's own
        variables; the driver adds ``removed_depth`` (from :meth:`removed`), ``stop_time`` and
        the ``cost_*``."""

    @abstractmethod
    def fingerprint_parts(self):
        """What identifies the body's problem, for checkpoints."""


class RadiusBody(Body):
    """A body whose wear variable is the radius deviation ``u`` (m) over the angle: wear lowers
    it, the depth limit and the variance look at every cell."""

    def start(self, u0):
        return checked_start(u0, 1.0, None).copy()

    def removed(self, u, u_start):
        return u_start - u

    def removal(self, increment):
        return increment

    def apply(self, u, increment):
        return u - increment

    def error_shape(self, u):
        return u.shape


@dataclass
class WearState:
    """Where a stepped run is: normed ``time``, ``steps`` taken, the body's wear variable ``u``,
    the Monte Carlo ``variance``, the wear law's volume (m³), the previous rate, error and step
    (Adams-Bashforth), the coupled carry, the next save mark, cost, outputs and generator."""

    time: float
    steps: int
    u: np.ndarray
    variance: np.ndarray
    law_volume: float
    previous: tuple
    carry: dict
    mark: int
    cost: dict
    saved: dict
    rng: np.random.Generator = field(repr=False, default=None)


CHECKPOINT_VERSION = 3  # 3: the driver saves the removed depth; the cost counters of COSTS


@dataclass(frozen=True)
class Checkpoint:
    """A resumable state: the strategy ``kind``, the format ``version``, the problem's
    ``fingerprint`` and plain ``fields`` (numbers, text, arrays)."""

    kind: str
    fingerprint: str
    fields: dict
    version: int = CHECKPOINT_VERSION

    def plain(self):
        """Flat ``{name: array}`` for an ``.npz`` file."""
        out = {"checkpoint_kind": np.array(self.kind), "checkpoint_version": np.array(self.version),
               "fingerprint": np.array(self.fingerprint)}
        out.update({f"field_{k}": np.asarray(v) for k, v in self.fields.items()})
        return out

    @classmethod
    def from_plain(cls, data, source="checkpoint"):
        """The checkpoint of :meth:`plain`'s fields; a file of another format, or one whose
        fields are missing, unknown or of the wrong type or shape, is refused in one line.

        The fields are those of the driver's loop (:mod:`railwear.longterm.driver`) or of the
        evolution equation's solver (``EvolutionCheckpoint``), as the strategy of the ``kind``
        says (:attr:`Strategy.checkpoint_format`).
        """
        from railwear.errors import CheckpointError

        # name -> (dtype kinds, ndim): the driver's loop, with any number of fields of the
        # prefixes, and the evolution equation's solver
        driven = {"time": ("fi", 0), "steps": ("iu", 0), "u": ("f", None), "variance": ("f", None),
                  "law_volume": ("fi", 0), "mark": ("iu", 0), "rng_state": ("U", 0), "previous_count": ("iu", 0)}
        prefixes = ("previous_", "carry_", "cost_", "saved_")
        evolution = {"fingerprint": ("U", 0), "intervals": ("iu", 0), "steps": ("iu", 1), "halvings": ("iu", 0),
                     "stabilisation": ("fi", 1), "spectra": ("c", 2), "active": ("b", 1), "stop_time": ("f", 1),
                     "saved": ("c", 3), "times": ("f", 1), "tail_peak": ("f", 1)}
        finite = ("time", "u", "variance", "law_volume", "stabilisation", "spectra", "saved", "times")

        def refuse(why):
            raise CheckpointError(f"{source}: {why}; start the run again")

        data = {k: np.asarray(v) for k, v in data.items()}

        def kind_of(name, kinds, ndim):
            value = data[name]
            if value.dtype.kind not in kinds or (ndim is not None and value.ndim != ndim):
                refuse(f"field {name} is {value.dtype} of shape {value.shape}")
            return value

        if "checkpoint_kind" not in data or "checkpoint_version" not in data or "fingerprint" not in data:
            refuse("not a railwear checkpoint of this version")
        version = int(kind_of("checkpoint_version", "iu", 0))
        if version != CHECKPOINT_VERSION:
            raise CheckpointError(f"{source}: checkpoint format {version}, this railwear reads {CHECKPOINT_VERSION}")
        kind, key = str(kind_of("checkpoint_kind", "U", 0)), str(kind_of("fingerprint", "U", 0))
        known = strategies()
        if kind not in known:
            refuse(f"unknown strategy {kind[:40]!r}")
        if len(key) != 64 or any(c not in "0123456789abcdef" for c in key):
            refuse("the fingerprint is not a SHA-256")
        unknown = [k for k in data if k not in ("checkpoint_kind", "checkpoint_version", "fingerprint")
                   and not k.startswith("field_")]
        fields = {k[len("field_"):]: v for k, v in data.items() if k.startswith("field_")}
        spec = evolution if known[kind].checkpoint_format == "evolution" else driven
        unknown += [k for k in fields if k not in spec and not k.startswith(prefixes if spec is driven else ())]
        if unknown:
            refuse(f"unknown field {unknown[0][:40]!r}")
        data = fields
        for name, (kinds, ndim) in spec.items():
            if name not in fields:
                refuse(f"field {name} is missing")
            kind_of(name, kinds, ndim)
        for name in fields:
            if name not in spec:
                kind_of(name, "biufc", None)
            if name in finite and not np.all(np.isfinite(fields[name])):
                refuse(f"field {name} is not finite")
        counts = ("intervals", "halvings") if spec is evolution else ("steps", "mark", "previous_count")
        if any(int(fields[n]) < 0 for n in counts) or np.any(fields["steps"] < 0):
            refuse("a negative count")
        if spec is evolution:
            rows, saved = fields["spectra"].shape[0], fields["saved"]
            if saved.shape[1:] != fields["spectra"].shape or fields["times"].shape != saved.shape[:1] or any(
                    fields[n].shape != (rows,) for n in ("steps", "stabilisation", "active", "stop_time", "tail_peak")):
                refuse("fields of inconsistent shapes")
        else:
            if fields["u"].shape == () or not all(f"previous_{i}" in fields for i in range(int(fields["previous_count"]))):
                refuse("the wear state or the previous steps are incomplete")
            rng_from_text(fields["rng_state"], source)
        return cls(kind, key, {k: plain_value(v) for k, v in fields.items()}, version)

    @property
    def steps(self):
        """Steps the run had taken (output intervals for the evolution equation)."""
        return int(self.fields["intervals"] if "intervals" in self.fields else self.fields["steps"])

    def check(self, kind, key, body="long-term"):
        """Refuse a checkpoint of another strategy or problem (of the ``body``)."""
        if self.kind != kind:
            raise ScenarioError(f"resume: the checkpoint is of the {self.kind} strategy, not {kind}")
        if self.fingerprint != key:
            raise ScenarioError(f"resume: the checkpoint belongs to another {body} problem or run")


def plain_value(value):
    """A field read from an ``.npz`` file: a Python number or text for a 0-d array, else a copy."""
    value = np.asarray(value)
    return value.item() if value.ndim == 0 else value.copy()


def fingerprint(*parts):
    """SHA-256 of arrays and plain values, to tie a checkpoint to its problem."""
    digest = hashlib.sha256()
    for part in parts:
        if isinstance(part, np.ndarray):
            digest.update(np.ascontiguousarray(part, dtype=float).tobytes())
        else:
            digest.update(repr(part).encode())
    return digest.hexdigest()


BIT_GENERATORS = {"PCG64": np.random.PCG64}


def rng_state_text(rng):
    """The state of a ``numpy.random.Generator`` as JSON text (it holds 128-bit integers)."""
    return json.dumps(rng.bit_generator.state)


def rng_from_text(text, source="checkpoint"):
    """A generator continuing from :func:`rng_state_text` (only the bit generators railwear
    writes, :data:`BIT_GENERATORS`; nothing else is looked up by a name from the file)."""
    try:
        state = json.loads(str(text))
        if not isinstance(state, dict) or state.get("bit_generator") not in BIT_GENERATORS:
            raise ValueError
        bit_generator = BIT_GENERATORS[state["bit_generator"]]()
        bit_generator.state = state
    except (ValueError, KeyError, TypeError, OverflowError, RecursionError):
        from railwear.errors import CheckpointError

        raise CheckpointError(f"{source}: the random generator state cannot be read") from None
    return np.random.Generator(bit_generator)


def stop_fraction(removed, increment, depth_limit):
    """Largest ``f`` in [0, 1] with ``max_j(removed_j + f increment_j) <= depth_limit`` (m): the
    part of a linear wear increment that brings the most worn spot exactly to the limit."""
    if depth_limit is None or np.max(removed + increment) < depth_limit:
        return 1.0
    room = depth_limit - removed
    with np.errstate(divide="ignore", invalid="ignore"):
        f = np.where(increment > 0, room / increment, np.inf)
    return float(np.clip(np.min(f), 0.0, 1.0))


def fraction_done(T, until, removed, depth_limit):
    """Progress of a run at normed time ``T``: the larger of ``T / until`` and the most worn
    spot's ``max(removed) / depth_limit`` (``removed`` in m), at most 1."""
    done = T / until
    if depth_limit is not None:
        done = max(done, float(np.max(removed)) / depth_limit)
    return min(done, 1.0)


def checked_run(until, depth_limit):
    """Refuse a run end that is not a positive normed time or depth (m)."""
    if not (np.isfinite(until) and until > 0):
        raise ScenarioError(f"until must be finite and > 0 (normed time), got {until}")
    if depth_limit is not None and not (np.isfinite(depth_limit) and depth_limit > 0):
        raise ScenarioError(f"depth_limit must be > 0 (m), got {depth_limit}")


def checked_start(u0, until, depth_limit):
    """``u0`` (m, over the angle) as a float array after the checks every run makes."""
    u0 = np.asarray(u0, float)
    if u0.ndim != 1 or u0.size < 4:
        raise ScenarioError("u0 must be 1-D with at least 4 angles")
    if not np.all(np.isfinite(u0)):
        raise ScenarioError("u0 must be finite")
    checked_run(until, depth_limit)
    return u0


def time_coordinates(times, life_distance, speed):
    """The contract's coordinates: normed ``time``, ``distance`` (km) at ``life_distance`` (m)
    per unit, ``speed`` (m/s)."""
    times = np.asarray(times, float)
    return {"time": ("time", times, {"units": "1", "long_name": "normed life time"}),
            "distance": ("time", times * life_distance / KM, {"units": "km", "long_name": "distance run"}),
            "speed": ((), float(speed), {"units": "m s-1", "long_name": "vehicle speed (mean of the service)"})}


def cost_variables(cost):
    """The ``cost_*`` variables of a ``cost`` dict, each named, in units, from :data:`COSTS`; an
    unknown counter is refused naming it."""
    unknown = sorted(set(cost) - set(COSTS))
    if unknown:
        raise ValueError(f"cost counter {unknown[0]!r} is not in longterm.base.COSTS ({', '.join(COSTS)}); add it there")
    return {f"cost_{k}": ((), v, {"units": COSTS[k][0], "long_name": COSTS[k][1]}) for k, v in cost.items()}


def stop_time(times):
    """The ``stop_time`` variable of the contract."""
    return ((), float(np.asarray(times)[-1]), {"units": "1", "long_name": "normed time at which the run stopped"})


def check_result(ds):
    """Refuse a Dataset that breaks the result contract (a ``ValueError`` naming what is missing)."""
    missing = [v for v in MANDATORY if v not in ds.variables] + [c for c in COORDINATES if c not in ds.coords]
    missing += [f"attribute {a}" for a in ATTRIBUTES if a not in ds.attrs]
    missing += [] if any(str(v).startswith("cost_") for v in ds.data_vars) else ["cost_*"]
    if missing:
        raise ValueError(f"result contract: missing {', '.join(missing)}")
    if ds.u.dims[0] != "time" or "angle" not in ds.u.dims or ds.u.attrs.get("units") != "m":
        raise ValueError(f"result contract: u must be in m over (time, ..., angle[, lateral]), not {ds.u.dims}")
    if ds.distance.attrs.get("units") != "km" or ds.speed.attrs.get("units") != "m s-1":
        raise ValueError("result contract: distance in km and speed in m s-1")
    return ds
