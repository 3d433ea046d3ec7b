"""Strategy 4 of the paper: the phenomenological evolution equation ``u_T = h(u_xx; u, u_x, v)``,
here ``h(u_xx; v) + drift(v) u_x + dispersion(v) u_xxx`` (as fitted by :mod:`railwear.longterm.fitting`)."""

from dataclasses import dataclass, field

import numpy as np
import xarray as xr

from railwear.geometry import roundness
from railwear.pde import as_wear_rate, solve_evolution


@dataclass(frozen=True)
class Phenomenological:
    """Evolve a wheel's radius deviation under a wear-rate form ``h`` at one or more speeds (m/s),
    with the odd terms ``drift u_x + dispersion u_xxx`` (rad and rad³ per unit normed time; one
    value or one per speed)."""

    h: object
    speed: float | np.ndarray
    epsilon: float = 0.0
    nu: float = 0.0
    drift: float | np.ndarray = 0.0
    dispersion: float | np.ndarray = 0.0
    options: dict = field(default_factory=dict)

    def run(self, u0, until=1.0, depth_limit=None, progress=None, checkpoint=None, resume=None):
        """Solve to normed time ``until`` or removed depth ``depth_limit`` (m); add the wheel's spectrum.

        ``checkpoint`` and ``resume`` are passed to :func:`~railwear.pde.solve_evolution`.
        """
        ds = solve_evolution(u0, until, as_wear_rate(self.h), self.speed, self.epsilon, self.nu,
                             depth_limit=depth_limit, progress=progress, checkpoint=checkpoint,
                             resume=resume, drift=self.drift, dispersion=self.dispersion, **self.options)
        return describe(ds)


def describe(ds: xr.Dataset):
    """Add removed depth over time and the initial and final polygon spectra to a solution."""
    u = ds.u
    batch = [d for d in u.dims if d not in ("time", "angle")]
    u0, u_end = u.isel(time=0), u.isel(time=-1)
    removed = (u0 - u).max("angle")
    ds["removed_depth"] = removed.assign_attrs(
        units="m", long_name="largest radius lost since the start (most worn spot)")
    ds["mean_removed_depth"] = (u0 - u).mean("angle").assign_attrs(
        units="m", long_name="mean radius lost since the start")
    deviation = u - u.mean("angle")
    rows = deviation.transpose(*batch, "time", "angle").values.reshape(-1, u.sizes["time"], u.sizes["angle"])
    spectra = [(roundness.polygon_spectrum(r[0]), roundness.polygon_spectrum(r[-1])) for r in rows]
    shape = [u.sizes[d] for d in batch]
    order = spectra[0][1]["order"]

    def per_row(key, which):
        return np.array([s[which][key] for s in spectra]).reshape(shape + list(np.shape(spectra[0][which][key])))

    dims_order = tuple(batch) + ("order",)
    ds = ds.assign_coords(order=("order", order, {"units": "1", "long_name": "polygon order"}))
    ds["amplitude"] = (dims_order, per_row("amplitude", 1),
                       {"units": "m", "long_name": "harmonic amplitude at the end"})
    ds["amplitude_initial"] = (dims_order, per_row("amplitude", 0),
                               {"units": "m", "long_name": "harmonic amplitude at the start"})
    ds["roughness_level"] = (dims_order, per_row("roughness_level", 1),
                             {"units": "dB", "long_name": "roughness level per order at the end, re 1 um rms"})
    ds["dominant_order"] = (tuple(batch), per_row("dominant_order", 1),
                            {"units": "1", "long_name": "order of the largest harmonic at the end"})
    ds["maxima"] = (tuple(batch), per_row("maxima", 1),
                    {"units": "1", "long_name": "radius maxima round the wheel at the end"})
    pp0, pp1 = per_row("peak_to_peak", 0), per_row("peak_to_peak", 1)
    ds["peak_to_peak_initial"] = (tuple(batch), pp0, {"units": "m", "long_name": "peak-to-peak deviation at the start"})
    ds["peak_to_peak"] = (tuple(batch), pp1, {"units": "m", "long_name": "peak-to-peak deviation at the end"})
    regimes = np.vectorize(roundness.regime, otypes=[object])(pp0, pp1)
    ds["regime"] = (tuple(batch), regimes.astype(str), {"long_name": "wear regime (stable, smoothing, onset, polygonalising)"})
    return ds
