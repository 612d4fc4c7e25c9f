"""The documentation builds, with every warning an error, and says what the code says.

Sphinx builds ``docs/`` into a temporary directory with ``-W`` and nitpicky
references: a broken cross-reference, a public name without a docstring, a page
outside every table of contents or a malformed docstring fails here. The test is
named so that it is collected first: it is the longest single test, and under
xdist it then runs beside the others instead of after them.
"""

from __future__ import annotations

import importlib.util
import re
import subprocess
import sys
from html.parser import HTMLParser

from tests.paths import REPO

DOCS = REPO / "docs"


def test_the_documentation_builds_with_warnings_as_errors(tmp_path):
    out = tmp_path / "html"
    done = subprocess.run(
        [sys.executable, "-m", "sphinx", "-b", "html", "-W", "--keep-going", "-n", "-q",
         "-d", str(tmp_path / "doctrees"), str(DOCS), str(out)],
        cwd=REPO, capture_output=True, text=True, timeout=900)
    assert done.returncode == 0, done.stdout + done.stderr
    pages = {p.relative_to(out).as_posix() for p in out.rglob("*.html")}
    for page in ("index.html", "tutorial.html", "skeleton.html", "reference/cli.html",
                 "reference/schema.html", "reference/api/analysis.html", "analysis.html",
                 "sensitivity.html", "explore.html", "architecture.html", "benchmarks.html",
                 "changelog.html", "howto/notebook.html"):
        assert page in pages, page
    # The reference describes the names a newcomer meets first, where they are defined.
    api = (out / "reference" / "api" / "api.html").read_text(encoding="utf-8")
    assert 'id="tegraph.api.analyze"' in api
    cli = _text(out / "reference" / "cli.html")
    for command in ("tegraph analyze", "tegraph sensitivity", "tegraph explore", "--max-events"):
        assert command in cli, command
    # each option with its own help, as --help prints it (not a bare parameter name)
    assert "--json Print the JSON report" in " ".join(cli.split()), "options lost their help"


def test_the_benchmarks_page_is_the_current_tables():
    spec = importlib.util.spec_from_file_location("current_tables",
                                                  REPO / "benchmarks" / "current_tables.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    assert (DOCS / "benchmarks.md").read_text(encoding="utf-8") == module.page(), (
        "docs/benchmarks.md is not the current tables: python benchmarks/current_tables.py")


class _Text(HTMLParser):
    def __init__(self) -> None:
        super().__init__()
        self.parts: list[str] = []

    def handle_data(self, data: str) -> None:
        self.parts.append(data)


def _text(path) -> str:
    parser = _Text()
    parser.feed(path.read_text(encoding="utf-8"))
    return " ".join(" ".join(parser.parts).split())


def test_the_tutorial_shows_its_files_as_they_are():
    """The tutorial's YAML blocks (which a reader of the plain Markdown sees too) are the
    files of docs/tutorial/ it runs, in its order."""

    text = (DOCS / "tutorial.md").read_text(encoding="utf-8")
    blocks = re.findall(r"```yaml\n(.*?)\n```", text, re.S)
    files = ["controller.yaml", "controller_deadlock.yaml", "controller_cpu.yaml"]
    assert blocks == [(DOCS / "tutorial" / f).read_text(encoding="utf-8").rstrip()
                      for f in files]
