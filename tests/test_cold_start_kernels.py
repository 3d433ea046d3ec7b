"""A cold cache compiles each evolution-loop kernel once, and Kalker's coefficients not at all
(issue 12, item 4).

Not timing tests: they check what a first run types or compiles."""

import numba
import numpy as np
from helpers import cold_probe

from railwear.pde import Cubic, solve_evolution, solver

PROBE = """
from railwear.contact import contact_constants, flexibilities, kalker_coefficients, linear_creep_forces
from railwear.contact import kalker

c = kalker_coefficients(np.geomspace(0.01, 100.0, 50), np.linspace(0.0, 0.45, 50))  # below the table too
contact_constants(1e5, 1 / 0.92, 1 / 0.6, 2.1e11, 0.28)
flexibilities(np.array([6e-3, 2e-3]), np.array([4e-3, 7e-3]), 8e10, 0.28)
linear_creep_forces(6e-3, 4e-3, 1e-3, 0.0, 0.0, 8e10, 0.28)
dispatchers = [name for name, f in vars(kalker).items() if isinstance(f, Dispatcher)]
print(json.dumps({"compiled": compiled, "dispatchers": dispatchers, "finite": bool(np.all(np.isfinite(c)))}))
"""


def test_kalkers_coefficients_compile_nothing(tmp_path):
    """Kalker's coefficients (every command builds a contact) are numpy: a cold call compiles no
    kernel (main compiled them, 2-3 s of every first run)."""
    result = cold_probe(PROBE, tmp_path / "cache")
    assert result["finite"]
    assert result["dispatchers"] == []
    assert result["compiled"] == []


def _layouts(monkeypatch, u0):
    """The numba types the solver hands the compiled loop for ``u0`` (the loop itself stubbed)."""
    seen = []

    def stub(v, n, *rest):
        seen.append(tuple(numba.typeof(a) for a in (v, n) + rest))
        return solver.OK, 0

    monkeypatch.setattr(solver, "advance_compiled", stub)
    solve_evolution(u0, 0.01, Cubic(c1=-1.0), np.array([10.0, 20.0]), 1e-3, n_save=3, dt=1e-3)
    return set(seen)


def _start():
    x = 2 * np.pi * np.arange(64) / 64
    return np.stack([1e-6 * np.cos(3 * x), 2e-6 * np.sin(5 * x)])


def test_the_loop_is_typed_once_whatever_the_start_layout(monkeypatch):
    """A start in Fortran order (a measured wheel's batch) and one in C order hand the compiled
    loop the same types, all C-ordered arrays: one compile, not one per layout (main passed the
    weights as views, 'A', and a Fortran start as 'F', and compiled the loop twice in a forecast)."""
    c_order = _layouts(monkeypatch, _start())
    f_order = _layouts(monkeypatch, np.asfortranarray(_start()))
    assert len(c_order) == 1 and c_order == f_order
    arrays = [t for t in next(iter(c_order)) if isinstance(t, numba.types.Array)]
    assert len(arrays) > 10 and all(t.layout == "C" for t in arrays)


def test_the_start_layout_does_not_change_the_numbers():
    u0 = _start()
    c_order = solve_evolution(u0, 0.05, Cubic(c1=-1.0, c3=-1e6), np.array([10.0, 20.0]), 0.05, n_save=3)
    f_order = solve_evolution(np.asfortranarray(u0), 0.05, Cubic(c1=-1.0, c3=-1e6), np.array([10.0, 20.0]), 0.05,
                              n_save=3)
    assert np.array_equal(c_order.u.values, f_order.u.values)
    assert not np.array_equal(c_order.u.values[-1], c_order.u.values[0])
