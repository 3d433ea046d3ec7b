"""From a validated scenario to the physics objects: the wear-rate form, the speeds, ``u0``."""

import csv
from pathlib import Path

import numpy as np

from railwear.errors import ScenarioError
from railwear.geometry import roundness
from railwear.pde import Cubic, DiskContact, Table
from railwear.scenario.schema import Scenario

_ANGLE_UNITS = {"angle_deg": np.pi / 180, "angle_rad": 1.0}
_DEVIATION_UNITS = {"deviation_um": 1e-6, "deviation_mm": 1e-3, "deviation_m": 1.0}


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


def read_measured(path):
    """Angles (rad) and deviations (m) from a CSV with a header naming angle and deviation columns.

    Angle columns: ``angle_deg`` in [0, 360) or ``angle_rad`` in [0, 2π); deviation columns:
    ``deviation_um``, ``deviation_mm`` or ``deviation_m``.
    """
    path = Path(path)
    if not path.is_file():
        raise ScenarioError(f"initial.file: {path.name} does not exist")
    with path.open(newline="") as f:
        rows = list(csv.reader(line for line in f if line.strip() and not line.startswith("#")))
    if not rows:
        raise ScenarioError(f"initial.file: {path.name} is empty")
    header = [h.strip() for h in rows[0]]
    angle_col = next((h for h in header if h in _ANGLE_UNITS), None)
    dev_col = next((h for h in header if h in _DEVIATION_UNITS), None)
    if angle_col is None:
        raise ScenarioError(f"initial.file: {path.name} has no angle_deg or angle_rad column")
    if dev_col is None:
        raise ScenarioError(
            f"initial.file: {path.name} has no deviation_um, deviation_mm or deviation_m column")
    ia, idev = header.index(angle_col), header.index(dev_col)
    values = []
    for line_no, row in enumerate(rows[1:], start=2):
        try:
            values.append((float(row[ia]), float(row[idev])))
        except (ValueError, IndexError):
            raise ScenarioError(f"initial.file: {path.name} line {line_no} is not two numbers") from None
    data = np.array(values)
    if data.size == 0 or not np.all(np.isfinite(data)):
        raise ScenarioError(f"initial.file: {path.name} has no rows or non-finite values")
    full_turn = 360.0 if angle_col == "angle_deg" else 2 * np.pi
    bad = np.flatnonzero((data[:, 0] < 0) | (data[:, 0] >= full_turn))
    if bad.size:
        raise ScenarioError(
            f"initial.file: {path.name} line {bad[0] + 2}: {angle_col} = {data[bad[0], 0]:g} "
            f"is outside [0, {full_turn:g})")
    if np.unique(data[:, 0]).size != data.shape[0]:
        raise ScenarioError(f"initial.file: {path.name} repeats an angle")
    return data[:, 0] * _ANGLE_UNITS[angle_col], data[:, 1] * _DEVIATION_UNITS[dev_col]


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
