"""Reading a measured wheel: a CSV of angle and radius deviation round the circumference (layer 4).

The header names the columns with their units (``angle_deg`` or ``angle_rad``; ``deviation_um``,
``deviation_mm`` or ``deviation_m``), or names them plainly (``angle``, ``deviation``) with the
units given by the caller. Lines starting with ``#`` are comments. Real files are messy, so each
of these is an error that names the line, never a quietly wrong wheel: a missing value, text in a
number column, a repeated or decreasing angle, degrees in a radians column or the reverse, an
angle outside one turn, and a record that does not go round the whole wheel.
"""

import csv
from pathlib import Path

import numpy as np

from railwear.errors import ScenarioError

ANGLE_UNITS = {"deg": np.pi / 180, "rad": 1.0}
DEVIATION_UNITS = {"um": 1e-6, "mm": 1e-3, "m": 1.0}
FULL_TURN = {"deg": 360.0, "rad": 2 * np.pi}
GAP_FACTOR = 3.0  # a gap this many times the median spacing means the record is not closed


def _column(header, kind, units, given_unit, field):
    named = [(i, h[len(kind) + 1 :]) for i, h in enumerate(header) if h.startswith(kind + "_") and h[len(kind) + 1 :] in units]
    plain = [i for i, h in enumerate(header) if h == kind]
    if named:
        return named[0]
    if plain:
        if given_unit is None:
            raise ScenarioError(f"{field}: line 1 names '{kind}' without a unit; give the unit "
                                f"({', '.join(units)}) or name the column {kind}_UNIT")
        if given_unit not in units:
            raise ScenarioError(f"{field}: unknown {kind} unit {given_unit!r}; use one of {', '.join(units)}")
        return plain[0], given_unit
    raise ScenarioError(
        f"{field}: line 1 must be a header naming an {kind} column "
        f"({', '.join(kind + '_' + u for u in units)}), got {','.join(header)!r}")


def read_measured(path, angle_unit=None, deviation_unit=None, field="initial.file"):
    """Angles (rad, increasing on one turn) and deviations (m) of a measured wheel."""
    path = Path(path)
    if not path.is_file():
        raise ScenarioError(f"{field}: {path} does not exist")
    with path.open(newline="") as f:
        lines = [(no, row) for no, row in enumerate(csv.reader(f), start=1)
                 if row and any(c.strip() for c in row) and not row[0].lstrip().startswith("#")]
    if not lines:
        raise ScenarioError(f"{field}: {path.name} is empty")
    header_no, header = lines[0]
    header = [h.strip().lower() for h in header]
    ia, a_unit = _column(header, "angle", ANGLE_UNITS, angle_unit, field)
    idev, d_unit = _column(header, "deviation", DEVIATION_UNITS, deviation_unit, field)
    values = []
    for no, row in lines[1:]:
        cells = []
        for i, name in ((ia, header[ia]), (idev, header[idev])):
            text = row[i].strip() if i < len(row) else ""
            if text == "" or text.lower() in ("nan", "na", "null"):
                raise ScenarioError(f"{field}: {path.name} line {no}: missing value in column {name}")
            try:
                cells.append(float(text))
            except ValueError:
                raise ScenarioError(f"{field}: {path.name} line {no}: {text!r} in column {name} is not a number") from None
        if not np.all(np.isfinite(cells)):
            raise ScenarioError(f"{field}: {path.name} line {no}: non-finite value")
        values.append((no, cells[0], cells[1]))
    if len(values) < 8:
        raise ScenarioError(f"{field}: {path.name} has {len(values)} rows; a wheel needs at least 8")
    numbers = np.array([v[0] for v in values])
    angle = np.array([v[1] for v in values])
    deviation = np.array([v[2] for v in values])
    turn = FULL_TURN[a_unit]
    for k in range(1, angle.size):
        if angle[k] == angle[k - 1]:
            raise ScenarioError(f"{field}: {path.name} line {numbers[k]}: angle {angle[k]:g} repeats line {numbers[k - 1]}")
        if angle[k] < angle[k - 1]:
            raise ScenarioError(f"{field}: {path.name} line {numbers[k]}: angles must increase "
                                f"({angle[k]:g} after {angle[k - 1]:g})")
    if a_unit == "rad" and angle.max() > turn * (1 + 1e-9):
        k = int(np.argmax(angle > turn))
        raise ScenarioError(f"{field}: {path.name} line {numbers[k]}: angle {angle[k]:g} exceeds 2π: "
                            "degrees in a radians column?")
    if a_unit == "deg" and angle.max() <= 2 * np.pi + 1e-9:
        raise ScenarioError(f"{field}: {path.name}: every angle is within [0, 2π] although the column "
                            f"is in degrees: radians in a degrees column?")
    if angle[0] < 0 or angle[-1] > angle[0] + turn * (1 + 1e-12):
        k = 0 if angle[0] < 0 else angle.size - 1
        raise ScenarioError(f"{field}: {path.name} line {numbers[k]}: angle {angle[k]:g} is outside one "
                            f"turn [0, {turn:g})")
    if np.isclose(angle[-1] - angle[0], turn, rtol=1e-9):  # the record repeats its first point
        angle, deviation, numbers = angle[:-1], deviation[:-1], numbers[:-1]
    gaps = np.diff(np.append(angle, angle[0] + turn))
    k = int(np.argmax(gaps))
    if gaps[k] > GAP_FACTOR * np.median(gaps):
        after = numbers[(k + 1) % numbers.size]
        raise ScenarioError(
            f"{field}: {path.name}: the record does not go round the wheel: a gap of {gaps[k]:g} "
            f"{a_unit} between line {numbers[k]} and line {after} (median spacing {np.median(gaps):g})")
    return angle * ANGLE_UNITS[a_unit], deviation * DEVIATION_UNITS[d_unit]
