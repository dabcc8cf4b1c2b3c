"""A test of a one-chapter suite answers to ``-k <that chapter>``.

``make test-chapter CH=...`` selects a chapter's tests with ``-k CH``: a test parametrised by a
chapter has it in its name, but the tests of a suite built on one chapter (its module's
``CHAPTER``: the tamper course, the trust suite's and the engines' everyday tests) did not, and
were left out of that chapter's run.
"""

from __future__ import annotations

import pytest


@pytest.hookimpl(tryfirst=True)   # before -k deselects
def pytest_collection_modifyitems(items: list[pytest.Item]) -> None:
    for item in items:
        chapter = getattr(getattr(item, "module", None), "CHAPTER", None)
        params = getattr(getattr(item, "callspec", None), "params", {})
        if isinstance(chapter, str) and "chapter" not in params:
            item.extra_keyword_matches.add(chapter)
