"""No history in the code: comments and docstrings say why, never when, by whom or how fast.

A date, a commit, an issue number, a session or a measured time in a comment is
true on the day it is written and stale soon after; figures live in
``benchmarks/results/`` and the documentation, history in ``CHANGELOG.md`` and
``git log``. Every comment and docstring of ``maxplus/``, ``tegraph/``,
``tests/`` and ``benchmarks/*.py`` is read (by :mod:`tokenize` and :mod:`ast`,
so code and strings that are data are left alone) and matched against the
patterns below. The patterns are a net, not a parser: they are tested on lines
that must and must not be caught, and a line a pattern wrongly catches is
rewritten rather than excused.
"""

from __future__ import annotations

import ast
import io
import re
import tokenize
from collections.abc import Iterator
from pathlib import Path

import pytest

from tests.paths import REPO

_NUMBER = r"\d(?:[\d,.]*\d)?"
_TIME = _NUMBER + r"\s*(?:µs|us|ns|ms|s|sec|seconds?|minutes?|hours?)\b"
_MEASURED = (r"(?:\d\s*m?s\s+CPU\b|CPU\s+time|\d\s*(?:times|x)\s+(?:faster|slower)|speed-?up"
             r"|measured|median|on\s+this\s+machine)")

PATTERNS: dict[str, re.Pattern[str]] = {
    "an issue number": re.compile(r"\bissues?\s+#?\d+", re.I),
    "a session or round of work": re.compile(
        r"\b(?:this|last|previous|earlier)\s+(?:sessions?|rounds?)\b"
        r"|\bsession(?:'s)?\s+(?:start|end)\b", re.I),
    "a date": re.compile(r"\b(?:19|20)\d\d-[01]\d-[0-3]\d\b"
                         r"|\b(?:Jan|Feb|Mar|Apr|May|Jun|Jul|Aug|Sep|Oct|Nov|Dec)[a-z]*\.?"
                         r"\s+(?:[0-3]?\d,?\s+)?(?:19|20)\d\d\b"),
    "a commit": re.compile(r"(?<![\w.])(?!\d+e\d+\b)(?=[0-9a-f]*[a-f])(?=[0-9a-f]*\d)"
                           r"[0-9a-f]{7,40}(?!\w)"),
    "a time in microseconds": re.compile(_NUMBER + r"\s*(?:µs|us|ns)\b"),
    "a time in seconds": re.compile(_NUMBER + r"(?:\s+s|\s*(?:sec|seconds?|minutes?))\b(?!-)"),
    "a measured cost": re.compile(
        r"\b(?:costs?|costing|took|spent|spends|saves?|saved|pays?|paid|some|about|~|≈)\s*"
        + _TIME, re.I),
    "a measurement": re.compile(_TIME + r".{0,60}" + _MEASURED + "|" + _MEASURED + r".{0,60}"
                                + _TIME, re.I),
    "a time before and after": re.compile(
        _NUMBER + r"\s*(?:µs|us|ms|s|MiB|MB)?\s*(?:->|→)\s*" + _NUMBER
        + r"\s*(?:µs|us|ms|s|MiB|MB)\b(?!\s+(?:period|clock|every))"),
    "a benchmark's name": re.compile(r"\b(?:groups|chain|chain-clocks|proc)-\d+k\b"),
}


def texts(path: Path) -> Iterator[tuple[int, str]]:
    """``(line, text)`` of every comment block and docstring of a Python file.

    A block of comments on consecutive lines is one text, and so is a docstring,
    its lines joined by spaces: a phrase cut by a line break is still read whole.
    """
    source = path.read_text(encoding="utf-8")
    block: list[str] = []
    start = last = 0
    for token in tokenize.generate_tokens(io.StringIO(source).readline):
        if token.type != tokenize.COMMENT:
            continue
        line = token.start[0]
        if block and line != last + 1:
            yield start, " ".join(block)
            block = []
        if not block:
            start = line
        block.append(token.string.lstrip("#:").strip())
        last = line
    if block:
        yield start, " ".join(block)
    for node in ast.walk(ast.parse(source)):
        body = getattr(node, "body", None)
        for statement in body if isinstance(body, list) else ():
            if (isinstance(statement, ast.Expr) and isinstance(statement.value, ast.Constant)
                    and isinstance(statement.value.value, str)):
                yield statement.lineno, " ".join(statement.value.value.split())


def findings(text: str) -> list[str]:
    """The kinds of history ``text`` holds (none for a comment that says why)."""
    return [kind for kind, pattern in PATTERNS.items() if pattern.search(text)]


def _files() -> list[Path]:
    found = [p for top in ("maxplus", "tegraph", "tests") for p in (REPO / top).rglob("*.py")
             if "data" not in p.relative_to(REPO).parts]
    return sorted(found + list((REPO / "benchmarks").glob("*.py")))


@pytest.mark.parametrize("text", [
    "# the one number parser (issue 21)",
    "# 2.5 -> 1.5 s CPU on groups-10k",
    "# importlib.metadata costs some 40 ms",
    "#: the analysis itself (0.21 s beside 0.44 s at 1,000 tasks)",
    "Python costs ~0.3 us per arc and iteration",
    "# the builder of commit c7d4bda",
    "measured 2026-11-29 on 2 cores",
    "# what this session changed",
    "a MemoryError after 17 s",
    "# before: 1.4 ms, median of 9",
])
def test_the_patterns_catch_history(text):
    assert findings(text), text


@pytest.mark.parametrize("text", [
    "# A (6 ms, priority 2) runs 0-6 and 10-16; B gets 6-10 and 16-18",
    "'NOT SCHEDULABLE (MT2 overruns at activation 3) -> schedulable ({MT1} 10 ms)'",
    "# lcm = 997*1009*1013*1019/1000 = 1038412611.331 ms",
    "@pytest.fixture(scope='session')",
    "ACM Transactions on Embedded Computing Systems 18(5s) (CASES), 2019.",
    "# 1e999999999 would take hours to expand: refused by its size",
    "# the sweep's small rounds, walked in Python; the next round lists them",
    "# One CPU, rate-monotonic: OBS.JL (1 ms) runs first; slower than 2 ms",
    "``{(x, s) : a_i·x - b_i·s <= 0, s >= 0}``",
    "# 0xdeadbeef and 1038412611331 are numbers",
])
def test_the_patterns_leave_the_why_alone(text):
    assert not findings(text), text


def test_no_comment_or_docstring_holds_history():
    found = [f"{path.relative_to(REPO)}:{line}: {', '.join(kinds)}: {text.strip()}"
             for path in _files() if path != Path(__file__)
             for line, text in texts(path) if (kinds := findings(text))]
    assert not found, "history in comments or docstrings:\n" + "\n".join(found)
