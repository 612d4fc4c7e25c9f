"""Fuzz smoke test: whatever bytes a file holds, every reader either reads it or refuses it
with one InputError; no other exception type ever comes out.

Random bytes and random mutations of the anchor files (tests/data/anchors) and of the
example skeletons are given to ``tegraph.io.read`` under each format. Bounded to a few
seconds: ``FUZZ_EXAMPLES`` sets the number of files (raise it to hunt, e.g. 5000).
"""

from __future__ import annotations

import os
import re
import tempfile
from pathlib import Path

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from tegraph.errors import InputError
from tegraph.io import read
from tests.paths import REPO, VENDORED_ANCHORS

READERS = ("pnml", "sdf3", "edges", "tpne-json", "tpne-teg", "skeleton")
SEEDS = {
    "tpne-teg": ["teg/SemiHoward.teg", "teg/SemiNetherlands.teg"],
    "tpne-json": ["teg/Howard2.json", "teg/EventGraph.json"],
    "edges": ["sdf/hsdf_edges/modem.hsdf.edges",
              "sdf/hsdf_edges/mp3decoder_granule_parallelism.hsdf.edges"],
    "sdf3": ["sdf/xml/mp3playback.xml", "sdf/xml/h263decoder.xml"],
    "pnml": ["pnml/CircularTrains-PT-012.pnml"],
}
SEED_BYTES = [(fmt, (VENDORED_ANCHORS / name).read_bytes())
              for fmt, names in SEEDS.items() for name in names]
SEED_BYTES += [("skeleton", (REPO / "examples" / name).read_bytes())
               for name in ("fig12_double_sync.yaml", "fig7b_wrong_order.yaml")]
SUFFIX = {"pnml": ".pnml", "sdf3": ".sdf3", "edges": ".edges", "tpne-json": ".json",
          "tpne-teg": ".teg", "skeleton": ".yaml"}
# What breaks readers: huge and negative numbers, exponents, surrogates, nesting, markup.
TOKENS = [b"9" * 30, b"9" * 5000, b"-1", b"1e999999999", b"1e-99999", b"0", b"nan", b"inf",
          b"1/0", b"\\ud800", b"[" * 200, b"{" * 200, b"<!DOCTYPE a [<!ENTITY e 'x'>]>", b"&e;",
          b'"', b":", b"\n", b"\x00", b"\xff\xfe", b"*a", b"&a ", b"<<: ", b"#", b" ",
          b"2305843009213693952", b"9223372036854775808", b"18446744073709551617"]
_VALUE = re.compile(rb"[0-9]+(?:\.[0-9]+)?|[A-Za-z_][A-Za-z0-9_]*")
FUZZ_EXAMPLES = int(os.environ.get("FUZZ_EXAMPLES", "120"))


@st.composite
def mutated(draw) -> tuple[str, bytes]:
    """An anchor's bytes with a few edits: overwrite, insert, delete, duplicate, a token
    anywhere, or a token in place of a number or a name."""
    fmt, data = draw(st.sampled_from(SEED_BYTES))
    data = bytearray(data)
    for _ in range(draw(st.integers(1, 6))):
        at = draw(st.integers(0, len(data)))
        edit = draw(st.sampled_from(["byte", "token", "delete", "duplicate", "insert",
                                     "value", "value"]))
        if edit == "value":  # the edit that reaches the checks of values
            spans = [m.span() for m in _VALUE.finditer(bytes(data))]
            if spans:
                lo, hi = spans[draw(st.integers(0, len(spans) - 1))]
                data[lo:hi] = draw(st.sampled_from(TOKENS))
        elif edit == "byte" and at < len(data):
            data[at] = draw(st.integers(0, 255))
        elif edit == "token":
            data[at:at] = draw(st.sampled_from(TOKENS))
        elif edit == "delete":
            del data[at:at + draw(st.integers(1, 64))]
        elif edit == "duplicate":
            data[at:at] = data[at:at + draw(st.integers(1, 256))]
        else:
            data[at:at] = draw(st.binary(min_size=1, max_size=16))
    return fmt, bytes(data)


def read_or_refuse(data: bytes, fmt: str) -> None:
    """Read ``data`` as ``fmt``: success or InputError; any other exception fails the test."""
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / f"fuzz{SUFFIX[fmt]}"
        path.write_bytes(data)
        try:
            read(path, fmt)
        except InputError as exc:
            assert str(exc), "an InputError says what is wrong"
            str(exc).encode("utf-8")  # the message itself can be printed


@settings(max_examples=FUZZ_EXAMPLES, deadline=None, database=None,
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
@given(mutated(), st.sampled_from(READERS))
def test_mutated_anchors_are_read_or_refused(case, other):
    fmt, data = case
    read_or_refuse(data, fmt)  # by the reader of its own format
    read_or_refuse(data, other)  # and by any other


@settings(max_examples=FUZZ_EXAMPLES // 2, deadline=None, database=None)
@given(st.binary(max_size=512), st.sampled_from(READERS))
def test_random_bytes_are_read_or_refused(data, fmt):
    read_or_refuse(data, fmt)
