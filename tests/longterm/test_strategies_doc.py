"""docs/strategies.py runs headless (its quick mode), and the comparison holds its shape."""

import subprocess
import sys
from pathlib import Path

import pytest

SCRIPT = Path(__file__).resolve().parents[2] / "docs" / "strategies.py"


@pytest.mark.slow
def test_strategies_script_writes_the_comparison(tmp_path):
    out = tmp_path / "strategies.md"
    subprocess.run([sys.executable, str(SCRIPT), "--quick", "--output", str(out)], check=True,
                   capture_output=True, env={"MPLBACKEND": "agg", "PATH": ""}, timeout=600)
    text = out.read_text()
    for strategy in ("direct", "stepwise", "Fourier", "phenomenological"):
        assert f"| {strategy} |" in text
    assert "## Targets" in text and "## Why" in text
