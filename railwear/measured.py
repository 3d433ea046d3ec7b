"""Reading a measured wheel: a CSV of angle and radius deviation round the circumference (layer 4).

The header names the columns with their units (``angle_deg`` or ``angle_rad``; ``deviation_um``,
``deviation_mm`` or ``deviation_m``), or names them plainly (``angle``, ``deviation``) with the
units given by the caller. Lines starting with ``#`` are comments. The file is UTF-8 (a byte-order
mark is fine), comma-separated, with numbers in the grammar of :data:`NUMBER` (``-1.5``, ``.5``,
``2e-3``; not ``1_0``, ``inf``, ``0x10`` or a decimal comma). Real files are messy, so each of
these is an error that names the file, line and column, never a quietly wrong wheel: a missing
value, text in a number column, a row with more cells than the header (a decimal comma?), a
repeated or decreasing angle, degrees in a radians column or the reverse, an angle outside one
turn, a deviation beyond :data:`LARGEST_DEVIATION`, and a record that does not go round the wheel.
"""

import csv
import io
import re
from pathlib import Path

import numpy as np

from railwear.errors import MeasuredFileError
from railwear.scenario import decode_text
from railwear.units import MM

ANGLE_UNITS = {"deg": np.pi / 180, "rad": 1.0}
DEVIATION_UNITS = {"um": 1e-6, "mm": 1e-3, "m": 1.0}
FULL_TURN = {"deg": 360.0, "rad": 2 * np.pi}
GAP_FACTOR = 3.0  # a gap this many times the median spacing means the record is not closed
BLANK = " \t"  # the only blanks allowed round a number
NUMBER = re.compile(r"[+-]?(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][+-]?\d+)?", re.ASCII)
LARGEST_DEVIATION = 50 * MM  # more than a wheel's whole wear allowance: not a measured wheel
MAX_ROWS = 10**6

def _column(header, kind, units, given_unit, field, line=1):
    """``(index, unit)`` of the ``kind`` column named in the header on ``line``."""
    named = [(i, h[len(kind) + 1 :]) for i, h in enumerate(header) if h.startswith(kind + "_") and h[len(kind) + 1 :] in units]
    plain = [i for i, h in enumerate(header) if h == kind]
    if named:
        return named[0]
    if plain:
        if given_unit is None:
            raise MeasuredFileError(f"{field} line {line}: names '{kind}' without a unit; give the unit "
                                    f"({', '.join(units)}) or name the column {kind}_UNIT")
        if given_unit not in units:
            raise MeasuredFileError(f"{field}: unknown {kind} unit {given_unit!r}; use one of {', '.join(units)}")
        return plain[0], given_unit
    raise MeasuredFileError(
        f"{field} line {line}: must be a header naming an {kind} column "
        f"({', '.join(kind + '_' + u for u in units)}), got {','.join(header)!r}")


def _rows(path, where):
    """``(line, cells)`` of the data lines (not blank, not comments) of a UTF-8 CSV file."""
    try:
        data = path.read_bytes()
    except OSError as e:
        raise MeasuredFileError(f"{where}: cannot be read ({e.strerror})") from None
    text = decode_text(data, where, MeasuredFileError)
    reader = csv.reader(io.StringIO(text, newline=""))
    rows = []
    try:
        for row in reader:
            if row and any(c.strip(BLANK) for c in row) and not row[0].lstrip().startswith("#"):
                rows.append((reader.line_num, row))
                if len(rows) > MAX_ROWS + 1:
                    raise MeasuredFileError(f"{where}: more than {MAX_ROWS} rows")
    except csv.Error as e:
        raise MeasuredFileError(f"{where} line {reader.line_num + 1}: not CSV ({e})") from None
    return rows


def _number(text, where, no, column, name):
    """A cell as a float by the grammar of :data:`NUMBER`, or an error naming line and column."""
    text = text.strip(BLANK)
    at = f"{where} line {no}, column {column} ({name})"
    if text == "" or text.lower() in ("nan", "na", "null"):
        raise MeasuredFileError(f"{at}: missing value")
    if not NUMBER.fullmatch(text):
        raise MeasuredFileError(f"{at}: {text!r} is not a number (digits, '.', an exponent)")
    value = float(text)
    if not np.isfinite(value):
        raise MeasuredFileError(f"{at}: {text!r} is out of range")
    return value


def read_measured(path, angle_unit=None, deviation_unit=None, field="initial.file"):
    """Angles (rad, increasing on one turn) and deviations (m) of a measured wheel."""
    path = Path(path)
    field = str(path) if field is None else field
    where = str(path) if field == str(path) else f"{field}: {path.name}"
    if not path.is_file():
        raise MeasuredFileError(f"{field}: {path} does not exist")
    lines = _rows(path, where)
    if not lines:
        raise MeasuredFileError(f"{where} is empty")
    header_no, header = lines[0]
    header = [h.strip().lower() for h in header]
    ia, a_unit = _column(header, "angle", ANGLE_UNITS, angle_unit, where, header_no)
    idev, d_unit = _column(header, "deviation", DEVIATION_UNITS, deviation_unit, where, header_no)
    values = []
    for no, row in lines[1:]:
        if len(row) > len(header):
            raise MeasuredFileError(f"{where} line {no}: {len(row)} cells where the header has {len(header)} "
                                    "(a decimal comma? use '.')")
        cells = [_number(row[i] if i < len(row) else "", where, no, i + 1, header[i]) for i in (ia, idev)]
        values.append((no, cells[0], cells[1]))
    if len(values) < 8:
        raise MeasuredFileError(f"{where} has {len(values)} rows; a wheel needs at least 8")
    numbers = np.array([v[0] for v in values])
    angle = np.array([v[1] for v in values])
    deviation = np.array([v[2] for v in values])
    turn = FULL_TURN[a_unit]
    for k in range(1, angle.size):
        if angle[k] == angle[k - 1]:
            raise MeasuredFileError(f"{where} line {numbers[k]}, column {ia + 1}: angle {angle[k]:g} repeats line {numbers[k - 1]}")
        if angle[k] < angle[k - 1]:
            raise MeasuredFileError(f"{where} line {numbers[k]}, column {ia + 1}: angles must increase "
                                    f"({angle[k]:g} after {angle[k - 1]:g})")
    if a_unit == "rad" and angle.max() > turn * (1 + 1e-9):
        k = int(np.argmax(angle > turn))
        raise MeasuredFileError(f"{where} line {numbers[k]}, column {ia + 1}: angle {angle[k]:g} exceeds 2π: "
                                "degrees in a radians column?")
    if a_unit == "deg" and angle.max() <= 2 * np.pi + 1e-9:
        raise MeasuredFileError(f"{where}, column {ia + 1}: every angle is within [0, 2π] although the column "
                                f"is in degrees: radians in a degrees column?")
    closing = angle[0] == 0 and np.isclose(angle[-1], turn, rtol=1e-9)  # the record repeats its first point
    outside = (angle < 0) | (angle >= turn * (1 - 1e-12))
    outside[-1] &= not closing
    if outside.any():
        k = int(np.argmax(outside))
        raise MeasuredFileError(f"{where} line {numbers[k]}, column {ia + 1}: angle {angle[k]:g} is outside one "
                                f"turn [0, {turn:g})")
    big = np.abs(deviation) * DEVIATION_UNITS[d_unit] > LARGEST_DEVIATION
    if big.any():
        k = int(np.argmax(big))
        raise MeasuredFileError(f"{where} line {numbers[k]}, column {idev + 1}: deviation {deviation[k]:g} {d_unit} "
                                f"is more than {LARGEST_DEVIATION / MM:g} mm: not a radius deviation")
    if closing:
        angle, deviation, numbers = angle[:-1], deviation[:-1], numbers[:-1]
    gaps = np.diff(np.append(angle, angle[0] + turn))
    k = int(np.argmax(gaps))
    if gaps[k] > GAP_FACTOR * np.median(gaps):
        after = numbers[(k + 1) % numbers.size]
        raise MeasuredFileError(
            f"{where}: the record does not go round the wheel: a gap of {gaps[k]:g} "
            f"{a_unit} between line {numbers[k]} and line {after} (median spacing {np.median(gaps):g})")
    return angle * ANGLE_UNITS[a_unit], deviation * DEVIATION_UNITS[d_unit]
