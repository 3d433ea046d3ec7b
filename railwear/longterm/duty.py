"""Duty cycles (layer 3): the service a wheel runs, as segments of its distance.

Segment ``k`` runs the share ``p_k`` of the distance (``Σ p_k = 1``) at the speed ``V_k`` (m/s)
under the signed longitudinal demand ``f_k = F_k / W`` (the creep force over the wheel load:
``> 0`` traction, ``< 0`` braking through the contact; coasting is the small braking of the
rolling resistance).

**Linear strategies average per distance.** In the Fourier technique every segment's operator is
diagonal in the polygon order ``n`` (``d û_n / dt = λ_n^k û_n``), so the segments' operators
commute and, over a distance ``s`` run in any order and any interleaving of the segments,

    û_n(s) = û_n(0) exp(s Σ_k p_k λ_n^k / V_k)

exactly; likewise the mean radius falls by ``s Σ_k p_k r_k / V_k`` (``r_k`` its rate, m/s). The
averaged technique (:class:`~railwear.longterm.fourier.FourierCycle`) keeps seconds at the
cycle's mean speed ``V̄ = 1 / Σ_k p_k / V_k`` (distance over time).

**Stepped strategies run the segments in proportion.** Frozen-geometry draws take segment ``k``
with the probability ``p_k`` (:class:`~railwear.longterm.disk_wheel.DutyService`); the direct
strategy runs every segment from its own settled state over the same surface and weighs its wear
per distance by ``p_k`` (:mod:`railwear.longterm.direct`).

**A line.** :func:`line_cycle` derives the distance-weighted segments of a run between stations
``spacing`` apart: accelerate at ``a`` to the top speed, cruise, brake at ``b`` (a triangle when
the spacing is too short to reach the top speed). Each phase is cut into ``m`` bins of equal
distance (``v² = 2 a x``: the ``i``-th spans ``V sqrt(i/m)`` to ``V sqrt((i+1)/m)``), each run at
its distance over its time, the mean of its end speeds, so that the cycle's run time
``Σ p_k / V_k`` is the trapezoid's exactly. Demands per wheel: a motor wheel pulls ``(1 + ρ) a / (g s_m) + r``
and brakes electrically at ``-(1 + ρ) b / (g s_m) + r`` (``s_m`` the share of the train's
weight on motor wheels, ``ρ`` the rotating-mass allowance, ``r`` the running resistance per
weight, which helps braking); a trailer wheel is pulled and carries ``-r_w`` (its own rolling
resistance) and brakes by its discs, through the contact, at ``-(1 + ρ) b / g``. Tread braking
(blocks on the tread) adds wear and heat at the tread itself, which no source at hand quantifies
per distance; it is left out. Dwell runs no distance and does not enter a distance cycle.
"""

from dataclasses import dataclass

import numpy as np

from railwear.errors import ScenarioError

GRAVITY = 9.81  # m/s²


@dataclass(frozen=True)
class DutySegment:
    """One segment: its ``share`` of the distance, ``speed`` (m/s) and signed ``traction_coefficient``
    (creep force over wheel load: traction > 0, braking < 0)."""

    share: float
    speed: float
    traction_coefficient: float


@dataclass(frozen=True)
class DutyCycle:
    """Segments whose shares of the distance sum to 1."""

    segments: tuple

    def __post_init__(self):
        if not self.segments:
            raise ScenarioError("duty cycle: needs at least one segment")
        for i, s in enumerate(self.segments):
            if not (np.isfinite(s.share) and s.share > 0):
                raise ScenarioError(f"duty cycle: segment {i}: share must be > 0, got {s.share}")
            if not (np.isfinite(s.speed) and s.speed > 0):
                raise ScenarioError(f"duty cycle: segment {i}: speed must be > 0 (m/s), got {s.speed}")
            if not (np.isfinite(s.traction_coefficient) and abs(s.traction_coefficient) < 1):
                raise ScenarioError(f"duty cycle: segment {i}: traction_coefficient must lie in (-1, 1), "
                                    f"got {s.traction_coefficient}")
        total = sum(s.share for s in self.segments)
        if abs(total - 1) > 1e-9:
            raise ScenarioError(f"duty cycle: the shares of the distance must sum to 1, not {total:.12g}")

    @property
    def shares(self):
        return np.array([s.share for s in self.segments])

    @property
    def speeds(self):
        """Segment speeds (m/s)."""
        return np.array([s.speed for s in self.segments])

    @property
    def demands(self):
        """Signed traction coefficients ``f_k``."""
        return np.array([s.traction_coefficient for s in self.segments])

    @property
    def mean_speed(self):
        """Distance over time, ``1 / Σ p_k / V_k`` (m/s)."""
        return float(1.0 / np.sum(self.shares / self.speeds))

    @property
    def mean_traction_coefficient(self):
        """Distance-weighted signed demand ``Σ p_k f_k``: the mean creep force over the load."""
        return float(np.sum(self.shares * self.demands))

    @property
    def braking_share(self):
        """Share of the distance run under a braking demand (``f_k < 0``)."""
        return float(np.sum(self.shares[self.demands < 0]))

    def describe(self):
        """One line for people: mean creep force over load and the braking share."""
        return (f"duty cycle of {len(self.segments)} segment(s): mean creep force {self.mean_traction_coefficient:+.4f} "
                f"x wheel load, braking over {self.braking_share:.0%} of the distance")


def _phase_bins(top, bins):
    """Speeds (m/s) of ``bins`` equal-distance bins of a constant-rate phase from 0 to ``top``:
    each bin's distance over its time, the mean of its end speeds."""
    ends = top * np.sqrt(np.arange(bins + 1) / bins)
    return 0.5 * (ends[:-1] + ends[1:])


def line_cycle(spacing, top_speed, acceleration, braking, wheel="motor", motored_share=1.0,
               rotating_allowance=0.08, resistance=0.002, bins=4):
    """The :class:`DutyCycle` of a stopping service: stations ``spacing`` (m) apart, ``top_speed``
    (m/s), ``acceleration`` and ``braking`` rates (m/s², both > 0), for a ``"motor"`` or
    ``"trailer"`` wheel (demands in this module's docstring); ``bins`` speed bins per
    acceleration and braking phase."""
    for name, value in (("spacing", spacing), ("top_speed", top_speed), ("acceleration", acceleration),
                        ("braking", braking), ("motored_share", motored_share)):
        if not (np.isfinite(value) and value > 0):
            raise ScenarioError(f"line: {name} must be > 0, got {value}")
    if wheel not in ("motor", "trailer"):
        raise ScenarioError(f"line: wheel must be 'motor' or 'trailer', not {wheel!r}")
    run_up = top_speed**2 / (2 * acceleration) + top_speed**2 / (2 * braking)
    peak = top_speed if run_up <= spacing else float(np.sqrt(2 * spacing * acceleration * braking / (acceleration + braking)))
    d_acc, d_brake = peak**2 / (2 * acceleration), peak**2 / (2 * braking)
    d_cruise = max(spacing - d_acc - d_brake, 0.0)
    inertia = 1 + rotating_allowance
    if wheel == "motor":
        pull, cruise, brake = inertia * acceleration / (GRAVITY * motored_share) + resistance, resistance, \
            -inertia * braking / (GRAVITY * motored_share) + resistance
    else:
        pull = cruise = -resistance
        brake = -inertia * braking / GRAVITY
    segments = [DutySegment(d_acc / spacing / bins, float(v), pull) for v in _phase_bins(peak, bins)]
    if d_cruise > 0:
        segments.append(DutySegment(d_cruise / spacing, peak, cruise))
    segments += [DutySegment(d_brake / spacing / bins, float(v), brake) for v in _phase_bins(peak, bins)]
    return DutyCycle(tuple(segments))
