"""The wear surface (paper Fig. 4): removed depth on a grid over angle × lateral position.

The grid is periodic in the angle (``n_angle`` cells of the circumference ``2π R0``) and bounded
laterally (cells between ``lateral_edges``, m). The wear of one instant, a volume (m³), is spread
over the cells under the contact patch (the paper's ``χ``): the patch is a set of rectangles
(x along the circumference, s across; each with its share of the volume), and each rectangle puts
its share into the cells it overlaps in proportion to the overlap area. That is exact for a
footprint that is constant on each rectangle, so the removed volume equals the deposited one to
round-off, across the periodic seam too. Rectangles reaching past the lateral edges are moved in
whole to the nearest edge cells (nothing is lost). A rectangle of zero length puts its share in
the cell under it: the "point" mode of codes that do not resolve the patch.
"""

import numpy as np
from numba import njit

from railwear.errors import ScenarioError


@njit(cache=True)
def _overlaps(lo, hi, origin, width, n, periodic, cells, fractions):
    """Cells ``k`` of a grid ``origin + k width`` that ``[lo, hi]`` covers, with the covered fractions."""
    count = 0
    length = hi - lo
    if length <= 0.0:
        k = int(np.floor((lo - origin) / width))
        if periodic:
            k %= n
        else:
            k = min(max(k, 0), n - 1)
        cells[0] = k
        fractions[0] = 1.0
        return 1
    if not periodic:  # shift the whole interval inside the grid, keeping its length
        top = origin + n * width
        if length >= n * width:
            lo, hi = origin, top
        elif lo < origin:
            lo, hi = origin, origin + length
        elif hi > top:
            lo, hi = top - length, top
    first = int(np.floor((lo - origin) / width))
    last = int(np.ceil((hi - origin) / width)) - 1
    for k in range(first, last + 1):
        a = max(lo, origin + k * width)
        b = min(hi, origin + (k + 1) * width)
        if b > a:
            cells[count] = k % n if periodic else k
            fractions[count] = (b - a) / (hi - lo)
            count += 1
    return count


@njit(cache=True)
def deposit_rectangles(depth, circumference, lateral_lo, lateral_width, x_lo, x_hi, s_lo, s_hi, volume):
    """Add ``volume[r]`` (m³) of rectangle ``r`` to ``depth`` (m), cell by overlap area.

    ``depth`` has shape ``(n_angle, n_lateral)``; x in metres along the circumference, s in
    metres across. Returns the volume added (m³), equal to ``volume.sum()`` up to round-off.
    """
    n_angle, n_lateral = depth.shape
    dx = circumference / n_angle
    area = dx * lateral_width
    xs = np.empty(n_angle + 2, np.int64)
    fx = np.empty(n_angle + 2)
    ss = np.empty(n_lateral + 2, np.int64)
    fs = np.empty(n_lateral + 2)
    added = 0.0
    for r in range(x_lo.size):
        if volume[r] == 0.0:
            continue
        # the flags as runtime booleans: literals would type (and compile) _overlaps once per value
        nx = _overlaps(x_lo[r], x_hi[r], 0.0, dx, n_angle, np.bool_(True), xs, fx)
        ns = _overlaps(s_lo[r], s_hi[r], lateral_lo, lateral_width, n_lateral, np.bool_(False), ss, fs)
        for i in range(nx):
            for k in range(ns):
                share = volume[r] * fx[i] * fs[k]
                depth[xs[i], ss[k]] += share / area
                added += share
    return added


def ellipse_footprint(a, b, n=16, weighting="hertz"):
    """Rectangles covering the patch ellipse ``(x/a)² + (s/b)² <= 1`` (m) and their shares (sum 1).

    The ellipse is cut into ``n`` strips across; each strip is cut into ``n`` equal pieces along
    its own length. ``weighting`` "hertz" weights a piece by the elliptic Hertz pressure at its
    centre times its area, "uniform" by its area.
    """
    if not (a > 0 and b > 0):
        raise ScenarioError(f"patch semi-axes must be > 0, got a={a}, b={b}")
    if weighting not in ("hertz", "uniform"):
        raise ScenarioError(f"weighting must be 'hertz' or 'uniform', not {weighting!r}")
    s_edges = np.linspace(-b, b, n + 1)
    s_mid = 0.5 * (s_edges[:-1] + s_edges[1:])
    half = a * np.sqrt(np.clip(1 - (s_mid / b) ** 2, 0, None))
    t = np.linspace(-1, 1, n + 1)
    x_edges = half[:, None] * t[None, :]
    x_lo, x_hi = x_edges[:, :-1], x_edges[:, 1:]
    s_lo = np.repeat(s_edges[:-1, None], n, axis=1)
    s_hi = np.repeat(s_edges[1:, None], n, axis=1)
    area = (x_hi - x_lo) * (s_hi - s_lo)
    if weighting == "hertz":
        xm, sm = 0.5 * (x_lo + x_hi), 0.5 * (s_lo + s_hi)
        weight = np.sqrt(np.clip(1 - (xm / a) ** 2 - (sm / b) ** 2, 0, None)) * area
    else:
        weight = area
    return x_lo.ravel(), x_hi.ravel(), s_lo.ravel(), s_hi.ravel(), (weight / weight.sum()).ravel()


class WearSurface:
    """Removed depth ``depth[i, k]`` (m) over angle cell ``i`` and lateral cell ``k`` of a wheel.

    ``radius`` R0 (m); ``lateral_edges`` are ``n_lateral + 1`` equally spaced positions (m).
    The radius deviation is ``u = -depth``.
    """

    def __init__(self, radius, n_angle, lateral_edges):
        edges = np.asarray(lateral_edges, float)
        if not radius > 0 or n_angle < 4:
            raise ScenarioError("a wear surface needs radius > 0 and at least 4 angle cells")
        if edges.ndim != 1 or edges.size < 2 or not np.allclose(np.diff(edges), edges[1] - edges[0]) \
                or edges[1] <= edges[0]:
            raise ScenarioError("lateral_edges must be increasing and equally spaced")
        self.radius, self.n_angle, self.lateral_edges = float(radius), int(n_angle), edges
        self.depth = np.zeros((self.n_angle, edges.size - 1))

    @property
    def circumference(self):
        return 2 * np.pi * self.radius

    @property
    def cell_area(self):
        """m² of one cell."""
        return self.circumference / self.n_angle * (self.lateral_edges[1] - self.lateral_edges[0])

    @property
    def angle(self):
        """Cell centres round the wheel (rad)."""
        return 2 * np.pi * (np.arange(self.n_angle) + 0.5) / self.n_angle

    def removed_volume(self):
        """m³ removed so far."""
        return float(self.depth.sum() * self.cell_area)

    def deposit(self, volume, angle, lateral, a=0.0, b=0.0, footprint="hertz", n=16):
        """Remove ``volume`` (m³) under a patch centred at ``angle`` (rad) and ``lateral`` (m).

        ``footprint``: "hertz" or "uniform" over the ellipse with semi-axes ``a`` along the
        circumference and ``b`` across (m); "point" puts it all in the cell under the centre.
        Arrays of instants (``volume``, ``angle``, ``lateral``, ``a``, ``b`` broadcast) are added
        in one call. Returns the volume added (m³).
        """
        volume, angle, lateral, a, b = np.broadcast_arrays(*(np.atleast_1d(np.asarray(v, float))
                                                             for v in (volume, angle, lateral, a, b)))
        if np.any(volume < 0) or not np.all(np.isfinite(volume)):
            raise ScenarioError("wear volumes must be finite and >= 0")
        centre_x = np.mod(angle, 2 * np.pi) * self.radius
        if footprint == "point":
            x_lo = x_hi = centre_x
            s_lo = s_hi = lateral
            share = volume
        else:
            parts = [ellipse_footprint(ai, bi, n, footprint) for ai, bi in zip(a, b)]
            x_lo = np.concatenate([p[0] + c for p, c in zip(parts, centre_x)])
            x_hi = np.concatenate([p[1] + c for p, c in zip(parts, centre_x)])
            s_lo = np.concatenate([p[2] + c for p, c in zip(parts, lateral)])
            s_hi = np.concatenate([p[3] + c for p, c in zip(parts, lateral)])
            share = np.concatenate([p[4] * v for p, v in zip(parts, volume)])
        dl = self.lateral_edges[1] - self.lateral_edges[0]
        return deposit_rectangles(self.depth, self.circumference, self.lateral_edges[0], dl,
                                  x_lo, x_hi, s_lo, s_hi, share)

    def deposit_cells(self, volume, angle, lateral, x, s, dx, ds, density):
        """Spread ``volume`` (m³) by a density on patch cells centred at ``(x, s)`` (m, relative to
        the patch centre at ``angle``, ``lateral``) of sizes ``dx``, ``ds`` (m); all broadcast.

        ``density`` (e.g. FASTSIM's frictional-power density, W/m²) is taken as constant on
        each cell. Returns the volume added (m³).
        """
        x, s, dx, ds, density = (np.asarray(v, float) for v in np.broadcast_arrays(x, s, dx, ds, density))
        if np.any(density < 0) or np.any(dx < 0) or np.any(ds < 0):
            raise ScenarioError("patch cells need sizes and a density >= 0")
        weight = density * dx * ds
        if not weight.sum() > 0:
            raise ScenarioError("the density has no weight on the patch")
        x0 = np.mod(angle, 2 * np.pi) * self.radius
        dl = self.lateral_edges[1] - self.lateral_edges[0]
        return deposit_rectangles(self.depth, self.circumference, self.lateral_edges[0], dl,
                                  (x0 + x - dx / 2).ravel(), (x0 + x + dx / 2).ravel(),
                                  (lateral + s - ds / 2).ravel(), (lateral + s + ds / 2).ravel(),
                                  (weight / weight.sum() * volume).ravel())

    def deposit_fastsim(self, volume, angle, lateral, result):
        """Spread ``volume`` (m³) by the frictional-power density of a FASTSIM result
        (:func:`railwear.contact.fastsim`); the rolling direction runs with the angle."""
        ny = result.y.shape[1]
        ds = abs(result.y[0, -1] - result.y[0, 0]) / (ny - 1) if ny > 1 else 2 * abs(result.y[0, 0])
        dx = np.asarray(result.cell_area)[None, :] / ds
        return self.deposit_cells(volume, angle, lateral, result.x, result.y, dx, ds, result.power_density)
