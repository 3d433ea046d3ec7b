"""docs/outputs.md's forecast worked example: the device file it describes, read and forecast,
prints what the page shows; the claims after it hold."""

import re

import numpy as np
import pytest
from typer.testing import CliRunner

from helpers import DOCS
from railwear import results
from railwear.cli import app

pytestmark = pytest.mark.filterwarnings("ignore::railwear.errors.ResolutionWarning")


def example():
    """``(file lines shown, the command's options, printed lines)`` of the page's text block."""
    (block,) = re.findall(r"```text\n(# wheel-23\.csv\n.*?)```", (DOCS / "outputs.md").read_text(encoding="utf-8"), re.S)
    lines = block.splitlines()
    k = next(i for i, line in enumerate(lines) if line.startswith("$ railwear forecast "))
    return lines[1:k], lines[k].split()[4:], lines[k + 1:]


def wheel_23(path):
    """The file as the page describes it: every 2 degrees, diameter in mm, decimal comma."""
    a = np.arange(0.0, 360.0, 2.0)
    d = 920 + 2e-3 * (10 * np.cos(np.radians(3 * a)) + 30 * np.cos(np.radians(11 * a) + 0.5))
    path.write_text("# wheel 23, bogie 2\nangle_deg;diameter_mm\n"
                    + "".join(f"{x:g};{y:.4f}\n".replace(".", ",") for x, y in zip(a, d)))
    return path


@pytest.fixture(scope="module")
def ran(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("wheel23")
    shown, args, printed = example()
    path = wheel_23(tmp / "wheel-23.csv")
    assert path.read_text().splitlines()[1:1 + len(shown) - 1] == shown[:-1] and shown[-1] == "..."
    result = CliRunner().invoke(app, ["forecast", str(path), *args, "-o", str(tmp / "out")])
    assert result.exit_code == 0, result.output
    return result.output, printed, results.read_netcdf(tmp / "out" / "forecast.nc"), path, tmp


def test_the_worked_example_prints_what_the_page_shows(ran):
    output, printed, _, _, tmp = ran
    lines = [line for line in output.splitlines() if not line.startswith(("railwear forecast:", "compiling"))]
    assert lines == printed + [f"wrote {tmp / 'out' / 'forecast.nc'}"]


def test_the_claims_after_it(ran):
    _, _, ds, path, tmp = ran
    crossed = np.isfinite(ds.crossing_distance.values)
    assert crossed.sum() == 4 and np.all(ds.speed_kmh.values[crossed] >= 245) and np.all(ds.speed_kmh.values[~crossed] < 245)
    text = (DOCS / "outputs.md").read_text(encoding="utf-8")
    said = re.search(r"`(already above the limit at 0 km[^`]*)`", text).group(1)
    result = CliRunner().invoke(app, ["forecast", str(path), "--scenario", "forecast", "--nominal-diameter", "920mm",
                                      "--limit", "26dB", "--samples", "16", "-o", str(tmp / "above")])
    assert result.exit_code == 0 and f"  {said}\n" in result.output
