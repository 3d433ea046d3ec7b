"""Run every Python block of docs/contact.md and check the printed values against the comments."""

import contextlib
import io
import re
from pathlib import Path

import pytest

DOC = Path(__file__).resolve().parents[2] / "docs" / "contact.md"
BLOCKS = re.findall(r"```python\n(.*?)```", DOC.read_text(encoding="utf-8"), flags=re.S)


@pytest.mark.parametrize("index", range(len(BLOCKS)))
def test_doc_block_runs_and_prints_what_it_says(index):
    code = BLOCKS[index]
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        exec(compile(code, f"contact.md block {index}", "exec"), {})
    printed = [line.strip() for line in out.getvalue().splitlines()]
    # expected output: the comment at the end of a print(...) line, and "# ..." lines that follow
    # a print statement (one per printed line)
    expected = []
    after_print = False
    for line in code.splitlines():
        stripped = line.strip()
        if stripped.startswith("print("):
            after_print = True
            if "  # " in line:
                expected.append(line.split("  # ", 1)[1].strip())
            continue
        if after_print and stripped.startswith("# "):
            expected.append(stripped[2:].strip())
            continue
        if stripped and not stripped.startswith("#") and not line.startswith((" ", "\t")):
            after_print = False
    for text in expected:
        assert any(text in p for p in printed), f"expected {text!r} in output {printed}"
