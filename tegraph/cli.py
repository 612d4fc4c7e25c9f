"""The ``tegraph`` command line: parse, call the library, print.

No analysis happens here. Exit status: 0 live and consistent, 1 the analysis
found a deadlock, an unbounded place or an overrun, 2 the input was refused
(one line on stderr naming the file, the key path and what is expected).
Output files are checked before any work: a missing directory is never
created, an existing file is never replaced without ``--force``.
"""

from __future__ import annotations

import atexit
import gc
import os
import re
import sys
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Annotated, NoReturn

import typer

from .errors import InputError, TegraphError
from .io.formats import FORMATS, readable, writable
from .model.budgets import (
    DEFAULT_MAX_BYTES,
    DEFAULT_MAX_FIRINGS,
    DEFAULT_MAX_MEMORY,
    DEFAULT_MAX_STATES,
    MAX_EVENTS,
)

app = typer.Typer(
    add_completion=True,
    pretty_exceptions_enable=False,
    rich_markup_mode=None,
    no_args_is_help=True,
    help="Deadlocks, periods and overruns of synchronized real-time task sets, "
         "by (max,+) algebra on timed event graphs.",
)

def _version(value: bool) -> None:
    if value:
        from importlib.metadata import version

        from .api import compiled_kernels

        built = compiled_kernels()
        width = max(map(len, built))
        typer.echo(f"tegraph {version('tegraph')}")
        typer.echo(f"compiled kernels: {sum(built.values())} of {len(built)} built")
        for name, is_built in built.items():
            typer.echo(f"  {name:<{width}}  {'built' if is_built else 'NOT BUILT'}")
        if not all(built.values()):
            typer.echo("(without a kernel its reference runs: the same results, slower; "
                       "build them where a C compiler is found: pip install -e . in a checkout, "
                       "or python setup.py build_ext --inplace)")
        raise typer.Exit()


@app.callback()
def _commands(
    version: Annotated[bool, typer.Option("--version", callback=_version, is_eager=True,
                                          help="Print the version and which compiled "
                                               "kernels are built, and exit.")] = False,
) -> None:
    """Deadlocks, periods and overruns of synchronized real-time task sets.

    Every command prints a report whose last line is its verdict; --json gives
    the same as a document (docs/report.schema.json).
    """


# The library names its parameters (in messages as `max_steps`, in key paths
# as chain[1]); the command line shows the options that set them.
_FLAGS = {"max_bytes": "--max-size", "max_steps": "--max-steps", "max_states": "--max-states",
          "max_seconds": "--max-seconds", "default_holding": "--default-holding",
          "chain": "--chain", "links": "--link", "clocks": "--clock",
          "objectives": "--objective", "scheduler": "--scheduler", "workers": "--workers",
          "output": "-o", "resume": "--resume", "overwrite": "--force", "plot": "--plot",
          "max_variants": "--max-variants", "batch_size": "--batch-size",
          "max_memory": "--max-memory", "max_firings": "--max-firings", "timed": "--timed",
          "max_jobs": "--max-jobs", "horizon": "--horizon"}
_FLAGS.update({"requires": "--require", "max_latency": "--max-latency", "forbid": "--forbid",
               "timeout": "--timeout", "all_links": "--all-links",
               "max_events": "--max-events", "processors": "--no-processors",
               "free_running": "--free-running", "offer": "--processors",
               "allocate": "--allocate", "pin": "--pin"})
_PARAMETER = re.compile(r"`(" + "|".join(_FLAGS) + r")`")


def _cli_words(text: str) -> str:
    """Library text with each `parameter` named by its command-line option."""
    return _PARAMETER.sub(lambda m: _FLAGS[m.group(1)], text)


def _fail(message: str) -> NoReturn:
    typer.echo(f"tegraph: error: {_cli_words(message)}", err=True)
    raise typer.Exit(2)


def _exists(path: object) -> NoReturn:
    """Refuse to replace the existing file ``path`` (exit 2): ``--force`` would."""
    _fail(f"{path}: the file exists already; pass --force to replace it")


@contextmanager
def _writing(path: Path) -> Iterator[None]:
    """Writing ``path``: an existing file, or a write the system refuses, is one message."""
    try:
        yield
    except FileExistsError:
        _exists(path)
    except OSError as exc:
        _fail(f"cannot write {path}: {exc.strerror}")


def _draw(draw: Callable[..., object], result: object, path: Path, force: bool) -> None:
    """Draw ``result`` into ``path`` with ``draw``; every refusal is one message, exit 2."""
    from .report.plot import PlotUnavailableError

    try:
        with _writing(path):
            draw(result, path, overwrite=force)
    except PlotUnavailableError as exc:
        _fail(str(exc))
    except InputError as exc:
        _fail(f"{path}: {exc.reason}")


def _need_matplotlib(drawing: str, without: str) -> None:
    """Refuse, before any work, a drawing where matplotlib is not installed: one line
    naming the extra that installs it (exit 2)."""
    from .report.plot import matplotlib_available, plot_unavailable

    if not matplotlib_available():
        _fail(str(plot_unavailable(drawing, without)))


def _output_file(path: Path, force: bool, where: str, source: Path, *,
                 replaces_input: bool = False) -> None:
    """Refuse, before any work, an output file that cannot or must not be written.

    ``where`` names the option that gave ``path`` (a library parameter name, shown as
    its option); ``source`` is the command's input. An output that is the input is
    refused whatever the flags (:func:`tegraph.io.input_as_output`), except where
    ``replaces_input`` (``fix``, whose output is the repaired input): there only
    ``--force`` replaces it.
    """
    from .io import input_as_output, same_file

    parent = path.parent if str(path.parent) else Path(".")
    if not parent.is_dir():
        _fail(f"{path}: the directory {parent} does not exist; create it first "
              "(tegraph creates no directory)")
    if path.is_dir():
        _fail(f"{path}: is a directory; expected a file name")
    if replaces_input:
        if same_file(path, source) and not force:
            _fail(f"{path}: this is the input file; pass --force to replace it (its comments "
                  "are not copied)")
    else:
        try:
            input_as_output(path, [source], where)
        except InputError as exc:
            _fail(_located(exc))
    if path.exists() and not force:
        _exists(path)


def _output_directory(path: Path, source: Path) -> None:
    """Refuse, before any work, a directory for the CSV files that is not one, or whose
    tasks.csv or groups.csv is the input ``source`` (whatever the flags)."""
    from .io import input_as_output

    if path.is_file():
        _fail(f"{path}: is a file; expected a directory for tasks.csv and groups.csv")
    if not path.is_dir():
        _fail(f"{path}: no such directory; create it first (tegraph creates no directory)")
    try:
        for name in ("tasks.csv", "groups.csv"):
            input_as_output(path / name, [source], "--csv")
    except InputError as exc:
        _fail(_located(exc))


def _located(exc: InputError) -> str:
    """An input error whose key path names a parameter, with the option instead.

    ``chain[1]`` becomes ``--chain[1]``, ``links.W:p -> R:q`` becomes
    ``--link W:p -> R:q``; a key path inside a file is left as it is.
    """
    head = re.split(r"[.\[]", exc.where, maxsplit=1)[0]
    if exc.file is None and head in _FLAGS:  # a key path in a file stays as written
        rest = exc.where[len(head):]
        exc.with_where(_FLAGS[head] + (" " + rest[1:] if rest.startswith(".") else rest))
    return _cli_words(str(exc))


@contextmanager
def _refusals(file: Path) -> Iterator[None]:
    """The library's refusals as one line on stderr and exit status 2, never a traceback.

    An :class:`InputError` names its file and key path itself; any other
    :class:`TegraphError` is prefixed with ``file``.
    """
    try:
        yield
    except InputError as exc:
        _fail(_located(exc))
    except TegraphError as exc:
        _fail(f"{file}: {exc}")


def _size_text(size: int) -> str:
    """A byte count as ``--help`` shows it, in the largest unit that divides it.

    >>> _size_text(2 * 2**30), _size_text(256 * 2**20), _size_text(1000)
    ('2G', '256M', '1000')
    """
    for unit, scale in (("G", 2**30), ("M", 2**20), ("k", 2**10)):
        if size % scale == 0:
            return f"{size // scale}{unit}"
    return str(size)


def _integer(text: str, option: str, least: int | None = None, most: int | None = None) -> int:
    """An integer option's value in the number grammar of every number (README): an
    integer, a decimal or one fraction whose value is whole (``1e3`` is 1000); anything
    else is one line naming the option, exit 2.

    >>> _integer("1e3", "--max-events"), _integer("10/2", "--width"), _integer("1_000", "--x")
    (1000, 5, 1000)
    """
    from maxplus.errors import MaxPlusValueError
    from maxplus.scalar import exact_time

    from .model.limits import shown

    expected = f"{option}: expected an integer such as 1000 or 1e6"
    if least is not None and most is not None:
        expected += f" (from {least} to {most:,})"
    elif least is not None:
        expected += f" (at least {least})"
    try:  # the one number parser: 1e999999999 is refused by its size, not expanded
        value = exact_time(text)
    except MaxPlusValueError as exc:
        reason = str(exc).removeprefix("value: ")
        _fail(f"{expected}; {reason}" if "digits" in reason
              else f"{expected}, got {shown(text)}")
    if value.denominator != 1:
        _fail(f"{expected}, got {shown(text)}, which is not a whole number")
    if (least is not None and value.numerator < least) or (
            most is not None and value.numerator > most):
        _fail(f"{expected}, got {shown(text)}")
    return value.numerator


def _whole(option: str, least: int | None = None, most: int | None = None
           ) -> Callable[[object], int]:
    """The parser of an integer option (typer's ``parser=``): :func:`_integer`; its
    default, an int already, is kept as it is. A budget (``least`` None) is refused
    below 1 by the library, in one line naming the option."""
    def parse(value: object) -> int:
        if isinstance(value, int) and not isinstance(value, bool):
            return value
        return _integer(str(value), option, least, most)
    return parse


def _seconds(value: object) -> float | None:
    """The parser of ``--max-seconds``: a time >= 0 in the number grammar (``1/2``, ``1e3``)."""
    if value is None or isinstance(value, float):
        return value
    from maxplus.errors import MaxPlusValueError
    from maxplus.scalar import exact_time

    from .model.limits import shown

    expected = "--max-seconds: expected a time in seconds >= 0 such as 30, 2.5 or 1/2"
    try:
        seconds = exact_time(str(value))
    except MaxPlusValueError as exc:
        reason = str(exc).removeprefix("value: ")
        _fail(f"{expected}; {reason}" if "digits" in reason
              else f"{expected}, got {shown(str(value))}")
    if seconds < 0:
        _fail(f"{expected}, got {shown(str(value))}")
    return float(seconds)


# The options that several commands share, each declared once. Budgets take their
# defaults from the library's constants (tegraph.model.budgets imports nothing,
# so --help loads no numpy); a budget of nothing is refused by the library in one
# line naming the option, not by a typer `min=` and its multi-line usage error.
SkeletonFile = Annotated[Path, typer.Argument(help="Skeleton file (.yaml, .yml or .json).")]
JsonFlag = Annotated[bool, typer.Option("--json",
                                        help="Print the JSON report (docs/report.schema.json).")]
MaxStates = Annotated[int, typer.Option(
    "--max-states", parser=_whole("--max-states"), metavar="N",
    help="State budget of the search (>= 1); beyond it the answer is inconclusive.")]
_MAX_MEMORY = _size_text(DEFAULT_MAX_MEMORY)
MaxMemory = Annotated[str, typer.Option(
    "--max-memory", help="Memory budget of the markings the untimed reachability search "
                         "stores (e.g. 512M, 4G).")]
MaxFirings = Annotated[int, typer.Option(
    "--max-firings", parser=_whole("--max-firings", 1), metavar="N",
    help="Largest homogeneous expansion of an SDF graph (firings per iteration).")]
_MAX_SIZE = _size_text(DEFAULT_MAX_BYTES)
MaxSize = Annotated[str, typer.Option(
    "--max-size", help="Refuse larger input files (e.g. 1G; at least 1 byte: 0 is refused, "
                       "there is no \"no limit\").")]
MaxSeconds = Annotated[float | None, typer.Option(
    "--max-seconds", parser=_seconds, metavar="SECONDS",
    help="Time budget of the search, in seconds.")]
Processors = Annotated[bool, typer.Option(
    "--processors/--no-processors",
    help="Answer on the skeleton's processors (preemptive fixed priorities, "
         "docs/skeleton.md §4b); --no-processors: every task on a processor of its own, "
         "the v1.1 answers.")]


def _force(what: str) -> typer.models.OptionInfo:
    """The ``--force`` option; its help names what it lets a command replace."""
    return typer.Option("--force", help=f"Replace {what}.")


def _chain(use: str) -> typer.models.OptionInfo:
    """The repeatable ``--chain`` option; its help says what the command does with it."""
    return typer.Option("--chain", metavar="A,B,C",
                        help=f"{use} this chain of tasks, sensor first, e.g. "
                             "TG.JS,TF.TT.JS,CO.JS (repeatable; adds to the file's chains).")


def _max_events(of: str, past: str) -> typer.models.OptionInfo:
    """The ``--max-events`` budget; its help names what it bounds and what happens past it."""
    return typer.Option("--max-events", parser=_whole("--max-events"), metavar="N",
                        help=f"Budget of event firings of {of}, from 1 to 2**63 - 1; past "
                             f"it, {past}.")


@app.command()
def analyze(
    file: SkeletonFile,
    json_out: JsonFlag = False,
    csv_dir: Annotated[Path | None, typer.Option(
        "--csv", metavar="DIR",
        help="Write tasks.csv and groups.csv into this existing directory.")] = None,
    force: Annotated[bool, _force("existing CSV files")] = False,
    max_steps: Annotated[int, typer.Option(
        "--max-steps", parser=_whole("--max-steps", 1), metavar="N",
        help="Budget on the firing index of the dater simulation.")] = 100_000,
    chain: Annotated[list[str] | None, _chain("Report the latency of")] = None,
    design: Annotated[bool, typer.Option(
        "--design/--no-design",
        help="Include design rules, schedulability and latencies.")] = True,
    processors: Processors = True,
    max_events: Annotated[int, _max_events(
        "the schedule on processors (docs/skeleton.md §4b)",
        "schedulability is undecided (exit status 1) and the report says why")] = MAX_EVENTS,
) -> None:
    """Analyze a synchronization skeleton: liveness, periods, overruns, slack, schedule.

    Exit status: 0 live, consistent and schedulable on its processors; 1 a deadlock,
    an unbounded place or an overrun (with a processor per task or on the processors),
    or schedulability undecided within --max-events; 2 the input was refused (one line
    on stderr); 130 interrupted (Ctrl-C).
    """
    # One analysis per process: it builds hundreds of thousands of long-lived
    # objects (places, Fractions, report entries) and leaves almost no cyclic
    # garbage, so the cyclic collector's passes re-scan live objects for nothing
    # (a quarter of the run at 10,000 tasks). Reference counting still frees the
    # rest; the process ends with the command.
    gc.disable()
    from .api import analyze as run_analysis
    from .design.latency import parse_chain
    from .io import load_skeleton

    if csv_dir is not None:
        _output_directory(csv_dir, file)
    with _refusals(file):
        skeleton = load_skeleton(file)
        chains = [parse_chain(c) for c in chain or []]
        report = run_analysis(skeleton, max_steps=max_steps, chains=chains, design=design,
                              processors=processors, max_events=max_events)
    # Each renderer is imported when used: --json needs neither the text report nor
    # the tables (their modules and tabulate).
    if csv_dir is not None:
        from .report import write_csv

        try:
            write_csv(report, csv_dir, overwrite=force)
        except FileExistsError as exc:  # which of the two files: the library names it
            _exists(exc.filename)
        except OSError as exc:
            _fail(f"cannot write CSV files to {csv_dir}: {exc.strerror}")
    if json_out:
        from .report import to_json_bytes

        _echo_document(to_json_bytes(report))
    else:
        from .report import render_text

        typer.echo(_cli_words(render_text(report)), nl=False)
    raise typer.Exit(report.exit_status)


def _echo_document(data: bytes) -> None:
    """Print a JSON document's UTF-8 bytes and a newline, as ``typer.echo`` prints bytes.

    ``typer.echo`` of the text would copy it to append the newline and, off a terminal,
    scan it for ANSI colour codes to strip: a JSON text holds none (its control
    characters are escaped), and the report of 10,000 tasks is tens of megabytes. The
    bytes go to the binary stream as they are, so a report of 100,000 tasks is never
    held as text as well.
    """
    sys.stdout.flush()  # whatever the text layer holds goes first
    out = getattr(sys.stdout, "buffer", None)
    if out is None:  # a text-only stream (an embedding program's): decode once
        sys.stdout.write(data.decode())
        sys.stdout.write("\n")
        sys.stdout.flush()
        return
    out.write(data)
    out.write(b"\n")
    out.flush()


# Further commands (reach, cycle-time, convert, fix, rules, timeline) are added
# below this line, one function each, in the same shape as `analyze`.


@app.command()
def reach(
    file: Annotated[Path, typer.Argument(
        help="Skeleton file (.yaml, .yml, .json) or a P/T net (.pnml and the other formats "
             "`convert` reads).")],
    timed: Annotated[bool, typer.Option(
        "--timed", help="Timed exploration (ORCCAD §5): periods, transients and overruns "
                        "from the first repeated state (skeletons only).")] = False,
    max_states: MaxStates = DEFAULT_MAX_STATES,
    max_seconds: MaxSeconds = None,
    max_memory: MaxMemory = _MAX_MEMORY,
    max_firings: MaxFirings = DEFAULT_MAX_FIRINGS,
    json_out: JsonFlag = False,
) -> None:
    """State-space baseline: the reachability graph (deadlocks) or, with --timed, the timed
    exploration (ORCCAD §5), which the (max,+) analysis is compared with.

    Exit status: 0 nothing found (or inconclusive within the budgets); 1 a
    deadlock or an overrun; 2 the input was refused; 130 interrupted (Ctrl-C).
    """
    import signal

    from .api import reach as run_search
    from .io import load_skeleton, read
    from .report import render_text, to_json

    memory = _size(max_memory, "--max-memory")
    with _refusals(file):
        model = (load_skeleton(file) if file.suffix.lower() in FORMATS["skeleton"].suffixes
                 else read(file))

    # Ctrl-C asks the search to stop at its next batch; the partial counts are printed.
    interrupted: list[int] = []
    bar = _ProgressBar()
    try:
        previous = signal.signal(signal.SIGINT, lambda *_: interrupted.append(1))
    except ValueError:  # not the main thread: Ctrl-C stays a KeyboardInterrupt
        previous = None
    try:
        with _refusals(file):
            result = run_search(
                model, timed=timed, max_states=max_states, max_seconds=max_seconds,
                max_memory=memory, max_firings=max_firings, stop=lambda: bool(interrupted),
                progress=lambda states, _, seconds: bar.show(
                    states / max(max_states, 1), f"{states:,} states, "
                    f"{states / seconds:,.0f}/s", seconds))
    finally:
        if previous is not None:
            signal.signal(signal.SIGINT, previous)
        bar.erase()
    typer.echo(to_json(result) if json_out else _cli_words(render_text(result)))
    if result.stopped_by == "interrupted":
        typer.echo("tegraph: interrupted; the counts above are partial", err=True)
        raise typer.Exit(130)
    raise typer.Exit(result.exit_status)


@app.command()
def fix(
    file: SkeletonFile,
    output: Annotated[Path | None, typer.Option(
        "-o", "--output",
        help="Write the live skeleton here (.yaml/.yml or .json), in an existing directory. "
             "Without -o nothing is written.")] = None,
    force: Annotated[bool, _force("an existing output file (the input file too, when -o "
                                  "names it; its comments are lost)")] = False,
) -> None:
    """Reorder ports (or threads, when no port order helps) so that the skeleton is live,
    keeping every declared order that is fine.

    Exit status: 0 live (or already live); 1 no port or thread order helps (nothing
    is written); 2 the input or the output file was refused; 130 interrupted (Ctrl-C).
    """
    from .analysis.repair import fix_ports
    from .io import dump_skeleton, load_skeleton
    from .report.design_text import fix_verdict, render_fix

    if output is not None:
        _output_file(output, force, "output", file, replaces_input=True)
    with _refusals(file):
        skeleton = load_skeleton(file)
        result = fix_ports(skeleton)
    if not result.live:
        typer.echo(render_fix(result, skeleton.name) + "nothing written\n" + fix_verdict(result))
        raise typer.Exit(1)
    if output is not None:
        try:
            with _writing(output):
                # Type: a live result (checked above) carries the fixed skeleton.
                dump_skeleton(result.skeleton, output, overwrite=force)  # type: ignore[arg-type]
        except InputError as exc:
            _fail(str(exc))
    typer.echo(render_fix(result, skeleton.name), nl=False)
    if output is not None:
        typer.echo(f"wrote {output} (live; comments of {file.name} are not copied)")
    else:
        typer.echo("nothing written (no -o given)")
    typer.echo(fix_verdict(result))
    raise typer.Exit(0)


@app.command()
def rules(
    file: SkeletonFile,
    chain: Annotated[list[str] | None, _chain("Report the latency of")] = None,
    json_out: JsonFlag = False,
    processors: Processors = True,
    max_events: Annotated[int, _max_events(
        "the exact schedule on processors (docs/skeleton.md §4b), as for analyze",
        "the verdict is undecided (exit status 1) and the report says why")] = MAX_EVENTS,
) -> None:
    """Design rules of ORCCAD section 6, threads, schedulability and chain latencies.

    The verdict is analyze's (spec §4b: the exact schedule on processors); the
    response-time test is a cross-check beside it. Exit status: 0 the rules are
    followed (info findings aside) and analyze's exit status is 0 (live, consistent,
    schedulable); 1 otherwise; 2 the input was refused; 130 interrupted (Ctrl-C).
    """
    from .api import rules as check_design
    from .design.latency import parse_chain
    from .io import load_skeleton
    from .report import render_text, to_json

    with _refusals(file):
        skeleton = load_skeleton(file)
        chains = [parse_chain(c) for c in chain or []]
        section = check_design(skeleton, chains=chains, processors=processors,
                               max_events=max_events)
    typer.echo(to_json(section) if json_out else _cli_words(render_text(section)), nl=json_out)
    raise typer.Exit(section.exit_status)


@app.command()
def timeline(
    file: SkeletonFile,
    output: Annotated[Path | None, typer.Option(
        "-o", "--output", help="Also draw the diagram into this .svg or .png file (needs "
                               "matplotlib: pip install '.[plot]').")] = None,
    horizon: Annotated[str | None, typer.Option(
        "--horizon", metavar="END|START..END",
        help="What the DRAWING shows: until END (e.g. 12 or 7/3), or the window "
             "START..END (e.g. 40..50). Default: 10 periods of the fastest clock around "
             "the first problem (overrun, deadlock, starved job) or from the periodic "
             "regime, or the whole proof when it fits; the report says which and how to see "
             "more. The verdict never depends on it.")] = None,
    width: Annotated[int, typer.Option("--width", parser=_whole("--width", 10, 10_000),
                                       metavar="COLUMNS",
                                       help="Columns of the text diagram (10 to "
                                            "10,000).")] = 96,
    force: Annotated[bool, _force("an existing drawing")] = False,
    max_events: Annotated[int, _max_events(
        "the exact schedule on processors (docs/skeleton.md §4b), as for analyze",
        "the verdict is undecided (exit status 1) and the report says why")] = MAX_EVENTS,
    chain: Annotated[list[str] | None, _chain("Draw the worst data path and print the "
                                              "latency of")] = None,
) -> None:
    """The schedule on its processors (spec §4b), a lane per processor, until its proof.

    The one semantics of analyze: preemptive fixed priorities, exact, drawn until the
    periodic regime is reached or the first overrun. Exit status: 0 schedulable
    (proven); 1 not schedulable (deadlock, overrun, starved job, growing place) or
    undecided within --max-events; 2 the input or the output file was refused, or
    matplotlib is missing for -o; 130 interrupted (Ctrl-C).
    """
    from maxplus.errors import MaxPlusValueError
    from maxplus.scalar import exact_time

    from .design.latency import parse_chain
    from .design.timeline import simulate_timeline
    from .io import load_skeleton
    from .report.plot import draw_timeline
    from .report.timeline_text import render_timeline

    end = begin = None
    if horizon is not None:
        first, dots, last = horizon.partition("..")
        texts = [first, last] if dots else [horizon]
        times = []
        for text in texts:
            try:  # the one number parser: 1e999999999 is refused by its size, not expanded
                times.append(exact_time(text))
            except MaxPlusValueError as exc:
                _fail(f"--horizon: expected a time > 0 such as 12 or 7/3, or a window "
                      f"START..END such as 40..50; {str(exc).removeprefix('value: ')}")
        end = times[-1]
        begin = times[0] if dots else None
        if end <= 0 or (begin is not None and not 0 <= begin < end):
            _fail(f"--horizon: expected a time > 0 such as 12 or 7/3, or a window "
                  f"START..END with 0 <= START < END such as 40..50, got {horizon!r}")
    if output is not None:
        _output_file(output, force, "output", file)
        _need_matplotlib("-o: drawing a timing diagram",
                         "the text diagram needs nothing: leave out -o")
    with _refusals(file):
        skeleton = load_skeleton(file)
        result = simulate_timeline(skeleton, end, max_events=max_events, start=begin,
                                   chains=[parse_chain(c) for c in chain or []])
    if output is not None:
        _draw(draw_timeline, result, output, force)
    typer.echo(_cli_words(render_timeline(result, width)), nl=False)
    if output is not None:  # on stderr: the verdict stays the last line of the report
        typer.echo(f"wrote {output}", err=True)
    raise typer.Exit(result.exit_status)


@app.command("cycle-time")
def cycle_time_command(
    file: Annotated[Path, typer.Argument(
        help="A timed event graph in any format tegraph reads: "
             f"{', '.join(FORMATS[name].holds for name in readable())}.")],
    json_out: JsonFlag = False,
    fmt: Annotated[str | None, typer.Option(
        "--format", help=f"Force the input format ({', '.join(readable())}).")] = None,
    max_size: MaxSize = _MAX_SIZE,
    default_holding: Annotated[str | None, typer.Option(
        "--default-holding", help="Holding time of every place of a net that carries no "
                                  "timing (default 0).")] = None,
    max_states: MaxStates = DEFAULT_MAX_STATES,
    max_seconds: MaxSeconds = None,
    max_memory: MaxMemory = _MAX_MEMORY,
    max_firings: MaxFirings = DEFAULT_MAX_FIRINGS,
) -> None:
    """Exact period, throughput and critical circuit of a timed event graph.

    A P/T net that is not a marked graph has no (max,+) figures: the report says
    why and gives the deadlock verdict of its untimed reachability graph instead.
    Exit status: 0 no deadlock found; 1 a deadlock (a circuit without token, or
    a reachable dead marking); 2 the input was refused; 130 interrupted (Ctrl-C).
    """
    from .api import cycle_time
    from .report import render_text, to_json

    with _refusals(file):
        result = cycle_time(file, format=fmt, max_bytes=_size(max_size, "--max-size"),
                            default_holding=default_holding, max_states=max_states,
                            max_seconds=max_seconds, max_memory=_size(max_memory, "--max-memory"),
                            max_firings=max_firings)
    typer.echo(to_json(result) if json_out else _cli_words(render_text(result)), nl=json_out)
    raise typer.Exit(result.exit_status)


@app.command()
def convert(
    source: Annotated[Path, typer.Argument(help="Input file (format detected from it).")],
    target: Annotated[Path, typer.Argument(
        help="Output file (format from its extension: "
             f"{', '.join(dict.fromkeys(e for f in FORMATS.values() for e in f.extensions()))}"
             ").")],
    from_fmt: Annotated[str | None, typer.Option("--from",
                                                 help="Force the input format.")] = None,
    to_fmt: Annotated[str | None, typer.Option(
        "--to", help=f"Force the output format ({', '.join(writable())}).")] = None,
    force: Annotated[bool, _force("an existing output file")] = False,
    max_size: MaxSize = _MAX_SIZE,
) -> None:
    """Convert between formats where the target can hold the content.

    A skeleton becomes a timed event graph, never the other way round; a P/T
    net that is not a marked graph goes only to net formats (PNML,
    TimedPetriNetEditor JSON, DOT).

    Exit status: 0 written; 2 the input or the output file was refused; 130
    interrupted (Ctrl-C).
    """
    from .api import write
    from .io import read

    _output_file(target, force, "TARGET", source)
    try:
        with _writing(target):
            model = read(source, from_fmt, max_bytes=_size(max_size, "--max-size"))
            written = write(model, target, to_fmt, overwrite=force)
    except InputError as exc:
        _fail(str(exc))
    except TegraphError as exc:
        _fail(f"{source}: {exc}")
    typer.echo(f"wrote {written}")


@app.command()
def explore(
    file: SkeletonFile,
    chain: Annotated[list[str] | None, _chain("Minimize the latency of")] = None,
    link: Annotated[list[str] | None, typer.Option(
        "--link", help="'W:p -> R:q=ASYN/SYN,SYN/SYN': choose this link's protocol among "
                       "these (all four without '='; repeatable).")] = None,
    all_links: Annotated[bool, typer.Option(
        "--all-links", help="Choose every link's protocol among all four; a link also given "
                            "by --link keeps the protocols --link gives it (the report says "
                            "so).")] = False,
    clock: Annotated[list[str] | None, typer.Option(
        "--clock", help="NAME=5,10,20: choose this clock's period among these (a task's own "
                        "clock is TASK.clock; repeatable).")] = None,
    objective: Annotated[list[str] | None, typer.Option(
        "--objective",
        help="latency (each chain's first use on processors, exact, in the file's unit), "
             "age and reaction (the same chain's figures, spec §4c), period (the period "
             "ratio: the "
             "largest task period over the task's designed period, its own clock's or its "
             "input group's fastest), load (the busiest processor's utilization) or "
             "utilization (the sum over the processors); repeatable or comma-separated; "
             "default all that apply (utilization with two processors or more), all "
             "minimized; ties are broken by fewer Rule 2 findings.")] = None,
    require: Annotated[list[str] | None, typer.Option(
        "--require", metavar="TASK.period=P",
        help="Keep only designs that run TASK at period P (or TASK.period<=P), in the "
             "file's unit (repeatable).")] = None,
    max_latency: Annotated[list[str] | None, typer.Option(
        "--max-latency", metavar="A,B,C=L",
        help="Keep only designs whose latency of chain A,B,C (its first use on "
             "processors, exact; undecided is rejected) is at most L (repeatable).")] = None,
    forbid: Annotated[list[str] | None, typer.Option(
        "--forbid", metavar="PROTOCOL",
        help="No link may use this protocol, e.g. SYN/SYN: it is taken out of every "
             "chosen link's choices (repeatable).")] = None,
    scheduler: Annotated[str | None, typer.Option(
        "--scheduler", help="Run on this Dask scheduler, e.g. tcp://HOST:8786.")] = None,
    workers: Annotated[int | None, typer.Option(
        "--workers", parser=_whole("--workers", 0), metavar="N",
        help=f"Local Dask worker processes, from 0 (judge in this process) to "
             f"{os.cpu_count() or 1} (this machine's cores; more run on a cluster: "
             "--scheduler); default: this process, until the measured work pays for a "
             "local cluster (docs/explore.md).")] = None,
    output: Annotated[Path | None, typer.Option(
        "-o", "--output", help="Write every judged variant to this .csv or .parquet file as "
                               "results arrive.")] = None,
    resume: Annotated[bool, typer.Option(
        "--resume", help="Continue the -o file: skip the variants it holds.")] = False,
    force: Annotated[bool, _force("an existing -o or --plot file")] = False,
    plot: Annotated[Path | None, typer.Option(
        "--plot", help="Draw the front into this .svg or .png file (needs matplotlib: "
                       "pip install '.[plot]').")] = None,
    max_variants: Annotated[int, typer.Option(
        "--max-variants", parser=_whole("--max-variants", 1), metavar="N",
        help="Search exhaustively up to this many variants; beyond, Pareto local search "
             "analyzes at most this many.")] = 10_000,
    batch_size: Annotated[int | None, typer.Option(
        "--batch-size", parser=_whole("--batch-size", 1), metavar="N",
        help="Variants per batch (default adaptive).")] = None,
    timeout: Annotated[str, typer.Option(  # text: the library's exact parser reads it
        "--timeout", help="Seconds to wait for the scheduler to answer, e.g. 30 or 5/2 (> 0, "
                          "at most 86400).")] = "10",
    max_events: Annotated[int, _max_events(
        "each variant's schedule on processors (docs/skeleton.md §4b)",
        "the variant is rejected as undecided; a decided variant stops at its proof (a few "
        "hundred firings for a small pipe-line)")] = MAX_EVENTS,
    free_running: Annotated[bool, typer.Option(
        "--free-running", help="Keep designs where a task runs free (no clock in its "
                               "group: as often as its processor lets it) that the input "
                               "design runs on a clock; by default they are rejected.")] = False,
    processors: Annotated[str | None, typer.Option(
        "--processors", metavar="CPU1,CPU2",
        help="Also choose where the tasks run, among these processors (comma-separated; "
             "their `processors:` properties apply, and the `network.delay` to the links "
             "that cross); interchangeable processors are not judged twice.")] = None,
    allocate: Annotated[str, typer.Option(
        "--allocate", metavar="groups|tasks",
        help="With --processors: move whole synchronized groups (default) or single "
             "tasks.")] = "groups",
    pin: Annotated[list[str] | None, typer.Option(
        "--pin", metavar="TASK=CPU",
        help="With --processors: keep TASK (its group, with --allocate groups) on CPU, "
             "one of --processors (repeatable).")] = None,
    all_ties: Annotated[bool, typer.Option(
        "--all-ties", help="List every design of the front; by default one row per "
                           "distinct objective vector, with its count of ties.")] = False,
    json_out: JsonFlag = False,
) -> None:
    """Search link protocols and clock periods for the Pareto front of live, consistent,
    schedulable designs (on their processors), locally or on a Dask cluster.

    Exit status: 0 some design kept; 1 none is live, consistent and
    schedulable; 2 the input was refused; 130 interrupted (the -o file keeps
    what was judged: --resume goes on).
    """
    from .api import explore as run_exploration
    from .design.latency import parse_chain
    from .io import load_skeleton
    from .report import to_json
    from .report.explore_plot import draw_front
    from .report.explore_text import render_exploration

    if output is not None:  # the library checks the rest (--resume, --force) itself
        from .io import input_as_output

        try:
            input_as_output(output, [file], "output")
        except InputError as exc:
            _fail(_located(exc))
    if plot is not None:
        _plot_suffix(plot)
        _output_file(plot, force, "plot", file)
        _need_matplotlib("--plot: drawing the front", "the text and JSON reports need nothing")
    # Lists, not dicts: a link or clock given twice is refused by the library, naming
    # both occurrences, instead of the second silently replacing the first.
    links = list(link or [])
    clocks = list(clock or [])
    objectives = None if not objective else [
        o for text in objective for o in text.split(",") if o.strip()]
    bar = _ProgressBar()

    def progress(p) -> None:
        bar.show(p.judged / max(p.total, 1), f"{p.judged:,}/{p.total:,} variants, "
                 f"{p.rate:,.1f}/s, front {p.front}")

    try:
        with _exploring(file, output):
            result = run_exploration(
                load_skeleton(file), links, all_links=all_links, clocks=clocks,
                chains=[parse_chain(c) for c in chain or []], objectives=objectives,
                scheduler=scheduler, workers=workers, output=output, resume=resume,
                overwrite=force, max_variants=max_variants, batch_size=batch_size,
                progress=progress, timeout=timeout, requires=require or [],
                max_latency=max_latency or [], forbid=forbid or [], max_events=max_events,
                free_running=free_running, offer=processors, allocate=allocate,
                pin=pin or [])
    finally:
        bar.erase()
    text = to_json(result) + "\n" if json_out else _cli_words(
        render_exploration(result, all_ties=all_ties))
    # (a JSON document ends with one newline, as a text report does)
    if plot is not None:
        _draw(draw_front, result, plot, force)
    typer.echo(text, nl=False)
    if plot is not None:  # on stderr: the verdict stays the last line of the report
        typer.echo(f"wrote {plot}", err=True)
    raise typer.Exit(0 if result.front else 1)


def _plot_suffix(plot: Path) -> None:
    """Refuse a drawing whose file name says neither SVG nor PNG."""
    if plot.suffix.lower() not in (".svg", ".png"):
        _fail(f"--plot: cannot draw to {plot.name!r}; expected a file name ending in "
              ".svg or .png")


@contextmanager
def _exploring(file: Path, output: Path | None) -> Iterator[None]:
    """The refusals of an exploration, and Ctrl-C: the -o file keeps what was judged."""
    try:
        with _refusals(file):
            yield
    except OSError as exc:
        _fail(f"cannot write {output}: {exc.strerror}")
    except KeyboardInterrupt:
        kept = f"; the verdicts so far are in {output}: add --resume to go on" if output else ""
        typer.echo(f"tegraph: interrupted{kept}", err=True)
        raise typer.Exit(130) from None


@app.command("sensitivity")
def sensitivity_command(
    file: SkeletonFile,
    vary: Annotated[list[str] | None, typer.Option(
        "--vary", metavar="PARAM[=LOW..HIGH]",
        help="A parameter to vary: TASK.duration, CLOCK.period (a task's own clock is "
             "TASK.clock), or a declared delay network.delay or links[i].delay (the i-th "
             "link of the file, from 0), optionally with its range, exact: "
             "A.duration=0..5/2, rtc.period=1.., network.delay=0..2 (repeatable; default: "
             "every duration over [0, inf)).")] = None,
    json_out: JsonFlag = False,
    plot: Annotated[Path | None, typer.Option(
        "--plot", metavar="OUT.svg|png",
        help="Also draw it (one parameter: the periods against it; two: the map of the "
             "regions); needs matplotlib: pip install '.[plot]'.")] = None,
    force: Annotated[bool, _force("an existing drawing")] = False,
    formulas: Annotated[bool, typer.Option(
        "--formulas/--no-formulas", help="Compute each group's period as a formula.")] = True,
    verify: Annotated[bool, typer.Option(
        "--verify/--no-verify", help="Check every finite end with the analysis (consistent "
                                     "at it, not just beyond): two analyses of a group "
                                     "each.")] = True,
    processors: Processors = True,
    max_events: Annotated[int, _max_events(
        "each simulation of a part of the schedule on processors (docs/skeleton.md §4b), "
        "and of each figure in all; the whole run fires at most 20 times as many",
        "the figure is only bounded and the report says why")] = MAX_EVENTS,
    chain: Annotated[list[str] | None, _chain(
        "Give the first use at each end of every margin and at the scaling factor of"
    )] = None,
) -> None:
    """How much durations can grow (scaling factor, margins), and each period as a formula.

    Exact: every end is a rational, found by searches that stop at an exact
    breakpoint, and checked with the analysis. By default on the skeleton's
    processors (§4b); --no-processors: with a processor per task. Exit status:
    0 consistent (and schedulable on its processors) at the nominal values;
    1 not (the sensitivity is reported anyway); 2 the
    input was refused (an unknown parameter, an empty or negative range, a
    range without the nominal value); 130 interrupted (Ctrl-C).
    """
    from .analysis.sensitivity import sensitivity
    from .design.latency import parse_chain
    from .io import load_skeleton
    from .report import render_text, to_json
    from .report.sensitivity_plot import draw_sensitivity

    if plot is not None:
        _plot_suffix(plot)
        if len(vary or ()) not in (1, 2):
            _fail("--plot: a drawing shows one or two parameters; name them with --vary "
                  f"(given: {len(vary or ())})")
        if not formulas:
            _fail("--plot draws the periods from their formulas; leave out --no-formulas")
        _need_matplotlib("--plot: drawing the sensitivity", "the text report needs nothing")
        _output_file(plot, force, "plot", file)
    import time

    bar = _ProgressBar()
    started = time.monotonic()

    def progress(done: int, figures: int, fired: int) -> None:
        bar.show(done / max(figures, 1), f"{done}/{figures} figures on processors, "
                 f"{fired:,} event firings", time.monotonic() - started)

    with _refusals(file):
        skeleton = load_skeleton(file)
        try:
            result = sensitivity(skeleton, vary or None, formulas=formulas,
                                 verify=verify, processors=processors,
                                 max_events=max_events, progress=progress,
                                 chains=[parse_chain(c) for c in chain or []])
        except InputError as exc:
            if exc.where.startswith("vary"):
                exc.with_where("--vary" + exc.where[len("vary"):])
            raise
        finally:
            bar.erase()
    if plot is not None:
        _draw(draw_sensitivity, result, plot, force)
    if json_out:
        typer.echo(to_json(result))
    else:
        typer.echo(_cli_words(render_text(result)), nl=False)
    if plot is not None:  # on stderr: the verdict stays the last line of the report
        typer.echo(f"wrote {plot}", err=True)
    raise typer.Exit(result.exit_status)


def _size(text: str, option: str) -> int:
    """A byte count from ``"300M"``, ``"2G"``, ``"512k"`` or a plain integer (exit 2 else).

    >>> _size("300M", "--max-memory"), _size("2G", "--max-memory"), _size("1000", "--max-size")
    (314572800, 2147483648, 1000)
    """
    m = re.fullmatch(r"\s*(\d{1,30})\s*([kKmMgG]?)[iI]?[bB]?\s*", text)
    shown = repr(text) if len(text) <= 40 else f"{text[:40]!r}... ({len(text):,} characters)"
    if not m:
        _fail(f"{option}: expected a size such as 300M or 2G, got {shown}")
    size = int(m.group(1)) * {"": 1, "k": 2**10, "m": 2**20, "g": 2**30}[m.group(2).lower()]
    if size < 1:  # 0 is no "no limit": it would refuse every file, or stop every search at once
        _fail(f"{option}: expected a size of at least 1 byte such as 300M or 2G, got {shown}")
    return size


class _ProgressBar:
    """A progress bar on stderr, only on a terminal, redrawn at most ten times a second."""

    def __init__(self) -> None:
        self.drawn = 0.0  # time.monotonic() of the last drawing; 0: never drawn

    def show(self, done: float, text: str, seconds: float | None = None) -> None:
        """Draw ``done`` (0 to 1) and ``text``; a search shows itself after a second."""
        import time

        now = time.monotonic()
        if (not sys.stderr.isatty() or (seconds is not None and seconds < 1)
                or now - self.drawn < 0.1):
            return
        self.drawn = now
        filled = int(30 * min(1.0, done))
        typer.echo(f"\r[{'#' * filled}{'-' * (30 - filled)}] {text} ", err=True, nl=False)

    def erase(self) -> None:
        if self.drawn:
            typer.echo("\r" + " " * 79 + "\r", err=True, nl=False)


def main() -> NoReturn:
    """Console-script entry point.

    The process ends as soon as the command is done (:func:`_end`): its exit
    handlers run and its output is flushed, but the interpreter does not tear
    down the modules and objects it is about to discard.
    """
    try:
        app()
    except KeyboardInterrupt:
        typer.echo("tegraph: interrupted", err=True)
        _end(130)
    except SystemExit as exc:  # every command ends here (click's standalone mode)
        _end(exc.code)
    _end(0)


def _end(code: object) -> NoReturn:
    """End the process with ``code`` as :func:`sys.exit` would, without the teardown.

    Tearing down numpy's, scipy's and typer's ~700 modules and an analysis's
    objects is a noticeable share of every command, for memory the system
    reclaims at once.
    What a normal exit does that matters still happens: the exit handlers run
    (a Dask cluster's, logging's, temporary directories'), then the output
    streams are flushed.
    """
    if code is None:
        status = 0
    elif isinstance(code, int):
        status = code
    else:  # sys.exit("message"): the message on stderr, status 1
        print(code, file=sys.stderr)
        status = 1
    atexit._run_exitfuncs()
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except (BrokenPipeError, ValueError):  # a reader that left (| head), a closed stream
            pass
    os._exit(status)


if __name__ == "__main__":  # pragma: no cover
    main()
