"""Stability maps of the evolution equation over speed and polygon order: derived and measured."""

import numpy as np
import xarray as xr

from railwear.pde.evolution import solve_evolution
from railwear.pde.forms import as_wear_rate
from railwear.pde.linear import dispersion


def stability_map(h, speeds, orders, epsilon=0.0, nu=0.0, amplitude=0.0):
    """Growth rate of polygon order ``n`` over speed (m/s) and order.

    With ``amplitude = 0`` this is the dispersion relation about the round wheel,
    ``a = -∂h/∂u_xx(0; v)``. With ``amplitude = A > 0`` (m) the slope is frozen at the crest of
    ``A cos(n x)``, where ``u_xx = -A n²``: the growth of a polygon that is already there, which is
    how a finite perturbation can grow where the round wheel is stable.
    """
    form = as_wear_rate(h)
    speeds = np.atleast_1d(np.asarray(speeds, float))
    orders = np.atleast_1d(np.asarray(orders, float))
    crest = -amplitude * orders**2
    a = np.array([-form.slope(crest, speed=v) for v in speeds])
    rate = dispersion(a, orders[None, :], epsilon, nu)
    return xr.Dataset(
        {"growth_rate": (("speed", "order"), rate,
                         {"units": "1", "long_name": "growth rate per unit normed time"}),
         "anti_diffusion": (("speed", "order"), a,
                            {"units": "rad2", "long_name": "-dh/du_xx at the crest"})},
        coords={"speed": ("speed", speeds, {"units": "m s-1", "long_name": "vehicle speed"}),
                "order": ("order", orders.astype(int), {"units": "1", "long_name": "polygon order"})},
        attrs={"epsilon": epsilon, "nu": nu, "amplitude": amplitude},
    )


def measured_growth_map(h, speeds, orders, epsilon=0.0, nu=0.0, amplitude=1e-12, duration=0.01,
                        n_points=128, dt=None):
    """Growth rate of each polygon order measured in one short batched solve over the speeds.

    Every order starts at ``amplitude`` (m), small enough for the linear regime about the round
    wheel; after ``duration`` (normed time) the rate is ``ln(|û_n(T)| / |û_n(0)|) / T``. In that
    regime it is :func:`stability_map` with ``amplitude = 0``, measured instead of derived.
    """
    speeds = np.atleast_1d(np.asarray(speeds, float))
    orders = np.atleast_1d(np.asarray(orders, int))
    x = 2 * np.pi * np.arange(n_points) / n_points
    u0 = amplitude * np.cos(orders[:, None] * x + 0.7 * orders[:, None]).sum(axis=0)
    ds = solve_evolution(u0, duration, h, speeds, epsilon, nu, n_save=2, dt=dt)
    spectrum = np.abs(np.fft.rfft(ds.u.values, axis=-1))[..., orders]
    rate = np.log(spectrum[-1] / spectrum[0]) / float(ds.time[-1])
    return xr.Dataset(
        {"growth_rate": (("speed", "order"), rate,
                         {"units": "1", "long_name": "measured growth rate per unit normed time"})},
        coords={"speed": ("speed", speeds, {"units": "m s-1", "long_name": "vehicle speed"}),
                "order": ("order", orders, {"units": "1", "long_name": "polygon order"})},
        attrs={"epsilon": epsilon, "nu": nu, "amplitude": amplitude, "duration": duration},
    )
