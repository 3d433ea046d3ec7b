"""Run the Python blocks of docs/dynamics.md; a print line's trailing comment is its output."""

import pytest
from helpers import doc_blocks, run_doc_block

BLOCKS = doc_blocks("dynamics.md")


def test_there_are_examples():
    assert BLOCKS


@pytest.mark.parametrize("index", range(len(BLOCKS)))
def test_doc_block_prints_what_it_says(index):
    printed, expected = run_doc_block(BLOCKS[index], f"dynamics.md block {index}")
    assert printed == expected
