"""Shared test fixtures: where the external reference data lives."""

from __future__ import annotations

from pathlib import Path

import pytest

from tests.paths import ANCHORS


@pytest.fixture(scope="session")
def anchors() -> Path:
    """The read-only reference data directory (never edited by tests)."""
    assert ANCHORS.is_dir(), f"reference data not found at {ANCHORS}"
    return ANCHORS


from hypothesis import settings  # noqa: E402

# "ci" caps every property test so the whole suite stays within minutes on
# two cores; "dev" (default) lets the committed max_examples stand.
settings.register_profile("ci", max_examples=60, deadline=None)
settings.register_profile("dev", deadline=None)
settings.load_profile(__import__("os").environ.get("HYPOTHESIS_PROFILE", "dev"))
