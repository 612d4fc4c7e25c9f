"""No command writes over its input file, whatever the flags, also through a link.

Only ``fix`` may replace its input (its output is the repaired input), and only with
``--force``. Every other output (a drawing, a results file, a converted file, the CSV
files) that resolves to the skeleton file is refused before any work, in one line
naming the option, exit status 2, and the input is left byte for byte as it was.
"""

from __future__ import annotations

import os
import shutil
from pathlib import Path

import pytest
from typer.testing import CliRunner

from tegraph.cli import app
from tegraph.errors import InputError
from tegraph.io import load_skeleton
from tests.paths import REPO

EXAMPLES = REPO / "examples"
SKELETON = "tasks:\n  A: {duration: 1, period: 4}  # a comment the user keeps\n"


def _input(tmp_path: Path) -> Path:
    path = tmp_path / "s.yaml"
    path.write_text(SKELETON, encoding="utf-8")
    return path


def _link(tmp_path: Path, name: str, to: Path) -> Path:
    link = tmp_path / name
    link.symlink_to(to)
    return link


# (the command's arguments, with {in} the input and {out} the output; the option named)
WRITERS = [
    (["timeline", "{in}", "-o", "{out}", "--force"], "-o", ".png"),
    (["sensitivity", "{in}", "--vary", "A.duration", "--plot", "{out}", "--force"], "--plot",
     ".svg"),
    (["explore", "{in}", "--clock", "A.clock=4,8", "-o", "{out}", "--force"], "-o", ".csv"),
    (["explore", "{in}", "--clock", "A.clock=4,8", "--plot", "{out}", "--force"], "--plot",
     ".png"),
    (["convert", "{in}", "{out}", "--force"], "TARGET", ".dot"),
]


@pytest.mark.parametrize("args, option, suffix", WRITERS)
@pytest.mark.parametrize("through_a_link", [True, False], ids=["symbolic link", "hard link"])
def test_an_output_that_is_the_input_is_refused_with_force(tmp_path, args, option, suffix,
                                                           through_a_link):
    # before: with --force each of them wrote its drawing, CSV or DOT over s.yaml
    source = _input(tmp_path)
    out = tmp_path / ("out" + suffix)
    if through_a_link:
        out.symlink_to(source)
    else:  # another name of the same file
        os.link(source, out)
    argv = [a.format(**{"in": source, "out": out}) for a in args]
    result = CliRunner().invoke(app, argv)
    assert result.exit_code == 2, result.output
    (line,) = result.output.strip().splitlines()
    assert line.startswith(f"tegraph: error: {option}: ") and "is the input file" in line
    assert source.read_text(encoding="utf-8") == SKELETON


def test_a_converted_file_over_its_own_input_is_refused(tmp_path):
    source = _input(tmp_path)
    result = CliRunner().invoke(app, ["convert", str(source), str(source), "--force"])
    assert result.exit_code == 2 and "is the input file" in result.output
    assert source.read_text(encoding="utf-8") == SKELETON


def test_a_csv_file_that_is_the_input_is_refused(tmp_path):
    # before: analyze --csv DIR --force wrote tasks.csv through the link into s.yaml
    source = _input(tmp_path)
    out = tmp_path / "csv"
    out.mkdir()
    _link(out, "tasks.csv", source)
    result = CliRunner().invoke(app, ["analyze", str(source), "--csv", str(out), "--force"])
    assert result.exit_code == 2
    (line,) = result.output.strip().splitlines()
    assert line.startswith("tegraph: error: --csv: ") and "is the input file" in line
    assert "(through a symbolic link)" in line
    assert source.read_text(encoding="utf-8") == SKELETON


def test_fix_alone_replaces_its_input_and_only_with_force(tmp_path):
    # fig7b: a wrong port order, which fix repairs; its output named by a link to it
    source = tmp_path / "fig7b.yaml"
    shutil.copy(EXAMPLES / "fig7b_wrong_order.yaml", source)
    link = _link(tmp_path, "link.yaml", source)
    refused = CliRunner().invoke(app, ["fix", str(source), "-o", str(link)])
    assert refused.exit_code == 2 and "this is the input file; pass --force" in refused.output
    replaced = CliRunner().invoke(app, ["fix", str(source), "-o", str(link), "--force"])
    assert replaced.exit_code == 0, replaced.output
    assert load_skeleton(source).tasks["MT1"].outputs == ("d", "a")  # the repaired order


def test_the_one_definition(tmp_path):
    from tegraph.io import input_as_output, same_file

    source = _input(tmp_path)
    link = _link(tmp_path, "l.svg", source)
    assert same_file(link, source) and same_file(source, source)
    assert not same_file(tmp_path / "new.svg", source)
    input_as_output(tmp_path / "new.svg", [source], "output")  # no file yet: no input
    with pytest.raises(InputError, match="through a symbolic link") as info:
        input_as_output(link, [source], "output")
    assert info.value.where == "output"
