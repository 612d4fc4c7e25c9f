"""The project's own rules, run by the test command: floors, dependencies, lint.

Each tool reads its configuration from ``pyproject.toml``; a failure prints
the tool's own report (the broken import, the undeclared dependency, the
lint finding).
"""

from __future__ import annotations

import shutil
import subprocess
import sys

import pytest

from tests.paths import REPO


def _run(*command: str) -> subprocess.CompletedProcess:
    return subprocess.run(command, cwd=REPO, capture_output=True, text=True, timeout=300)


def test_floors_and_independence_hold():
    """import-linter: no import upwards, io and analysis independent, maxplus apart."""
    tool = shutil.which("lint-imports")
    assert tool, "lint-imports is part of the test extra: pip install -e '.[test]'"
    # The checkout, not an installed copy, is what the contracts must hold for.
    done = _run(sys.executable, "-c",
                "import sys; sys.path.insert(0, '.'); "
                "from importlinter.cli import lint_imports_command; lint_imports_command()")
    assert done.returncode == 0, done.stdout + done.stderr


def test_every_dependency_declared_and_used():
    """deptry: every import is declared in pyproject.toml, every declared package imported."""
    done = _run(sys.executable, "-m", "deptry", ".")
    assert done.returncode == 0, done.stdout + done.stderr


def test_types_check():
    """mypy with the [tool.mypy] configuration: strict on maxplus, basic on tegraph.

    The cache is the project's ``.mypy_cache``: mypy keys it by its version, options and
    each file's content, so a warm run finds in a moment what a cold one finds in many.
    """
    done = _run(sys.executable, "-m", "mypy", "--config-file", "pyproject.toml")
    assert done.returncode == 0, done.stdout + done.stderr


def test_maxplus_is_the_strict_one():
    """No override loosens maxplus: only tegraph modules switch parts of `strict` off."""
    tomllib = pytest.importorskip("tomllib", reason="tomllib is in Python 3.11 and later")
    mypy = tomllib.loads((REPO / "pyproject.toml").read_text())["tool"]["mypy"]
    assert mypy["strict"] is True and "maxplus" in mypy["files"]
    for override in mypy.get("overrides", []):
        loosened = [k for k, v in override.items() if v is False or k == "ignore_errors"]
        if loosened:
            modules = override["module"]
            modules = [modules] if isinstance(modules, str) else modules
            assert all(m.split(".")[0] == "tegraph" for m in modules), (modules, loosened)


@pytest.mark.parametrize("tree", ["maxplus", "tegraph", "tests", "benchmarks"])
def test_ruff_clean(tree):
    """ruff, with the rule set chosen in pyproject.toml."""
    done = _run(sys.executable, "-m", "ruff", "check", "--no-cache", tree)
    assert done.returncode == 0, done.stdout + done.stderr


def test_analyze_with_advice_does_not_load_networkx():
    """networkx is some 300 modules of start-up: only the code that needs it loads it
    (the advice re-forming groups, the readers of its graphs), not a plain analysis.
    computed_torque has design-rule findings, so the advice runs."""
    done = _run(sys.executable, "-c",
                "import sys; sys.path.insert(0, '.')\n"
                "from tegraph.api import analyze\n"
                "from tegraph.report import render_text\n"
                "r = analyze('examples/computed_torque.yaml')\n"
                "assert r.design is not None and r.design.rules\n"
                "render_text(r)\n"
                "print('networkx' in sys.modules)")
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "False"


def test_the_analyze_command_loads_no_other_command_code():
    """Renderers resolve on first use: analyze imports no explore, timeline or baseline code.

    (``analysis.sensitivity.margins`` is analyze's own "can grow by" column, so it stays.)
    """
    done = _run(sys.executable, "-c",
                "import sys; sys.path.insert(0, '.')\n"
                "from tegraph.api import analyze\n"
                "from tegraph.report import render_text, to_json, write_csv\n"
                "from tegraph import Skeleton\n"
                "r = analyze(Skeleton.from_dict({'tasks': {'A': {'duration': 1, 'period': 3}}}))\n"
                "render_text(r); to_json(r)\n"
                "print(sorted(m for m in sys.modules if m.startswith('tegraph')))")
    assert done.returncode == 0, done.stderr
    loaded = done.stdout
    for family in ("tegraph.design.explore", "tegraph.design.timeline",
                   "tegraph.analysis.baselines.timed_reachability", "tegraph.report.explore",
                   "tegraph.report.timeline", "tegraph.report.sensitivity",
                   "tegraph.analysis.sensitivity.core", "tegraph.analysis.sensitivity.results",
                   "tegraph.analysis.sensitivity.on_processors"):
        assert family not in loaded, family
