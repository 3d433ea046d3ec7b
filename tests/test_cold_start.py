"""A cold cache compiles the model a run integrates, not every model (issue 12, item 4).

Not a timing test: it checks which compiled functions a first run typed, in a fresh process with
an empty numba cache."""

import json
import os
import subprocess
import sys

import numpy as np

from railwear.dynamics import kernels

PROBE = """
import json, math
import numpy as np
from railwear.dynamics import integrators as integ, kernels as k
p = np.array([2.0, 0.0, 1.0, -1.0, 0.0])  # y' = A y, A = [[0, 1], [-1, 0]]: a rotation
out = integ.integrate(k.KIND_LINEAR, p, np.zeros(0), np.array([1.0, 0.0]), 0.0, 1.0, 1e-10, 1e-12,
                      integ.METHOD_DOPRI5, 0.0, math.inf, 10**6, np.array([1.0]), 1, False, 1e6, np.zeros(0))
again = integ.integrate(k.KIND_LINEAR, p, np.zeros(0), np.array([1.0, 0.0]), 0.0, 1.0, 1e-10, 1e-12,
                        integ.METHOD_DOPRI5, 0.0, math.inf, 10**6, np.array([1.0]), 1, False, 1e6, np.zeros(0))
print(json.dumps({"y": list(out[1][0]), "again": list(again[1][0]),
                  "typed": {name: len(getattr(k, name).signatures) for name in
                            ("bogie_rhs", "table_wheelset_rhs", "cooperrider_rhs", "_table_forces", "_fastsim_factor")},
                  "dop853": len(integ._dop853_dense.signatures),
                  "other_methods": {name: len(getattr(integ, name).signatures) for name in
                                    ("_rosenbrock_step", "_jacobian", "_dop853_error_norm", "_deposit_step")},
                  "entries": len(integ.integrate._entries)}))
"""


def test_a_cold_run_compiles_only_its_model(tmp_path):
    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path / "cache"))
    done = subprocess.run([sys.executable, "-c", PROBE], env=env, capture_output=True, text=True, check=True)
    result = json.loads(done.stdout.splitlines()[-1])
    np.testing.assert_allclose(result["y"], [np.cos(1.0), -np.sin(1.0)], atol=1e-8)
    assert result["again"] == result["y"]
    assert result["typed"] == dict.fromkeys(result["typed"], 0)  # main compiled all of them for any model
    assert result["dop853"] == 0  # a DOPRI5 run compiled DOP853's dense output too (before issue 23)
    # and the Rosenbrock step, its Jacobian and DOP853's error measure (before issue 23's fifth round),
    # and the disk wheel's energy deposit (before the seventh)
    assert result["other_methods"] == dict.fromkeys(result["other_methods"], 0)
    assert result["entries"] == 1  # the second call went straight to the compiled code


def test_python_calls_reach_the_models_as_before():
    """``rhs``, ``outputs``, ``event`` and ``switching`` from Python: the same numbers as the model
    functions themselves, on the fast path after the first call."""
    from railwear.dynamics import WheelsetModel

    model = WheelsetModel(mass=1022.0, yaw_inertia=678.0, lateral_stiffness=1.823e6, yaw_stiffness=2e6, f11=6.4e6,
                          f22=5.9e6, half_gauge=0.7163, rolling_radius=0.4572, conicity=0.2, speed=60.0,
                          flange_clearance=5e-3, flange_stiffness=1.5e7, friction_coefficient=0.3)
    p, surf, y = model.params(), model.surface(), np.array([6e-3, 1e-3, 0.01, -0.02])
    via, direct = np.zeros(4), np.zeros(4)
    for _ in range(2):
        kernels.rhs(model.kind, 0.0, y, p, surf, via)
    kernels.wheelset_rhs(0.0, y, p, surf, direct)
    assert np.array_equal(via, direct) and np.any(direct != 0.0)
    assert kernels.switching(model.kind, 0.0, y, p, surf) == abs(y[0]) - 5e-3
    assert kernels.event(model.kind, 0.0, y, p, surf) == 1.0
    rows = kernels.outputs(model.kind, np.zeros(2), np.stack([y, y]), p, surf, kernels.WS_N_OUTPUTS)
    one = np.zeros(kernels.WS_N_OUTPUTS)
    kernels.wheelset_outputs(0.0, y, p, surf, one)
    assert np.array_equal(rows, np.stack([one, one]))


TABLE_PROBE = """
import json
import numpy as np
from railwear.dynamics import kernels as k
# a contact table of three shifts, one resultant contact per wheel: radius, angle, N, f11, f22, f23, f33, position
wheel = [0.46, 0.46, 0.46, 0.03, 0.05, 0.08, 5e4, 5.2e4, 5.5e4, 8e6, 8.1e6, 8.3e6, 7e6, 7.1e6, 7.2e6,
         1e4, 1.1e4, 1.2e4, 1e2, 1.1e2, 1.2e2, 0.0, 1e-3, 2e-3]
surf = np.array(wheel + wheel)
p = np.zeros(k.TW_N_PARAMS)
p[[k.TW_SPEED, k.TW_MASS, k.TW_YAW_INERTIA, k.TW_LATERAL_STIFFNESS, k.TW_YAW_STIFFNESS, k.TW_HALF_GAUGE,
   k.TW_FRICTION, k.TW_CREEP_SCALE, k.TW_Y_MIN, k.TW_DY, k.TW_N_POINTS, k.TW_OUTSIDE_STIFFNESS]] = [
    40.0, 1022.0, 678.0, 1.8e6, 2e6, 0.75, 0.3, 1.0, -0.01, 0.01, 3, 1e8]
y = np.array([4e-3, 1e-3, 0.02, -0.03])
resultant, points = np.zeros(4), np.zeros(4)
k.rhs(k.KIND_TABLE_WHEELSET, 0.0, y, p, surf, resultant)
before = len(k._strip_point.signatures)
k.rhs(k.KIND_TABLE_POINTS, 0.0, y, p, surf, points)
print(json.dumps({"resultant": list(resultant), "points": list(points), "strips_typed": [before,
                  len(k._strip_point.signatures)]}))
"""


def test_a_table_without_contacts_compiles_no_strips(tmp_path):
    """The table wheelset on a table of per-wheel resultants (``KIND_TABLE_WHEELSET``, a hertz
    table) is compiled without the contacts' path and its strip-wise FASTSIM; the kind that has
    them (``KIND_TABLE_POINTS``) gives the same right-hand side to the bit on that table."""
    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path / "cache"))
    done = subprocess.run([sys.executable, "-c", TABLE_PROBE], env=env, capture_output=True, text=True, check=True)
    result = json.loads(done.stdout.splitlines()[-1])
    assert result["strips_typed"] == [0, 1]  # [1, 1] before issue 23's seventh round
    assert result["resultant"] == result["points"] and all(np.isfinite(result["resultant"]))
    assert result["resultant"][2] != 0.0
