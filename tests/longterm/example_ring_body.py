"""A new body, as a user would add one: a ring worn at a known rate, no dynamics.

Each cell of the ring loses ``mean + amplitude cos(order x)`` (m per unit normed time), the
Monte Carlo draws scatter it by ``scatter`` (relative), the coupled run takes segments of
``segment_time`` normed time; the removed volume per metre of depth is ``cell_volume`` per cell."""

from dataclasses import dataclass

import numpy as np
import xarray as xr

from railwear.longterm.base import RadiusBody, time_coordinates
from railwear.longterm.spectra import describe


@dataclass(frozen=True)
class Ring(RadiusBody, name="ring"):
    mean: float = 2e-4
    amplitude: float = 5e-5
    order: int = 6
    scatter: float = 0.01
    segment_time: float = 0.01
    cell_volume: float = 1e-6
    samples: int = 4

    label = "ring"

    def rate(self, n):
        x = 2 * np.pi * np.arange(n) / n
        return self.mean + self.amplitude * np.cos(self.order * x)

    def new_cost(self):
        return {"draws": 0}

    def rates(self, u, rng, cost):
        draws = self.rate(u.size) * (1 + self.scatter * rng.standard_normal((self.samples, 1)))
        cost["draws"] += self.samples
        rate = draws.mean(0)
        return rate, draws.std(0, ddof=1) / np.sqrt(self.samples), float(rate.sum() * self.cell_volume), None

    def couple(self, u, rng, acceleration, cost):
        return {}

    def segment(self, u, carry, acceleration, remaining, cost):
        increment = self.rate(u.size) * self.segment_time
        return increment, self.segment_time, False, float(increment.sum() * self.cell_volume), None, carry

    def record(self, u, seen, law_volume):
        return {"u": u.copy(), "law_volume": law_volume}

    def result(self, records, times, cost, error, attrs):
        u = np.asarray(records["u"])
        n = u.shape[1]
        data = {"u": (("time", "angle"), u, {"units": "m", "long_name": "radius deviation"}),
                "removed_volume": ("time", (u[0] - u).sum(1) * self.cell_volume, {"units": "m3"}),
                "law_volume": ("time", np.asarray(records["law_volume"]), {"units": "m3"})}
        if error is not None:
            data["u_standard_error"] = (("time", "angle"), np.asarray(error), {"units": "m"})
        coords = time_coordinates(times, 1e6, 30.0)
        coords["angle"] = ("angle", 2 * np.pi * np.arange(n) / n, {"units": "rad"})
        return describe(xr.Dataset(data, coords=coords, attrs=attrs))

    def fingerprint_parts(self):
        return (self.mean, self.amplitude, self.order, self.scatter, self.segment_time, self.cell_volume, self.samples)
