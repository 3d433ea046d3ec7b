"""'railwear plot' in a fresh interpreter draws a plan.nc and a load.nc again: their figures and
their one-file reports."""

import subprocess
import sys

import pytest

from railwear import results

pytestmark = pytest.mark.e2e


def test_plot_redraws_a_plan_and_a_load_from_their_files(tmp_path):
    sys.path.insert(0, str(__import__("pathlib").Path(__file__).parents[1] / "maintenance"))
    from test_reports import small_load, small_plan

    results.write_netcdf(small_plan(), tmp_path / "plan.nc")
    results.write_netcdf(small_load(), tmp_path / "load.nc")
    runs = {name: subprocess.Popen([sys.executable, "-m", "railwear", "plot", str(tmp_path / f"{name}.nc"), "-o",
                                    str(tmp_path / name)], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                                   stdin=subprocess.DEVNULL)
            for name in ("plan", "load")}  # side by side: each pays the interpreter's start-up
    for name, process in runs.items():
        out, err = process.communicate(timeout=300)
        assert process.returncode == 0 and "Traceback" not in err, err
        assert f"wrote {tmp_path / name / f'{name}.html'}" in out
    assert (tmp_path / "plan" / "plan.png").is_file()
    assert (tmp_path / "load" / "load-peak.png").is_file() and (tmp_path / "load" / "load-trace.png").is_file()
