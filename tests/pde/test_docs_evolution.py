"""Run the Python block of docs/evolution.md and check the printed lines against its comments."""

from helpers import doc_blocks, run_doc_block


def test_doc_block_prints_what_it_says():
    (code,) = doc_blocks("evolution.md")
    printed, expected = run_doc_block(code, "evolution.md")
    assert printed == expected and expected
