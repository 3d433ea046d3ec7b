"""The built-in ``[body]`` sections, each with its builder: the disk wheel, the wheel on the
track and the wheelset on real profiles (see :class:`~railwear.scenario.schema.BodySection`).

A section's fields are the body's own; ``build(scenario, speed)`` returns the long-term
:class:`~railwear.longterm.base.Body`, ``linear_model(scenario, speed)`` the linear model of the
Fourier technique and the multiplier law with its wear band (m). Units convert here.
"""

from typing import Annotated, ClassVar, Literal

import numpy as np
from pydantic import Field, model_validator

from railwear.errors import ScenarioError
from railwear.scenario.schema import (BodySection, Damping, Mass, PathText, Stiffness, body_section, refuse)
from railwear.units import GPA, KN, MM, MN, UM

def _build():
    """The builders, imported when a body is built: the schema loads without the physics."""
    from railwear.scenario import build

    return build


Revolutions = Annotated[int, Field(ge=0, le=100000)]
Samples = Annotated[int, Field(ge=2, le=100000)]  # Monte Carlo draws per frozen-geometry step: 2 for a variance
MAX_WHEELS = 8  # wheels on one rail: the four of a car, or two cars' facing bogies


class RollingWheel(BodySection):
    """A wheel rolling over its angle: ``samples`` draws of phase and speed (from ``[service]``)
    per frozen-geometry step, each of ``revolutions`` after ``transient_revolutions`` without
    wear; the coupled run updates the surface ``updates_per_revolution`` times a revolution after
    ``transient_revolutions``."""

    samples: Samples = 8
    revolutions: Annotated[int, Field(ge=1, le=100000)] = 4
    transient_revolutions: Revolutions = 4
    updates_per_revolution: Annotated[int, Field(ge=1, le=1000)] = 1

    provides: ClassVar[frozenset] = frozenset({"rates", "segment", "linear_model"})
    serves: ClassVar[dict] = {"samples": ("rates",), "revolutions": ("rates",),
                              "transient_revolutions": ("rates", "segment"), "updates_per_revolution": ("segment",)}

    def settings(self):
        """The run settings the long-term disk wheel takes."""
        return {k: getattr(self, k) for k in ("revolutions", "transient_revolutions", "samples",
                                              "updates_per_revolution")}


@body_section
class DiskWheelSection(RollingWheel):
    """``kind = "disk_wheel"``: vertical and rotational dynamics of the disk wheel (paper Fig. 5)
    on a rail mass on pads (the P2 resonance). The wheel mass is ``wheel.unsprung_mass_kg``;
    radius, load, contact and traction come from ``[wheel]`` and ``[contact]``."""

    kind: Literal["disk_wheel"] = "disk_wheel"
    wheel_inertia_kg_m2: Annotated[float, Field(ge=1e-3, le=1e5)] = 80.0
    primary_stiffness_N_m: Stiffness = 1.2e6
    primary_damping_N_s_m: Damping = 2e4
    sprung_mass_kg: Annotated[float, Field(ge=1, le=1e6)] | None = None  # up to a loaded wagon
    rail_mass_kg: Mass | None = 150.0
    pad_stiffness_N_m: Annotated[float, Field(ge=1e3, le=1e10)] = 1e8  # 1e11: the Fourier rates overflow
    pad_damping_N_s_m: Damping = 6e4

    label: ClassVar[str] = "disk-wheel dynamics"
    validated_against: ClassVar[str] = ("the paper's disk wheel on a rail mass (its Figs 1-8, qualitatively) and the "
                                         "strategies against one another (docs/strategies.md); no field observations")

    def model(self, scenario, speed):
        """The :class:`~railwear.dynamics.DiskWheelModel` at ``speed`` (m/s), with Hertz and Kalker constants."""
        from railwear.dynamics import DiskWheelModel, contact_constants

        w, c = scenario.wheel, scenario.contact
        load = w.static_load_kN * KN
        constants = contact_constants(load, 1 / (2 * w.radius_m), 1 / (2 * c.rail_head_radius_m),
                                      c.youngs_modulus_GPa * GPA, c.poisson)
        return DiskWheelModel(
            speed=float(speed), radius=w.radius_m, wheel_mass=w.unsprung_mass_kg,
            wheel_inertia=self.wheel_inertia_kg_m2, static_load=load,
            hertz_constant=constants["hertz_constant"], primary_stiffness=self.primary_stiffness_N_m,
            primary_damping=self.primary_damping_N_s_m, f11=constants["f11"],
            sprung_mass=self.sprung_mass_kg, rail_mass=self.rail_mass_kg, pad_stiffness=self.pad_stiffness_N_m,
            pad_damping=self.pad_damping_N_s_m, friction_coefficient=c.friction_coefficient,
            traction_torque=c.traction_coefficient * load * w.radius_m,
            patch_half_length=constants["patch_half_length"])

    def build(self, scenario, speed=None):
        from railwear.longterm.disk_wheel import DiskWheel
        from railwear.longterm.disk_wheel_state import StatefulDiskWheel

        service, law = _build().service_speeds(scenario), _build().wear_law(scenario)
        model = self.model(scenario, service.mean if speed is None else speed)
        args = (model, law, _build().band_width(scenario), _build().life_distance(scenario), service)
        if getattr(law, "stateful", False):
            return StatefulDiskWheel(*args, **self.settings(), state_scale=scenario.wear.state_scale_um * UM)
        return DiskWheel(*args, **self.settings())

    def linear_model(self, scenario, speed):
        return self.model(scenario, speed), _build().band_width(scenario)


@body_section
class VehicleTrackSection(RollingWheel):
    """``kind = "vehicle_track"``: one wheel of a vehicle on the rail of ``[track]``. The unsprung
    mass, radius and load are ``[wheel]``'s; per wheel: the polar inertia (half the wheelset's),
    the primary suspension to the bogie frame's share ``sprung_mass_kg`` (none: a rigid frame);
    flexible modes of the wheelset as modal data, one entry per mode in
    ``wheel_mode_frequencies_hz``, ``wheel_mode_masses_kg`` (modal mass at the contact point) and
    ``wheel_mode_damping_ratios`` (the Fourier technique and the multiplier only). Defaults: the
    metro motor car of docs/vehicle_track.md (Math. Probl. Eng. 2020, 1584624, Table 6)."""

    kind: Literal["vehicle_track"] = "vehicle_track"
    # METRO's (longterm.vehicle_track), written out so that the schema loads without the physics;
    # tests/longterm/test_metro_scenario.py holds them equal
    wheel_inertia_kg_m2: Annotated[float, Field(ge=1e-3, le=1e5)] = 60.0
    sprung_mass_kg: Annotated[float, Field(ge=1, le=1e6)] | None = 855.0
    primary_stiffness_MN_m: Annotated[float, Field(ge=0, le=1e3)] = 1.7
    primary_damping_kN_s_m: Annotated[float, Field(ge=0, le=1e4)] = 10.0
    wheel_mode_frequencies_hz: Annotated[list[Annotated[float, Field(ge=1, le=1e4)]], Field(max_length=100)] = []
    wheel_mode_masses_kg: Annotated[list[Annotated[float, Field(ge=1, le=1e5)]], Field(max_length=100)] = []
    wheel_mode_damping_ratios: Annotated[list[Annotated[float, Field(ge=0, le=1)]], Field(max_length=100)] = []
    # the wheels on this rail, m from the first (0, 2.5: a bogie); a car is 4, a bogie pair 20 m apart
    # couples no more (docs/vehicle_track.md, Several wheels on one rail); None: one wheel
    wheel_positions_m: Annotated[list[Annotated[float, Field(ge=0, le=100, allow_inf_nan=False)]],
                                 Field(min_length=1, max_length=MAX_WHEELS)] | None = None
    # the wheels' polygons: "locked" at their relative angles (equal diameters), or "drifting" (the
    # diameters of different axles differ; each wheel grows on its own); None: locked
    wheel_phases: Literal["locked", "drifting"] | None = None
    # the rolling contact of the linear strategies (docs/vehicle_track.md, Short-wavelength contact
    # physics): Kalker's steady creep, or the non-steady contact (half-space or simplified theory);
    # None: steady
    rolling_contact: Literal["steady", "transient", "simplified"] | None = None
    # longitudinal compliances in series with the contact: the rail head's, the wheel centre's
    # (a free mass); None: both rigid
    tangential_compliance: Annotated[list[Literal["rail", "wheel"]], Field(max_length=2)] | None = None

    sections: ClassVar[tuple] = ("track",)
    label: ClassVar[str] = "wheel on the discrete track"
    validated_against: ClassVar[str] = (
        "metro wheels under traction at 60-80 km/h on ballasted track: the P2 resonance selects orders 6-9 as in "
        "service; the rail receptance against an independent model (docs/vehicle_track.md)")
    SPEEDS_KMH: ClassVar[tuple] = (40.0, 120.0)  # the speeds the field comparison covers
    SHORTEST_WAVE: ClassVar[float] = 10.0  # patch lengths: below, the steady creep law does not hold

    def scope(self, scenario, ds):
        """Outside the validation: a speed beyond :attr:`SPEEDS_KMH`, braking (the steady contact
        lets short waves grow), a dominant polygon shorter than :attr:`SHORTEST_WAVE` patch lengths."""
        from railwear.units import kmh_to_m_s, m_s_to_kmh

        notes, op = [], scenario.operation
        duty = op.duty()
        speeds = m_s_to_kmh(np.atleast_1d(duty.speeds if duty else op.speeds))
        low, high = self.SPEEDS_KMH
        braking = duty.braking_share if duty else float(scenario.contact.traction_coefficient < 0)
        if speeds.min() < low or speeds.max() > high:
            text = f"speed {speeds.min():g}-{speeds.max():g} km/h lies outside the {low:g}-{high:g} km/h of the field comparison"
            if speeds.max() > high:
                text += (", and high-speed polygons (orders 18-26 at 250-350 km/h) are not reproduced under net traction"
                         if braking == 0 else ", and at high speed orders near the field's 18-26 grow here only under braking, "
                         "the order set weakly by a wheelset mode whose modal mass and damping are assumptions, and no "
                         "measured growth rate has been compared (docs/vehicle_track.md, The high-speed built-in)")
            notes.append(text)
        if braking > 0:
            mean = duty.mean_traction_coefficient if duty else scenario.contact.traction_coefficient
            notes.append(f"braking over {braking:.0%} of the distance (mean creep force {mean:+.4f} x wheel load): under "
                         "braking the rolling-radius term grows every order up to the contact filter, steady or non-steady "
                         "contact alike (on the metro wheel it grows orders near 50 that the field does not report)")
        if "dominant_order" in ds and "order" in ds.dims:
            n = int(np.max(ds.dominant_order.values))
            model = self.linear_model(scenario, kmh_to_m_s(float(np.mean(speeds))))[0]
            wave, patch = 2 * np.pi * scenario.wheel.radius_m / max(n, 1), 2 * model.patch_half_length
            if n > 1 and wave < self.SHORTEST_WAVE * patch and self.contact_model == "steady":
                notes.append(f"the dominant order {n} is {wave * 1e3:.0f} mm long, under {self.SHORTEST_WAVE:g} patch "
                             f"lengths ({patch * 1e3:.1f} mm): the steady creep law does not hold there")
        return notes

    @model_validator(mode="after")
    def _modes(self):
        x = self.wheel_positions_m
        if x is not None and (x[0] != 0 or any(b <= a for a, b in zip(x, x[1:]))):
            raise refuse("wheel_positions_m", f"the wheels' distances from the first (m): 0, then increasing, got {x}")
        if self.tangential_compliance is not None and len(set(self.tangential_compliance)) != len(
                self.tangential_compliance):
            raise refuse("tangential_compliance", f"each of rail, wheel once, got {self.tangential_compliance}")
        if self.wheel_phases is not None and not self.several_wheels:
            raise refuse("wheel_phases", "the relative phases of several wheels' polygons: give wheel_positions_m "
                                         "with two wheels or more")
        modes = len(self.wheel_mode_frequencies_hz)
        for name in ("wheel_mode_masses_kg", "wheel_mode_damping_ratios"):
            if len(getattr(self, name)) != modes:
                raise refuse(name, f"give one value per mode in wheel_mode_frequencies_hz ({modes}), "
                                   f"not {len(getattr(self, name))}")
        return self

    def case(self, scenario):
        """The :class:`~railwear.longterm.vehicle_track.VehicleCase` of ``[wheel]``, ``[contact]``,
        this section and ``[track]``, its wear band from :func:`~railwear.scenario.build.band_width`."""
        from railwear.longterm.vehicle_track import VehicleCase

        w, c = scenario.wheel, scenario.contact
        return VehicleCase(
            name=scenario.name, diameter=2 * w.radius_m, static_load=w.static_load_kN * KN,
            unsprung_mass=w.unsprung_mass_kg, wheel_inertia=self.wheel_inertia_kg_m2,
            sprung_mass=self.sprung_mass_kg, primary_stiffness=self.primary_stiffness_MN_m * MN,
            primary_damping=self.primary_damping_kN_s_m * KN, track=_build().track(scenario),
            traction_coefficient=c.traction_coefficient, band_width=_build().band_width(scenario),
            rail_head_radius=c.rail_head_radius_m, friction_coefficient=c.friction_coefficient,
            youngs_modulus=c.youngs_modulus_GPa * GPA, poisson=c.poisson,
            wheel_modes=tuple(zip(self.wheel_mode_frequencies_hz, self.wheel_mode_masses_kg,
                                  self.wheel_mode_damping_ratios)))

    def build(self, scenario, speed=None):
        """The wheel on the time-domain track (a ring of ``track.ring_sleepers`` bays); with
        ``wheel_positions_m`` all the wheels on it (the stepwise and direct strategies)."""
        from railwear.longterm.vehicle_track_body import VehicleTrackBody, ring_for

        service, case, t = _build().service_speeds(scenario), self.case(scenario), scenario.track
        if scenario.strategy.kind not in ("stepwise", "direct"):
            self.one_wheel(f"the time-domain vehicle-track body under the {scenario.strategy.kind} strategy")
        if case.wheel_modes:
            raise ScenarioError("body.wheel_mode_frequencies_hz: the time-domain vehicle-track body has no flexible "
                                "wheelset modes; use the fourier or multiplier strategy")
        wheels = {"wheel_positions": tuple(self.wheel_positions_m)} if self.several_wheels else {}
        if self.phases == "drifting":
            raise ScenarioError("body.wheel_phases: the time-domain track runs identical wheels, whose polygons keep "
                                "their angles (locked); drifting phases run with the Fourier technique")
        if self.contact_model != "steady" or self.tangential:
            field = "rolling_contact" if self.contact_model != "steady" else "tangential_compliance"
            raise ScenarioError(f"body.{field}: the time-domain body rolls with Kalker's steady creep on a rigid "
                                "rail head; the non-steady contact and the compliances run with the Fourier technique")
        try:
            return VehicleTrackBody(case.wheel(service.mean if speed is None else speed), _build().wear_law(scenario),
                                    case.band_width, _build().life_distance(scenario), service, **self.settings(),
                                    ring=ring_for(case.track, t.ring_sleepers, t.ring_max_frequency_hz), **wheels)
        except ScenarioError as e:  # the wheels' spacing on the ring: the scenario's name for it
            if str(e).startswith("wheel_positions:"):
                raise ScenarioError(f"body.wheel_positions_m{str(e)[len('wheel_positions'):]} (or raise "
                                    "track.ring_sleepers)") from None
            raise

    @property
    def contact_model(self) -> str:
        """``rolling_contact`` or ``"steady"``."""
        return self.rolling_contact or "steady"

    @property
    def tangential(self) -> tuple:
        """``tangential_compliance`` as a tuple (empty: rigid)."""
        return tuple(self.tangential_compliance or ())

    @property
    def phases(self) -> str:
        """The wheels' relative phases, ``wheel_phases`` or ``"locked"``."""
        return self.wheel_phases or "locked"

    @property
    def several_wheels(self) -> bool:
        """More than one wheel on the rail (``wheel_positions_m``)."""
        return self.wheel_positions_m is not None and len(self.wheel_positions_m) > 1

    def one_wheel(self, what):
        """Refuse several wheels, naming the field, for ``what`` (a model of one wheel)."""
        if self.several_wheels:
            raise ScenarioError(f"body.wheel_positions_m: {what} carries one wheel; several wheels on one rail run "
                                "with the Fourier technique (strategy fourier, or multiplier with local = \"none\") "
                                "or on the time-domain track with the stepwise or direct strategy")

    def wheels(self, scenario, speed):
        """The :class:`~railwear.longterm.vehicle_track.WheelsOnRail` of ``wheel_positions_m`` at
        ``speed`` (m/s) on :meth:`linear_model`'s wheel and track."""
        from railwear.longterm.vehicle_track import WheelsOnRail

        return WheelsOnRail(self.linear_model(scenario, speed)[0], tuple(self.wheel_positions_m or (0.0,)))

    def linear_model(self, scenario, speed):
        """The wheel closed through the rail receptance, averaged over ``track.bay_positions``."""
        from railwear.longterm.vehicle_track import VehicleTrackModel

        case = self.case(scenario)
        return VehicleTrackModel(case.wheel(speed), case.track, scenario.track.bay_positions, case.wheel_modes,
                                 case._contact(self.contact_model), self.tangential), case.band_width

    def growth_map(self, scenario, speeds, orders):
        """The Fourier growth map with the rail receptance evaluated once per bay offset; with
        several wheels, the fastest combination's (:func:`~railwear.longterm.vehicle_track.wheels_growth_map`)."""
        if self.several_wheels:
            from railwear.longterm.vehicle_track import wheels_growth_map

            return wheels_growth_map(self.case(scenario), self.wheel_positions_m, speeds, orders,
                                     _build().wear_law(scenario), scenario.track.bay_positions, self.phases,
                                     self.contact_model, self.tangential)
        return self.case(scenario).growth_map(speeds, orders, _build().wear_law(scenario), scenario.track.bay_positions,
                                              contact=self.contact_model, tangential=self.tangential)


@body_section
class WheelsetSection(BodySection):
    """``kind = "wheelset"``: long-term wear of the wheelset on real profiles, the worn lateral
    profile over distance and the angular pattern at the end; it starts from the new profile.

    The suspension is ``[wheelset]`` (mass, yaw inertia, stiffnesses; its conicity and half gauge
    are not used: the contact table of the profiles gives the geometry), the speed
    ``operation.speed_kmh`` (one), friction and elasticity ``[contact]``, the nominal rolling
    radius ``wheel.radius_m``, the axle load twice ``wheel.static_load_kN``, the law ``[wear]``.
    Frozen geometry (stepwise): ``samples`` random starts of ``seconds_per_sample_s`` each;
    coupled (direct): the profile and the contact table updated every ``update_interval_s`` of
    simulated time. ``wheel_profile``/``rail_profile`` a built-in name (S1002, UIC60) or a SIMPACK
    profile file; ``shift_max_mm``/``shift_step_mm`` the table's lateral shifts;
    ``lateral_min_mm``, ``lateral_max_mm``, ``lateral_cells`` and ``angle_cells`` the wear surface
    on the wheel profile; ``transient_s`` run before wear is gathered; each run starts from rest at
    a random lateral offset between ``offset_min_mm`` and ``offset_max_mm`` (random sign);
    ``output_rate_Hz`` the output times of the dynamics per simulated second; ``contact_model``
    the tables' contact: "hertz", "multi-hertz" or "semi-hertzian". Example::

        [strategy]
        kind = "stepwise"
        step_limit_um = 1.0

        [body]
        kind = "wheelset"
        samples = 2
        wheel_profile = "S1002"
        rail_profile = "UIC60"
        seconds_per_sample_s = 1.0
    """

    kind: Literal["wheelset"] = "wheelset"
    samples: Samples = 8
    wheel_profile: PathText = "S1002"
    rail_profile: PathText = "UIC60"
    shift_max_mm: Annotated[float, Field(gt=0, le=50, allow_inf_nan=False)] = 10.0
    shift_step_mm: Annotated[float, Field(gt=0, le=10, allow_inf_nan=False)] = 0.1
    lateral_min_mm: Annotated[float, Field(ge=-200, le=200)] = -50.0  # a tread is ~140 mm wide
    lateral_max_mm: Annotated[float, Field(ge=-200, le=200)] = 40.0
    lateral_cells: Annotated[int, Field(ge=2, le=10000)] = 180
    angle_cells: Annotated[int, Field(ge=4, le=100000)] = 64
    transient_s: Annotated[float, Field(ge=0, le=3600)] = 3.0  # simulated seconds: an hour is plenty
    offset_min_mm: Annotated[float, Field(ge=0, le=50)] = 1.0  # past the flange at ~10 mm
    offset_max_mm: Annotated[float, Field(ge=0, le=50)] = 3.0
    output_rate_Hz: Annotated[float, Field(ge=1, le=1e6)] = 2000.0
    footprint: Literal["hertz", "uniform"] = "hertz"
    contact_model: Literal["hertz", "multi-hertz", "semi-hertzian"] = "hertz"
    seconds_per_sample_s: Annotated[float, Field(gt=0, le=3600)] = 2.0
    update_interval_s: Annotated[float, Field(ge=1e-4, le=3600)] = 0.5

    provides: ClassVar[frozenset] = frozenset({"rates", "segment"})
    serves: ClassVar[dict] = {"samples": ("rates",)}
    starts_new: ClassVar[bool] = True
    saves_every_segment: ClassVar[bool] = True
    longitudinal_demand: ClassVar[bool] = False  # the table wheelset runs free: no traction torque
    label: ClassVar[str] = "wheelset on real profiles"
    validated_against: ClassVar[str] = ("the worn lateral profile of the stepwise strategy against the direct one "
                                        "(docs/strategies.md); no field wear data")

    @model_validator(mode="after")
    def _ranges(self):
        if not self.lateral_min_mm < self.lateral_max_mm:
            raise refuse("lateral_min_mm", f"lateral_min_mm must be below lateral_max_mm ({self.lateral_min_mm:g} mm "
                                           f">= {self.lateral_max_mm:g} mm)")
        if self.offset_min_mm > self.offset_max_mm:
            raise refuse("offset_min_mm", f"must not exceed offset_max_mm ({self.offset_max_mm:g})")
        if self.shift_step_mm > self.shift_max_mm:
            raise refuse("shift_step_mm", f"must not exceed shift_max_mm ({self.shift_max_mm:g})")
        return self

    def profile(self, which):
        """The wheel or rail profile (``which`` "wheel" or "rail")."""
        from railwear.geometry import load_profile

        name = getattr(self, f"{which}_profile")
        try:
            return load_profile(name)
        except (OSError, ValueError, ScenarioError) as e:
            message = str(e).splitlines()[0] if str(e) else type(e).__name__
            raise ScenarioError(f"body.{which}_profile: cannot load {name!r}: built-in S1002 or UIC60, "
                                f"or a SIMPACK profile file ({message})") from None

    def problem(self, scenario):
        """The :class:`~railwear.longterm.wheelset_wear.WheelsetWear` problem with the suspension
        of ``[wheelset]`` at the one operation speed."""
        from railwear.dynamics import TableWheelsetModel
        from railwear.geometry import contact_table
        from railwear.longterm.wheelset_wear import WheelsetWear

        speed, c, w, ws = _build().one_speed(scenario), scenario.contact, scenario.wheel, scenario.wheelset
        n = max(int(round(self.shift_max_mm / self.shift_step_mm)), 1)
        shifts = np.round(np.linspace(-self.shift_max_mm, self.shift_max_mm, 2 * n + 1) * MM, 12)
        wheel, rail = self.profile("wheel"), self.profile("rail")
        table = contact_table(wheel, rail, y=shifts, axle_load=2 * w.static_load_kN * KN, rolling_radius=w.radius_m,
                              youngs_modulus=c.youngs_modulus_GPa * GPA, poisson=c.poisson,
                              contact_model=self.contact_model)
        model = TableWheelsetModel(speed=float(speed), mass=ws.mass_kg, yaw_inertia=ws.yaw_inertia_kg_m2,
                                   lateral_stiffness=ws.lateral_stiffness_N_m, yaw_stiffness=ws.yaw_stiffness_N_m_rad,
                                   table=table, friction_coefficient=c.friction_coefficient)
        edges = np.round(np.linspace(self.lateral_min_mm, self.lateral_max_mm, self.lateral_cells + 1) * MM, 12)
        return WheelsetWear(model, wheel, rail, _build().wear_law(scenario), _build().life_distance(scenario),
                            shifts=tuple(shifts), lateral_edges=tuple(edges), n_angle=self.angle_cells,
                            transient=self.transient_s, offsets=(self.offset_min_mm * MM, self.offset_max_mm * MM),
                            output_rate=self.output_rate_Hz, footprint=self.footprint,
                            contact_model=self.contact_model)

    def build(self, scenario, speed=None):
        """The wheelset as a long-term body (``run(None, ...)`` starts from the new profile)."""
        from railwear.longterm.wheelset_wear import Wheelset

        if getattr(_build().wear_law(scenario), "stateful", False):
            raise ScenarioError(f"wear.law: {scenario.wear.law!r} carries a state per cell, which the wheelset "
                                "body does not; use it with a body that rolls over its angle (disk_wheel)")
        return Wheelset(self.problem(scenario), seconds=self.seconds_per_sample_s, samples=self.samples,
                        update_seconds=self.update_interval_s)
