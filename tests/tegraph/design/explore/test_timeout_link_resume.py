"""explore's options: the timeout read by the one
number parser and shown as given, --link with --all-links said in the report, and the
refusal of a foreign file under --resume --force saying what to do.
"""

from __future__ import annotations

import socket

import pytest
from typer.testing import CliRunner

from tegraph import InputError, load_skeleton
from tegraph.api import explore
from tegraph.cli import app
from tests.paths import REPO

FIG4 = str(REPO / "examples" / "fig4_pipeline_synchronized.yaml")
LINK = "MT1:x1 -> MT2:x1"


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def one_line(out) -> str:
    assert out.exit_code == 2, (out.stdout, out.stderr)
    lines = out.stderr.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in out.stderr, out.stderr
    return lines[0]


def with_timeout(value: str):
    return CliRunner().invoke(app, ["explore", FIG4, "--all-links", "--scheduler",
                                    f"tcp://127.0.0.1:{free_port()}", "--timeout", value])


def test_a_timeout_of_a_billion_digits_is_refused_by_its_size_not_read_as_inf():
    line = one_line(with_timeout("1e999999999"))
    assert line.startswith("tegraph: error: --timeout: expected a number of seconds > 0")
    assert "1,000,000,000 digits; at most 4,300" in line and "inf" not in line


@pytest.mark.parametrize("value", ["0", "0.0", "-0.5", "2e5", "1/0", "inf"])
def test_a_refused_timeout_is_shown_as_given(value):
    line = one_line(with_timeout(value))
    assert "--timeout: expected a number of seconds > 0 and at most 86400" in line
    assert repr(value) in line or "zero denominator" in line, line
    assert "got 0.0" not in line and "got inf" not in line


def test_an_exact_timeout_is_taken():
    # Half a second, read exactly: the scheduler that does not answer is named with it.
    line = one_line(with_timeout("1/2"))
    assert "within 0.5 s" in line, line


def test_the_library_shows_the_timeout_as_given():
    sk = load_skeleton(FIG4)
    with pytest.raises(InputError, match=r"got 0\.0$") as caught:
        explore(sk, all_links=True, workers=0, timeout=0.0)
    assert caught.value.where == "timeout"
    with pytest.raises(InputError, match="1,000,000,000 digits"):
        explore(sk, all_links=True, workers=0, timeout="1e999999999")


def test_link_with_all_links_narrows_that_link_and_the_report_says_so():
    # Chosen: keep the combination (the one way to vary every link but restrict one),
    # and say it: the link's line and a note name the narrowing.
    out = CliRunner().invoke(app, ["explore", FIG4, "--all-links", "--link",
                                   f"{LINK}=ASYN/SYN", "--objective", "period"])
    assert out.exit_code in (0, 1), out.output
    assert f"link {LINK}: ASYN/SYN (narrowed by --link; --all-links gives the other" \
           in out.stdout, out.stdout
    assert f"note: --link narrows --all-links for {LINK}" in out.stdout
    # Without --all-links, or with --link naming all four, nothing is narrowed.
    out = CliRunner().invoke(app, ["explore", FIG4, "--link", f"{LINK}=ASYN/SYN,SYN/SYN",
                                   "--objective", "period"])
    assert "narrow" not in out.stdout
    out = CliRunner().invoke(app, ["explore", FIG4, "--all-links", "--link", LINK,
                                   "--objective", "period"])
    assert "narrow" not in out.stdout


def test_resume_with_force_on_a_foreign_file_says_what_to_do(tmp_path):
    target = tmp_path / "mine.csv"
    target.write_bytes(b"my,own,data\n1,2,3\n")
    out = CliRunner().invoke(app, ["explore", FIG4, "--all-links", "-o", str(target),
                                   "--resume", "--force", "--workers", "0"])
    line = one_line(out)
    assert "pass --force to replace it" not in line
    assert "--force does not replace a file being resumed" in line
    assert "a new -o file" in line and "drop --resume" in line
    assert target.read_bytes() == b"my,own,data\n1,2,3\n"
    # Without --force, the plain advice stays.
    out = CliRunner().invoke(app, ["explore", FIG4, "--all-links", "-o", str(target),
                                   "--resume", "--workers", "0"])
    assert "pass --force to replace it" in one_line(out)
