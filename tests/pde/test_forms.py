"""The wear-rate registry: built-in forms by name, and a new form registered by name reaches the solver."""

from dataclasses import dataclass

import numpy as np
import pytest

from railwear.errors import ScenarioError
from railwear.pde import (
    BuiltinRate, Cubic, DiskContact, Pointwise, Table, as_wear_rate, rate_names, register_rate,
    solve_evolution, wear_rate,
)


@register_rate
@dataclass(frozen=True)
class Quadratic(BuiltinRate):
    """``h = c0 + c1 s + c2 s²``: a form the package does not have (m, rad², m·rad⁴ per unit time)."""

    c0: float = -1e-3
    c1: float = 0.02
    c2: float = 0.5
    name = "test_quadratic"

    def at_speed(self, speed):
        return Pointwise(np.array([self.c0, self.c1, self.c2]))


def test_builtin_forms_are_selected_by_name():
    assert {"cubic", "disk_contact", "table", "test_quadratic"} <= set(rate_names())
    assert wear_rate("cubic", c1=0.1, c3=2.0) == Cubic(c1=0.1, c3=2.0)
    assert as_wear_rate("disk_contact") == DiskContact()
    s = np.linspace(-1.0, 2.0, 5)
    table = wear_rate("table", curvature=s, rate=0.5 * s)
    assert isinstance(table, Table)
    np.testing.assert_allclose(table(np.array([0.3])), [0.15], rtol=1e-12)


@pytest.mark.parametrize("call, message", [
    (lambda: as_wear_rate("nope"), "'cubic', 'disk_contact'"),
    (lambda: as_wear_rate("table"), "needs curvature, rate"),
    (lambda: wear_rate("cubic", c4=1.0), "unknown parameters c4"),
])
def test_bad_names_and_parameters_are_named(call, message):
    with pytest.raises(ScenarioError, match=message):
        call()


def test_a_name_cannot_be_taken_twice():
    @dataclass(frozen=True)
    class Other(BuiltinRate):
        name = "cubic"

        def at_speed(self, speed):
            return Pointwise(np.zeros(1))

    with pytest.raises(ValueError, match="taken by Cubic"):
        register_rate(Other)


def test_registered_form_is_solved_by_name():
    """The compiled run of the registered name equals the Python run of the same formula; the
    quadratic term matters (without it the result differs by far more than the tolerance)."""
    x = 2 * np.pi * np.arange(64) / 64
    u0 = 1e-3 * np.cos(2 * x) + 5e-4 * np.cos(5 * x)
    form = Quadratic()
    run = dict(t_end=0.1, speed=0.0, epsilon=1e-4, n_save=5, dt=1e-3)
    by_name = solve_evolution(u0, h="test_quadratic", **run)
    by_formula = solve_evolution(
        u0, h=lambda s, u, ux, v: form.c0 + form.c1 * s + form.c2 * s**2, **run)
    without = solve_evolution(u0, h=Cubic(c0=form.c0, c1=form.c1), **run)
    assert by_name.attrs["h_form"] == "test_quadratic"
    np.testing.assert_allclose(by_name.u.values, by_formula.u.values, rtol=0, atol=1e-12)
    assert np.max(np.abs(by_name.u.values - without.u.values)) > 1e-7
    tuned = solve_evolution(u0, h=wear_rate("test_quadratic", c2=0.0), **run)
    np.testing.assert_allclose(tuned.u.values, without.u.values, rtol=0, atol=1e-12)
