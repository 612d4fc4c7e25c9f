"""Write ``docs/benchmarks.md``: the current table of each benchmark, headed by where it was run.

Each file of ``benchmarks/results/current/`` holds one benchmark's current figures: a
header (title, script, commit, date, machine, the log it comes from) between ``---``
lines, then a legend and the table. When a benchmark is run again, its file there is
replaced by the new table and the old one goes to the benchmark's log in
``benchmarks/results/`` (the history); then run this script. The test suite checks that
``docs/benchmarks.md`` is what this script writes.

    python benchmarks/current_tables.py
"""

from __future__ import annotations

from pathlib import Path

HERE = Path(__file__).resolve().parent
CURRENT = HERE / "results" / "current"
PAGE = HERE.parent / "docs" / "benchmarks.md"

INTRODUCTION = """\
# Benchmarks

The current figures of each benchmark, one table each, headed by the commit, the date and
the machine it was measured on. Speed is checked here, never by timed unit tests; peers
run side by side in one run (A B A B, medians, spread as min-max). The scripts are in
`benchmarks/`; each result's log in `benchmarks/results/` says how it was run, what else
shared the machine, and what came before. This page is written by
`python benchmarks/current_tables.py` from `benchmarks/results/current/`.
"""


def read(path: Path) -> tuple[dict[str, str], str]:
    """The header fields and the body of one current-results file."""
    text = path.read_text(encoding="utf-8")
    _, header, body = text.split("---\n", 2)
    pairs = (line.partition(":") for line in header.splitlines())
    fields = {k.strip(): v.strip() for k, _, v in pairs}
    return fields, body.strip()


def page() -> str:
    """The text of ``docs/benchmarks.md``."""
    parts = [INTRODUCTION]
    for path in sorted(CURRENT.glob("*.md")):
        fields, body = read(path)
        log = f"; log: `benchmarks/results/{fields['log']}`" if fields.get("log") else ""
        parts.append(f"## {fields['title']}\n\n*Commit {fields['commit']}, {fields['date']}, "
                     f"{fields['machine']}; `{fields['script']}`{log}.*\n\n{body}\n")
    return "\n".join(parts)


if __name__ == "__main__":
    PAGE.write_text(page(), encoding="utf-8")
    print(f"wrote {PAGE}")
