"""The dictionary form of a skeleton (spec §1): read it with every check, write it.

:func:`skeleton_fields` turns the dictionary a skeleton file holds into the
fields of a :class:`~tegraph.model.skeleton.core.Skeleton`, refusing what the
format refuses; :func:`skeleton_to_data` is its inverse. Reading the file itself (YAML, JSON,
line numbers) is :mod:`tegraph.io.skeleton_file`'s job.
"""

from __future__ import annotations

import difflib
import functools
import math
import re
from collections.abc import Mapping, Sequence
from decimal import Decimal
from fractions import Fraction
from typing import Any

from maxplus.errors import MaxPlusValueError
from maxplus.scalar import exact_time, size_problem

from ..elements import Clock, Link, Processor, Protocol, Task
from ..limits import text_problem, written
from .checks import KeyPath, Locator, check_name, check_skeleton
from .shape import SkeletonShape

__all__ = ["skeleton_fields", "skeleton_to_data"]

# The spec §6 extensions (chains; priority, processor) come last, so that the
# messages that list the v1 keys keep their wording.
TOP_KEYS = ("name", "unit", "clocks", "tasks", "links", "threads", "chains", "processors",
            "network")
CLOCK_KEYS = ("period", "phase")
TASK_KEYS = ("duration", "clock", "period", "phase", "inputs", "outputs", "priority",
             "processor")
LINK_KEYS = ("from", "to", "protocol", "delay")
PROCESSOR_KEYS = ("preemptive",)
NETWORK_KEYS = ("delay",)
_PROTOCOLS = ", ".join(p.value for p in Protocol)
# What a task's body and a protocol are expected to be, worded once (not per element).
_TASK_MAPPING = f"a mapping of task fields ({', '.join(TASK_KEYS)})"
_A_PROTOCOL = f"a protocol ({_PROTOCOLS})"
_PROTOCOL_OF = {p.value: p for p in Protocol}
_NUMBER = 'a finite number such as 2, 0.5 or "7/3"'
_DECIMAL_INT = re.compile(r"[+-]?[0-9][0-9_]*")


def _kind(value: Any) -> str:
    """How a refused value is named in messages."""
    if value is None:
        return "nothing (null)"
    if isinstance(value, bool):
        return f"the boolean {str(value).lower()}"
    if isinstance(value, str):
        return f"the text {value!r}"
    if isinstance(value, Mapping):
        return "a mapping"
    if isinstance(value, (list, tuple)):
        return "a list"
    return f"{type(value).__name__} {value!r}"


def _mapping(value: Any, path: KeyPath, what: str, loc: Locator) -> Mapping[Any, Any]:
    if type(value) is dict:  # what a file gives: no abstract-class check per task
        return value
    if not isinstance(value, Mapping):
        raise loc.error(f"expected {what}, got {_kind(value)}", path)
    return value


def _sequence(value: Any, path: KeyPath, what: str, loc: Locator) -> Sequence[Any]:
    if type(value) is list:  # what a file gives: no abstract-class check per port list
        return value
    if value is None:  # `links:` with every entry commented out
        return ()
    if isinstance(value, (str, bytes, Mapping)) or not isinstance(value, Sequence):
        raise loc.error(f"expected {what}, got {_kind(value)}", path)
    return value


def _known_keys(body: Mapping[Any, Any], allowed: tuple[str, ...], path: KeyPath,
                loc: Locator) -> None:
    for key in body:
        if key not in allowed:
            hint = difflib.get_close_matches(str(key), allowed, n=1)
            maybe = f" (did you mean {hint[0]!r}?)" if hint else ""
            raise loc.error(
                f"unknown key {key!r}{maybe}; expected one of: {', '.join(allowed)}",
                (*path, str(key)),
            )


def _text(value: Any, path: KeyPath, what: str, loc: Locator) -> str:
    if isinstance(value, str):
        return value
    if value is not None and path in loc.raw:
        # YAML 1.1 reads `on` as true and `1` as an int; the user wrote a name.
        return loc.raw[path]
    raise loc.error(f"expected {what} (a text), got {_kind(value)}", path)


def _time(value: Any, path: KeyPath, what: str, positive: bool, loc: Locator) -> Fraction:
    if loc.raw and path in loc.raw:
        # The text the user wrote is exact ("0.1", "010" is ten); YAML's float or
        # octal reading of it is not. Words like .inf fall through to the checks.
        value = _from_text(loc.raw[path].replace("_", ""), value)
    kind = type(value)
    if (kind is str and len(value) <= _SHORT) or (kind is int and value.bit_length() < 64):
        known = _short_time(value, positive)
        if known is not None:
            return known
    bound = "> 0" if positive else ">= 0"
    detail = None
    # An int or a text (what a file mostly holds) is no Mapping: no abstract-class check.
    if value is None or isinstance(value, (bool, list, tuple)) or (
            type(value) is not int and type(value) is not str and isinstance(value, Mapping)):
        detail = _kind(value)
    elif isinstance(value, float) and not math.isfinite(value):
        detail = "NaN" if math.isnan(value) else "infinity"
    elif isinstance(value, Decimal) and not value.is_finite():
        detail = "NaN" if value.is_nan() else "infinity"
    else:
        too_big = size_problem(value)  # refused by its size, never expanded
        if too_big is not None:
            raise loc.error(f"{too_big} (expected {what} {bound})", path)
        try:
            result = exact_time(value)
        except MaxPlusValueError as err:
            zero = "zero denominator" in str(err)
            detail = f"{value!r}, which has a zero denominator" if zero else _kind(value)
    if detail is not None:
        raise loc.error(f"expected {what} {bound}: {_NUMBER}, got {detail}", path)
    # The sign of a Fraction is its numerator's (an int comparison, not Fraction's).
    if result.numerator < 0 or (positive and result.numerator == 0):
        raise loc.error(f"expected {what} {bound}, got "
                        f"{written(result, loc.raw.get(path) if loc.raw else None)}", path)
    return result


_SHORT = 40  # the texts (and 64-bit ints) whose time is remembered


@functools.lru_cache(maxsize=16384)
def _short_time(value: str | int, positive: bool) -> Fraction | None:
    """The time of a short text or an int, or None when :func:`_time` refuses it.

    A file repeats its values (a handful of periods; the generated chain of 10,000
    tasks has 100 durations): each is read once (a file of mostly distinct durations
    neither gains nor loses). At most 16,384 values
    of at most 40 characters are kept (a few MB). The checks of :func:`_time` word
    every refusal; a Fraction is immutable, so sharing one is safe.
    """
    if size_problem(value) is not None:
        return None
    try:
        result = exact_time(value)
    except MaxPlusValueError:
        return None
    # The sign of a Fraction is its numerator's (an int comparison, not Fraction's).
    if result.numerator < 0 or (positive and result.numerator == 0):
        return None
    return result


_NO_PHASE = Fraction(0)


def _phase(body: Mapping[Any, Any], path: KeyPath, loc: Locator) -> Fraction:
    """The phase of a clock (or of a task's private clock): 0 when not given (most
    clocks; no number to read)."""
    if "phase" not in body:
        return _NO_PHASE
    return _time(body["phase"], (*path, "phase"), "a phase", False, loc)


def _from_text(text: str, parsed: Any) -> Any:
    if ":" in text:
        return text  # YAML 1.1 reads 1:30 as 90 (base 60); YAML 1.2 and users do not
    if size_problem(text) is not None:
        return text  # a number, too long: refused by its size in _time
    try:
        exact_time(text)
    except MaxPlusValueError:
        return parsed  # .inf, .nan, true, 0x1A: keep YAML's reading (refused, or hex)
    return text


def _time_text(t: Fraction) -> int | str:
    return t.numerator if t.denominator == 1 else f"{t.numerator}/{t.denominator}"


def _priority(value: Any, path: KeyPath, loc: Locator) -> int:
    """An integer priority (spec §6), read as written: ``010`` is ten, not eight."""
    raw = loc.raw.get(path)
    if isinstance(value, int) and not isinstance(value, bool):
        if raw is not None and _DECIMAL_INT.fullmatch(raw):
            return int(raw.replace("_", ""))
        return value
    raise loc.error(f"expected a priority (an integer such as 3; larger is more urgent), "
                    f"got {_kind(value)}", path)


def _names(value: Any, path: KeyPath, what: str, loc: Locator) -> tuple[str, ...]:
    if value is None:  # no such list (most tasks lack inputs or outputs)
        return ()
    if type(value) is list and _good_names(value):
        return tuple(value)  # what the checks below give, without a call per name
    items = _sequence(value, path, f"a list of {what}s such as [a, b]", loc)
    return tuple(
        check_name(_text(item, (*path, i), f"a {what}", loc), (*path, i), what, loc)
        for i, item in enumerate(items)
    )


def _good_names(items: list[Any]) -> bool:
    """Whether :func:`check_name` accepts every item, checked on the list as a whole.

    Texts, none empty; their concatenation holds no ':' and encodes (UTF-8 pairs no
    surrogates, so it fails exactly when one of them holds a lone surrogate). False
    sends the list through the checks one name at a time, which word the refusal.
    """
    try:
        joined = "".join(items)  # a TypeError when one is no text
    except TypeError:
        return False
    return all(items) and ":" not in joined and text_problem(joined) is None


def _clock(key: str, body: Any, loc: Locator) -> Clock:
    path: KeyPath = ("clocks", str(key))
    check_name(key, path, "clock name", loc)
    body = _mapping(body, path, "a mapping with 'period' (and optional 'phase')", loc)
    _known_keys(body, CLOCK_KEYS, path, loc)
    if "period" not in body:
        raise loc.error("missing; expected a period > 0 for every clock", (*path, "period"))
    period = _time(body["period"], (*path, "period"), "a period", True, loc)
    phase = _phase(body, path, loc)
    return Clock(key, period, phase)


def _task(key: str, body: Any, declared: Mapping[str, Clock], loc: Locator
          ) -> tuple[Task, Clock | None]:
    path: KeyPath = ("tasks", str(key))
    check_name(key, path, "task name", loc)
    body = _mapping(body, path, _TASK_MAPPING, loc)
    _known_keys(body, TASK_KEYS, path, loc)
    if "duration" not in body:
        raise loc.error("missing; expected a duration >= 0 for every task", (*path, "duration"))
    duration = _time(body["duration"], (*path, "duration"), "a duration", False, loc)
    clock = None
    if "clock" in body:
        clock = check_name(_text(body["clock"], (*path, "clock"), "a clock name", loc),
                           (*path, "clock"), "clock name", loc)
    private = None
    if "period" in body:
        if clock is not None:
            raise loc.error(
                f"task {key!r} has both 'clock' and 'period'; expected one of them "
                "('clock' names a shared clock, 'period' makes a private one)",
                (*path, "period"),
            )
        clock = f"{key}.clock"
        if clock in declared:
            raise loc.error(
                f"its private clock {clock!r} collides with the clock declared at "
                f"clocks.{clock}; expected distinct clock names (rename that clock, or "
                f"write clock: {clock} instead of period)",
                (*path, "period"),
            )
        period = _time(body["period"], (*path, "period"), "a period", True, loc)
        phase = _phase(body, path, loc)
        private = Clock(clock, period, phase, private=True)
    elif "phase" in body:
        raise loc.error(
            "'phase' goes with 'period'; expected 'period' too (the phase of a shared "
            "clock is set under clocks)",
            (*path, "phase"),
        )
    inputs = _names(body.get("inputs"), (*path, "inputs"), "port name", loc)
    outputs = _names(body.get("outputs"), (*path, "outputs"), "port name", loc)
    priority = processor = None
    if "priority" in body:
        priority = _priority(body["priority"], (*path, "priority"), loc)
    if "processor" in body:
        processor = check_name(_text(body["processor"], (*path, "processor"),
                                     "a processor name", loc),
                               (*path, "processor"), "processor name", loc)
    return Task(key, duration, clock, inputs, outputs, priority, processor), private


def _endpoint(value: Any, path: KeyPath, loc: Locator) -> tuple[str, str]:
    text = _text(value, path, 'a port "TASK:PORT"', loc)
    task, colon, port = text.partition(":")
    if not colon or not task or not port or ":" in port:
        raise loc.error(f'expected "TASK:PORT" such as "MT1:b", got {text!r}', path)
    return task, port


def _protocol(value: Any, path: KeyPath, loc: Locator) -> Protocol:
    if isinstance(value, Protocol):
        return value
    text = _text(value, path, _A_PROTOCOL, loc)
    protocol = _PROTOCOL_OF.get(text)  # as written in the spec, the common case
    if protocol is not None:
        return protocol
    spelled = "".join(text.split()).upper().replace("-", "/")
    for protocol in Protocol:
        if protocol.value == spelled:
            return protocol
    raise loc.error(
        f"unknown protocol {text!r}; expected one of {_PROTOCOLS} "
        "(case-insensitive, '-' may stand for '/')",
        path,
    )


_LINK_PARTS = (("from", 'the writer "TASK:PORT"'), ("to", 'the reader "TASK:PORT"'),
               ("protocol", f"one of {_PROTOCOLS}"))


def _link(body: Any, i: int, loc: Locator) -> Link:
    path: KeyPath = ("links", i)
    body = _mapping(body, path, "a mapping with 'from', 'to' and 'protocol'", loc)
    _known_keys(body, LINK_KEYS, path, loc)
    for key, expected in _LINK_PARTS:
        if key not in body:
            raise loc.error(f"missing; expected {expected} in every link", (*path, key))
    delay = None
    if "delay" in body:  # v1.3 (§4d)
        delay = _time(body["delay"], (*path, "delay"), "a delay", False, loc)
    return Link(_endpoint(body["from"], (*path, "from"), loc),
                _endpoint(body["to"], (*path, "to"), loc),
                _protocol(body["protocol"], (*path, "protocol"), loc), delay)


def _processors(value: Any, loc: Locator) -> dict[str, Processor]:
    """``processors:`` (v1.3, §4d): each entry's properties; which processors exist is
    the tasks' to say (:func:`~.checks.check_skeleton` refuses an entry naming none)."""
    if value is None:  # `processors:` with every entry commented out
        return {}
    out: dict[str, Processor] = {}
    for key, body in _mapping(value, ("processors",), "a mapping from processor names to "
                              "their properties, such as {can0: {preemptive: false}}",
                              loc).items():
        path: KeyPath = ("processors", str(key))
        check_name(key, path, "processor name", loc)
        body = _mapping(body, path, "a mapping of processor properties (preemptive)", loc)
        _known_keys(body, PROCESSOR_KEYS, path, loc)
        preemptive = body.get("preemptive", True)
        if not isinstance(preemptive, bool):
            raise loc.error(f"expected true or false (whether a running job can be "
                            f"preempted), got {_kind(preemptive)}", (*path, "preemptive"))
        out[key] = Processor(key, preemptive)
    return out


def _network_delay(value: Any, loc: Locator) -> Fraction | None:
    """``network.delay`` (v1.3, §4d), or None when not given."""
    if value is None:
        return None
    body = _mapping(value, ("network",), "a mapping such as {delay: 0.2}", loc)
    _known_keys(body, NETWORK_KEYS, ("network",), loc)
    if "delay" not in body:
        return None
    return _time(body["delay"], ("network", "delay"), "a delay", False, loc)


def skeleton_fields(data: Any, default_name: str = "skeleton", source: str | None = None,
                    *, locator: Locator | None = None) -> dict[str, Any]:
    """The fields of a skeleton, read from the dictionary a skeleton file holds.

    Each value is checked on its own here; the cross references (a link names
    an existing port...) are checked on the built skeleton by
    :func:`~tegraph.model.skeleton.checks.check_skeleton`, which
    :meth:`Skeleton.from_dict <tegraph.model.skeleton.Skeleton.from_dict>` runs.

    Parameters
    ----------
    data : mapping
        As in spec §1: ``tasks`` (required), ``name``, ``unit``, ``clocks``,
        ``links``, ``threads``; and the extensions ``chains``, the task
        keys ``priority`` and ``processor``, ``processors``, ``network`` and a link's
        ``delay`` (v1.3). Times may be ints, Fractions, decimals,
        ``"7/3"`` strings or floats (read by their shortest decimal text).
    default_name : str
        The name when ``data`` has none (a file's stem).
    source : str, optional
        The file named in error messages and kept as ``Skeleton.source``.
    locator : Locator, optional
        Lines and source texts of a parsed file (see :mod:`tegraph.io.skeleton_file`).

    Returns
    -------
    dict
        Keyword arguments of :class:`~tegraph.model.skeleton.Skeleton`: tasks
        and declared clocks in the given order; the private clocks ``T.clock``
        of the ``period:`` shorthand follow the declared ones.

    Raises
    ------
    SkeletonError
        With the key path (and line, when known) of the first refused element.

    Examples
    --------
    >>> fields = skeleton_fields({"tasks": {"A": {"duration": "7/3", "period": 0.1}}})
    >>> fields["tasks"]["A"].duration
    Fraction(7, 3)
    >>> fields["clocks"]["A.clock"]  # doctest: +NORMALIZE_WHITESPACE
    Clock(name='A.clock', period=Fraction(1, 10), phase=Fraction(0, 1),
          private=True)
    """
    loc = locator if locator is not None else Locator(file=source)
    top = _mapping(data, (), "a mapping with at least a 'tasks' key", loc)
    _known_keys(top, TOP_KEYS, (), loc)
    name = _text(top.get("name", default_name), ("name",), "a name", loc)
    unit = _text(top.get("unit", "ms"), ("unit",), "a unit", loc)
    clocks_data = top.get("clocks")
    declared: dict[str, Clock] = {}
    if clocks_data is not None:
        for key, body in _mapping(clocks_data, ("clocks",), "a mapping from clock names "
                                  "to clocks", loc).items():
            declared[key] = _clock(key, body, loc)
    if "tasks" not in top:
        raise loc.error("missing; expected a mapping from task names to tasks (at least one)",
                        ("tasks",))
    tasks_data = _mapping(top["tasks"], ("tasks",), "a mapping from task names to tasks", loc)
    if not tasks_data:
        raise loc.error("no task; expected at least one task", ("tasks",))
    tasks: dict[str, Task] = {}
    private: dict[str, Clock] = {}
    for key, body in tasks_data.items():
        tasks[key], own = _task(key, body, declared, loc)
        if own is not None:
            private[own.name] = own
    links = [_link(body, i, loc) for i, body in
             enumerate(_sequence(top.get("links"), ("links",), "a list of links", loc))]
    threads = []
    for i, thread in enumerate(_sequence(top.get("threads"), ("threads",),
                                         "a list of threads", loc)):
        members = _sequence(thread, ("threads", i), "a list of task names such as [MT1, MT2]",
                            loc)
        threads.append(tuple(_text(t, ("threads", i, j), "a task name", loc)
                             for j, t in enumerate(members)))
    chains = []
    for i, chain in enumerate(_sequence(top.get("chains"), ("chains",),
                                        "a list of chains such as [[MT1, MT2, MT3]]", loc)):
        members = _sequence(chain, ("chains", i),
                            "a list of task names, sensor first, such as [MT1, MT2, MT3]", loc)
        chains.append(tuple(_text(t, ("chains", i, j), "a task name", loc)
                            for j, t in enumerate(members)))
    return dict(name=name, tasks=tasks, clocks={**declared, **private}, links=links,
                threads=threads, unit=unit, source=source if source is not None else loc.file,
                chains=chains, processors=_processors(top.get("processors"), loc),
                network_delay=_network_delay(top.get("network"), loc))


def skeleton_to_data(sk: SkeletonShape) -> dict[str, Any]:
    """The dictionary form of a skeleton, as a skeleton file holds it.

    Exact times are written as ints or ``"7/3"`` strings; private clocks go
    back to their task's ``period``/``phase`` shorthand; empty optional parts
    are left out. ``Skeleton.from_dict(skeleton_to_data(sk)) == sk``.

    Raises
    ------
    SkeletonError
        When ``sk`` breaks a rule of spec §1 or §6, or holds ``extra`` keys, which
        the format has no place for (writing them would make an unreadable file).

    Examples
    --------
    >>> from tegraph.model.skeleton import Skeleton
    >>> sk = Skeleton.from_dict({"tasks": {"A": {"duration": "7/3", "period": 4}}}, "s")
    >>> skeleton_to_data(sk)
    {'name': 's', 'unit': 'ms', 'tasks': {'A': {'duration': '7/3', 'period': 4}}}
    """
    check_skeleton(sk, Locator(file=sk.source))
    for key in sk.extra:
        raise Locator(file=sk.source).error(
            f"the v1 file format has no key {key!r}; expected no extra keys to write",
            ("extra", str(key)),
        )
    data: dict[str, Any] = {"name": sk.name, "unit": sk.unit}
    clocks = {key: _clock_data(c) for key, c in sk.clocks.items() if not c.private}
    if clocks:
        data["clocks"] = clocks
    tasks: dict[str, Any] = {}
    for key, task in sk.tasks.items():
        body: dict[str, Any] = {"duration": _time_text(Fraction(task.duration))}
        if task.clock is not None and sk.clocks[task.clock].private:
            body.update(_clock_data(sk.clocks[task.clock]))
        elif task.clock is not None:
            body["clock"] = task.clock
        for side in ("inputs", "outputs"):
            if getattr(task, side):
                body[side] = list(getattr(task, side))
        if task.priority is not None:
            body["priority"] = int(task.priority)
        if task.processor is not None:
            body["processor"] = task.processor
        tasks[key] = body
    data["tasks"] = tasks
    if sk.links:
        data["links"] = [_link_data(link) for link in sk.links]
    if sk.threads:
        data["threads"] = [list(thread) for thread in sk.threads]
    if sk.chains:
        data["chains"] = [list(chain) for chain in sk.chains]
    if sk.processors:
        data["processors"] = {key: {"preemptive": bool(p.preemptive)}
                              for key, p in sk.processors.items()}
    if sk.network_delay is not None:
        data["network"] = {"delay": _time_text(Fraction(sk.network_delay))}
    return data


def _link_data(link: Link) -> dict[str, Any]:
    body: dict[str, Any] = {"from": ":".join(link.writer), "to": ":".join(link.reader),
                            "protocol": link.protocol.value}
    if link.delay is not None:
        body["delay"] = _time_text(Fraction(link.delay))
    return body


def _clock_data(clock: Clock) -> dict[str, Any]:
    body: dict[str, Any] = {"period": _time_text(Fraction(clock.period))}
    if clock.phase:
        body["phase"] = _time_text(Fraction(clock.phase))
    return body
