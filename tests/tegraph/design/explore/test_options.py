"""`tegraph explore` options that could break or silently overrule each other:
Dask addresses and timeouts, a repeated --link or --clock, the `dask` dependency, and
the schema the JSON report follows.

Nothing here starts a Dask server: refused addresses are refused before any
connection, and the one address that is tried (a port nothing listens on) is on
127.0.0.1.
"""

from __future__ import annotations

import ast
import json
import re
import socket
import subprocess
import sys
import time

import jsonschema
import pytest
from typer.testing import CliRunner

from tegraph import InputError, load_skeleton
from tegraph.api import explore
from tegraph.cli import app
from tegraph.design.explore import scheduler_address
from tests.paths import REPO

FIG4 = str(REPO / "examples" / "fig4_pipeline_synchronized.yaml")


def free_port() -> int:
    """A 127.0.0.1 port that nothing listens on (bound, then released)."""
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def one_line_refusal(out, words: str) -> None:
    assert out.exit_code == 2, (out.stdout, out.stderr)
    assert "Traceback" not in out.stderr and len(out.stderr.strip().splitlines()) == 1, \
        out.stderr
    assert words in out.stderr, out.stderr


# ------------------------------------------------------------- Dask addresses and timeouts

@pytest.mark.parametrize("address, words", [
    ("tls://127.0.0.1:1", "--scheduler: cannot use 'tls://127.0.0.1:1': a TLS scheduler "
                          "needs certificates"),
    ("tcp://127.0.0.1:abc", "--scheduler: cannot read 'tcp://127.0.0.1:abc' as a Dask "
                            "scheduler address"),
    ("tcp://127.0.0.1:70000", "with a port from 1 to 65535"),
    ("inproc://x", "the inproc:// transport is not supported"),
    ("127.0.0.1", "cannot read '127.0.0.1'"),
])
def test_a_malformed_or_tls_address_is_refused_at_once(address, words):
    start = time.monotonic()
    out = CliRunner().invoke(app, ["explore", FIG4, "--all-links", "--scheduler", address])
    one_line_refusal(out, words)
    assert time.monotonic() - start < 5  # before any connection


@pytest.mark.parametrize("value", ["inf", "nan", "0", "-1", "1e9"])
def test_a_timeout_that_dask_cannot_take_is_refused(value):
    out = CliRunner().invoke(app, ["explore", FIG4, "--all-links", "--scheduler",
                                   f"tcp://127.0.0.1:{free_port()}", "--timeout", value])
    one_line_refusal(out, "--timeout: expected a number of seconds > 0 and at most 86400")


def test_a_malformed_address_leaves_no_traceback_at_exit():
    # The command as a user runs it: a half-built Client would print, after the
    # refusal and its own timeout, a TimeoutError traceback from its __del__.
    start = time.monotonic()
    out = subprocess.run([sys.executable, "-m", "tegraph.cli", "explore", FIG4, "--all-links",
                          "--scheduler", "tcp://127.0.0.1:abc"], cwd=REPO,
                         capture_output=True, text=True, timeout=60)
    assert out.returncode == 2
    assert out.stderr.count("\n") == 1 and "Traceback" not in out.stderr, out.stderr
    assert time.monotonic() - start < 15


def test_the_library_checks_the_address_and_timeout_before_connecting():
    sk = load_skeleton(FIG4)
    with pytest.raises(InputError) as err:
        explore(sk, all_links=True, scheduler="tls://127.0.0.1:1")
    assert err.value.where == "scheduler"
    with pytest.raises(InputError) as err:
        explore(sk, all_links=True, scheduler=f"tcp://127.0.0.1:{free_port()}",
                timeout=float("inf"))
    assert err.value.where == "timeout"
    assert scheduler_address("localhost:8786") == "tcp://localhost:8786"
    assert scheduler_address("tcp://[::1]:8786") == "tcp://[::1]:8786"


# ---------------------------------------- options that overruled each other

def test_a_link_chosen_twice_is_refused_naming_both():
    # Before: the second --link replaced the first (one dict key), silently.
    out = CliRunner().invoke(app, ["explore", FIG4, "--link", "MT1:x1 -> MT2:x1=ASYN/SYN",
                                   "--link", "MT2:x2 -> MT3:x2", "--link",
                                   "MT1:x1->MT2:x1=SYN/SYN", "--workers", "0"])
    one_line_refusal(out, "--link[2]: the link 'MT1:x1 -> MT2:x1' is chosen twice, by "
                          "--link[0] and --link[2]")


def test_a_clock_chosen_twice_is_refused_naming_both():
    out = CliRunner().invoke(app, ["explore", FIG4, "--clock", "rtc=5,10", "--clock",
                                   "rtc=20", "--workers", "0"])
    one_line_refusal(out, "--clock rtc: the clock 'rtc' is chosen twice, by --clock[0] and "
                          "--clock[1]")


def test_a_period_on_the_command_line_goes_through_the_bounded_parser():
    start = time.monotonic()
    out = CliRunner().invoke(app, ["explore", FIG4, "--clock", "rtc=1e999999999",
                                   "--workers", "0"])
    one_line_refusal(out, "--clock rtc[0]: expected a period > 0")
    assert "digits" in out.stderr and time.monotonic() - start < 5


# -------------------------------------------------------- the dask dependency

def test_dask_is_a_benchmark_extra_not_a_runtime_dependency():
    tomllib = pytest.importorskip("tomllib", reason="tomllib is in Python 3.11 and later")
    project = tomllib.loads((REPO / "pyproject.toml").read_text())["project"]
    names = {re.split(r"[<>=!~ \[]", d, maxsplit=1)[0].lower() for d in project["dependencies"]}
    assert "distributed" in names and "dask" not in names
    assert any(d.startswith("dask") for d in project["optional-dependencies"]["bench"])
    # Nothing installed with tegraph imports dask itself (distributed is what runs).
    for path in [*(REPO / "tegraph").rglob("*.py"), *(REPO / "maxplus").rglob("*.py")]:
        for node in ast.walk(ast.parse(path.read_text(), str(path))):
            if isinstance(node, ast.Import):
                assert all(a.name.split(".")[0] != "dask" for a in node.names), path
            elif isinstance(node, ast.ImportFrom) and node.module:
                assert node.module.split(".")[0] != "dask", path


# ------------------------------------------------------------- the schema

def test_every_schema_the_sources_and_docs_name_exists():
    # docs/explore.md and Exploration.to_dict named docs/explore.schema.json, which did
    # not exist: explore's document is $defs/explore of docs/report.schema.json.
    sources = [*(REPO / "docs").glob("*.md"), REPO / "README.md",
               *(REPO / "tegraph").rglob("*.py"), *(REPO / "maxplus").rglob("*.py")]
    named = {(m, path) for path in sources
             for m in re.findall(r"docs/[\w.-]+\.schema\.json", path.read_text())}
    missing = sorted(f"{path.relative_to(REPO)} names {m}" for m, path in named
                     if not (REPO / m).is_file())
    assert not missing


def test_the_json_with_constraints_and_rejections_follows_the_schema(tmp_path):
    schema = json.loads((REPO / "docs" / "report.schema.json").read_text())
    out = CliRunner().invoke(app, [
        "explore", FIG4, "--link", "MT1:x1 -> MT2:x1", "--clock", "rtc=5,10,20",
        "--forbid", "SYN/SYN", "--require", "MT1.period<=10", "--max-latency",
        "MT1,MT2,MT3,MT4=6", "--workers", "0", "--json"])
    assert out.exit_code == 0, out.stderr
    doc = json.loads(out.stdout)
    jsonschema.validate(doc, schema)
    assert doc["constraints"] == {
        "periods": [{"task": "MT1", "op": "<=", "period": "10"}],
        "latencies": [{"chain": ["MT1", "MT2", "MT3", "MT4"], "at_most": "6"}],
        "forbidden": ["SYN/SYN"], "free_running": False}
    assert doc["choices"]["links"] == {"MT1:x1 -> MT2:x1": ["ASYN/ASYN", "ASYN/SYN",
                                                             "SYN/ASYN"]}
    assert sum(doc["rejected"].values()) + doc["kept"] == doc["variants"] == 9
