"""Measuring devices' CSV dialects: ';' or tab separators with a decimal comma, absolute radius
or diameter against the nominal diameter; each read to the same wheel as the plain file."""

import numpy as np
import pytest
from typer.testing import CliRunner

from railwear.cli import app
from railwear.errors import MeasuredFileError
from railwear.measured import read_measured

ANGLES = np.arange(0.0, 360.0, 10.0)
DEVIATION_UM = 10 * np.cos(np.radians(3 * ANGLES)) + 2.5 * np.sin(np.radians(7 * ANGLES))
NOMINAL = 0.84  # m


def write(tmp_path, header, values, sep=",", comma=False, name="wheel.csv"):
    rows = [f"{a:g}{sep}{v:.9f}" for a, v in zip(ANGLES, values)]
    if comma:
        rows = [r.replace(".", ",") for r in rows]
    path = tmp_path / name
    path.write_text("# device export\n" + header + "\n" + "\n".join(rows) + "\n", encoding="utf-8")
    return path


@pytest.fixture
def plain(tmp_path):
    return read_measured(write(tmp_path, "angle_deg,deviation_um", DEVIATION_UM, name="plain.csv"))


@pytest.mark.parametrize("header, values, sep, comma", [
    ("angle_deg;deviation_um", DEVIATION_UM, ";", True),  # semicolon and decimal comma
    ("angle_deg;deviation_um", DEVIATION_UM, ";", False),  # semicolon and point
    ("angle_deg\tdeviation_um", DEVIATION_UM, "\t", True),  # tab and decimal comma
    ("angle_deg;radius_mm", NOMINAL / 2 * 1e3 + DEVIATION_UM * 1e-3, ";", True),  # absolute radius
    ("angle_deg,diameter_mm", NOMINAL * 1e3 + 2 * DEVIATION_UM * 1e-3, ",", False),  # absolute diameter
    ("angle_deg;diameter_m", NOMINAL + 2 * DEVIATION_UM * 1e-6, ";", True),
])
def test_a_dialect_reads_as_the_plain_file(tmp_path, plain, header, values, sep, comma):
    atol = 1e-9 if header.endswith('_m') else 1e-12  # m: 9 decimals of the written unit
    angle, deviation = read_measured(write(tmp_path, header, values, sep, comma), nominal_diameter=NOMINAL)
    np.testing.assert_array_equal(angle, plain[0])
    np.testing.assert_allclose(deviation, plain[1], rtol=0, atol=atol)


def test_a_file_mixing_decimal_marks_is_refused_naming_line_and_column(tmp_path):
    path = write(tmp_path, "angle_deg;deviation_um", DEVIATION_UM, ";", True)
    lines = path.read_text().splitlines()
    lines[5] = lines[5].replace(",", ".")  # line 6: 40;-1.25 with a point among decimal commas
    path.write_text("\n".join(lines) + "\n")
    with pytest.raises(MeasuredFileError, match=r"wheel.csv line 6, column 2 \(deviation_um\): '-1.250000000' has a '.' "
                                                "where the file's numbers have a decimal comma"):
        read_measured(path)


def test_a_thousands_separator_is_not_a_decimal_mark(tmp_path):
    path = write(tmp_path, "angle_deg;radius_mm", NOMINAL / 2 * 1e3 + DEVIATION_UM * 1e-3, ";", True)
    path.write_text(path.read_text().replace("420,010", "1.420,010"))
    with pytest.raises(MeasuredFileError, match="has a '.' where"):
        read_measured(path, nominal_diameter=NOMINAL)


def test_an_absolute_column_needs_the_right_nominal(tmp_path):
    path = write(tmp_path, "angle_deg;radius_mm", NOMINAL / 2 * 1e3 + DEVIATION_UM * 1e-3, ";", True)
    with pytest.raises(MeasuredFileError, match="column 2: radius_mm is absolute, not a deviation; give nominal_diameter"):
        read_measured(path)
    with pytest.raises(MeasuredFileError, match="line 3, column 2: radius 420.01 mm .*a diameter in a radius column"):
        read_measured(path, nominal_diameter=NOMINAL / 2)  # a radius given as the nominal diameter
    with pytest.raises(MeasuredFileError, match=r"nominal_diameter: must be in \[0.1, 4\] m"):
        read_measured(path, nominal_diameter=840.0)  # mm given as m


def test_cli_forecast_reads_a_device_file_with_its_nominal(tmp_path):
    from test_forecast import scenario_text

    (tmp_path / "s.toml").write_text(scenario_text(10.0, samples=4))
    path = write(tmp_path, "angle_deg;diameter_mm", NOMINAL * 1e3 + 2 * DEVIATION_UM * 1e-3, ";", True)
    runner = CliRunner()
    r = runner.invoke(app, ["forecast", str(path), "--scenario", str(tmp_path / "s.toml"), "--nominal-diameter", "840mm",
                            "--set", "wheel.radius_m=0.42", "-o", str(tmp_path / "out")])  # the scenario's wheel is that wheel
    assert r.exit_code == 0, r.output
    ptp = np.ptp(DEVIATION_UM)
    assert "measured wheel: " in r.output and abs(float(r.output.split("measured wheel: ")[1].split()[0]) - ptp) < 0.5
    for value in ("5m", "840", "0mm"):
        r = runner.invoke(app, ["forecast", str(path), "--scenario", str(tmp_path / "s.toml"),
                                "--nominal-diameter", value, "-o", str(tmp_path / "bad")])
        assert r.exit_code == 2 and r.output.startswith("railwear: error: --nominal-diameter: ")
        assert r.output.count("\n") == 1 and not (tmp_path / "bad").exists()
