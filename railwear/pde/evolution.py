"""Solve the evolution equation of the wheel radius in one call (paper eq. 4).

    (1 - nu ∂xx) u_T = h(u_xx; u, u_x, v) - epsilon u_xxxx

:func:`solve_evolution` builds the :class:`~railwear.pde.equation.EvolutionEquation`, runs the
:class:`~railwear.pde.solver.ETDRK4Solver` and returns the result as an ``xarray.Dataset``.
"""

import numpy as np
import xarray as xr

from railwear.pde.equation import EvolutionEquation, wavenumbers
from railwear.pde.solver import ETDRK4Solver, EvolutionCheckpoint

__all__ = ["EvolutionCheckpoint", "solve_evolution", "to_dataset", "wavenumbers"]  # the first and last: old paths


def solve_evolution(
    u0, t_end, h, speed=0.0, epsilon=0.0, nu=0.0, *, dt=None, n_save=101, dealias=True,
    stabilisation=None, depth_limit=None, tail_tolerance=1e-3, max_halvings=6, progress=None,
    checkpoint=None, resume=None, resolution_tolerance=3e-5, rtol=1e-4, drift=0.0, dispersion=0.0,
):
    """Solve the evolution equation from ``u0`` (m) over normed time ``[0, t_end]``.

    Parameters
    ----------
    u0 : array (angle,) or (batch, angle)
        Radius deviation on an even number of equally spaced angles ``2π j / n`` (m).
    h : wear-rate form, registered name, or callable ``h(s, u, ux, speed)`` (see
        :mod:`railwear.pde.forms`), or a list of built-in forms, one per batch row.
    speed : float or 1-D array
        Vehicle speed (m/s); an array makes a batch over speeds, advanced together.
    epsilon, nu : float
        Regularisation ``-epsilon u_xxxx`` (rad⁴ per unit time) and ``+nu u_xxT`` (rad²).
    drift : float or 1-D array
        A term ``+drift u_x`` of ``h`` (rad per unit time; one per batch row or one for all): the
        pattern travels round the wheel at ``-drift`` without changing its growth. Taken exactly in
        the linear part.
    dispersion : float or 1-D array
        A term ``+dispersion u_xxx`` of ``h`` (rad³ per unit time; per row or one for all): order
        ``k`` travels at ``dispersion k²`` more. Taken exactly in the linear part.
    dt : float, optional
        A fixed time step, which turns the step-size control off. By default the first step
        comes from the largest linear growth rate met at the start and ``rtol`` controls it.
    n_save : int
        Number of equally spaced output times.
    dealias : bool
        2/3-rule dealiasing of the wear rate.
    stabilisation : float, optional
        The ``S`` of the split; by default the largest slope ``∂h/∂u_xx`` met.
    depth_limit : float, optional
        Stop a row when its most worn spot has lost this depth (m) since ``u0``.
    tail_tolerance : float
        The top quarter of the kept orders may grow to this fraction of the largest amplitude
        (and beyond 1000 times its start) before the run is declared ill-posed.
    rtol : float or None
        Step-size control (when ``dt`` is not given) for a relative error of about ``rtol`` in
        the out-of-round deviation at the end. Each output interval is also taken with half the steps, and the difference
        over 15 (Richardson, order 4) estimates its error; a row whose estimate passes its share
        ``rtol * interval / t_end`` takes the interval again with twice the steps, one far below
        it (1/32) halves them for the next. Costs half as much again per interval. ``None``
        keeps the first step throughout.
    resolution_tolerance : float
        Where the top quarter of the kept orders reaches this fraction of the largest amplitude
        (and ten times its start) the run warns (:class:`~railwear.errors.ResolutionWarning`)
        that the grid may not resolve it; the largest fraction met is ``spectral_tail``.
    progress : callable, optional
        Called with the fraction of ``t_end`` done after each output interval.
    checkpoint : callable, optional
        Called with an :class:`EvolutionCheckpoint` after each output interval.
    resume : EvolutionCheckpoint, optional
        Continue from a checkpoint of the same problem; the result is bit for bit that of an
        uninterrupted run.

    Returns an ``xarray.Dataset`` with ``u`` over (``time``, [``speed`` | ``member``], ``angle``)
    and the stop time per row. Raises :class:`~railwear.errors.IllPosedError` on growth at the grid
    scale and :class:`~railwear.errors.NumericalInstabilityError` on a blow-up that step halving
    does not cure; both carry the last good state.
    """
    equation = EvolutionEquation.from_input(u0, h, speed, epsilon, nu, drift=drift, dispersion=dispersion,
                                            dealias=dealias)
    solver = ETDRK4Solver(dt=dt, n_save=n_save, stabilisation=stabilisation, depth_limit=depth_limit,
                          tail_tolerance=tail_tolerance, max_halvings=max_halvings, rtol=rtol,
                          resolution_tolerance=resolution_tolerance)
    run = solver.solve(equation, t_end, progress=progress, checkpoint=checkpoint, resume=resume)
    return to_dataset(equation, solver, run)


def to_dataset(equation, solver, run):
    """The run as an ``xarray.Dataset``: ``u`` (m) over (``time``, [``speed`` | ``member``],
    ``angle``), the stop time, time step and spectral tail per row, the parameters as attributes."""
    n, speeds, batch_dim, stop, dt = equation.n, equation.speeds, equation.batch, run.stop_time, run.time_step
    u = np.fft.irfft(run.saved, n, axis=-1)
    times, angle = run.times, 2 * np.pi * np.arange(n) / n
    coords = {
        "time": ("time", times, {"units": "1", "long_name": "normed life time"}),
        "angle": ("angle", angle, {"units": "rad", "long_name": "angle round the wheel"}),
    }
    u_attrs = {"units": "m", "long_name": "radius deviation from the nominal radius"}
    stop_attrs = {"units": "1", "long_name": "normed time at which the run stopped"}
    step_attrs = {"units": "1", "long_name": "time step of the run"}
    if batch_dim is None:
        data = {"u": (("time", "angle"), u[:, 0, :], u_attrs),
                "stop_time": ((), stop[0], stop_attrs), "time_step": ((), dt[0], step_attrs)}
        coords["speed"] = ((), speeds[0], {"units": "m s-1", "long_name": "vehicle speed"})
    else:
        data = {"u": (("time", batch_dim, "angle"), u, u_attrs),
                "stop_time": ((batch_dim,), stop, stop_attrs),
                "time_step": ((batch_dim,), dt, step_attrs)}
        if batch_dim == "speed":
            coords["speed"] = ("speed", speeds, {"units": "m s-1", "long_name": "vehicle speed"})
        else:
            coords["member"] = ("member", np.arange(len(speeds)), {"long_name": "batch member"})
            coords["speed"] = ((), speeds[0], {"units": "m s-1", "long_name": "vehicle speed"})
    attrs = {
        "h_form": equation.forms[0].name, "epsilon": float(equation.epsilon), "nu": float(equation.nu),
        "drift": equation.drift, "dispersion": equation.dispersion,
        "time_step": float(np.min(dt)),
        "dealias": int(equation.dealias), "stabilisation": float(np.max(run.stabilisation)),
        "depth_limit": float(solver.depth_limit) if solver.depth_limit is not None else 0.0,
        "method": "pseudo-spectral Fourier, ETDRK4 (Kassam & Trefethen 2005)",
    }
    ds = xr.Dataset(data, coords=coords, attrs=attrs)
    tail = run.spectral_tail
    ds["spectral_tail"] = ((batch_dim,) if batch_dim else (), tail if batch_dim else tail[0],
                           {"units": "1", "long_name": "largest amplitude in the top quarter of the kept orders over the largest amplitude"})
    ds.attrs["resolution_tolerance"] = solver.resolution_tolerance
    return ds
