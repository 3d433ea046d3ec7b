"""Reading a measured wheel: a CSV of angle and radius deviation round the circumference (layer 4).

The header names the columns with their units (``angle_deg`` or ``angle_rad``; ``deviation_um``,
``deviation_mm`` or ``deviation_m``), or names them plainly (``angle``, ``deviation``) with the
units given by the caller. In place of a deviation a measuring device may give the absolute
radius or diameter (``radius_mm``, ``diameter_mm``, also in ``um`` or ``m``) with the nominal
wheel diameter given by the caller: the deviation is ``r - D_nom/2`` or ``(d - D_nom)/2``.
Lines starting with ``#`` are comments. The file is UTF-8 (a byte-order mark is fine); its
separator is the one its header line uses: ``;`` (then a decimal comma is read, as such devices
write it), a tab, or ``,``. Numbers follow the grammar of :data:`NUMBER` (``-1.5``, ``.5``,
``2e-3``; not ``1_0``, ``inf``, ``0x10``; a decimal comma only where ``,`` does not separate).
Real files are messy, so each of these is an error that names the file, line and column, never
a quietly wrong wheel: a missing value, text in a number column, a row with more cells than the
header (a decimal comma?), both ``.`` and ``,`` as decimal marks in one file, a repeated or
decreasing angle, degrees in a radians column or the reverse, an angle outside one turn, a
deviation beyond :data:`LARGEST_DEVIATION`, and a record that does not go round the wheel.
"""

import csv
import io
import re
from pathlib import Path

import numpy as np

from railwear.errors import MeasuredFileError
from railwear.textfiles import decode_text
from railwear.units import MM

ANGLE_UNITS = {"deg": np.pi / 180, "rad": 1.0}
DEVIATION_UNITS = {"um": 1e-6, "mm": 1e-3, "m": 1.0}
FULL_TURN = {"deg": 360.0, "rad": 2 * np.pi}
GAP_FACTOR = 3.0  # a gap this many times the median spacing means the record is not closed
BLANK = " \t"  # the only blanks allowed round a number
NUMBER = re.compile(r"[+-]?(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][+-]?\d+)?", re.ASCII)
LARGEST_DEVIATION = 50 * MM  # more than a wheel's whole wear allowance: not a measured wheel
MAX_ROWS = 10**6

SEPARATORS = (";", "\t")  # the header line's first of these separates, else ','
ABSOLUTE = ("radius", "diameter")  # absolute columns, read against the nominal diameter
NOMINAL_DIAMETER = (0.1, 4.0)  # m: the wheels railwear models (Wheel.radius_m 0.05 to 2 m)


def _named(header, kind, units):
    """``(index, unit)`` of the first column named ``KIND_UNIT``, or None."""
    named = [(i, h[len(kind) + 1 :]) for i, h in enumerate(header) if h.startswith(kind + "_") and h[len(kind) + 1 :] in units]
    return named[0] if named else None


def _column(header, kind, units, given_unit, field, line=1, also=""):
    """``(index, unit)`` of the ``kind`` column named in the header on ``line``."""
    plain = [i for i, h in enumerate(header) if h == kind]
    named = _named(header, kind, units)
    if named:
        return named
    if plain:
        if given_unit is None:
            raise MeasuredFileError(f"{field} line {line}: names '{kind}' without a unit; give the unit "
                                    f"({', '.join(units)}) or name the column {kind}_UNIT")
        if given_unit not in units:
            raise MeasuredFileError(f"{field}: unknown {kind} unit {given_unit!r}; use one of {', '.join(units)}")
        return plain[0], given_unit
    raise MeasuredFileError(
        f"{field} line {line}: must be a header naming an {kind} column "
        f"({', '.join(kind + '_' + u for u in units)}{also}), got {','.join(header)!r}")


def separator(text):
    """The separator of a CSV text: ``;`` or a tab if its header line (the first line neither
    blank nor a comment) holds one, else ``,``."""
    for line in text.splitlines():
        if line.strip(BLANK) and not line.lstrip().startswith("#"):
            return next((s for s in SEPARATORS if s in line), ",")
    return ","


def _rows(path, where):
    """``(rows, separator)``: the data lines (not blank, not comments) of a UTF-8 CSV file as
    ``(line, cells)``, split at the :func:`separator` of its header line."""
    try:
        data = path.read_bytes()
    except OSError as e:
        raise MeasuredFileError(f"{where}: cannot be read ({e.strerror})") from None
    text = decode_text(data, where, MeasuredFileError)
    sep = separator(text)
    reader = csv.reader(io.StringIO(text, newline=""), delimiter=sep)
    rows = []
    try:
        for row in reader:
            if row and any(c.strip(BLANK) for c in row) and not row[0].lstrip().startswith("#"):
                rows.append((reader.line_num, row))
                if len(rows) > MAX_ROWS + 1:
                    raise MeasuredFileError(f"{where}: more than {MAX_ROWS} rows")
    except csv.Error as e:
        raise MeasuredFileError(f"{where} line {reader.line_num + 1}: not CSV ({e})") from None
    return rows, sep


def _number(text, where, no, column, name, decimal_comma=False):
    """A cell as a float by the grammar of :data:`NUMBER` (with ``,`` for ``.`` given
    ``decimal_comma``), or an error naming line and column."""
    text = text.strip(BLANK)
    at = f"{where} line {no}, column {column} ({name})"
    if text == "" or text.lower() in ("nan", "na", "null"):
        raise MeasuredFileError(f"{at}: missing value")
    if decimal_comma:
        if "." in text:
            raise MeasuredFileError(f"{at}: {text!r} has a '.' where the file's numbers have a decimal comma "
                                    "(a thousands separator?)")
        text = text.replace(",", ".")
    if not NUMBER.fullmatch(text):
        raise MeasuredFileError(f"{at}: {text!r} is not a number (digits, '.', an exponent)")
    value = float(text)
    if not np.isfinite(value):
        raise MeasuredFileError(f"{at}: {text!r} is out of range")
    return value


def _nominal(nominal_diameter, kind, where, column):
    """The nominal diameter (m) an absolute ``kind`` column is read against, checked."""
    low, high = NOMINAL_DIAMETER
    if nominal_diameter is None:
        raise MeasuredFileError(f"{where}, column {column}: {kind} is absolute, not a deviation; give nominal_diameter, "
                                "the nominal wheel diameter it is measured against (forecast --nominal-diameter 840mm)")
    if not (np.isfinite(nominal_diameter) and low <= nominal_diameter <= high):
        raise MeasuredFileError(f"nominal_diameter: must be in [{low:g}, {high:g}] m, got {nominal_diameter!r}")
    return float(nominal_diameter)


def _cells(lines, header, columns, sep, where):
    """``(line, [numbers])`` of the ``columns`` of each data row after the header; a decimal
    comma is read where ``,`` does not separate and some cell of those columns has one."""
    decimal_comma = sep != "," and any("," in row[i] for _, row in lines[1:] for i in columns if i < len(row))
    for no, row in lines[1:]:
        if len(row) > len(header):
            raise MeasuredFileError(f"{where} line {no}: {len(row)} cells where the header has {len(header)}"
                                    + (" (a decimal comma? use '.')" if sep == "," else ""))
        yield no, [_number(row[i] if i < len(row) else "", where, no, i + 1, header[i], decimal_comma) for i in columns]


def read_table(path, field):
    """``(header, numbers)`` of a CSV table of numbers in the dialects :func:`read_measured`
    reads: the header's names (lower case) and an array of rows by columns."""
    path = Path(path)
    where = f"{field}: {path.name}"
    if not path.is_file():
        raise MeasuredFileError(f"{field}: {path} does not exist")
    lines, sep = _rows(path, where)
    if len(lines) < 2:
        raise MeasuredFileError(f"{where}: needs a header and at least one row")
    header = [h.strip().lower() for h in lines[0][1]]
    return header, np.array([cells for _, cells in _cells(lines, header, range(len(header)), sep, where)])


def read_measured(path, angle_unit=None, deviation_unit=None, field="initial.file", nominal_diameter=None):
    """Angles (rad, increasing on one turn) and deviations (m) of a measured wheel;
    ``nominal_diameter`` (m) for a file of absolute radius or diameter."""
    path = Path(path)
    field = str(path) if field is None else field
    where = str(path) if field == str(path) else f"{field}: {path.name}"
    if not path.is_file():
        raise MeasuredFileError(f"{field}: {path} does not exist")
    lines, sep = _rows(path, where)
    if not lines:
        raise MeasuredFileError(f"{where} is empty")
    header_no, header = lines[0]
    header = [h.strip().lower() for h in header]
    ia, a_unit = _column(header, "angle", ANGLE_UNITS, angle_unit, where, header_no)
    absolute = next((kind for kind in ABSOLUTE if _named(header, kind, DEVIATION_UNITS)), None)
    if absolute is None or "deviation" in header or _named(header, "deviation", DEVIATION_UNITS):
        absolute = None
        idev, d_unit = _column(header, "deviation", DEVIATION_UNITS, deviation_unit, where, header_no,
                               also=", or radius_UNIT or diameter_UNIT with the nominal diameter")
    else:
        idev, d_unit = _named(header, absolute, DEVIATION_UNITS)
        nominal = _nominal(nominal_diameter, header[idev], where, idev + 1)
    values = [(no, *cells) for no, cells in _cells(lines, header, (ia, idev), sep, where)]
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
    read = deviation
    deviation = deviation * DEVIATION_UNITS[d_unit]  # m
    if absolute is not None:  # the radius deviation from the nominal
        deviation = deviation - nominal / 2 if absolute == "radius" else (deviation - nominal) / 2
    big = np.abs(deviation) > LARGEST_DEVIATION
    if big.any():
        k = int(np.argmax(big))
        what = (f"deviation {read[k]:g} {d_unit}" if absolute is None else
                f"{absolute} {read[k]:g} {d_unit} (nominal diameter {nominal / MM:g} mm) gives a radius deviation of "
                f"{deviation[k] / MM:g} mm, which")
        raise MeasuredFileError(f"{where} line {numbers[k]}, column {idev + 1}: {what} is more than "
                                f"{LARGEST_DEVIATION / MM:g} mm: not a radius deviation"
                                + ("" if absolute is None else " (a diameter in a radius column, or the wrong nominal?)"))
    if closing:
        angle, deviation, numbers = angle[:-1], deviation[:-1], numbers[:-1]
    gaps = np.diff(np.append(angle, angle[0] + turn))
    k = int(np.argmax(gaps))
    if gaps[k] > GAP_FACTOR * np.median(gaps):
        after = numbers[(k + 1) % numbers.size]
        raise MeasuredFileError(
            f"{where}: the record does not go round the wheel: a gap of {gaps[k]:g} "
            f"{a_unit} between line {numbers[k]} and line {after} (median spacing {np.median(gaps):g})")
    return angle * ANGLE_UNITS[a_unit], deviation
