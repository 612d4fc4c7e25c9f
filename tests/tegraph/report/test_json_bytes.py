"""``to_json_bytes`` is ``to_json`` encoded, byte for byte, on every path of ``_dumps``."""

import json

import pytest

from tegraph import Skeleton, analyze
from tegraph.report import to_json, to_json_bytes
from tegraph.report.document import _dumps

# A name outside ASCII: both write it as UTF-8, not as an escape.
SKELETON = {"tasks": {"Capteur_é": {"duration": 1, "period": 4, "outputs": ["x"]},
                      "B": {"duration": 2, "inputs": ["x"]}},
            "links": [{"from": "Capteur_é:x", "to": "B:x", "protocol": "ASYN/SYN"}]}


@pytest.mark.parametrize("indent", [2, None, 4])
def test_bytes_are_the_text_encoded(indent):
    r = analyze(Skeleton.from_dict(SKELETON))
    text = to_json(r, indent=indent)
    assert "Capteur_é" in text
    assert to_json_bytes(r, indent=indent) == text.encode()


def test_integers_past_64_bits_fall_back_to_json_on_both():
    doc = {"big": 2**70, "name": "é"}
    # orjson refuses the integer: json writes it, as text (to_json returns it as is).
    assert _dumps(doc, 2) == json.dumps(doc, indent=2, ensure_ascii=False)
    # within 64 bits, orjson's bytes are json's text encoded
    small = {"big": 2**62, "name": "é", "list": [1, {"a": None}]}
    assert _dumps(small, 2) == json.dumps(small, indent=2, ensure_ascii=False).encode()
