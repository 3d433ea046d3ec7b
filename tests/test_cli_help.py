"""The command line's help, version and ``python -m railwear``."""

import subprocess
import sys

import pytest
import typer
from typer.testing import CliRunner

import railwear
from railwear.cli import app

GROUP = typer.main.get_command(app)


def _flat(text):
    return " ".join(text.split())


@pytest.mark.parametrize("name", sorted(GROUP.commands))
def test_help_shows_every_text_as_written(name):
    """Every option's and argument's help, and the command's own, appear whole: no emoji for
    A:B:STEP's ':B:', square brackets kept."""
    command = GROUP.commands[name]
    result = CliRunner().invoke(app, [name, "--help"], terminal_width=200)
    assert result.exit_code == 0, result.output
    shown = _flat(result.output)
    texts = [p.help for p in command.params if getattr(p, "help", None)] + [command.help.split("\n\n")[0]]
    for text in texts:
        assert _flat(text) in shown, (text, result.output)
    assert all(ord(c) < 0x2000 for c in result.output), result.output  # no emoji, no box drawing


def test_range_options_read_a_b_step():
    result = CliRunner().invoke(app, ["fit", "--help"])
    assert "A:B:STEP" in result.output and "(default: the [service] peaks)" in _flat(result.output)


def test_version():
    result = CliRunner().invoke(app, ["--version"])
    assert result.exit_code == 0 and result.output == f"railwear {railwear.__version__}\n"


def test_python_m_railwear():
    done = subprocess.run([sys.executable, "-m", "railwear", "--version"], capture_output=True, text=True)
    assert done.returncode == 0 and done.stdout == f"railwear {railwear.__version__}\n", done.stderr


def test_readme_table_has_every_command():
    from pathlib import Path

    readme = (Path(__file__).resolve().parents[1] / "README.md").read_text(encoding="utf-8")
    table = readme.split("## Command line", 1)[1].split("\n\n", 2)[1]
    for name in GROUP.commands:
        assert f"| `railwear {name}" in table, name
    assert "| `railwear --version`" in table
