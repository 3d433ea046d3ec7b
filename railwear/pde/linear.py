"""Linear analysis of the evolution equation: dispersion relation, unstable band, stability maps."""

import numpy as np
import xarray as xr

from railwear.pde.forms import as_wear_rate


def dispersion(a, k, epsilon=0.0, nu=0.0):
    """Linear growth rate of ``cos(k x)`` for ``∂h/∂u_xx = -a`` (per unit normed time).

    ``σ(k) = (a k² - epsilon k⁴) / (1 + nu k²)``; ``a > 0`` is the anti-diffusive (unstable)
    case. Broadcasts over its arguments.
    """
    k2 = np.asarray(k, float) ** 2
    return (np.asarray(a, float) * k2 - epsilon * k2**2) / (1.0 + nu * k2)


def unstable_band(a, epsilon=0.0, nu=0.0):
    """``(k_max, k_fastest)``: upper edge of the unstable band and the fastest real wavenumber.

    ``σ > 0`` for ``0 < k < sqrt(a / epsilon)``; ``dσ/dk = 0`` where
    ``epsilon nu K² + 2 epsilon K - a = 0`` with ``K = k²``. Without ``epsilon`` both are infinite
    (no mode is preferred); with ``a <= 0`` the band is empty and both are 0.
    """
    if a <= 0:
        return 0.0, 0.0
    if epsilon == 0:
        return np.inf, np.inf
    if nu == 0:
        K = a / (2 * epsilon)
    else:
        K = (-epsilon + np.sqrt(epsilon**2 + epsilon * nu * a)) / (epsilon * nu)
    return float(np.sqrt(a / epsilon)), float(np.sqrt(K))


def fastest_order(a, epsilon=0.0, nu=0.0, highest=None):
    """The integer polygon order ``n >= 1`` with the largest growth rate (0 if none grows)."""
    k_edge, k_fast = unstable_band(a, epsilon, nu)
    if k_edge == 0:
        return 0
    if not np.isfinite(k_fast):
        return int(highest) if highest is not None else 0
    candidates = np.array([max(1, np.floor(k_fast)), np.ceil(k_fast)])
    return int(candidates[np.argmax(dispersion(a, candidates, epsilon, nu))])


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
    from railwear.pde.evolution import solve_evolution

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
