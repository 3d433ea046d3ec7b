"""A forecast under a scenario of another diameter says so or refuses (issue 22, item 6): an
840 mm wheel given with its nominal diameter is not read as the 920 mm wheel of the built-in
'forecast' scenario."""

import numpy as np
import pytest
from typer.testing import CliRunner

from railwear.cli import app
from railwear.errors import OptionError
from railwear.forecast import forecast_file


def wheel(path, diameter_mm=None):
    """10 um of order 8 round a wheel, as a deviation or, with ``diameter_mm``, as the diameter."""
    a = np.arange(0.0, 360.0, 2.0)
    d = 10.0 * np.cos(np.radians(8 * a))
    if diameter_mm is None:
        path.write_text("angle_deg,deviation_um\n" + "".join(f"{x:g},{y:.6f}\n" for x, y in zip(a, d)))
    else:
        path.write_text("angle_deg,diameter_mm\n"
                        + "".join(f"{x:g},{diameter_mm + 2e-3 * y:.6f}\n" for x, y in zip(a, d)))
    return path


def test_a_wheel_of_another_diameter_is_refused(tmp_path):
    path = wheel(tmp_path / "w.csv", 840.0)
    with pytest.raises(OptionError) as e:
        forecast_file(path, "forecast", nominal_diameter=0.84)
    said = str(e.value)
    assert said.startswith("--nominal-diameter: the measured wheel is 840 mm, the scenario's 920 mm "
                           "(wheel.radius_m = 0.46)") and "--set wheel.radius_m=0.42" in said
    done = CliRunner().invoke(app, ["forecast", str(path), "--scenario", "forecast", "--nominal-diameter", "840mm",
                                    "-o", str(tmp_path / "out")])
    assert done.exit_code == 2 and "railwear: error: --nominal-diameter: the measured wheel is 840 mm" in done.stderr
    assert not (tmp_path / "out" / "forecast.nc").exists()


@pytest.mark.parametrize("nominal, says", [
    ("840mm", "wheel diameter 840 mm, the scenario's (wheel.radius_m): the measured wheel's nominal diameter agrees"),
    (None, "wheel diameter 840 mm, the scenario's (wheel.radius_m); the measured wheel's is not given, so a wheel "
           "of another size is read as this one (--nominal-diameter checks it)"),
])
def test_the_forecast_says_which_diameter_it_read(tmp_path, nominal, says):
    path = wheel(tmp_path / "w.csv", None if nominal is None else 840.0)
    args = ["forecast", str(path), "--scenario", "metro", "--samples", "2", "--horizon-km", "1000",
            "--limit", "0.3mm", "-o", str(tmp_path / "out")]
    done = CliRunner().invoke(app, args + ([] if nominal is None else ["--nominal-diameter", nominal]))
    assert done.exit_code == 0, done.output
    assert f"\n  {says}\n" in done.stdout
