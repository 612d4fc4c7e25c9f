"""The vendored reference data is a verbatim copy of the team's shared anchors."""

from __future__ import annotations

import hashlib

import pytest

from tests.paths import SHARED_ANCHORS, VENDORED_ANCHORS


def _digests(root):
    return {p.relative_to(root).as_posix(): hashlib.sha256(p.read_bytes()).hexdigest()
            for p in sorted(root.rglob("*")) if p.is_file()}


def test_copy_equals_the_shared_anchors():
    if not SHARED_ANCHORS.is_dir():
        pytest.skip(f"no shared anchors at {SHARED_ANCHORS} to compare with")
    assert _digests(VENDORED_ANCHORS) == _digests(SHARED_ANCHORS)


def test_copy_holds_the_files_the_tests_name():
    # The cases files every anchor test reads, and one file of each kind.
    for rel in ("maxplus/cases.json", "sdf/cases.json", "pnml/cases.json",
                "pnml/HouseConstruction-PT-00002.pnml", "teg/SemiHoward.teg"):
        assert (VENDORED_ANCHORS / rel).is_file(), rel
