"""Which wheels of a fleet a wheel-impact-load detector flags, at which speed, and when the
predicted growth takes each wheel over (issue 24, item 4, for ``railwear fleet``; layer 4).

For one wheel (its measured line ``u0`` on the grid, its :class:`RateTable` at its diameter):

- **now**: the peak vertical wheel–rail force at each speed, the time-domain run of
  :mod:`railwear.maintenance.impact` (:func:`~railwear.maintenance.impact.peak_forces`; the wheel
  of the vehicle–track case at the wheel's own diameter);
- **when**: for each detector threshold ``T`` (ascending), the least distance ``s`` at which the
  grown shape ``u(s)`` (the fleet's exact Fourier evolution, :func:`~railwear.maintenance.turning.evolve_batch`,
  at growth 1) puts a peak above ``T`` at any of the speeds. Found by bisection on ``s``, each
  midpoint taken where the shape's peak to peak is the geometric mean of the bracket's, until the
  peak to peak across the bracket differs by less than ``tolerance`` (or by 1 km of distance).

The approximations, stated: the peak force of each speed grows monotonically with the distance
(a speed whose peak is known to stay under ``T`` at a farther distance is not run nearer, and the
search needs a bracket ``under T`` / ``over T``); the wheel keeps its measured diameter and runs
without turnings (the grown shape is the polygon the wheel would carry if nobody acted); the
detector reads the peak force at the contact over the recorded revolutions, at the listed speeds
only (a peak between two of them is missed). The polygon at ``s`` under the growth multiplier
``g`` is the polygon at ``g s`` under 1 and the mean radius does not load the rail, so the
distance under ``g`` is the distance under 1 divided by ``g``, exactly. A shape more than
:data:`~railwear.maintenance.impact.LARGEST_SHAPE` from its mean is no wheel in service: the
search stops there, as it does at the horizon.
"""

from dataclasses import dataclass, replace

import numpy as np

from railwear.units import KM

TOLERANCE = 0.02  # the peak to peak across the final bracket differs by less than this
LEAST_STEP_KM = 1.0  # or the bracket is narrower than this
SCAN_POINTS = 400  # cheap scan of the peak to peak up to the horizon (to stop at the largest shape)


@dataclass(frozen=True, eq=False)
class WheelTask:
    """One wheel's inputs (SI): the vehicle–track ``case`` at the wheel's diameter, ``u0`` (m on
    the grid), its rate ``table``, ``speeds`` (m/s), ``thresholds`` (N), ``horizon`` (m), the
    ``tolerance`` on the peak to peak, and the time-domain run's ring and record."""

    case: object
    u0: np.ndarray
    table: object
    speeds: tuple
    thresholds: tuple
    horizon: float
    tolerance: float = TOLERANCE
    ring_sleepers: int = 32
    ring_max_frequency_hz: float = 3000.0
    revolutions: int = 8
    transient: float = 1.0


@dataclass(frozen=True)
class WheelFlags:
    """One wheel's answer: ``peak_now`` (N, per speed), and per threshold the ``distance`` (m,
    ``inf``: not within the search), the ``speed`` (m/s) whose peak passes it first, that
    ``peak`` (N), the shape's peak to peak there (``peak_to_peak``, m) and ``why`` a distance is
    not found (''); ``runs`` the time-domain runs it took."""

    peak_now: np.ndarray
    distance: np.ndarray
    speed: np.ndarray
    peak: np.ndarray
    peak_to_peak: np.ndarray
    why: tuple
    runs: int


class _Search:
    """The time-domain peaks of one wheel's grown shapes, kept per distance (NaN: a speed not run)."""

    def __init__(self, task):
        from railwear.maintenance.turning import evolve_batch
        from railwear.maintenance.impact import DynamicLoad

        self.task = task
        self.u0 = np.asarray(task.u0, float)
        self.spectrum = np.fft.rfft(self.u0)[None, :]
        table = task.table
        self.rates = (table.rates(np.arange(1, self.spectrum.shape[-1])) / table.speed)[None, :]
        self.slope = np.array([table.mean_rate / table.speed])
        self.evolve_batch = evolve_batch
        self.speeds = np.asarray(task.speeds, float)
        self.memo = {}  # distance (m) -> peaks per speed (N)
        self.runs = 0
        self.inputs = DynamicLoad(task.case, self.u0, speeds=tuple(self.speeds), ring_sleepers=task.ring_sleepers,
                                  ring_max_frequency_hz=task.ring_max_frequency_hz, revolutions=task.revolutions,
                                  transient=task.transient, wheel="a grown wheel")
        self.ring = self.inputs.ring()

    def shape(self, s):
        """The grown radius deviation (m) after ``s`` (m), its mean removed."""
        u = self.evolve_batch(self.spectrum, self.rates, self.slope, self.u0.size, np.array([[float(s)]]))[0, 0]
        return u - u.mean()

    def ptp(self, s):
        u = self.shape(s)
        return float(np.ptp(u)) if np.all(np.isfinite(u)) else np.inf

    def reach(self):
        """``(distance, why)``: how far the search may go: the horizon, or where the shape first
        passes the largest shape of a wheel in service (a scan, then a bisection)."""
        from railwear.maintenance.impact import LARGEST_SHAPE

        def too_large(s):
            u = self.shape(s)
            return not np.all(np.isfinite(u)) or float(np.max(np.abs(u))) > LARGEST_SHAPE

        end = float(self.task.horizon)
        grid = np.linspace(0.0, end, SCAN_POINTS + 1)
        s = grid[1:]
        u = self.evolve_batch(self.spectrum, self.rates, self.slope, self.u0.size, s[None, :])[0]
        with np.errstate(invalid="ignore"):
            big = ~np.all(np.isfinite(u), axis=-1) | (np.max(np.abs(u - u.mean(axis=-1, keepdims=True)), axis=-1)
                                                      > LARGEST_SHAPE)
        if not big.any():
            return end, "not within the horizon"
        k = int(np.argmax(big))
        lo, hi = grid[k], s[k]
        for _ in range(60):
            mid = 0.5 * (lo + hi)
            lo, hi = (lo, mid) if too_large(mid) else (mid, hi)
        return lo, f"the shape passes {LARGEST_SHAPE * 1e3:g} mm from its mean first (no wheel in service)"

    def peaks(self, s, threshold, bound):
        """Run, at distance ``s``, the speeds whose peak may pass ``threshold`` (``bound`` per speed:
        a peak known at a farther distance, ``inf`` if none), highest bound first, until one passes."""
        from railwear.maintenance.impact import DynamicLoad, peak_forces

        known = self.memo.setdefault(s, np.full(self.speeds.size, np.nan))
        if np.nanmax(known, initial=-np.inf) > threshold:
            return known
        u = None
        for i in np.argsort(-bound, kind="stable"):
            if not np.isnan(known[i]) or (np.isfinite(bound[i]) and bound[i] <= threshold):
                continue  # run, or known to stay under at a farther distance
            if u is None:
                u = self.shape(s)
                inputs = replace(self.inputs, deviation=u) if np.any(u) else self.inputs
            known[i] = peak_forces(inputs, (self.speeds[i],), self.ring)[0]
            self.runs += 1
            if known[i] > threshold:
                break
        return known

    def bound(self, s):
        """The least peak per speed known at ``s`` or farther (monotone growth): ``inf`` if none."""
        out = np.full(self.speeds.size, np.inf)
        for d, p in self.memo.items():
            if d >= s:
                out = np.fmin(out, np.where(np.isnan(p), np.inf, p))
        return out

    def state(self, s, threshold):
        """+1 over ``threshold`` at ``s``, -1 under it, 0 not known."""
        p = self.memo[s]
        if np.nanmax(p, initial=-np.inf) > threshold:
            return 1
        return -1 if np.all(self.bound(s) <= threshold) else 0

    def midpoint(self, lo, hi):
        """The distance between ``lo`` and ``hi`` where the peak to peak is the geometric mean of
        theirs (a bisection in the logarithm of the shape's size; the middle where it is not monotone)."""
        a, b = self.ptp(lo), self.ptp(hi)
        if not (np.isfinite(a) and np.isfinite(b) and 0 < a < b):
            return 0.5 * (lo + hi)
        target, x, y = np.sqrt(a * b), lo, hi
        for _ in range(40):
            m = 0.5 * (x + y)
            x, y = (x, m) if self.ptp(m) >= target else (m, y)
        return min(max(y, lo + 0.05 * (hi - lo)), hi - 0.05 * (hi - lo))


def wheel_flags(task: WheelTask) -> WheelFlags:
    """The peak force now at each speed and the distance to each threshold (module docstring)."""
    search = _Search(task)
    n_s = search.speeds.size
    thresholds = np.asarray(task.thresholds, float)
    now = search.peaks(0.0, np.inf, np.full(n_s, np.inf)).copy()  # every speed: the table of today
    reach, beyond = search.reach()
    k_t = thresholds.size
    distance, speed, peak, ptp = (np.full(k_t, np.inf), np.full(k_t, np.nan), np.full(k_t, np.nan), np.full(k_t, np.nan))
    why = [""] * k_t
    for j in np.argsort(thresholds, kind="stable"):
        t = thresholds[j]
        if search.state(0.0, t) > 0:
            hi = 0.0
        else:
            if reach not in search.memo or search.state(reach, t) == 0:
                search.peaks(reach, t, search.bound(reach))
            if search.state(reach, t) < 0:
                why[j] = beyond
                continue
            while True:
                points = sorted(search.memo)
                over = [s for s in points if search.state(s, t) > 0]
                hi = min(over)
                under = [s for s in points if s < hi and search.state(s, t) < 0]
                lo = max(under) if under else 0.0
                a, b = search.ptp(lo), search.ptp(hi)
                if hi - lo <= LEAST_STEP_KM * KM or (np.isfinite(a) and a > 0 and b / a - 1 <= task.tolerance):
                    break
                mid = search.midpoint(lo, hi)
                search.peaks(mid, t, search.bound(mid))
        p = search.memo[hi]
        i = int(np.nanargmax(p))
        distance[j], speed[j], peak[j], ptp[j] = hi, search.speeds[i], p[i], search.ptp(hi)
    return WheelFlags(now, distance, speed, peak, ptp, tuple(why), search.runs)


def flag_batch(tasks):
    """:func:`wheel_flags` of each task of a batch (what a worker of the fleet's executor runs)."""
    return [wheel_flags(task) for task in tasks]
