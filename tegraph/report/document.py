"""JSON documents of every command (``docs/report.schema.json``).

Each result's ``to_dict()`` gives its data (exact numbers as strings); a
document adds ``schema_version`` and the ``report`` name (the command), so a
program reading any of them knows which it holds. ``analyze``'s document is the
one of ``docs/skeleton.md`` §5 with these two keys first.
"""

from __future__ import annotations

import json
from typing import Any

import orjson

from .registry import Renderers

__all__ = ["SCHEMA_VERSION", "json_report", "to_document", "to_json", "to_json_bytes"]

SCHEMA_VERSION = 2


def json_report(command: str, body: dict[str, Any]) -> dict[str, Any]:
    """A command's JSON document: ``schema_version`` and ``report`` first, then ``body``.

    ``docs/report.schema.json`` describes each command's document.

    >>> json_report("reach", {"states": 3})
    {'schema_version': 2, 'report': 'reach', 'states': 3}
    """
    return {"schema_version": SCHEMA_VERSION, "report": command, **body}


def to_document(result: Any) -> dict[str, Any]:
    """The JSON document of a result, as Python data.

    Parameters
    ----------
    result : Report, DesignSection, CycleTimeResult, Reachability, TimedExploration or
        Exploration
        A result of this project.

    Returns
    -------
    dict
        The document of ``docs/report.schema.json``, with its
        ``schema_version``.

    Raises
    ------
    TypeError
        For an object that is no result of this project.

    See Also
    --------
    to_json : the same as JSON text.

    Examples
    --------
    >>> from tegraph import Skeleton, analyze
    >>> r = analyze(Skeleton.from_dict({"tasks": {"A": {"duration": 1, "period": 3}}}))
    >>> to_document(r)["schema_version"], to_document(r)["report"], to_document(r)["live"]
    (2, 'analyze', True)
    """
    return _DOCUMENTS.find(result)(result)


# Each result type by its dotted name (imported only when such a result is written).
_DOCUMENTS = Renderers("JSON document", {
    "tegraph.analysis.results.Report": "tegraph.report.document:_analyze",
    "tegraph.design.section.DesignSection": "tegraph.report.document:_rules",
    "tegraph.analysis.cycle_time.CycleTimeResult": "tegraph.report.document:_cycle_time",
    "tegraph.design.explore.exploration.Exploration": "tegraph.report.document:_explore",
    "tegraph.analysis.sensitivity.results.SensitivityResult":
        "tegraph.report.document:_sensitivity",
    "tegraph.analysis.baselines.reachability.Reachability": "tegraph.report.document:_reach",
    "tegraph.analysis.baselines.timed_reachability.TimedExploration":
        "tegraph.report.document:_reach",
})


def _analyze(result: Any) -> dict[str, Any]:
    return json_report("analyze", result.to_dict())


def _rules(result: Any) -> dict[str, Any]:
    # The verdict is the analysis's (spec §4b), with how it was obtained, as in analyze's
    # document; the design section's response-time test is its cross-check.
    return json_report("rules", {"name": result.name, "unit": result.unit,
                                 "schedulable": result.schedulable,
                                 "schedule": result.analysis.schedule_summary(),
                                 **result.to_dict()})


def _cycle_time(result: Any) -> dict[str, Any]:
    return json_report("cycle-time", result.to_dict())


def _explore(result: Any) -> dict[str, Any]:
    """The exploration's document.

    >>> from tegraph import load_skeleton
    >>> from tegraph.design.explore import explore_design
    >>> from tegraph.design.explore.space import design_space
    >>> space = design_space(load_skeleton("examples/fig4_pipeline_synchronized.yaml"),
    ...                      clocks={"rtc": [10, 20]}, objectives=["load"])
    >>> doc = to_document(explore_design(space, workers=0))
    >>> doc["report"], doc["exhaustive"], doc["front"][0]["clocks"], doc["front"][0]["objectives"]
    ('explore', True, {'rtc': '20'}, {'load': '3/10'})
    """
    return json_report("explore", result.to_dict())


def _sensitivity(result: Any) -> dict[str, Any]:
    return json_report("sensitivity", result.to_dict())


def _reach(result: Any) -> dict[str, Any]:
    return json_report("reach", result.to_dict())


def to_json(result: Any, indent: int | None = 2) -> str:
    """:func:`to_document` as JSON text (UTF-8 characters kept as they are).

    Parameters
    ----------
    result : Report, CycleTimeResult, Reachability, TimedExploration or Exploration
        A result of this project.
    indent : int or None
        Indentation of the JSON text; None writes one line.

    Returns
    -------
    str
        The document of ``docs/report.schema.json`` for that result.

    Raises
    ------
    TypeError
        For an object that is no result of this project.

    See Also
    --------
    to_document : the same as Python data.
    tegraph.report.render_text : the human report of the same result.

    Examples
    --------
    >>> from tegraph import Skeleton, analyze
    >>> r = analyze(Skeleton.from_dict({"tasks": {"A": {"duration": 1, "period": 3}}}))
    >>> to_json(r, indent=None)[:61]
    '{"schema_version": 2, "report": "analyze", "name": "skeleton"'
    """
    # The document is freed before its text is decoded (``_dumps`` has returned): a
    # report of 100,000 tasks is some 100 MiB as Python data, 160 MB as text.
    data = _dumps(to_document(result), indent)
    return data if isinstance(data, str) else data.decode()


def to_json_bytes(result: Any, indent: int | None = 2) -> bytes:
    """:func:`to_json` as UTF-8 bytes, never held as text as well.

    For writing to a binary stream (``typer.echo`` and ``click.echo`` write bytes
    as they are): a report of 100,000 tasks is 160 MB of JSON, which
    :func:`to_json` holds twice (bytes, then the text) and a text stream encodes
    once more.

    Examples
    --------
    >>> from tegraph import Skeleton, analyze
    >>> r = analyze(Skeleton.from_dict({"tasks": {"A": {"duration": 1, "period": 3}}}))
    >>> to_json_bytes(r) == to_json(r).encode()
    True
    """
    data = _dumps(to_document(result), indent)
    return data.encode() if isinstance(data, str) else data


def _dumps(doc: dict[str, Any], indent: int | None) -> bytes | str:
    """The JSON of ``doc``: orjson's UTF-8 bytes for ``indent=2``, else json's text."""
    if indent == 2:
        # orjson writes the bytes of json.dumps(doc, indent=2, ensure_ascii=False), in C:
        # the standard library encodes in Python once it indents, slow on the report of
        # 10,000 tasks. Integers beyond 64 bits are left to json.
        try:
            return orjson.dumps(doc, option=orjson.OPT_INDENT_2)
        except orjson.JSONEncodeError:
            pass
    return json.dumps(doc, indent=indent, ensure_ascii=False)
