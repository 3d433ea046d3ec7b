"""Layer 1: the contact package stands without the dynamics (DESIGN.md, the shape of the code),
and its creep tables are FASTSIM's."""

import subprocess
import sys

import numpy as np

from railwear.contact import CREEP_CURVE_POINTS, fastsim, fastsim_creep_curve, fastsim_factor_table, kalker_coefficients


def test_contact_imports_nothing_of_the_layers_above():
    code = ("import sys, railwear.contact; "
            "print(sorted(m for m in sys.modules if m.startswith('railwear.') and not m.startswith("
            "('railwear.contact', 'railwear.errors', 'railwear.units', 'railwear._numba_cache'))))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "[]"


def test_creep_tables_are_fastsims_curve_and_its_factor_on_another_patch():
    curve, factor = fastsim_creep_curve(), fastsim_factor_table()
    assert curve.shape == factor.shape == (CREEP_CURVE_POINTS,) and not curve.flags.writeable
    r = np.linspace(0.0, 1.0, CREEP_CURVE_POINTS)
    i = 100
    s = r[i] / (1.0 - r[i])  # s = f11 xi / (mu N)
    a, b, normal, mu, shear, nu = 4e-3, 7e-3, 8e4, 0.25, 8.1e10, 0.3  # not the tabulated patch
    f11 = shear * a * b * float(kalker_coefficients(a / b, nu)[0])
    ratio = -fastsim(a, b, normal, s * mu * normal / f11, 0.0, 0.0, mu, shear, nu).Fx / (mu * normal)
    assert abs(curve[i] / ratio - 1) < 2e-3
    assert abs(factor[i] * s / curve[i] - 1) < 1e-12
    assert abs(factor[0] - (1 + 1 / (2 * 40**2))) < 1e-6  # FASTSIM's discretised slope, 40 strips
