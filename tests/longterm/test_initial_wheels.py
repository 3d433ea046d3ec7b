"""Several wheels on one rail, each from its own starting surface (``[[initial.wheels]]``): the
scenario validates one entry per wheel; the Fourier technique evolves every wheel's harmonics
with the 2x2 rate matrix of the bogie (a shaped wheel ahead of a round one); the stepwise body
starts from each wheel's surface; the spectrum figure draws every wheel on its own floor;
`railwear run` takes such a file."""

import json
import subprocess
import sys

import numpy as np
import pytest
from scipy.linalg import expm

from railwear import api, plots
from railwear.errors import ScenarioError
from railwear.scenario import build, builtin_text, load_scenario, parse_scenario, scenario_hash

ORDER, AMPLITUDE = 8, 20e-6  # the leading wheel's polygon (m); the trailing wheel starts round
PER_WHEEL = f"""[[initial.wheels]]
kind = "harmonics"
orders = [{ORDER}]
amplitudes_um = [{AMPLITUDE * 1e6:g}]

[[initial.wheels]]
kind = "round"

"""


def bogie_text(initial=PER_WHEEL, positions="[0, 2.4]", replace=()):
    """The metro scenario as a bogie of wheelbase 2.4 m (four sleeper bays: both wheels see the
    same track), its ``[initial]`` replaced by ``initial``."""
    text = builtin_text("metro")
    start, end = text.index("[initial]"), text.index("[strategy]")
    text = text[:start] + initial + text[end:]
    text = text.replace('kind = "vehicle_track"', f'kind = "vehicle_track"\nwheel_positions_m = {positions}')
    for old, new in replace:
        assert old in text, old
        text = text.replace(old, new)
    return text


@pytest.fixture(scope="module")
def bogie():
    sc = parse_scenario(bogie_text())
    return sc, api.run(sc)


def harmonic(u, n):
    """The rfft coefficient of order ``n`` of ``u`` over its last axis (the linear model's convention)."""
    return np.fft.rfft(u, axis=-1)[..., n]


def test_the_shaped_wheel_grows_and_the_round_one_takes_what_the_rail_couples(bogie):
    """Order 8 on the two wheels evolves as ``ĉ(t) = expm(M t) ĉ(0)`` with ``M`` the bogie's 2x2
    rate matrix (an exponential computed apart from the run's eigen-decomposition), to 1e-10 of the
    leading wheel's harmonic at every saved time. The matrix is symmetric with equal diagonals
    ``a`` (reciprocity, the bay averaged), so from ``(c, 0)``: ``ĉ_1 = c e^{at} cosh(bt)``,
    ``ĉ_2 = c e^{at} sinh(bt)``; the trailing wheel's order 8 over the leading's is ``tanh(bt)``,
    and every other order stays round on both (under 1e-12 of the polygon)."""
    sc, ds = bogie
    technique = build.fourier_technique(sc)
    M = technique.rate_matrix([ORDER])[0]
    a, b = M[0, 0], M[0, 1]
    np.testing.assert_allclose([M[1, 1], M[1, 0]], [a, b], rtol=1e-10)
    seconds = ds.service_time.values
    c = harmonic(ds.u.values, ORDER)  # (time, wheel)
    c0 = harmonic(build.initial_wear(sc), ORDER)
    assert abs(c0[0]) > 0 and c0[1] == 0
    expected = np.array([expm(M * t) @ c0 for t in seconds])
    np.testing.assert_allclose(c, expected, rtol=0, atol=1e-10 * np.abs(c[:, :1]).max())
    np.testing.assert_allclose(c[:, 1] / c[:, 0], np.tanh(b * seconds), rtol=1e-10, atol=1e-12)
    # the leading wheel grows at its own rate a, modulated by cosh(bt) (measured: x2.5 over the run)
    np.testing.assert_allclose(c[:, 0], c0[0] * np.exp(a * seconds) * np.cosh(b * seconds), rtol=1e-10)
    others = np.delete(np.abs(np.fft.rfft(ds.u.values, axis=-1)[..., 1:]), ORDER - 1, axis=-1)
    assert others.max() < 1e-12 * np.abs(c).max()
    # both wheels' mean radius falls alike: the steady driver does not couple them
    np.testing.assert_allclose(ds.u.mean("angle").values[:, 0], ds.u.mean("angle").values[:, 1], rtol=1e-12, atol=1e-18)
    assert ds.u.dims == ("time", "wheel", "angle") and list(ds.wheel.values) == [0.0, 2.4]


def test_drifting_phases_leave_the_round_wheel_round():
    """Drifting phases average the coupling out: each wheel's harmonics grow at its own
    ``M̄_jj``, so the round wheel stays round (its shape under 1e-12 of the other's) and the
    shaped one's order 8 is ``c e^{M_11 t}`` to 1e-10."""
    sc = parse_scenario(bogie_text(positions="[0, 2.4]\nwheel_phases = \"drifting\""))
    ds = api.run(sc)
    c = harmonic(ds.u.values, ORDER)
    rate = build.fourier_technique(sc).wheel_rates([ORDER])[0, 0]
    np.testing.assert_allclose(c[:, 0], c[0, 0] * np.exp(rate * ds.service_time.values), rtol=1e-10)
    shape = ds.u - ds.u.mean("angle")
    assert float(np.abs(shape.isel(wheel=1)).max()) < 1e-12 * float(np.abs(shape.isel(wheel=0)).max())


def test_the_scenario_refuses_what_does_not_fit_by_name():
    """One entry per wheel; not beside the fields of [initial]; not for one wheel; not under the
    multiplier (its wheels run in one growing combination); orders on the solver grid per wheel."""
    cases = [
        (bogie_text(PER_WHEEL + '[[initial.wheels]]\nkind = "round"\n\n'),
         r"^scenario: initial\.wheels: one \[\[initial\.wheels\]\] per wheel of body\.wheel_positions_m \(2\)"),
        (bogie_text('[initial]\nkind = "round"\n\n' + PER_WHEEL),
         r"^scenario: initial\.kind: the wheels' surfaces are given"),
        (bogie_text(positions="[0]"), r"^scenario: initial\.wheels: one surface per wheel needs several wheels"),
        (bogie_text(replace=(('[strategy]\nkind = "fourier"', '[strategy]\nkind = "multiplier"'),)),
         r"^scenario: initial\.wheels: the multiplier strategy runs the wheels in one growing combination"),
        (bogie_text(PER_WHEEL.replace("orders = [8]", "orders = [300]")),
         r"^scenario: initial\.wheels\[0\]\.orders\[0\]: must be at most 255"),
            (bogie_text(PER_WHEEL.replace('kind = "round"', 'kind = "roundish"')),
             r"^scenario: field 'initial\.wheels\[1\]\.kind': Input should be"),
    ]
    for text, message in cases:
        with pytest.raises(ScenarioError, match=message):
            parse_scenario(text)


def test_the_hash_leaves_the_field_out_while_unset_and_one_wheel_paths_refuse_it(bogie):
    """``initial.wheels`` unset leaves the hash of every earlier scenario as it was (the metro's is
    held in tests/test_months.py); set, it changes it. Paths that start from one wheel refuse it
    in one line naming it."""
    sc, _ = bogie
    plain = parse_scenario(bogie_text('[initial]\nkind = "round"\n\n'))
    assert "wheels" not in plain.applicable()["initial"] and scenario_hash(plain) != scenario_hash(sc)
    with pytest.raises(ScenarioError, match=r"^initial\.wheels: railwear load \(the shaped wheel leads"):
        from railwear.maintenance import impact

        impact.wheel_load(sc, [70.0])


def test_the_stepwise_body_starts_from_each_wheel(tmp_path):
    """The small stepwise bogie (64 cells, 2 draws): ``u`` at the start is each wheel's own
    surface (the leading wheel's measured file, taken from the scenario's folder, and a round
    wheel), to round-off."""
    angle = np.arange(0, 360, 5.0)
    (tmp_path / "lead.csv").write_text("angle_deg,deviation_um\n" + "".join(
        f"{a:g},{10 * np.cos(np.radians(6 * a)):.9f}\n" for a in angle))
    initial = '[[initial.wheels]]\nkind = "measured"\nfile = "lead.csv"\n\n[[initial.wheels]]\nkind = "round"\n\n'
    text = bogie_text(initial, positions="[0, 2.4]\nsamples = 2\nrevolutions = 2\ntransient_revolutions = 1", replace=(
        ('[strategy]\nkind = "fourier"', '[strategy]\nkind = "stepwise"\nstep_limit_um = 10.0'),
        ("points = 512\nt_end = 5.0", "points = 64\nt_end = 0.02"), ("peak_to_peak_limit_mm = 0.1\n", ""),
        ("speed_scatter_kmh = 5.0", "speed_scatter_kmh = 0.0")))
    sc = parse_scenario(text, base_dir=tmp_path)
    u0 = build.initial_wear(sc)
    assert u0.shape == (2, 64) and not u0[1].any()
    np.testing.assert_allclose(np.abs(np.fft.rfft(u0[0]))[6] * 2 / 64, 10e-6, rtol=1e-3)
    ds = api.run(sc)
    assert ds.u.dims == ("time", "wheel", "angle")
    np.testing.assert_allclose(ds.u.isel(time=0).values, u0, rtol=0, atol=1e-18)


def test_the_spectrum_draws_each_wheel_on_its_own_floor(bogie):
    """Each wheel's floor is 40 dB under its own largest amplitude (stated in the legend), so the
    trailing wheel's end spectrum is drawn down to its floor, not the leading wheel's; its round
    start is said in the legend and not drawn."""
    _, ds = bogie
    ax = plots.spectrum(ds).axes[0]
    lines = {line.get_label(): line for line in ax.get_lines()}
    lead, trail = (float(ds.amplitude.isel(wheel=k).max()) / 1e-6 for k in (0, 1))
    assert lead > trail
    for where, largest in (("0", lead), ("2.4", trail)):
        floor = [line for label, line in lines.items() if label.startswith(f"wheel at {where} m: floor")]
        assert len(floor) == 1 and floor[0].get_ydata()[0] == pytest.approx(largest / 100, rel=1e-12)
        end = np.asarray(lines[f"wheel at {where} m, end"].get_ydata(), float)
        assert end.min() == pytest.approx(largest / 100, rel=1e-12) and end.max() == pytest.approx(largest, rel=1e-12)
    assert "wheel at 2.4 m, start: round (< 1 pm)" in lines
    assert len(lines["wheel at 2.4 m, start: round (< 1 pm)"].get_xdata()) == 0
    assert ax.get_ylim()[0] == pytest.approx(trail / 100 / 1.6, rel=1e-9)


def test_railwear_run_on_a_file_with_a_surface_per_wheel(tmp_path):
    """The user path in a fresh interpreter: the bogie file runs, the summary names each wheel;
    three entries for two wheels are one line naming the field, exit 2."""
    command = [sys.executable, "-m", "railwear", "run", "-o", str(tmp_path / "out"), "--no-figures"]
    (tmp_path / "bogie.toml").write_text(bogie_text())
    out = subprocess.run(command + [str(tmp_path / "bogie.toml")], capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stderr
    runs = json.loads((tmp_path / "out" / "summary.json").read_text())["runs"]
    assert [r["wheel"] for r in runs] == [0.0, 2.4] and [r["dominant_order"] for r in runs] == [ORDER, ORDER]
    assert runs[1]["peak_to_peak_initial_um"] == 0 and runs[1]["round_at_start"]
    assert "wheel at 2.4 m, 70 km/h: " in out.stdout
    import xarray as xr

    with xr.open_dataset(tmp_path / "out" / "result.nc") as ds:  # the stored scenario reads back, same hash
        stored = parse_scenario(ds.attrs["scenario"])
        assert stored.initial.wheels is not None and scenario_hash(stored) == ds.attrs["scenario_hash"]
    (tmp_path / "bad.toml").write_text(bogie_text(PER_WHEEL + '[[initial.wheels]]\nkind = "round"\n\n'))
    bad = subprocess.run(command + [str(tmp_path / "bad.toml")], capture_output=True, text=True, timeout=300)
    assert bad.returncode == 2 and "Traceback" not in bad.stderr and bad.stderr.strip().count("\n") == 0
    assert "initial.wheels: one [[initial.wheels]] per wheel" in bad.stderr


def test_the_docs_example_is_what_its_script_prints(tmp_path, capsys):
    """docs/initial_wheels.py (the metro bogie, leading wheel re-profiled, trailing wheel round):
    its table is the one in docs/vehicle_track.md, and its figure is written."""
    import importlib.util
    from pathlib import Path

    docs = Path(__file__).resolve().parents[2] / "docs"
    spec = importlib.util.spec_from_file_location("initial_wheels", docs / "initial_wheels.py")
    script = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(script)
    script.main(tmp_path / "spectrum.png")
    table = [line for line in capsys.readouterr().out.splitlines() if line.startswith("|")]
    text = (docs / "vehicle_track.md").read_text()
    assert len(table) == 4 and all(line in text for line in table)
    assert (tmp_path / "spectrum.png").stat().st_size > 10_000


def test_the_direct_bogie_follows_the_linear_matrix_from_each_wheels_start():
    """The direct strategy on the time-domain track (64 cells, A = 2e4, 500 km), the leading wheel
    with 20 um of order 8 and the trailing one round: over the run each wheel's order-8 change is
    ``expm(M t) ĉ(0) - ĉ(0)`` of the linear bogie (its rates with the grid's ``sinc³(8/64)``),
    the leading wheel's within 2 % and the round wheel's pickup within 10 % (measured -1.3 % and
    -8.1 %; docs/vehicle_track_time.md holds each wheel's orders within 9 %)."""
    text = bogie_text(positions="[0, 2.4]\ntransient_revolutions = 1", replace=(
        ('[strategy]\nkind = "fourier"', '[strategy]\nkind = "direct"\nacceleration_factor = 20000.0'),
        ("points = 512\nt_end = 5.0", "points = 64\nt_end = 0.005"), ("peak_to_peak_limit_mm = 0.1\n", ""),
        ("speed_scatter_kmh = 5.0", "speed_scatter_kmh = 0.0")))
    sc = parse_scenario(text)
    ds = api.run(sc)
    M = build.fourier_technique(parse_scenario(bogie_text())).rate_matrix([ORDER])[0] * np.sinc(ORDER / 64) ** 3
    seconds = float(ds.distance[-1]) * 1e3 / build.one_speed(sc)
    c0 = harmonic(build.initial_wear(sc), ORDER)
    ratio = (harmonic(ds.u.isel(time=-1).values, ORDER) - c0) / (expm(M * seconds) @ c0 - c0)
    assert abs(ratio[0] - 1) < 0.02 and abs(ratio[1] - 1) < 0.10
