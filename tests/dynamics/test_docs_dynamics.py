"""Run the Python blocks of docs/dynamics.md; a print line's trailing comment is its output."""

import contextlib
import io
import re
from pathlib import Path

import pytest

DOC = Path(__file__).resolve().parents[2] / "docs" / "dynamics.md"
BLOCKS = re.findall(r"```python\n(.*?)```", DOC.read_text(encoding="utf-8"), flags=re.S)


def test_there_are_examples():
    assert BLOCKS


@pytest.mark.parametrize("index", range(len(BLOCKS)))
def test_doc_block_prints_what_it_says(index):
    code = BLOCKS[index]
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        exec(compile(code, f"dynamics.md block {index}", "exec"), {})
    printed = [line.strip() for line in out.getvalue().splitlines()]
    expected = [line.split("  # ", 1)[1].strip() for line in code.splitlines()
                if line.strip().startswith("print(") and "  # " in line]
    assert printed == expected
