"""From a validated scenario to the physics objects: the wear-rate form, the speeds, ``u0``."""

import numpy as np

from railwear.geometry import roundness
from railwear.measured import read_measured
from railwear.pde import Cubic, DiskContact, Table
from railwear.scenario.schema import Scenario

def wear_rate(scenario: Scenario):
    """The ``h`` of the scenario, in SI units (rate in m per unit normed time)."""
    w = scenario.wear_rate
    if w.form == "cubic":
        return Cubic(w.c0, w.c1, w.c3)
    if w.form == "table":
        speed = None if w.table_speed_kmh is None else np.array(w.table_speed_kmh) / 3.6
        return Table(np.array(w.curvature_m), np.array(w.rate_m), speed)
    wheel, contact, wear = scenario.wheel, scenario.contact, scenario.wear
    return DiskContact(
        wheel_radius=wheel.radius_m, unsprung_mass=wheel.unsprung_mass_kg,
        static_load=wheel.static_load_kN * 1e3,
        traction_coefficient=contact.traction_coefficient,
        friction_coefficient=contact.friction_coefficient,
        youngs_modulus=contact.youngs_modulus_GPa * 1e9, poisson=contact.poisson,
        rail_head_radius=contact.rail_head_radius_m, load_scatter=contact.load_scatter,
        specific_wear=wear.specific_wear_ug_per_J * 1e-9, density=wear.density_kg_m3,
        life_distance=scenario.operation.life_distance_km * 1e3,
        wear_band_width=None if wear.band_width_mm is None else wear.band_width_mm * 1e-3,
    )


def initial_state(scenario: Scenario):
    """``u0`` on the solver grid (m), seeded by ``initial.seed``."""
    init, n = scenario.initial, scenario.solver.points
    if init.kind == "round":
        return np.zeros(n)
    if init.kind == "random":
        rng = np.random.default_rng(init.seed)
        return roundness.random_perturbation(n, init.rms_um * 1e-6, init.lowest_order,
                                             init.highest_order, rng)
    if init.kind == "harmonics":
        phases = None if init.phases_deg is None else np.deg2rad(init.phases_deg)
        return roundness.harmonics(n, init.orders, np.array(init.amplitudes_um) * 1e-6, phases)
    angle, deviation = read_measured(init.file)
    return roundness.resample_measured(angle, deviation, n)
