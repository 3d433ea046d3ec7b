"""The frozen-geometry figures (paper Figs 4, 7, 8) from the built-in 'stepwise' scenario, headless."""

import numpy as np
import pytest
from typer.testing import CliRunner

from railwear.cli import app
from railwear.geometry.wear_surface import WearSurface
from railwear.longterm.disk_wheel import surface_wear


@pytest.mark.parametrize("name", ["teeth", "wear-surface", "fitted-h"])
def test_figure_command_writes_the_png(tmp_path, name):
    result = CliRunner().invoke(app, ["figure", name, "-o", str(tmp_path)])
    assert result.exit_code == 0, result.output
    assert (tmp_path / f"{name}.png").stat().st_size > 10_000


def test_unknown_figure_is_a_usage_error(tmp_path):
    result = CliRunner().invoke(app, ["figure", "fig99", "-o", str(tmp_path)])
    assert result.exit_code == 2
    assert "unknown name" in result.output


def test_surface_wear_removes_beta_times_the_frictional_energy(wheel_220, rough_u0):
    beta = 5.3e-9 / 7850.0
    surface = WearSurface(wheel_220.radius, 90, np.linspace(-0.01, 0.01, 9))
    surface, volume = surface_wear(wheel_220, rough_u0, beta, surface, turns=3, per_turn=400, lateral_half_axis=0.005)
    assert surface.removed_volume() == pytest.approx(volume, rel=1e-12)
    # the round wheel's steady power over the time of three turns, within the vertical dynamics' share
    m = wheel_220
    steady = beta * abs(m.traction_torque / m.radius * m.steady_creepage()) * 3 * 2 * np.pi * m.radius
    assert volume == pytest.approx(steady, rel=0.05)
    # the tread outside the band is untouched
    assert np.all(surface.depth[:, [0, -1]] == 0)
