"""The ``tegraph`` command line: parse, call the library, print.

No analysis happens here. Exit status: 0 live and consistent, 1 the analysis
found a deadlock, an unbounded place or an overrun, 2 the input was refused
(one line on stderr naming the file, the key path and what is expected).
"""

from __future__ import annotations

import sys
from pathlib import Path
from typing import Optional

import typer

from .errors import InputError, TegraphError

app = typer.Typer(
    add_completion=False,
    pretty_exceptions_enable=False,
    rich_markup_mode=None,
    no_args_is_help=True,
    help="Deadlocks, periods and overruns of synchronized real-time task sets, "
         "by (max,+) algebra on timed event graphs.",
)


@app.callback()
def _commands() -> None:
    """Deadlocks, periods and overruns of synchronized real-time task sets."""


def _fail(message: str) -> None:
    typer.echo(f"tegraph: error: {message}", err=True)
    raise typer.Exit(2)


@app.command()
def analyze(
    file: Path = typer.Argument(..., help="Skeleton file (.yaml, .yml or .json)."),
    json_out: bool = typer.Option(False, "--json", help="Print the JSON report (docs/skeleton.md §5)."),
    csv_dir: Optional[Path] = typer.Option(None, "--csv", help="Write tasks.csv and groups.csv here."),
    force: bool = typer.Option(False, "--force", help="Overwrite existing CSV files."),
    max_steps: int = typer.Option(100_000, "--max-steps", min=1,
                                  help="Budget on the firing index of the dater simulation."),
) -> None:
    """Analyze a synchronization skeleton: liveness, periods, overruns, slack."""
    from .analysis import analyze as run_analysis
    from .io.skeleton_file import load_skeleton
    from .report import render_text, write_csv

    try:
        skeleton = load_skeleton(file)
        report = run_analysis(skeleton, max_steps=max_steps)
    except InputError as exc:
        _fail(str(exc))
    except TegraphError as exc:
        _fail(f"{file}: {exc}")
    if csv_dir is not None:
        try:
            write_csv(report, csv_dir, overwrite=force)
        except FileExistsError as exc:
            _fail(str(exc))
        except OSError as exc:
            _fail(f"cannot write CSV files to {csv_dir}: {exc.strerror}")
    typer.echo(report.to_json() if json_out else render_text(report), nl=not json_out)
    raise typer.Exit(report.exit_status)


# Further commands (reach, cycle-time, convert, fix, rules, timeline) are added
# below this line, one function each, in the same shape as `analyze`.


def main() -> None:
    """Console-script entry point."""
    try:
        app()
    except KeyboardInterrupt:
        typer.echo("tegraph: interrupted", err=True)
        sys.exit(130)


if __name__ == "__main__":  # pragma: no cover
    main()
