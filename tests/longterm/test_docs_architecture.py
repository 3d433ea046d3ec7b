"""The worked example of docs/architecture.md runs and prints what it says."""

from helpers import doc_blocks, run_doc_block


def test_doc_block_prints_what_it_says():
    (code,) = doc_blocks("architecture.md")
    printed, expected = run_doc_block(code, "architecture.md")
    assert printed == expected and len(expected) == 2
