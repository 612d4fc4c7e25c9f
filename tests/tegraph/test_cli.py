"""The command line: exit statuses, output formats, refusals without tracebacks.

Most tests run the commands in this process through typer's ``CliRunner`` (no
interpreter start-up); a few, marked *end to end*, run ``python -m tegraph.cli``
in a subprocess as a user does, for the exit statuses and output streams of a
real process.
"""

from __future__ import annotations

import gc
import json
import subprocess
import sys
from pathlib import Path

import pytest
from click.testing import Result
from typer.testing import CliRunner

from tegraph.cli import app
from tests.paths import REPO

LIVE = """\
name: pipeline
tasks:
  A: {duration: 2, period: 10, outputs: [x]}
  B: {duration: "7/3", inputs: [x]}
links:
  - {from: "A:x", to: "B:x", protocol: ASYN/SYN}
"""

# Figure 7a of the ORCCAD paper: each task waits to read from the next one.
CIRCULAR = """\
tasks:
  MT1: {duration: 1, inputs: [c], outputs: [a]}
  MT2: {duration: 1, inputs: [a], outputs: [b]}
  MT3: {duration: 1, inputs: [b], outputs: [c]}
links:
  - {from: "MT1:a", to: "MT2:a", protocol: ASYN/SYN}
  - {from: "MT2:b", to: "MT3:b", protocol: ASYN/SYN}
  - {from: "MT3:c", to: "MT1:c", protocol: ASYN/SYN}
"""


def run(*args: str) -> subprocess.CompletedProcess:
    """End to end: the command in a fresh interpreter, as from a shell."""
    return subprocess.run([sys.executable, "-m", "tegraph.cli", *args],
                          capture_output=True, text=True, timeout=120)


def invoke(*args: object) -> Result:
    """The command in this process; ``stdout`` and ``stderr`` are kept apart."""
    return CliRunner().invoke(app, [str(a) for a in args])


def no_traceback(result: Result) -> bool:
    """In process, an escaped error is ``result.exception``; an exit is a SystemExit."""
    return result.exception is None or isinstance(result.exception, SystemExit)


@pytest.fixture(autouse=True)
def _collector_back_on():
    # `analyze` turns the cyclic collector off for its one-shot process; in this
    # process the other tests still need it.
    yield
    gc.enable()


@pytest.fixture
def live_file(tmp_path: Path) -> Path:
    path = tmp_path / "pipeline.yaml"
    path.write_text(LIVE)
    return path


def test_end_to_end_live_and_consistent_exits_0_with_exact_figures(live_file):
    out = run("analyze", str(live_file), "--json")
    assert out.returncode == 0, out.stderr
    assert out.stderr == ""
    report = json.loads(out.stdout)
    # One group under A's clock: period 10. No path leads from B back to A, so
    # the only circuit through B.compute is B's chain (read -> compute ->
    # return place holding 7/3, 1 token): slack 10*1 - 7/3 = 23/3. A's only
    # circuit through A.compute is its chain (holding 2, 1 token): slack 8.
    assert report["groups"][0]["period"] == "10"
    assert report["tasks"]["B"]["period"] == "10"
    assert report["tasks"]["B"]["slack"] == "23/3"
    assert report["tasks"]["A"]["slack"] == "8"
    assert report["live"] is True and report["consistent"] is True
    # Like every command's document: the version and the command first.
    assert list(report)[:2] == ["schema_version", "report"]
    assert report["schema_version"] == 2 and report["report"] == "analyze"


def test_human_report_names_verdicts_and_methods(live_file):
    out = invoke("analyze", live_file)
    assert out.exit_code == 0 and out.stderr == ""
    # The liveness line gives the verdict and its theorem ("live" alone would also
    # match the verdict line, so the test could not fail on it).
    liveness = next(line for line in out.stdout.splitlines() if line.startswith("liveness:"))
    assert liveness.split(None, 2)[1] == "live" and "Commoner's theorem" in liveness
    # 23/3 = 7.666...: a non-terminating decimal, rounded and marked.
    assert "23/3 ms (≈7.66667)" in out.stdout
    assert out.stdout.splitlines()[-1] == (
        "verdict: live, consistent and schedulable on its processors (exit status 0)")


def test_end_to_end_deadlock_exits_1_and_names_the_circuit(tmp_path):
    path = tmp_path / "fig7a.yaml"
    path.write_text(CIRCULAR)
    out = run("analyze", str(path), "--json")
    assert out.returncode == 1 and "Traceback" not in out.stderr
    report = json.loads(out.stdout)
    assert report["live"] is False
    assert report["reorder"]["possible"] is False
    (deadlock,) = report["deadlocks"]
    assert sorted(deadlock["tasks"]) == ["MT1", "MT2", "MT3"]
    assert "MT1.read:c" in deadlock["events"]


@pytest.mark.parametrize("text, where", [
    ("tasks:\n  A: {duration: -1}\n", "tasks.A.duration"),
    ("tasks: {}\n", "tasks"),
    ("tasks:\n  A: {duration: 1, colour: red}\n", "tasks.A.colour"),
])
def test_refused_input_exits_2_with_one_line(tmp_path, text, where):
    path = tmp_path / "bad.yaml"
    path.write_text(text)
    out = invoke("analyze", path)
    assert out.exit_code == 2 and no_traceback(out)
    assert out.stdout == ""
    assert "Traceback" not in out.stderr
    line = out.stderr.strip()
    assert line.startswith("tegraph: error: ") and str(path) in line and where in line


def test_end_to_end_the_process_ends_with_its_handlers_run_and_its_output_whole(tmp_path):
    # main() ends the process without the interpreter's teardown (os._exit): what a
    # normal exit guarantees must still hold. An exit handler registered before the
    # command runs, and a report of 400 tasks (some 200 kB, beyond any pipe buffer)
    # arrives whole: the JSON parses and names every task.
    tasks = "".join(f"  T{i}: {{duration: 1, period: {i % 7 + 2}}}\n" for i in range(400))
    path = tmp_path / "many.yaml"
    path.write_text("tasks:\n" + tasks)
    code = ("import atexit, sys; "
            "atexit.register(lambda: print('handler ran', file=sys.stderr)); "
            "sys.argv = ['tegraph', 'analyze', '--json', sys.argv[1]]; "
            "from tegraph.cli import main; main()")
    out = subprocess.run([sys.executable, "-c", code, str(path)], capture_output=True,
                         text=True, timeout=120)
    # Exit 1: the 400 tasks share the one processor of spec §4b's default, at a
    # utilization of sum(1/period) over the tasks, about 98 (some 57 tasks per period 2..8).
    assert out.returncode == 1, out.stderr
    assert out.stderr == "handler ran\n"
    assert sorted(json.loads(out.stdout)["tasks"]) == sorted(f"T{i}" for i in range(400))
    # A refusal keeps its status 2 and its one line.
    out = subprocess.run([sys.executable, "-c", code, str(tmp_path / "none.yaml")],
                         capture_output=True, text=True, timeout=120)
    assert out.returncode == 2 and out.stdout == ""
    assert out.stderr.startswith("tegraph: error: ") and out.stderr.endswith("handler ran\n")


def test_end_to_end_missing_file_exits_2(tmp_path):
    out = run("analyze", str(tmp_path / "nothing.yaml"))
    assert out.returncode == 2 and "Traceback" not in out.stderr
    assert "nothing.yaml" in out.stderr and out.stdout == ""


def test_csv_tables_and_no_silent_overwrite(live_file, tmp_path):
    out_dir = tmp_path / "tables"
    # No directory is created silently: a missing one is refused, before any work.
    missing = invoke("analyze", live_file, "--csv", out_dir)
    assert missing.exit_code == 2 and "no such directory" in missing.stderr
    assert not out_dir.exists()
    # A file where a directory is expected: one clear line, no errno text.
    as_file = invoke("analyze", live_file, "--csv", live_file)
    assert as_file.exit_code == 2 and "is a file; expected a directory" in as_file.stderr
    assert "Errno" not in as_file.stderr
    out_dir.mkdir()
    assert invoke("analyze", live_file, "--csv", out_dir).exit_code == 0
    rows = (out_dir / "tasks.csv").read_text().splitlines()
    assert rows[0] == ('task,group,period (ms),"period (ms, decimal)",overrun,'
                       'overrun_at (activation),slack (ms),"slack (ms, decimal)",critical,'
                       'processor,priority,period on processors (ms),'
                       '"period on processors (ms, decimal)",overrun on processors,'
                       'overrun_at on processors (activation),response from release (ms),'
                       '"response from release (ms, decimal)",response from tick (ms),'
                       '"response from tick (ms, decimal)"')
    # A: clocked, slack 8 < its period, so it never overruns; B: no clock of its own,
    # period 10, slack 23/3 (derivation in test_live_and_consistent_exits_0...).
    # On the one processor (one group: priority 1 both): A's job runs 0-2 from its
    # tick, B's is released by its read at 2 and runs 2-13/3: responses 2 and 7/3
    # from release, 2 from A's tick; B has no clock, so no time from a tick.
    assert rows[1] == "A,0,10,10,never,,8,8,False,default,1,10,10,never,,2,2,2,2"
    assert rows[2] == ("B,0,10,10,no clock,,23/3,7.66666666666667,False,default,1,10,10,"
                       "no clock,,7/3,2.33333333333333,,")
    verdict = (out_dir / "verdict.csv").read_text().splitlines()
    assert verdict[0] == ("name,live,consistent,on processors,schedulable,exit status,"
                          "method,why undecided")
    assert verdict[1].startswith("pipeline,True,True,True,True,0,") and verdict[1].endswith(",")
    (out_dir / "tasks.csv").write_text("mine")
    again = invoke("analyze", live_file, "--csv", out_dir)
    assert again.exit_code == 2 and again.stderr == (
        f"tegraph: error: {out_dir / 'tasks.csv'}: the file exists already; pass --force "
        "to replace it\n")
    assert (out_dir / "tasks.csv").read_text() == "mine"
    assert invoke("analyze", live_file, "--csv", out_dir, "--force").exit_code == 0
    assert (out_dir / "tasks.csv").read_text().splitlines()[1:] == rows[1:]


def _refusal_cases():
    # The loader's own table of every refusal of spec §1 (with the key path
    # and wording each must produce), replayed through the command line.
    from tests.tegraph.io.test_skeleton_file import JSON_REFUSALS, REFUSALS

    return [pytest.param(case.values[0], case.values[1], suffix, id=case.id)
            for cases, suffix in ((REFUSALS, ".yaml"), (JSON_REFUSALS, ".json"))
            for case in cases]


@pytest.mark.parametrize("text, key_path, suffix", _refusal_cases())
def test_every_spec_refusal_exits_2_through_the_cli(tmp_path, text, key_path, suffix):
    path = tmp_path / f"plant{suffix}"
    path.write_text(text, encoding="utf-8")
    result = CliRunner().invoke(app, ["analyze", str(path)])
    assert result.exit_code == 2
    assert isinstance(result.exception, SystemExit)  # not an escaped error
    message = result.output.strip()
    assert message.startswith("tegraph: error: ") and str(path) in message
    assert "Traceback" not in message
    if key_path:
        assert f"{key_path}: " in message


def test_version_says_which_compiled_kernels_are_built(monkeypatch):
    # Every compiled module of both packages, one line each; one not built is said so,
    # with what runs instead and how to build it.
    from tegraph import api

    names = list(api.compiled_kernels())
    assert len(names) == 4 and names[0] == "maxplus._howard_kernel"
    monkeypatch.setattr(api, "compiled_kernels", lambda: dict.fromkeys(names, True))
    lines = invoke("--version").stdout.splitlines()
    assert lines[1] == "compiled kernels: 4 of 4 built"
    assert [line.split() for line in lines[2:]] == [[name, "built"] for name in names]
    monkeypatch.setattr(api, "compiled_kernels", lambda: {**dict.fromkeys(names, True),
                                                          names[0]: False})
    lines = invoke("--version").stdout.splitlines()
    assert lines[1] == "compiled kernels: 3 of 4 built"
    assert lines[2].split() == [names[0], "NOT", "BUILT"]
    assert "its reference runs" in lines[-1] and "build_ext --inplace" in lines[-1]


def test_end_to_end_version_is_the_package_metadata():
    from importlib.metadata import entry_points, version

    import maxplus
    import tegraph

    out = run("--version")
    assert out.returncode == 0 and out.stdout.splitlines()[0] == f"tegraph {version('tegraph')}"
    assert tegraph.__version__ == maxplus.__version__ == version("tegraph")
    # The console script is main(), which `python -m tegraph.cli` runs above.
    (script,) = entry_points(group="console_scripts", name="tegraph")
    assert script.value == "tegraph.cli:main"


@pytest.mark.parametrize("command", ["analyze", "reach", "fix", "rules", "timeline",
                                     "cycle-time", "convert"])
def test_every_command_lists_its_exit_statuses(command):
    out = invoke(command, "--help")
    assert out.exit_code == 0
    text = " ".join(out.stdout.split())
    assert "Exit status: 0" in text and " 2 the input" in text


def test_chain_option_shows_a_readable_metavar():
    text = invoke("analyze", "--help").stdout
    assert "--chain A,B,C" in text and "list[str]" not in text


FIG4 = REPO / "examples" / "fig4_pipeline_unsynchronized.yaml"


def _fig4_chain(path: Path, *options: str) -> dict:
    out = invoke("analyze", path, "--chain", "MT1,MT2,MT3,MT4", "--json", *options)
    assert out.exit_code == 0, out.stderr
    (chain,) = json.loads(out.stdout)["chains"]
    assert chain["tasks"] == ["MT1", "MT2", "MT3", "MT4"]
    return chain


def test_analyze_json_gives_figure_4_s_first_use_on_its_processor():
    # One CPU, equal periods of 10 ms, MT1 the most urgent (file order): each period
    # MT1 runs 0-1, MT2 1-3, MT3 3-5, MT4 5-6. Each non-blocking read is at its job's
    # start, after its writer's write on the same processor (1, 3, 5): the sample read
    # at 0 reaches the actuator at 6: first use 6 ms; a change just after 0 is sampled
    # at 10 and reaches it at 16: reaction 16.
    chain = _fig4_chain(FIG4)
    assert chain["on_processors"] == {"first_use": "6", "age": "6", "age_min": "6",
                                      "reaction": "16", "why_undecided": None}


def test_analyze_json_gives_figure_4_reversed_first_use(tmp_path):
    # The paper's lower half of Figure 4: MT4 the most urgent, MT1 the least. Each period
    # MT4 runs 0-1, MT3 1-3, MT2 3-5, MT1 5-6: every read comes before its writer's write
    # of the period. The sample read at 5 (MT1, written at 6) is read by MT2 at 13 (write
    # 15), by MT3 at 21 (write 23), by MT4 at 30, posted at 31: 31 - 5 = 26 ms; reaction
    # 26 + 10 = 36.
    text = FIG4.read_text()  # a larger priority is more urgent
    for task, priority in (("MT1", 1), ("MT2", 2), ("MT3", 3), ("MT4", 4)):
        text = text.replace(f"  {task}:\n", f"  {task}:\n    priority: {priority}\n", 1)
    assert text.count("    priority: ") == 4
    path = tmp_path / "fig4_reversed.yaml"
    path.write_text(text)
    chain = _fig4_chain(path)
    assert chain["on_processors"]["first_use"] == "26"
    assert chain["on_processors"]["reaction"] == "36"
    # With a processor per task the priorities do not matter: every job starts at its
    # tick 10(k-1) and sees only what was written strictly before (MT1's write at 1 by
    # MT2 at 10, ...), posted at 31 by MT4: 31 - 0 = 31, reaction 41.
    assert (chain["first_use"], chain["reaction"]) == ("31", "41")
    alone = _fig4_chain(path, "--no-processors")
    assert alone["on_processors"]["first_use"] == alone["first_use"] == "31"


@pytest.mark.parametrize("args", [
    ("timeline", "{example}", "-o", "{missing}/t.svg"),
    ("convert", "{example}", "{missing}/x.dot"),
    ("fix", "{example}", "-o", "{missing}/x.yaml"),
])
def test_no_output_directory_is_created_silently(tmp_path, args):
    example = REPO / "examples" / "fig7b_wrong_order.yaml"
    missing = tmp_path / "not" / "there"
    argv = [a.format(example=example, missing=missing) for a in args]
    out = invoke(*argv)
    assert out.exit_code == 2 and out.stdout == "" and no_traceback(out)
    assert f"the directory {missing} does not exist" in out.stderr
    assert not (tmp_path / "not").exists()


def test_every_command_help_lists_its_exit_statuses_with_130():
    # main() turns Ctrl-C into exit status 130 for every command (the README says
    # so), so every --help must say it, beside 0 and 2.
    from typer.main import get_command

    group = get_command(app)
    assert len(group.commands) >= 9
    for name in group.commands:
        text = " ".join(CliRunner().invoke(app, [name, "--help"], terminal_width=200)
                        .stdout.split())
        assert "Exit status: 0" in text, name
        assert "2 the input" in text and "130 interrupted" in text, name


@pytest.mark.parametrize("example, expected", [
    # By hand in each example's header: fig7b is dead (MT1 has the clock rtc, MT2
    # and MT3 none); in overrun_in_step MT2 overruns at activation 2, MT1 never.
    ("fig7b_wrong_order.yaml", {"MT1": "not live", "MT2": "no clock", "MT3": "no clock"}),
    ("overrun_in_step.yaml", {"MT1": "never", "MT2": "at activation 2"}),
])
def test_csv_overrun_tells_never_from_no_clock_from_not_live(tmp_path, example, expected):
    import csv

    out = CliRunner().invoke(app, ["analyze", str(REPO / "examples" / example), "--csv",
                                   str(tmp_path)])
    assert out.exit_code == 1
    with open(tmp_path / "tasks.csv", newline="") as fh:
        rows = {row["task"]: row for row in csv.DictReader(fh)}
    assert {t: rows[t]["overrun"] for t in expected} == expected
    late = {t: rows[t]["overrun_at (activation)"] for t in expected}
    assert late == {t: (w.split()[-1] if w.startswith("at ") else "") for t, w in expected.items()}


# ------------------------------------------- output files: one refusal, one wording

@pytest.mark.parametrize("args", [
    ("analyze", "{live}", "--csv", "{dir}"),
    ("fix", "{fig7b}", "-o", "{dir}/taken.yaml"),
    ("convert", "{live}", "{dir}/taken.edges"),
    ("timeline", "{live}", "-o", "{dir}/taken.svg"),
    ("sensitivity", "{live}", "--vary", "A.duration", "--plot", "{dir}/taken.svg"),
    ("explore", "{live}", "--plot", "{dir}/taken.svg"),
], ids=lambda a: a[0])
def test_every_command_refuses_to_replace_a_file_in_the_same_words(tmp_path, live_file, args):
    # Each existing target is kept, with one line naming it, until --force is given.
    taken = {"analyze": tmp_path / "tasks.csv"}.get(args[0], tmp_path / Path(args[-1]).name)
    taken.write_text("mine")
    fig7b = REPO / "examples" / "fig7b_wrong_order.yaml"
    out = invoke(*(a.format(live=live_file, fig7b=fig7b, dir=tmp_path) for a in args))
    assert out.exit_code == 2 and out.stdout == "" and no_traceback(out)
    assert out.stderr == (f"tegraph: error: {taken}: the file exists already; pass --force "
                          "to replace it\n")
    assert taken.read_text() == "mine"


def test_fix_refuses_to_replace_its_input_without_force(tmp_path):
    path = tmp_path / "fig7b.yaml"
    text = (REPO / "examples" / "fig7b_wrong_order.yaml").read_text()
    path.write_text(text)
    out = invoke("fix", path, "-o", path)
    assert out.exit_code == 2 and out.stdout == ""
    assert out.stderr == (f"tegraph: error: {path}: this is the input file; pass --force to "
                          "replace it (its comments are not copied)\n")
    assert path.read_text() == text


# ------------------------------------------- shared options: declared once, library defaults

def _options_by_flag() -> dict[str, list[tuple[str, object]]]:
    """Each option flag -> (command, click parameter) for every command declaring it."""
    from typer.main import get_command

    found: dict[str, list[tuple[str, object]]] = {}
    for name, command in get_command(app).commands.items():
        for param in command.params:
            for flag in (o for o in param.opts if o.startswith("-")):
                found.setdefault(flag, []).append((name, param))
    return found


def test_budget_defaults_are_the_library_constants():
    # The library's own constants, read where the library defines them (these modules
    # load numpy, which the command line must not do before --help).
    from tegraph.analysis.baselines.reachability import DEFAULT_MAX_MEMORY
    from tegraph.analysis.processors import MAX_EVENTS
    from tegraph.api import analyze, cycle_time, explore, reach
    from tegraph.cli import _size
    from tegraph.io import DEFAULT_MAX_BYTES
    from tegraph.model.limits import DEFAULT_MAX_FIRINGS

    def default(function, name):
        import inspect
        return inspect.signature(function).parameters[name].default

    expected = {"--max-events": MAX_EVENTS, "--max-states": default(reach, "max_states"),
                "--max-memory": DEFAULT_MAX_MEMORY, "--max-firings": DEFAULT_MAX_FIRINGS,
                "--max-size": DEFAULT_MAX_BYTES, "--max-steps": default(analyze, "max_steps"),
                "--max-variants": default(explore, "max_variants")}
    assert default(cycle_time, "max_states") == expected["--max-states"]
    options = _options_by_flag()
    assert {flag: len(options[flag]) for flag in expected} == {
        "--max-events": 5, "--max-states": 2, "--max-memory": 2, "--max-firings": 2,
        "--max-size": 2, "--max-steps": 1, "--max-variants": 1}
    for flag, value in expected.items():
        for command, param in options[flag]:
            shown = param.default
            if flag in ("--max-memory", "--max-size"):  # a size text, e.g. "2G"
                shown = _size(shown, flag)
            assert shown == value, (command, flag)


def test_a_shared_option_says_the_same_in_every_command():
    # --force, --chain and --max-events name the command's object (a drawing, CSV files;
    # report or minimize a latency; what the events are fired for): one sentence shape.
    options = _options_by_flag()
    shapes = {"--force": "Replace ", "--chain": " this chain of tasks, sensor first, e.g. ",
              "--max-events": "Budget of event firings of "}
    shared = {flag: found for flag, found in options.items() if len(found) > 1}
    assert {"--json", "--force", "--chain", "--max-events", "--max-states", "--max-memory",
            "--processors", "--max-seconds", "--max-firings", "--max-size"} <= set(shared)
    for flag, found in shared.items():
        if flag == "--processors":  # explore's names the processors it may place tasks on
            found = [(command, param) for command, param in found if command != "explore"]
        helps = {command: param.help for command, param in found}
        if flag in ("-o", "--output", "--plot"):  # a different file in each command
            continue
        if flag in shapes:
            assert all(shapes[flag] in text for text in helps.values()), helps
        else:
            assert len(set(helps.values())) == 1, (flag, helps)


def test_end_to_end_the_command_line_loads_no_numpy_before_its_work():
    # --help and every refusal of an option come before any analysis: importing the
    # command line (and the library's budgets it shows) loads neither numpy nor scipy.
    done = subprocess.run([sys.executable, "-c", "import sys; import tegraph.cli; "
                           "print(sorted({'numpy', 'scipy'} & set(sys.modules)))"],
                          capture_output=True, text=True, timeout=120, cwd=REPO)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "[]"
