"""The scalar path of Kalker's coefficients (one contact: FASTSIM's single call) gives the numbers
of the array path bit for bit."""

import numpy as np

from railwear.contact import kalker
from railwear.contact.fastsim import _flexibilities_scalar, fastsim, flexibilities


def test_scalar_coefficients_equal_the_array_path_bit_for_bit():
    rng = np.random.default_rng(5)
    nodes = np.arange(1, 11) * 0.1
    aob = np.concatenate([np.exp(rng.uniform(np.log(1e-4), np.log(1e4), 20000)), nodes, 1 / nodes, [0.0999999, 10.0001]])
    nu = np.concatenate([rng.uniform(0.0, 0.5, 20000), np.tile([0.0, 0.25, 0.49], 8)[: nodes.size * 2 + 2]])
    ref = kalker._kalker_many(aob, nu)
    got = np.array([kalker._kalker_scalar(float(g), float(n)) for g, n in zip(aob, nu)]).T
    assert np.array_equal(got, ref)
    one = kalker.kalker_coefficients(0.37, 0.28)
    assert all(isinstance(c, np.floating) for c in one)
    assert np.array_equal(np.array(one)[:, None], np.array(kalker.kalker_coefficients(np.array([0.37]), 0.28)))


def test_single_fastsim_uses_the_array_flexibilities_bit_for_bit():
    rng = np.random.default_rng(6)
    for a, b, nu in zip(rng.uniform(1e-3, 1e-2, 200), rng.uniform(1e-3, 1e-2, 200), rng.uniform(0.0, 0.49, 200)):
        assert _flexibilities_scalar(a, b, 8e10, nu) == tuple(float(v) for v in flexibilities(a, b, 8e10, nu))
    r = fastsim(6e-3, 4e-3, 80e3, 1e-3, -5e-4, 0.1, 0.3, 8e10, 0.28)
    assert (r.L1, r.L2, r.L3) == tuple(float(v) for v in flexibilities(6e-3, 4e-3, 8e10, 0.28))
