"""The benchmark's plain Python wheelset (the alternative a user writes) is the compiled kernel's model."""

import importlib.util
from pathlib import Path

import numpy as np
import pytest

from railwear.dynamics import WheelsetModel, kernels

_SPEC = importlib.util.spec_from_file_location(
    "benchmark_dynamics", Path(__file__).resolve().parents[2] / "benchmarks" / "dynamics.py")
bench = importlib.util.module_from_spec(_SPEC)
_SPEC.loader.exec_module(bench)

BASE = dict(bench.WHEELSET, speed=152.5, flange_clearance=5e-3, flange_stiffness=1.5e7, friction_coefficient=0.3,
            wheel_load=50e3)
CASES = [
    BASE,  # the benchmark's case
    dict(BASE, f23=1.5e4, f33=800.0, lateral_damping=2e4, yaw_damping=3e3, speed=40.0),  # spin creep, dampers
    dict(BASE, friction_coefficient=float("inf"), flange_clearance=float("inf")),  # linear, no flange
]


@pytest.mark.parametrize("case", CASES)
def test_plain_rhs_equals_the_compiled_kernel_at_random_states(case):
    model = WheelsetModel(**case)
    p, surf = model.params(), model.surface()
    plain = bench.plain_wheelset_rhs(**case)
    rng = np.random.default_rng(7)
    # |y| to 12 mm (both flanges), yaw to 10 mrad, rates of a hunting motion at the case's speed:
    # the creep forces run from the linear range far into full slip
    rate = 0.6 * case["speed"] / BASE["speed"]
    scale = np.array([12e-3, 10e-3, rate, rate])
    below_full_slip = 0
    for _ in range(2000):
        y = scale * rng.uniform(-1.0, 1.0, 4)
        compiled = np.empty(4)
        kernels.rhs(model.kind, 0.0, y, p, surf, compiled)
        np.testing.assert_allclose(plain(0.0, y), compiled, rtol=1e-12, atol=1e-12 * np.abs(compiled[2:]).max())
        out = np.empty(kernels.WS_N_OUTPUTS)
        kernels.wheelset_outputs(0.0, y, p, surf, out)
        # the cubic law's saturated force reaches mu Q exactly where it switches to full slip
        below_full_slip += np.hypot(out[3], out[4]) < 0.999 * case["friction_coefficient"] * case["wheel_load"]
    if np.isfinite(case["friction_coefficient"]):
        assert 100 < below_full_slip < 1900  # both branches of the saturation law are visited
