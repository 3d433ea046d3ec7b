"""Several wheels on one rail (WheelsOnRail): the Fourier technique over the wheels of a bogie,
coupled through the rail's transfer receptance; each order's rate an eigenproblem over them."""

import numpy as np
import pytest

from railwear.longterm.fourier import Fourier
from railwear.longterm.vehicle_track import WheelsOnRail
from railwear.scenario import build, load_scenario

ORDERS = np.arange(2, 21)


@pytest.fixture(scope="module")
def metro():
    sc = load_scenario("metro")
    model, band = build.linear_model(sc, build.one_speed(sc))
    law = build.wear_law(sc)
    return model, law, band, Fourier.disk_wheel(model, law, band).rates(ORDERS)


def test_one_wheel_is_the_single_wheel_model(metro):
    model, law, band, single = metro
    lam, modes = WheelsOnRail(model, (0.0,)).rates(ORDERS, law, band)
    np.testing.assert_allclose(lam[:, 0], single, rtol=1e-12)  # measured 2e-14 (the bay unfolded)
    np.testing.assert_allclose(np.abs(modes), 1.0, rtol=1e-15)


def test_two_wheels_far_apart_are_two_independent_wheels(metro):
    """60 m apart the rail carries nothing from one to the other: both rates are the single wheel's."""
    model, law, band, single = metro
    lam, _ = WheelsOnRail(model, (0.0, 60.0)).rates(ORDERS, law, band)
    np.testing.assert_allclose(lam, np.column_stack([single, single]), rtol=1e-6)


def test_a_bogie_splits_each_order_into_in_phase_and_anti_phase(metro):
    """Wheelbase 2.4 m, four sleeper bays: the bay-averaged matrix is symmetric (reciprocity) with
    equal diagonals, so its combinations are the wheels in phase and in anti-phase, (1, ±1)/√2, to
    1e-10; at order 8 they grow at different rates (anti-phase +0.19, in phase +0.16 per 10 000 km,
    the single wheel's +0.18 between them: a split of 12 % of it, the mean 3.5 % below)."""
    model, law, band, single = metro
    lam, modes = WheelsOnRail(model, (0.0, 2.4)).rates(ORDERS, law, band)
    ratio = modes[:, 1, :] / modes[:, 0, :]
    np.testing.assert_allclose(np.abs(ratio), 1.0, atol=1e-10)
    assert np.all(np.isclose(ratio.real, 1.0, atol=1e-10) | np.isclose(ratio.real, -1.0, atol=1e-10))
    k = list(ORDERS).index(8)
    assert lam[k, 0].real > single[k].real > lam[k, 1].real and ratio[k, 0].real == pytest.approx(-1.0)
    assert 0.1 < (lam[k, 0].real - lam[k, 1].real) / single[k].real < 0.15


def test_where_the_coupling_is_weak_the_mean_of_the_pair_is_the_single_wheel(metro):
    """At 4.8 m the split is first order in the coupling (0.8 % of the rate at order 8), the mean's
    departure from the single wheel second order (measured at most 7e-4 over orders 2-20)."""
    model, law, band, single = metro
    lam, _ = WheelsOnRail(model, (0.0, 4.8)).rates(ORDERS, law, band)
    np.testing.assert_allclose(lam.real.mean(axis=1), single.real, rtol=1e-3)
    k = list(ORDERS).index(8)
    assert (lam[k, 0].real - lam[k, 1].real) / single[k].real > 5e-3


def test_positions_are_checked():
    sc = load_scenario("metro")
    model, _ = build.linear_model(sc, build.one_speed(sc))
    with pytest.raises(Exception, match="positions"):
        WheelsOnRail(model, (1.0, 2.0))


def test_the_docs_table_is_what_its_script_prints(capsys):
    """docs/vehicle_track.md's wheelbase table is docs/wheels_on_rail.py's output, row for row."""
    import runpy
    from pathlib import Path

    docs = Path(__file__).resolve().parents[2] / "docs"
    runpy.run_path(str(docs / "wheels_on_rail.py"), run_name="__main__")
    rows = [line for line in capsys.readouterr().out.splitlines() if line.startswith("| 0")]
    page = (docs / "vehicle_track.md").read_text(encoding="utf-8")
    assert len(rows) == 5 and all(row in page for row in rows)
