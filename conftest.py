"""Doctests of maxplus and tegraph write their example files under pytest's temporary
directory (which pytest prunes), not in the system's: ``tempfile.mkdtemp()`` in an
example then leaves nothing behind."""

from __future__ import annotations

import tempfile

import pytest


@pytest.fixture(autouse=True)
def _temporary_files_under_pytest(tmp_path_factory, monkeypatch):
    monkeypatch.setattr(tempfile, "tempdir", str(tmp_path_factory.mktemp("examples")))
