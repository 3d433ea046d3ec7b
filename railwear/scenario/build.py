"""From a validated scenario to the physics objects: the wear-rate form, the speeds, ``u0``."""

import numpy as np

from railwear.errors import ScenarioError

from railwear.geometry import roundness
from railwear.measured import read_measured
from railwear.scenario.schema import Scenario
from railwear.units import GPA, KM, KN, MM, UG, UM, kmh_to_m_s, m_s_to_kmh

DISK_CONTACT_TRACTION = 1e-4  # least demand of the derived h: its load table refines as 1/f (1e-7: 2.7 GB)


def wear_rate(scenario: Scenario):
    """The ``h`` of the scenario, in SI units (rate in m per unit normed time)."""
    from railwear.pde import Cubic, DiskContact, Table  # here: the evolution equation's import (rocket-fft) costs 0.2-0.5 s

    w = scenario.wear_rate
    if w.form == "cubic":
        return Cubic(w.c0, w.c1, w.c3)
    if w.form == "table":
        speed = None if w.table_speed_kmh is None else kmh_to_m_s(np.array(w.table_speed_kmh))
        return Table(np.array(w.curvature_m), np.array(w.rate_m), speed)
    wheel, contact, wear = scenario.wheel, scenario.contact, scenario.wear
    if contact.traction_coefficient < DISK_CONTACT_TRACTION:
        raise ScenarioError(f"contact.traction_coefficient: the disk_contact form of h is derived for a traction "
                            f"demand of at least {DISK_CONTACT_TRACTION:g} x the load (its load table refines as the "
                            f"demand falls), not {contact.traction_coefficient:g}; use a cubic or table form")
    if wear.law != "energy":
        raise ScenarioError(f"wear.law: the disk_contact form of h is derived for the energy law, not {wear.law!r}; "
                            "use law = \"energy\" or a cubic or table form")
    return DiskContact(
        wheel_radius=wheel.radius_m, unsprung_mass=wheel.unsprung_mass_kg,
        static_load=wheel.static_load_kN * KN,
        traction_coefficient=contact.traction_coefficient,
        friction_coefficient=contact.friction_coefficient,
        youngs_modulus=contact.youngs_modulus_GPa * GPA, poisson=contact.poisson,
        rail_head_radius=contact.rail_head_radius_m, load_scatter=contact.load_scatter,
        specific_wear=wear.specific_wear_ug_per_J * UG, density=wear.density_kg_m3,
        life_distance=life_distance(scenario),
        wear_band_width=None if wear.band_width_mm is None else wear.band_width_mm * MM,
    )


def odd_terms(scenario: Scenario):
    """Drift and dispersion of ``h`` (rad and rad³ per unit normed time) at the operation speeds,
    linear in the speed between the table's speeds."""
    w, speeds = scenario.wear_rate, np.asarray(scenario.operation.speeds, float)
    return tuple(np.interp(speeds, kmh_to_m_s(np.array(w.table_speed_kmh)), value) if isinstance(value, list) else value
                 for value in (w.drift_rad, w.dispersion_rad3))


def initial_state(scenario: Scenario, what="this"):
    """``u0`` on the solver grid (m) of the one wheel ``[initial]`` describes; ``[[initial.wheels]]``
    (:func:`initial_wheels`) is refused, saying ``what`` takes one wheel."""
    if scenario.initial.wheels is not None:
        raise ScenarioError(f"initial.wheels: {what} starts from one wheel; give the fields of [initial] "
                            "instead of a [[initial.wheels]] per wheel")
    return wheel_surface(scenario.initial, scenario.solver.points)


def initial_wheels(scenario: Scenario):
    """``u0`` of every wheel of ``[[initial.wheels]]`` on the solver grid (m), ``(wheels, points)``."""
    return np.array([wheel_surface(init, scenario.solver.points, f"initial.wheels[{k}]")
                     for k, init in enumerate(scenario.initial.surfaces)])


def wheel_surface(init, n, field="initial"):
    """The radius deviation (m) on ``n`` angles of one wheel's ``[initial]`` (an
    :class:`~railwear.scenario.schema.InitialWheel`, named ``field`` in errors), seeded by its ``seed``."""
    if init.kind == "round":
        return np.zeros(n)
    if init.kind == "random":
        rng = np.random.default_rng(init.seed)
        return roundness.random_perturbation(n, init.rms_um * UM, init.lowest_order,
                                             init.highest_order, rng, init.amplitude_slope)
    if init.kind == "harmonics":
        phases = None if init.phases_deg is None else np.deg2rad(init.phases_deg)
        return roundness.harmonics(n, init.orders, np.array(init.amplitudes_um) * UM, phases)
    angle, deviation = read_measured(init.file, field=f"{field}.file")
    return roundness.resample_measured(angle, deviation, n)


def initial_wear(scenario: Scenario):
    """What the strategy starts from: ``u0`` (m; with ``[[initial.wheels]]`` one row per wheel),
    or ``None`` for a body that starts new (the wheelset's new profile)."""
    if scenario.body.starts_new:
        return None
    return initial_state(scenario) if scenario.initial.wheels is None else initial_wheels(scenario)


def patch(scenario: Scenario):
    """Hertz patch of the round wheel on the rail head at the static load."""
    from railwear.contact import hertz_contact

    w, c = scenario.wheel, scenario.contact
    return hertz_contact(w.static_load_kN * KN, 1 / (2 * w.radius_m), 1 / (2 * c.rail_head_radius_m),
                         c.youngs_modulus_GPa * GPA, c.poisson)


def disk_wheel_model(scenario: Scenario, speed):
    """The disk wheel (:class:`~railwear.dynamics.DiskWheelModel`) of a body that has one, at
    ``speed`` (m/s); other bodies are refused naming ``body.kind``."""
    model = getattr(scenario.body, "model", None)
    if model is None:
        raise ScenarioError(f"body.kind: this needs the disk wheel (kind 'disk_wheel'), not {scenario.body.kind!r}")
    return model(scenario, speed)


BUILDERS: dict = {}


def builds(kind):
    """Register ``fn(scenario)`` as the builder of the strategy ``kind`` (its body from :func:`body`)."""
    def register(fn):
        BUILDERS[kind] = fn
        return fn
    return register


def strategy(scenario: Scenario):
    """The long-term strategy of the scenario, ready to ``run(u0, until, depth_limit, ...)``."""
    return BUILDERS[scenario.strategy.kind](scenario)


def one_speed(scenario: Scenario, instead="; sweep over speeds instead"):
    """The operation speed (m/s) of a strategy that takes one; a list is refused naming its field,
    saying what to do ``instead``."""
    speeds = scenario.operation.speeds
    if isinstance(speeds, list):
        field = "speed_kmh" if scenario.operation.speed_kmh is not None else "speed_m_s"
        raise ScenarioError(f"operation.{field}: the {scenario.strategy.kind} strategy takes one speed{instead}")
    return speeds


@builds("phenomenological")
def phenomenological(scenario: Scenario):
    """Strategy 4: the evolution equation with ``[wear_rate]`` and ``[solver]``, batched over the speeds."""
    from railwear.longterm.phenomenological import Phenomenological

    solver = scenario.solver
    return Phenomenological(wear_rate(scenario), np.asarray(scenario.operation.speeds, float), solver.epsilon,
                            solver.nu, *odd_terms(scenario),
                            options={"n_save": solver.n_save, "dealias": solver.dealias, "dt": solver.dt},
                            life_distance=life_distance(scenario), radius=scenario.wheel.radius_m)


def track(scenario: Scenario):
    """The :class:`~railwear.track.Track` of ``[track]`` (SI), smeared for ``support = "continuous"``:
    the rail on the support of ``base`` (``railwear.track.support_of``)."""
    from railwear.track import Track, rail, support_of

    t = scenario.track
    support = support_of(t.base, **t.support_values())
    discrete = Track(rail(t.rail, loss_factor=t.rail_loss_factor), support, t.sleeper_spacing_m, t.beam)
    return discrete.smeared() if t.support == "continuous" else discrete


def at_demand(scenario: Scenario, traction_coefficient):
    """The scenario with ``contact.traction_coefficient`` set to a duty segment's demand."""
    contact = scenario.contact.model_copy(update={"traction_coefficient": float(traction_coefficient)})
    return scenario.model_copy(update={"contact": contact})


def fourier_technique(scenario: Scenario):
    """The Fourier technique on the body's linear model at the one speed, or over the segments of
    the ``[operation]`` duty cycle (:class:`~railwear.longterm.fourier.FourierCycle`)."""
    from railwear.longterm.fourier import Fourier, FourierCycle

    duty, law = scenario.operation.duty(), wear_law(scenario)
    segments = ([(scenario, one_speed(scenario))] if duty is None else
                [(at_demand(scenario, s.traction_coefficient), s.speed) for s in duty.segments])
    shares = (1.0,) if duty is None else duty.shares
    if getattr(scenario.body, "several_wheels", False):
        from railwear.longterm.vehicle_track import WheelsFourier

        return WheelsFourier(tuple(sc.body.wheels(sc, v) for sc, v in segments), law, band_width(scenario),
                             tuple(float(p) for p in shares), scenario.body.phases)

    def at(sc, speed):
        model, band = linear_model(sc, speed)
        return Fourier.disk_wheel(model, law, band)

    return FourierCycle.of([at(sc, v) for sc, v in segments], shares)


@builds("fourier")
def fourier(scenario: Scenario):
    """Strategy 2: the Fourier technique on the linearised disk wheel, or on the wheel of
    ``[body]`` over ``[track]`` (bay-averaged), at the one speed or over the duty cycle, stopping
    at ``solver.peak_to_peak_limit_mm``."""
    from railwear.longterm.fourier import FourierStrategy

    technique = fourier_technique(scenario)
    limit = scenario.solver.peak_to_peak_limit_mm
    return FourierStrategy(technique, life_distance(scenario), scenario.solver.n_save, body=scenario.body.kind,
                           peak_to_peak_limit=None if limit is None else limit * MM)


def linear_model(scenario: Scenario, speed):
    """The body's linear model at ``speed`` (m/s) and its wear band (m); a body without one is
    refused naming ``body.kind``."""
    return scenario.body.linear_model(scenario, speed)


@builds("multiplier")
def multiplier(scenario: Scenario):
    """The multiplier law on the body's linear model (``[strategy] local``) at the one speed, or
    with ``local = "none"`` over the ``[operation]`` duty cycle on its averaged Fourier rates
    (:func:`fourier_technique`), stopping at ``solver.peak_to_peak_limit_mm``."""
    from railwear.longterm.multiplier import Multiplier

    st, solver = scenario.strategy, scenario.solver
    limit = solver.peak_to_peak_limit_mm
    options = {"grid_points": st.grid_points, "body": scenario.body.kind,
               "peak_to_peak_limit": None if limit is None else limit * MM, "epsilon": solver.epsilon, "nu": solver.nu,
               "options": {"n_save": solver.n_save, "dealias": solver.dealias, "dt": solver.dt}}
    if st.local == "none":
        return Multiplier.from_fourier(fourier_technique(scenario), life_distance(scenario), **options)
    if getattr(scenario.body, "several_wheels", False):
        scenario.body.one_wheel('the multiplier law with a local form (strategy.local)')
    model, band = linear_model(scenario, one_speed(scenario))
    return Multiplier.from_model(model, wear_law(scenario), band, life_distance(scenario), **options)


def wear_law(scenario: Scenario):
    """The :class:`~railwear.wear.WearLaw` of ``[wear]`` (``law`` and its fields)."""
    return scenario.wear.build()


def band_width(scenario: Scenario):
    """Lateral width the tread wear spreads over (m): ``wear.band_width_mm``, else the Hertz ``2b``."""
    width = scenario.wear.band_width_mm
    return width * MM if width else 2 * float(patch(scenario).b)


def service_speeds(scenario: Scenario):
    """The speed distribution (m/s) of ``[service]``; without peaks there, the operation speed
    with the service scatter; over an ``[operation]`` duty cycle its segments, each drawn with its
    share of the distance at its speed (with the service scatter) and demand
    (:class:`~railwear.longterm.disk_wheel.DutyService`)."""
    from railwear.longterm.disk_wheel import DutyService, ServiceSpeeds

    service, speeds, duty = scenario.service, scenario.operation.speeds, scenario.operation.duty()
    if duty is not None:
        return DutyService.of(duty, kmh_to_m_s(service.speed_scatter_kmh))
    if service.speed_kmh is not None:
        peaks = kmh_to_m_s(list(service.speed_kmh))
    else:
        peaks = [one_speed(scenario, ", or peaks in service.speed_kmh")]
    return ServiceSpeeds(tuple(peaks), None if service.speed_weights is None else tuple(service.speed_weights),
                         kmh_to_m_s(service.speed_scatter_kmh))


def life_distance(scenario: Scenario):
    """Metres run in one unit of normed time."""
    return scenario.operation.life_distance_km * KM


@builds("stepwise")
def stepwise(scenario: Scenario):
    """Strategy 3 on the body, the disk wheel over the ``[service]`` speeds or the segments of the
    ``[operation]`` duty cycle (:func:`service_speeds`), seeded by ``service.seed``."""
    from railwear.longterm.stepwise import Stepwise

    st = scenario.strategy
    return Stepwise(body(scenario), st.step_limit_um * UM, seed=scenario.service.seed,
                    limit_on=st.step_limit_on, scheme=st.scheme)


@builds("direct")
def direct(scenario: Scenario):
    """Strategy 1 on the body at the operation speed, or over the ``[operation]`` duty cycle (the
    body at each segment's speed and demand): the disk wheel's outputs at ``solver.n_save``
    marks, the wheelset's after every update."""
    from railwear.longterm.direct import Direct

    duty = scenario.operation.duty()
    cycle = () if duty is None else tuple((s.share, body(at_demand(scenario, s.traction_coefficient), s.speed))
                                          for s in duty.segments)
    return Direct(body(scenario, one_speed(scenario)), scenario.strategy.acceleration_factor,
                  n_save=None if scenario.body.saves_every_segment else scenario.solver.n_save,
                  seed=scenario.service.seed, cycle=cycle)


def body(scenario: Scenario, speed=None):
    """The long-term body of ``[body]`` at ``speed`` (m/s, default the service mean)."""
    return scenario.body.build(scenario, speed)


def fitted_h(scenario: Scenario, speeds=None, scales=(0.5, 1.0, 1.5, 2.0), degree=3, bins=16):
    """Strategy 4's fit from the scenario's disk wheel: frozen-geometry statistics at ``speeds``
    (m/s; default the ``[service]`` peaks, else the operation speed), each with the service
    scatter, over the initial wheel scaled by ``scales``; returns ``(statistics, fit)``."""
    from dataclasses import replace

    from railwear.longterm.disk_wheel import ServiceSpeeds
    from railwear.longterm.fitting import fit_h, gather

    disk_wheel_model(scenario, 1.0)  # a disk wheel's, or refused
    op = scenario.operation
    if op.duty() is not None:
        raise ScenarioError(f"operation.{'cycle' if op.cycle is not None else 'line'}: h is fitted at one traction demand "
                            "(contact.traction_coefficient) over speeds; fit a scenario at one operating point")
    frozen = body(scenario)
    speeds = np.atleast_1d(service_speeds(scenario).peaks if speeds is None else speeds).astype(float)
    scatter = frozen.service.scatter
    u0 = initial_state(scenario)
    stats = gather(lambda v: replace(frozen, model=disk_wheel_model(scenario, v), service=ServiceSpeeds((v,), None, scatter)),
                   np.sort(speeds), [u0 * s for s in scales], np.random.default_rng(scenario.service.seed))
    return stats, fit_h(stats, degree=degree, bins=bins)


def with_fitted_h(scenario: Scenario, fit):
    """The scenario with the fitted ``h`` as its ``[wear_rate]`` table and the phenomenological
    strategy."""
    table = fit.table
    rate = table.rate.tolist()
    wear_rate = scenario.wear_rate.model_copy(update={
        "form": "table", "curvature_m": table.curvature.tolist(), "rate_m": rate,
        "table_speed_kmh": None if table.speed is None else m_s_to_kmh(table.speed).tolist(),
        "drift_rad": fit.drift.tolist() if table.speed is not None else float(fit.drift[0]),
        "dispersion_rad3": fit.dispersion.tolist() if table.speed is not None else float(fit.dispersion[0])})
    from railwear.scenario.schema import PhenomenologicalSection

    strategy = PhenomenologicalSection()
    return scenario.model_copy(update={"wear_rate": wear_rate, "strategy": strategy,
                                       "name": f"{scenario.name}-fitted",
                                       "description": f"h fitted to the frozen-geometry statistics of '{scenario.name}'"})
