"""The guide's pages on bodies, on bodies that change and on Monte Carlo studies run as written: their `>>>`
examples are doctests."""

from __future__ import annotations

import doctest
from pathlib import Path

import pytest

GUIDE = Path(__file__).resolve().parents[3] / "docs" / "guide"


@pytest.mark.parametrize("page", ["bodies.md", "changing.md", "montecarlo.md", "orbit.md"])
def test_the_guides_examples_run_as_written(page: str) -> None:
    path = GUIDE / page
    if not path.exists():
        pytest.skip(f"no docs/guide/{page} beside the tests")
    test = doctest.DocTestParser().get_doctest(path.read_text(encoding="utf-8"), {}, page,
                                               str(path), 0)
    assert len(test.examples) > 10
    runner = doctest.DocTestRunner(optionflags=doctest.NORMALIZE_WHITESPACE)
    runner.run(test)
    assert runner.summarize(verbose=False).failed == 0
