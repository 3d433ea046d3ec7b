"""Reading a fleet of measured wheels: a manifest CSV of one row per measured line, each pointing at
a file of the line's radius deviation round the wheel (layer 4; docs/maintenance.md, "Fleets").

The manifest (``fleet.csv``) names its columns in its header, in any order; units are in the names:

=================  =====================================================================  ========
column             what                                                                   required
=================  =====================================================================  ========
``wheel_id``       the wheel's name, unique in the fleet (text)                           yes
``car``            the car it is under (text: a number or a name)                          yes
``axle``           the axle's position in the car, 1 the leading one (a whole number)      yes
``side``           ``L`` or ``R`` (``left``, ``right``)                                    yes
``diameter_mm``    the wheel's measured running-circle diameter (mm)                       yes
``mileage_km``     the wheel's odometer at the measurement (km)                            yes
``date``           the day of the measurement, ISO 8601 (``2024-05-14``)                   yes
``file``           the measured line: a CSV read by :func:`railwear.measured.read_measured` yes
                   (``angle_deg``/``angle_rad`` with ``deviation_um``/``_mm``/``_m``, or
                   absolute ``radius_*``/``diameter_*`` read against ``diameter_mm``); its
                   path relative to the manifest's folder
``last_turning_km`` the odometer at the wheel's last turning (or when it was new, km): the  with an
                   distance since then is what an interval trigger counts                  interval
``lateral_mm``     where on the tread the line was measured (mm, as the device gives it):  several
                   a wheel with several lines has one row per line, same metadata          lines
=================  =====================================================================  ========

The file is UTF-8 and split at the separator of its header line, as the measured-wheel files are
(``;`` with decimal commas, a tab, or ``,``); ``#`` starts a comment line. Each bad row and each
bad measured file is refused with its file and line named, and the rest of the fleet is read:
:func:`read_fleet` returns the lines it read and the refusals, one line of text each. A manifest
that cannot be read at all (no such file, no header, a required column missing) raises
:class:`~railwear.errors.MeasuredFileError`.
"""

import datetime
from dataclasses import dataclass
from importlib import resources
from pathlib import Path

import numpy as np

from railwear.errors import MeasuredFileError
from railwear.measured import BLANK, _number, _rows, read_measured
from railwear.units import KM, MM

REQUIRED = ("wheel_id", "car", "axle", "side", "diameter_mm", "mileage_km", "date", "file")
OPTIONAL = ("last_turning_km", "lateral_mm")
SIDES = {"l": "L", "left": "L", "r": "R", "right": "R"}
DIAMETER_RANGE_MM = (100.0, 4000.0)  # the wheels railwear models
MILEAGE_RANGE_KM = (0.0, 1e8)
LATERAL_RANGE_MM = (-500.0, 500.0)
MAX_AXLE = 64
MAX_NAME = 64  # characters of a wheel id or a car
MAX_LINES = 100_000  # rows of a manifest
EXAMPLE = "example-fleet"  # the built-in example: railwear/maintenance/data/example-fleet/fleet.csv


@dataclass(frozen=True)
class Line:
    """One measured line of a wheel: the manifest's metadata (SI: ``diameter`` m, ``mileage`` and
    ``since`` m, ``lateral`` m or NaN; ``since`` the distance since the last turning, NaN when
    not given), ``angle`` (rad) and ``deviation`` (m) as read, and where it came from
    (``file`` as the manifest writes it, ``row`` the manifest's line)."""

    wheel_id: str
    car: str
    axle: int
    side: str
    diameter: float
    mileage: float
    date: datetime.date
    since: float
    lateral: float
    file: str
    row: int
    angle: np.ndarray
    deviation: np.ndarray


def example_path():
    """The manifest of the built-in example fleet (synthetic wheels, see docs/maintenance.md)."""
    return Path(str(resources.files("railwear.maintenance") / "data" / EXAMPLE / "fleet.csv"))


def fleet_path(path_or_name):
    """The manifest a name stands for: a file of that name, else the built-in ``example-fleet``;
    a missing file or a folder is refused naming it."""
    name = str(path_or_name)
    path = Path(name)
    if path.is_file():
        return path
    if name == EXAMPLE:
        return example_path()
    if path.is_dir():
        raise MeasuredFileError(f"fleet {name} is a folder, not a manifest CSV (its fleet.csv?)")
    raise MeasuredFileError(f"fleet file {name} does not exist (or give the built-in {EXAMPLE})")


def _text(cell, at, name):
    text = cell.strip(BLANK)
    if not text:
        raise MeasuredFileError(f"{at}, column {name}: missing value")
    if len(text) > MAX_NAME:
        raise MeasuredFileError(f"{at}, column {name}: more than {MAX_NAME} characters")
    return text


def _in(value, low, high, at, name, unit):
    if not low <= value <= high:
        raise MeasuredFileError(f"{at}, column {name}: {value:g} {unit} is outside [{low:g}, {high:g}] {unit}")
    return value


def _row(cells, header, sep, where, no, interval):
    """The metadata of one manifest row (SI), or a :class:`MeasuredFileError` naming line and column."""
    at = f"{where} line {no}"
    if len(cells) > len(header):
        raise MeasuredFileError(f"{at}: {len(cells)} cells where the header has {len(header)}"
                                + (" (a decimal comma? use '.')" if sep == "," else ""))
    cell = {h: (cells[i] if i < len(cells) else "") for i, h in enumerate(header)}

    def number(name):
        text = cell[name]
        return _number(text, where, no, header.index(name) + 1, name, decimal_comma=sep != "," and "," in text)

    wheel, car, file = (_text(cell[n], at, n) for n in ("wheel_id", "car", "file"))
    axle_text = cell["axle"].strip(BLANK)
    if not (axle_text.isascii() and axle_text.isdigit() and 1 <= int(axle_text) <= MAX_AXLE):
        raise MeasuredFileError(f"{at}, column axle: {axle_text!r} is not a whole number in [1, {MAX_AXLE}]")
    side = SIDES.get(cell["side"].strip(BLANK).lower())
    if side is None:
        raise MeasuredFileError(f"{at}, column side: {cell['side'].strip(BLANK)!r} is not L or R")
    diameter = _in(number("diameter_mm"), *DIAMETER_RANGE_MM, at, "diameter_mm", "mm")
    mileage = _in(number("mileage_km"), *MILEAGE_RANGE_KM, at, "mileage_km", "km")
    try:
        date = datetime.date.fromisoformat(cell["date"].strip(BLANK))
    except ValueError:
        raise MeasuredFileError(f"{at}, column date: {cell['date'].strip(BLANK)!r} is not a date YYYY-MM-DD") from None
    since = np.nan
    if "last_turning_km" in cell and (cell["last_turning_km"].strip(BLANK) or interval):
        turned = _in(number("last_turning_km"), 0.0, mileage, at, "last_turning_km", "km")
        since = (mileage - turned) * KM
    lateral = np.nan
    if "lateral_mm" in cell and cell["lateral_mm"].strip(BLANK):
        lateral = _in(number("lateral_mm"), *LATERAL_RANGE_MM, at, "lateral_mm", "mm") * MM
    return dict(wheel_id=wheel, car=car, axle=int(axle_text), side=side, diameter=diameter * MM, mileage=mileage * KM,
                date=date, since=since, lateral=lateral, file=file, row=no)


SAME = ("car", "axle", "side", "diameter", "mileage", "date", "since")  # what the lines of one wheel share
COLUMN = {"diameter": "diameter_mm", "mileage": "mileage_km", "since": "last_turning_km"}


def _conflict(meta, first, where):
    """Why a row cannot be a further line of the wheel of ``first`` (its earlier row), or None."""
    for key in SAME:
        a, b = meta[key], first[key]
        if not (a == b or (isinstance(a, float) and np.isnan(a) and np.isnan(b))):
            return (f"{where} line {meta['row']}, column {COLUMN.get(key, key)}: wheel {meta['wheel_id']} has "
                    f"another {COLUMN.get(key, key)} on line {first['row']}")
    if np.isnan(meta["lateral"]) or np.isnan(first["lateral"]):
        return (f"{where} line {meta['row']}: wheel {meta['wheel_id']} is also on line {first['row']}; a wheel "
                "with several measured lines needs lateral_mm on each")
    return None


def read_manifest(path, interval=False):
    """``(rows, failed)``: the manifest's rows as dicts of SI metadata (with ``row``, the line,
    and ``file`` as written), and a line of text for each row refused. ``interval``: the
    policy counts an interval since the last turning, so ``last_turning_km`` is required."""
    path = Path(path)
    where = path.name
    lines, sep = _rows(path, where)
    if not lines:
        raise MeasuredFileError(f"{where} is empty: it needs a header ({','.join(REQUIRED)}) and a row per wheel")
    header_no, header = lines[0]
    header = [h.strip(BLANK).lower() for h in header]
    missing = [c for c in REQUIRED if c not in header]
    if missing:
        raise MeasuredFileError(f"{where} line {header_no}: the header has no column {', '.join(missing)} "
                                f"(it needs {','.join(REQUIRED)}; optional {','.join(OPTIONAL)})")
    if interval and "last_turning_km" not in header:
        raise MeasuredFileError(f"{where} line {header_no}: the policy turns at an interval since the last turning: "
                                "the header needs a last_turning_km column (the odometer at the last turning, km)")
    twice = sorted({h for h in header if header.count(h) > 1 and h})
    if twice:
        raise MeasuredFileError(f"{where} line {header_no}: column {twice[0]} is named twice")
    if len(lines) > MAX_LINES + 1:
        raise MeasuredFileError(f"{where}: more than {MAX_LINES} rows")
    rows, failed, wheels, places = [], [], {}, {}
    for no, cells in lines[1:]:
        try:
            meta = _row(cells, header, sep, where, no, interval)
        except MeasuredFileError as e:
            failed.append(str(e))
            continue
        first = wheels.get(meta["wheel_id"])
        place = (meta["car"], meta["axle"], meta["side"])
        if first is not None:
            why = _conflict(meta, first[0], where)
            if why is None and any(meta["lateral"] == m["lateral"] for m in first):
                why = (f"{where} line {no}, column lateral_mm: wheel {meta['wheel_id']}'s line at "
                       f"{meta['lateral'] / MM:g} mm is also on line {next(m['row'] for m in first if m['lateral'] == meta['lateral'])}")
            if why is not None:
                failed.append(why)
                continue
            first.append(meta)
        elif place in places:
            failed.append(f"{where} line {no}: car {place[0]} axle {place[1]} side {place[2]} is wheel {places[place][0]} "
                          f"on line {places[place][1]}")
            continue
        else:
            wheels[meta["wheel_id"]] = [meta]
            places[place] = (meta["wheel_id"], no)
        rows.append(meta)
    return rows, failed


def read_fleet(path_or_name, interval=False):
    """``(lines, failed, manifest)``: every measured :class:`Line` that could be read, the
    refusals (one line of text each, naming the file and line), and the manifest's path.
    ``interval``: the policy counts an interval since the last turning (``last_turning_km``
    required)."""
    manifest = fleet_path(path_or_name)
    rows, failed = read_manifest(manifest, interval)
    lines = []
    for meta in rows:
        path = manifest.parent / meta["file"]
        context = f"(wheel {meta['wheel_id']}, {manifest.name} line {meta['row']})"
        if not path.is_file():
            failed.append(f"{meta['file']}: no such file {context}")
            continue
        try:
            angle, deviation = read_measured(path, field=str(path), nominal_diameter=meta["diameter"])
        except MeasuredFileError as e:
            message = str(e)
            failed.append((meta["file"] + message[len(str(path)):] if message.startswith(str(path)) else message)
                          + f" {context}")
            continue
        lines.append(Line(**meta, angle=angle, deviation=deviation))
    return lines, failed, manifest


def write_synthetic(directory, wheels, rng, diameter_range_mm=(780.0, 840.0), orders=(6, 10), amplitude_um=(5.0, 30.0),
                    points=180, roughness_um=1.0, axles=4, date="2024-05-14"):
    """Write a synthetic fleet (not measured wheels): ``fleet.csv`` and ``wheels/ID.csv`` for
    ``wheels`` wheels, ``axles`` axles a car and two sides, each wheel one polygon order drawn from
    ``orders`` (inclusive) with an amplitude (µm) from ``amplitude_um`` and a random phase, plus
    ``roughness_um`` rms of orders 1-40, on ``points`` equal angles (deg, µm); diameters from
    ``diameter_range_mm``, mileage and the last turning drawn too. Returns the manifest's path and
    the wheels' ``(order, amplitude m, phase rad, diameter m)``; ``rng`` a numpy Generator."""
    from railwear import results

    directory = Path(directory)
    x = np.arange(points) * 2 * np.pi / points
    head = "wheel_id,car,axle,side,diameter_mm,mileage_km,date,last_turning_km,file"
    rows, truth = [head], []
    per_car = 2 * axles
    for w in range(wheels):
        car, rest = divmod(w, per_car)
        axle, side = rest // 2 + 1, "LR"[rest % 2]
        n = int(rng.integers(orders[0], orders[1] + 1))
        a = rng.uniform(*amplitude_um)
        phase = rng.uniform(0, 2 * np.pi)
        d = rng.uniform(*diameter_range_mm)
        u = a * np.cos(n * x + phase)
        if roughness_um:  # equal amplitudes on orders 1-40, random phases: rms roughness_um
            k = np.arange(1, 41)
            u = u + roughness_um * np.sqrt(2 / k.size) * np.sum(
                np.cos(k[:, None] * x + rng.uniform(0, 2 * np.pi, k.size)[:, None]), axis=0)
        mileage = float(np.round(rng.uniform(20_000, 400_000)))
        turned = max(float(np.round(mileage - rng.uniform(5_000, 180_000))), 0.0)
        name = f"W{w + 1:04d}"
        rows.append(f"{name},{car + 1},{axle},{side},{d:.2f},{mileage:.0f},{date},{turned:.0f},wheels/{name}.csv")
        text = "angle_deg,deviation_um\n" + "".join(f"{np.degrees(xi):.4f},{ui:.6f}\n" for xi, ui in zip(x, u))
        results.write_text(text, directory / "wheels" / f"{name}.csv")
        truth.append((n, a * 1e-6, phase, d * MM))
    return results.write_text("\n".join(rows) + "\n", directory / "fleet.csv"), truth
