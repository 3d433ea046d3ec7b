"""Run every Python block of docs/contact.md and check the printed values against the comments."""

import pytest
from helpers import doc_blocks, run_doc_block

BLOCKS = doc_blocks("contact.md")


@pytest.mark.parametrize("index", range(len(BLOCKS)))
def test_doc_block_runs_and_prints_what_it_says(index):
    printed, expected = run_doc_block(BLOCKS[index], f"contact.md block {index}")
    for text in expected:
        assert any(text in p for p in printed), f"expected {text!r} in output {printed}"
