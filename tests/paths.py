"""Where the test data lives: the team's reference anchors, or the copy kept here."""

from __future__ import annotations

from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
SHARED_ANCHORS = REPO.parent / "shared" / "anchors"
"""The team's reference data, beside a checkout (read-only, the contract)."""
VENDORED_ANCHORS = REPO / "tests" / "data" / "anchors"
"""A verbatim copy kept in the repository, so that a clone alone can run the
suite; test_anchor_copy checks it is byte-identical to ``SHARED_ANCHORS``
wherever both exist."""
ANCHORS = SHARED_ANCHORS if SHARED_ANCHORS.is_dir() else VENDORED_ANCHORS
