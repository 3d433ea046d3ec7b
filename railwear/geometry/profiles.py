"""Wheel and rail profiles: SIMPACK ``.prw``/``.prr`` reader, built-in S1002 and UIC60, analytic
conical and circular profiles, worn profiles.

Convention (SI units): a profile is ``z(y)`` with ``y`` the lateral coordinate, positive towards
the field side (away from the track centre; the flange of a wheel lies at negative ``y``), and
``z`` positive downwards. For a wheel ``z`` is the increase of the radius over the nominal
rolling radius (``r(y) = r0 + z(y)``; the flange tip has ``z`` of about +28 mm on S1002); for a
rail ``z`` is the depth below the reference point (the highest point of the head for UIC60).
These are the axes of the SIMPACK files after their own ``mirror.y`` / ``inversion`` flags.

The profile is interpolated by a C² cubic spline through the points, so slope and curvature are
continuous (the rail head radii 300, 80 and 13 mm of UIC60 are recovered to 0.1 %).
"""

from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path

import numpy as np

from railwear.errors import ScenarioError

__all__ = [
    "Profile",
    "worn_profile",
    "read_simpack_profile",
    "load_profile",
    "conical_profile",
    "circular_profile",
    "BUILTIN_PROFILES",
]

# built-in name -> (file in railwear/geometry/data, inclination already in the data)
BUILTIN_PROFILES = {
    "S1002": ("MBench_S1002_v3.prw", 0.0),
    "UIC60": ("MBench_UIC60_v3.prr", 1.0 / 40.0),
}


@dataclass(frozen=True, eq=False)
class Profile:
    """A wheel or rail profile ``z(y)`` [m] with a C² spline interpolant.

    kind: "wheel" or "rail"; cant: inclination [rad-ish, tan] already contained in the points
    (1/40 for the built-in UIC60, 0 otherwise); name: label for tables and plots.
    """

    y: np.ndarray
    z: np.ndarray
    kind: str
    name: str = ""
    cant: float = 0.0
    _spline: "CubicSpline" = field(init=False, repr=False, compare=False)  # noqa: F821  (scipy's, imported when made)

    def __post_init__(self):
        y = np.asarray(self.y, dtype=float)
        z = np.asarray(self.z, dtype=float)
        if y.ndim != 1 or y.shape != z.shape or y.size < 4:
            raise ScenarioError(f"profile {self.name!r}: needs matching y and z arrays of at least 4 points")
        if not (np.all(np.isfinite(y)) and np.all(np.isfinite(z))):
            raise ScenarioError(f"profile {self.name!r}: points must be finite")
        if self.kind not in ("wheel", "rail"):
            raise ScenarioError(f"profile kind must be 'wheel' or 'rail', got {self.kind!r}")
        order = np.argsort(y, kind="stable")
        y, z = y[order], z[order]
        keep = np.concatenate(([True], np.diff(y) > 0.0))  # drop repeated y (vertical steps)
        y, z = y[keep], z[keep]
        object.__setattr__(self, "y", y)
        object.__setattr__(self, "z", z)
        from scipy.interpolate import CubicSpline  # here: 0.2-0.5 s to import, and a run may need no profile

        spline = CubicSpline(y, z, bc_type="natural")
        swing = np.max(np.abs(spline(0.5 * (y[1:] + y[:-1])) - 0.5 * (z[1:] + z[:-1])))
        if not swing <= np.ptp(z):
            raise ScenarioError(f"profile {self.name!r}: its spline swings {swing:.3g} m between points; points "
                                f"nearly repeat in y (a near-vertical face?), drop them")
        object.__setattr__(self, "_spline", spline)

    @property
    def span(self):
        """(y_min, y_max) of the point table [m]."""
        return float(self.y[0]), float(self.y[-1])

    def __call__(self, y):
        """Interpolated z [m] at y [m] (inside the span)."""
        return self._spline(y)

    def slope(self, y):
        """dz/dy [-]."""
        return self._spline(y, 1)

    def curvature(self, y):
        """Signed curvature ``z'' / (1 + z'²)^(3/2)`` [1/m]; positive where the surface is convex
        seen from below (a rail head)."""
        s = self._spline(y, 1)
        return self._spline(y, 2) / (1.0 + s * s) ** 1.5

    def spline_coefficients(self):
        """(breakpoints, coefficients (4, n)) of the piecewise cubic, for compiled evaluation."""
        return self._spline.x, self._spline.c

    def canted(self, inclination):
        """This profile rotated so that it carries the total inclination ``inclination`` (e.g. 1/40),
        the rotation being about the origin, field side up for a rail (lower gauge side)."""
        delta = float(inclination) - self.cant
        if delta == 0.0:
            return self
        angle = np.arctan(delta)
        c, s = np.cos(angle), np.sin(angle)
        # positive inclination tilts the head towards the track centre: the gauge side (y < 0)
        # moves down (z grows), i.e. a rotation y' = c y + s z, z' = -s y + c z
        y = c * self.y + s * self.z
        z = -s * self.y + c * self.z
        keep = _visible(y)
        return Profile(y=y[keep], z=z[keep], kind=self.kind, name=self.name, cant=float(inclination))


def _visible(y, spacing=1e-9):
    """Points of a rotated profile (in the order of the unrotated one) that stay a function of
    ``y``: walking out from the point nearest ``y = 0`` to either side, a side ends where ``y``
    turns back (a near-vertical face rotated past the vertical: its lower part is hidden under
    the corner), and points nearer than ``spacing`` [m] to the last kept one are dropped (they
    make the interpolating spline swing by metres)."""
    keep = np.zeros(y.size, dtype=bool)
    start = int(np.argmin(np.abs(y)))
    keep[start] = True
    for step in (1, -1):
        last = y[start]
        for i in range(start + step, y.size if step > 0 else -1, step):
            if step * (y[i] - last) < 0.0:
                break
            if step * (y[i] - last) >= spacing:
                keep[i] = True
                last = y[i]
    return keep


def worn_profile(profile, deviation, y=None):
    """Profile plus a deviation: ``z_worn(y) = z(y) + u(y)`` [m].

    ``deviation`` is an array on the profile's points (or on ``y``), a callable ``u(y)``, or a
    2-D array ``u(x, y)`` with one row per angle round the wheel, which gives a tuple of profiles,
    one per angle. For a wheel ``u`` is the change of radius (railwear's wear surface: ``u < 0`` is
    material removed); for a rail ``u > 0`` lowers the surface.
    """
    ys = profile.y if y is None else np.asarray(y, dtype=float)
    zs = profile(ys)
    u = deviation(ys) if callable(deviation) else np.asarray(deviation, dtype=float)
    if u.ndim == 2 and u.shape[1] == ys.size:
        return tuple(
            Profile(y=ys, z=zs + row, kind=profile.kind, name=f"{profile.name} worn[{k}]", cant=profile.cant)
            for k, row in enumerate(u)
        )
    if u.shape != ys.shape:
        raise ScenarioError(f"deviation must have one value per profile point ({ys.size}), got shape {u.shape}")
    return Profile(y=ys, z=zs + u, kind=profile.kind, name=f"{profile.name} worn", cant=profile.cant)


def _split_comment(line):
    i = line.find("!")
    return (line if i < 0 else line[:i]).strip()


def read_simpack_profile(path, name=None):
    """Read a SIMPACK profile file (``.prw`` wheel, ``.prr`` rail) into a :class:`Profile`.

    Honours ``units.len.f`` (file units per metre), ``shift.y``/``shift.z``, ``rotate``
    (about x, file angle units), ``mirror.y``/``mirror.z`` and the ``bound.*`` window; the point
    order (``inversion``) does not matter since points are sorted by y. Raises ScenarioError if
    the file has no point table.
    """
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8", errors="replace")
    except OSError as exc:
        raise ScenarioError(f"profile file {path.name!r} cannot be read: {exc.strerror}") from None
    params = {}
    points = []
    in_points = False
    found_table = False
    section = ""
    for raw in text.splitlines():
        line = _split_comment(raw)
        if not line:
            continue
        low = line.lower()
        if low.endswith(".begin") and low != "point.begin":
            section = low[: -len(".begin")] + "."
            continue
        if low.endswith(".end") and low != "point.end":
            section = ""
            continue
        if low == "point.begin":
            in_points, found_table = True, True
            continue
        if low == "point.end":
            in_points = False
            continue
        if in_points:
            fields = line.replace(",", " ").split()
            try:
                points.append((float(fields[0]), float(fields[1])))
            except (IndexError, ValueError):
                raise ScenarioError(f"profile file {path.name!r}: bad point line {raw.strip()!r}") from None
            continue
        if "=" in line:
            key, value = (s.strip() for s in line.split("=", 1))
            params[section + key.lower()] = value.strip("'\"")
    if not found_table or len(points) < 4:
        raise ScenarioError(f"profile file {path.name!r} has no point table (point.begin ... point.end)")

    def num(key, default):
        try:
            return float(params.get(key, default))
        except ValueError:
            raise ScenarioError(f"profile file {path.name!r}: {key} is not a number") from None

    kind_flag = int(num("header.type", 0 if path.suffix.lower() == ".prr" else 1))
    kind = "wheel" if kind_flag == 1 else "rail"
    pts = np.array(points)
    y, z = pts[:, 0] + num("spline.shift.y", 0.0), pts[:, 1] + num("spline.shift.z", 0.0)
    angle = num("spline.rotate", 0.0) / num("spline.units.ang.f", 1.0)
    if angle != 0.0:
        c, s = np.cos(angle), np.sin(angle)
        y, z = c * y - s * z, s * y + c * z
    ymin, ymax = num("spline.bound.y.min", 1.0), num("spline.bound.y.max", 0.0)
    zmin, zmax = num("spline.bound.z.min", 1.0), num("spline.bound.z.max", 0.0)
    keep = np.ones(y.size, dtype=bool)
    if ymin < ymax:
        keep &= (y >= ymin) & (y <= ymax)
    if zmin < zmax:
        keep &= (z >= zmin) & (z <= zmax)
    y, z = y[keep], z[keep]
    if int(num("spline.mirror.y", 0)):
        y = -y
    if int(num("spline.mirror.z", 0)):
        z = -z
    factor = num("spline.units.len.f", 1.0)
    if factor <= 0.0:
        raise ScenarioError(f"profile file {path.name!r}: units.len.f must be > 0")
    return Profile(y=y / factor, z=z / factor, kind=kind, name=name or path.stem)


def load_profile(path_or_name, cant=None):
    """A profile from a SIMPACK file path or a built-in name ("S1002", "UIC60").

    ``cant``: inclination already contained in a file's points (built-ins know their own).
    """
    key = str(path_or_name).upper()
    if key in BUILTIN_PROFILES:
        filename, builtin_cant = BUILTIN_PROFILES[key]
        with resources.as_file(resources.files("railwear.geometry") / "data" / filename) as p:
            profile = read_simpack_profile(p, name=key)
        inclination = builtin_cant if cant is None else float(cant)
    else:
        profile = read_simpack_profile(path_or_name)
        inclination = 0.0 if cant is None else float(cant)
    return Profile(y=profile.y, z=profile.z, kind=profile.kind, name=profile.name, cant=inclination)


def conical_profile(conicity, half_width=0.07, kind="wheel", n=281, name=None):
    """A straight (conical) wheel tread ``z = -conicity * y`` (radius falls towards the field side)
    over |y| <= half_width [m]; for kind="rail" a straight inclined line ``z = conicity * y``."""
    if not np.isfinite(conicity) or conicity < 0:
        raise ScenarioError(f"conicity must be a finite number >= 0, got {conicity}")
    y = np.linspace(-half_width, half_width, n)
    z = -conicity * y if kind == "wheel" else conicity * y
    return Profile(y=y, z=z, kind=kind, name=name or f"cone {conicity:g}")


def circular_profile(radius, half_width=0.03, kind="rail", n=241, name=None):
    """A circular arc of ``radius`` [m] with its extreme point at y = 0.

    rail: convex head, ``z = R - sqrt(R² - y²)`` (depth below the top); wheel: a convex tread
    barrel, ``z = -(R - sqrt(R² - y²))`` (radius largest at y = 0). A negative radius gives the
    concave (hollow) counterpart.
    """
    R = float(radius)
    if not np.isfinite(R) or R == 0.0 or abs(R) <= half_width:
        raise ScenarioError(f"radius must be finite with |radius| > half_width, got {radius}")
    y = np.linspace(-half_width, half_width, n)
    sag = np.sign(R) * (abs(R) - np.sqrt(R * R - y * y))
    z = sag if kind == "rail" else -sag
    return Profile(y=y, z=z, kind=kind, name=name or f"circle {R:g}")
