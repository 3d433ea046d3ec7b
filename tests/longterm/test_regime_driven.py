"""The regime of a wheel driven by the other wheels on its rail (docs/outputs.md, "The summary and
the regime"): a wheel that starts round has no order of its own to read a growth from, so the rule
of orders present at the start called it stable however much it picked up through the rail. With
several wheels, a wheel round at the start and not at the end while another started out of round
is "driven by the other wheels"; a single wheel's label is as before."""

import json
import subprocess
import sys

import numpy as np
import xarray as xr

from railwear import results
from railwear.longterm import regime
from railwear.longterm.spectra import describe

from test_initial_wheels import AMPLITUDE, ORDER, bogie_text

LIFE = 50000.0  # km per unit normed time of the hand-made runs


def wheels_run(rows, times):
    """A hand-made result of several wheels on one rail: ``rows`` (one ``(time, angle)`` array of
    ``u`` in m per wheel) at normed ``times``, described and labelled by the one rule."""
    u = np.stack(rows, axis=1)
    ds = xr.Dataset({"u": (("time", "wheel", "angle"), u)},
                    coords={"time": times, "wheel": np.arange(len(rows)) * 2.5,
                            "angle": np.arange(u.shape[-1]) * 2 * np.pi / u.shape[-1],
                            "distance": ("time", times * LIFE)})
    ds["stop_time"] = ((), float(times[-1]))
    return describe(ds)


def polygon(t, order, start, growth_per_10000_km, points=128):
    """``start`` (m) of ``order`` growing ``growth_per_10000_km`` at normed times ``t``."""
    x = np.arange(points) * 2 * np.pi / points
    return start * np.exp(np.log1p(growth_per_10000_km) * LIFE / 1e4 * t)[:, None] * np.cos(order * x)[None, :]


def test_the_round_wheel_behind_a_shaped_one_is_driven_in_railwear_run(tmp_path):
    """The user path in a fresh interpreter, the bogie of tests/longterm/test_initial_wheels.py
    (20 um of order 8 on the leading wheel, the trailing one round, 2.4 m): the trailing wheel
    picks up order 8 through the rail (``tanh(bt)`` of the leading wheel's, ``b`` the coupling of
    the bogie's rate matrix, held to 1e-10 there; measured 28 um peak to peak, 0.28 of the leading
    wheel's, by 55 200 km), and is labelled driven, not stable (fails before); the leading wheel keeps
    polygonalising. The summary says where its out-of-round came from."""
    (tmp_path / "bogie.toml").write_text(bogie_text())
    out = subprocess.run([sys.executable, "-m", "railwear", "run", str(tmp_path / "bogie.toml"), "-o",
                          str(tmp_path / "out"), "--no-figures"], capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stderr
    runs = json.loads((tmp_path / "out" / "summary.json").read_text())["runs"]
    assert [r["regime"] for r in runs] == ["polygonalising", regime.DRIVEN]
    assert runs[1]["round_at_start"] and runs[1]["peak_to_peak_um"] > 1e6 * regime.ROUND_PEAK_TO_PEAK
    assert "wheel at 2.4 m, 70 km/h: driven by the other wheels, 8 maxima" in out.stdout
    assert "round at the start: its out-of-round came through the rail from the other wheels" in out.stdout
    with xr.open_dataset(tmp_path / "out" / "result.nc") as ds:
        c = np.fft.rfft(ds.u.isel(time=-1).values, axis=-1)[:, ORDER]
        assert ds.regime.attrs["rule"] == regime.REGIME_RULE and regime.DRIVEN in ds.regime.attrs["long_name"]
    assert abs(c[0]) * 2 / 512 > AMPLITUDE and 0.1 < abs(c[1] / c[0]) < 1  # tanh(bt): test_initial_wheels.py


def test_the_label_needs_another_wheel_that_started_out_of_round():
    """Hand-made runs of two wheels (order 8 on the first, 20 um growing 20 % per 10 000 km):
    a round second wheel that picks up 5 um is driven; one that stays round is stable; two wheels
    both round at the start, one picking up 1 um of noise, keep the single wheel's label (stable:
    no wheel to be driven by); the shaped wheel's label is its own, polygonalising."""
    t = np.linspace(0.0, 0.5, 11)
    shaped = polygon(t, 8, 20e-6, 0.20)
    picked = polygon(t, 8, 5e-6, 0.20) * (t / t[-1])[:, None]
    ds = wheels_run([shaped, picked], t)
    assert list(ds.regime.values) == ["polygonalising", regime.DRIVEN]
    assert list(wheels_run([shaped, np.zeros_like(shaped)], t).regime.values) == ["polygonalising", "stable"]
    noise = polygon(t, 3, 1e-6, 0.0) * (t / t[-1])[:, None]
    assert list(wheels_run([np.zeros_like(noise), noise], t).regime.values) == ["stable", "stable"]


def test_one_wheel_round_at_the_start_keeps_its_label():
    """A single wheel that starts round and ends with 5 um (no other wheel to be driven by) reads
    as before: stable, its orders absent at the start; the summary still says nothing grew from
    its start."""
    t = np.linspace(0.0, 0.5, 11)
    u = polygon(t, 8, 5e-6, 0.20) * (t / t[-1])[:, None]
    ds = xr.Dataset({"u": (("time", "angle"), u)},
                    coords={"time": t, "angle": np.arange(128) * 2 * np.pi / 128, "distance": ("time", t * LIFE)})
    ds["stop_time"] = ((), float(t[-1]))
    ds = describe(ds)
    assert str(ds.regime.values) == "stable" == results.wheel_regime(ds, LIFE)
