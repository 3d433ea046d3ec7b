"""``--format pdf|svg`` and ``--dpi`` on the commands that write figures (through ``plots.save``)."""

import pytest
import xarray as xr
from typer.testing import CliRunner

from railwear import plots, results
from railwear.cli import app
from test_cli_plot import _forecast


def _figure():
    fig, (ax,) = plots._figure(3, 2)
    ax.plot([0, 1], [0, 1])
    return fig


@pytest.mark.parametrize("fmt, magic", [("pdf", b"%PDF"), ("svg", b"<?xml")])
def test_save_writes_the_png_and_the_requested_format(tmp_path, fmt, magic):
    path = plots.save(_figure(), tmp_path / "f.png", fmt)
    assert path == tmp_path / f"f.{fmt}" and path.read_bytes().startswith(magic)
    assert (tmp_path / "f.png").read_bytes().startswith(b"\x89PNG")


def test_dpi_sets_the_png_size(tmp_path):
    from PIL import Image

    small, large = (Image.open(plots.save(_figure(), tmp_path / f"{d}.png", dpi=d)).size for d in (50, 200))
    assert small == (150, 100) and large == (600, 400)


def test_save_refuses_a_format_it_does_not_write(tmp_path):
    with pytest.raises(ValueError, match="format"):
        plots.save(_figure(), tmp_path / "f.png", "jpeg")


def test_plot_format_pdf_writes_a_pdf(tmp_path):
    results.write_netcdf(_forecast(), tmp_path / "forecast.nc")
    out = CliRunner().invoke(app, ["plot", str(tmp_path / "forecast.nc"), "--format", "pdf", "--dpi", "60"])
    assert out.exit_code == 0, out.output
    assert (tmp_path / "forecast.pdf").read_bytes().startswith(b"%PDF")
    assert "forecast.pdf" in out.output


@pytest.mark.parametrize("args, said", [(["--format", "jpeg"], "--format"), (["--dpi", "5"], "--dpi")])
def test_a_bad_format_or_dpi_is_a_one_line_error(tmp_path, args, said):
    results.write_netcdf(_forecast(), tmp_path / "forecast.nc")
    out = CliRunner().invoke(app, ["plot", str(tmp_path / "forecast.nc"), *args])
    assert out.exit_code == 2 and said in out.output


@pytest.mark.parametrize("command", ["run", "resume", "plot", "stability", "track", "sweep", "forecast",
                                     "hunting-map", "simulate", "figure", "fit"])
def test_every_figure_command_takes_format_and_dpi(command):
    out = CliRunner().invoke(app, [command, "--help"])
    assert "--format" in out.output and "--dpi" in out.output
