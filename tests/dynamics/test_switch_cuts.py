"""Steps cut at the flange switching points: same trajectories, fewer rejected steps."""

import dataclasses

import numpy as np
import pytest

from railwear.dynamics import BogieModel, WheelsetModel, kernels, linear_critical_speed
from railwear.dynamics import integrators as integ

WHEELSET = dict(mass=1022.0, yaw_inertia=678.0, lateral_stiffness=1.823e6, yaw_stiffness=2.0e6, f11=6.4e6,
                f22=5.9e6, half_gauge=0.7163, rolling_radius=0.4572, conicity=0.05)
T_END = 10.0
T_EVAL = np.linspace(0.0, T_END, 2001)


def _hunting(track=False):
    """The benchmark's wheelset at 1.2 Vc in a flange-bounded limit cycle (about 7 mm, 5 mm dead
    band); ``track``: on a random lateral alignment of about 1 mm."""
    extra = {}
    if track:
        extra = dict(lateral_irregularity=tuple(1e-3 * np.random.default_rng(3).standard_normal(16)),
                     irregularity_wavelength=60.0)
    return WheelsetModel(speed=1.2 * linear_critical_speed(**WHEELSET), **WHEELSET, flange_clearance=5e-3,
                         flange_stiffness=1.5e7, friction_coefficient=0.3, wheel_load=50e3, **extra)


MODELS = {"wheelset": _hunting(), "wheelset on an aligned track": _hunting(track=True),
          "Cooperrider bogie": dataclasses.replace(BogieModel.cooperrider(50.0), initial_lateral_displacement=8e-3)}


def _run(model, method, rtol, cut):
    out = integ.integrate(model.kind, model.params(), model.surface(), model.initial_state(), 0.0, T_END, rtol,
                          rtol / 100.0, method, 0.0, np.inf, 10**8, T_EVAL, 1, False, 1e6, np.zeros(0), cut)
    assert out[3] == integ.STATUS_OK
    return out[1][:, 0], out[6]


@pytest.mark.parametrize("name", MODELS)
@pytest.mark.parametrize("method", [integ.METHOD_DOPRI5, integ.METHOD_DOP853])
def test_cut_steps_keep_the_trajectory_and_reject_fewer_steps(name, method):
    model = MODELS[name]
    reference, _ = _run(model, integ.METHOD_DOP853, 1e-12, False)
    assert np.abs(reference).max() > 6e-3  # the motion runs into the flanges (5 mm dead band)
    plain, plain_stats = _run(model, method, 1e-10, False)
    cut, cut_stats = _run(model, method, 1e-10, True)
    # over 10 s (about 30 cycles) both are within 2.2e-9 m of the reference (measured), 1e-8 asserted
    assert np.abs(plain - reference).max() < 1e-8
    assert np.abs(cut - reference).max() < 1e-8
    assert np.abs(cut - plain).max() < 1e-8
    # measured: rejected steps 0.28-0.6 (Dormand-Prince 5(4)) and 0.4-0.74 (8(5,3)) of those without
    assert cut_stats[integ.STAT_NREJECT] < (0.7 if method == integ.METHOD_DOPRI5 else 0.9) * plain_stats[
        integ.STAT_NREJECT]
    assert cut_stats[integ.STAT_NFEV] < 0.9 * plain_stats[integ.STAT_NFEV]


def test_switching_function_changes_sign_where_the_flange_force_starts():
    model = MODELS["wheelset on an aligned track"]
    p, surf = model.params(), model.surface()
    rng = np.random.default_rng(5)
    out = np.empty(kernels.WS_N_OUTPUTS)
    contacts = 0
    for _ in range(500):
        t = rng.uniform(0.0, 1.0)
        y = np.array([rng.uniform(-8e-3, 8e-3), 0.0, 0.0, 0.0])
        kernels.wheelset_outputs(t, y, p, surf, out)
        g = kernels.switching(model.kind, t, y, p, surf)
        assert (g > 0.0) == (out[16] != 0.0)
        np.testing.assert_allclose(abs(g), abs(out[16]) / model.flange_stiffness if g > 0.0 else
                                   model.flange_clearance - abs(y[0] - out[18]), rtol=1e-12, atol=1e-18)
        contacts += g > 0.0
    assert 50 < contacts < 450
    bogie = MODELS["Cooperrider bogie"]
    c = bogie.flange_clearance
    for y1, y2, sign in ((0.0, 0.0, 1.0), (1.5 * c, 0.0, -1.0), (0.0, -1.5 * c, -1.0), (1.5 * c, -1.2 * c, 1.0)):
        y = np.zeros(12)
        y[0], y[2] = y1, y2
        assert np.sign(kernels.switching(bogie.kind, 0.0, y, bogie.params(), bogie.surface())) == sign


@pytest.mark.parametrize("rtol", [1e-6, 1e-7])
def test_loose_tolerance_steps_are_not_cut_forever(rtol):
    # a retried step may be cut twice at most: unbounded cuts once made DOP853 loop here until the
    # step budget was spent (10^6 steps, 0.49 s reached)
    model = MODELS["wheelset"]
    out = integ.integrate(model.kind, model.params(), model.surface(), model.initial_state(), 0.0, T_END, rtol,
                          rtol / 100.0, integ.METHOD_DOP853, 0.0, np.inf, 20000, T_EVAL, 1, False, 1e6, np.zeros(0),
                          True)
    assert out[3] == integ.STATUS_OK and out[4] == T_END
