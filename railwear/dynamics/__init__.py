"""Short-time multibody dynamics: disk wheel, wheelset, bogie (layer 2).

- ``linear_critical_speed``: closed-form critical speed of the linear wheelset;
- ``critical_speed(model)``: from the eigenvalue crossing of ``model.state_matrix(speed)``;
- ``WheelsetModel``, ``TableWheelsetModel`` (real profiles), ``DiskWheelModel``, ``BogieModel``
  (two wheelsets and a frame without roll), ``TableBogieModel`` (real profiles),
  ``CooperriderBogie`` (the published Cooperrider bogie, frame roll included):
  frozen, validated model dataclasses;
- ``build_model(kind, section)``: a model from a scenario section (unknown/missing fields are errors);
- ``simulate(model, t_end, **options)``: a run into an ``xarray.Dataset`` (CF units, long names);
- ``ramp_down(model, speeds)``: the nonlinear critical speed by following the limit cycle down;
- ``railwear.dynamics.dae``: the GGL index-2 DAE forms solved with SUNDIALS IDA;
- ``Integrator(method, rtol, atol, ...).run(kind, params, surface, y0, t0, t_end)``: the compiled
  integrators (Dormand-Prince 5(4) and 8(5,3), Rosenbrock 2(3); ``railwear.dynamics.integrators``)
  with the model right-hand sides of ``railwear.dynamics.kernels`` in the loop, options and result
  named (``IntegrationResult``).

The compiled functions' numba caches are keyed on their sources and the files those import
(``railwear._numba_cache``): an edited kernel is recompiled, never run stale.
"""

from railwear import _numba_cache  # noqa: F401  (first: numba caches keyed on the sources)


def __getattr__(name):
    """Each name imported from its module on first use (PEP 562): a run that builds one model
    (the metro run's disk wheel) does not import the integrators, the other models or the
    bifurcation code with the package."""
    if name in ("IntegrationResult", "IntegrationStats", "Integrator"):
        from railwear.dynamics import integration as module
    elif name in ("critical_speed", "linear_critical_speed", "max_real_part", "wheelset_state_matrix"):
        from railwear.dynamics import linear as module
    elif name == "DiskWheelModel":
        from railwear.dynamics import disk_wheel as module
    elif name in ("BogieModel", "CooperriderBogie", "TableBogieModel", "TableWheelsetModel", "WheelsetModel",
                  "build_model", "contact_constants"):
        from railwear.dynamics import models as module
    elif name == "simulate":
        from railwear.dynamics import simulation as module
    elif name in ("RampDown", "ramp_down"):
        from railwear.dynamics import bifurcation as module
    else:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    return getattr(module, name)


__all__ = [
    "BogieModel",
    "CooperriderBogie",
    "RampDown",
    "DiskWheelModel",
    "IntegrationResult",
    "IntegrationStats",
    "Integrator",
    "TableBogieModel",
    "TableWheelsetModel",
    "WheelsetModel",
    "build_model",
    "contact_constants",
    "critical_speed",
    "linear_critical_speed",
    "max_real_part",
    "ramp_down",
    "simulate",
    "wheelset_state_matrix",
]
