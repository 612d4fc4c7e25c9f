"""The calls of tegraph.api that cross floors, as a library user makes them."""

from __future__ import annotations

from fractions import Fraction
from pathlib import Path

import pytest

import tegraph
from tegraph import InputError
from tests.paths import REPO

TORQUE = REPO / "examples" / "computed_torque.yaml"


@pytest.mark.parametrize("path", [str(TORQUE), TORQUE])
def test_analyze_accepts_a_path_as_load_skeleton_would(path):
    # The same report as loading first: a newcomer's tegraph.analyze("file.yaml").
    by_path = tegraph.analyze(path)
    by_skeleton = tegraph.analyze(tegraph.load_skeleton(TORQUE))
    assert tegraph.to_json(by_path) == tegraph.to_json(by_skeleton)
    # By hand (the example's header): OBS.JL alone on its 1 ms clock, CO.JS in the
    # group of the 2 ms clock ctl.
    assert by_path.tasks["OBS.JL"].period == Fraction(1)
    assert by_path.tasks["CO.JS"].period == Fraction(2)


def test_analyze_of_something_else_names_load_skeleton():
    with pytest.raises(TypeError, match=r"skeleton: expected a Skeleton \(tegraph.load_skeleton"):
        tegraph.analyze({"tasks": {}})


def test_analyze_of_a_missing_file_is_an_input_error(tmp_path: Path):
    with pytest.raises(InputError, match="nothing.yaml"):
        tegraph.analyze(tmp_path / "nothing.yaml")
