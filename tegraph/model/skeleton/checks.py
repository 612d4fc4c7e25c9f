"""Cross-reference checks of a synchronization skeleton (spec §1).

The rules that relate one part of a skeleton to another (a link names an
existing output port, an input port has one writer, a task is in at most one
thread...) are checked here, on the dataclasses of :mod:`tegraph.model.skeleton`, so
that a skeleton read from a file and one built in code obey the same rules
and get the same messages. The checks read a skeleton through
:class:`~tegraph.model.skeleton.shape.SkeletonShape`: the class that calls them
is built above this module, which never imports it. Every refusal is a
:class:`~tegraph.errors.SkeletonError` whose key path points into the
dictionary form of the skeleton (``tasks.MT2.inputs[1]``, ``links[0].to``).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from fractions import Fraction
from numbers import Integral
from typing import Any

from ...errors import SkeletonError
from ..elements import DEFAULT_PROCESSOR, Clock, Link, Processor, Protocol, Task
from ..limits import text_problem, written
from .shape import SkeletonShape

__all__ = ["KeyPath", "Locator", "check_chain", "check_skeleton", "format_path"]

KeyPath = tuple[str | int, ...]
"""A place in the document: mapping keys (str) and list indices (int)."""


def format_path(path: KeyPath) -> str:
    """Write a key path the way messages show it.

    >>> format_path(("tasks", "MT2", "inputs", 1)), format_path(("threads", 0, 2))
    ('tasks.MT2.inputs[1]', 'threads[0][2]')
    """
    text = ""
    for part in path:
        if isinstance(part, int):
            text += f"[{part}]"
        else:
            text += f".{part}" if text else part
    return text


@dataclass
class Locator:
    """Where the parts of a document came from, to build located errors.

    Attributes
    ----------
    file : str or None
        The file name put in every message.
    lines : dict of KeyPath to int
        1-based line of each key or list item (empty when unknown).
    raw : dict of KeyPath to str
        Source text of the plain scalars that YAML resolved to something
        other than text (``on`` -> True, ``0.1`` -> float): names and exact
        times are taken from what the user wrote, not from YAML 1.1's reading.
    """

    file: str | None = None
    lines: dict[KeyPath, int] = field(default_factory=dict)
    raw: dict[KeyPath, str] = field(default_factory=dict)

    def line_of(self, path: KeyPath) -> int | None:
        """Line of ``path``, or of its nearest enclosing element that has one.

        >>> Locator(lines={("tasks", "A"): 3}).line_of(("tasks", "A", "duration"))
        3
        """
        # A missing key has no line of its own: point at the element that lacks it.
        for end in range(len(path), -1, -1):
            line = self.lines.get(path[:end])
            if line is not None:
                return line
        return None

    def error(self, reason: str, path: KeyPath) -> SkeletonError:
        """A :class:`SkeletonError` at ``path`` (to be raised by the caller)."""
        return SkeletonError(
            reason, where=format_path(path), file=self.file, line=self.line_of(path)
        )


def _names(items: Sequence[str]) -> str:
    # Long lists are cut: the message has to stay one readable line.
    shown = ", ".join(items[:12])
    return shown + (", ..." if len(items) > 12 else "") if items else "none"


def check_name(name: Any, path: KeyPath, what: str, loc: Locator) -> str:
    """Refuse a task, port or clock name that is not a non-empty text without ':'.

    >>> check_name("MT1", ("tasks", "MT1"), "task name", Locator())
    'MT1'
    """
    if not isinstance(name, str):
        raise loc.error(
            f"expected a {what} (a text), got {type(name).__name__} {name!r}", path
        )
    if not name:
        raise loc.error(f"expected a non-empty {what}", path)
    why = text_problem(name)  # "\ud800" from JSON: no file or report could hold it
    if why is not None:
        raise loc.error(f"the {what} {why}", path)
    if ":" in name:
        raise loc.error(
            f"the {what} {name!r} contains ':'; expected a name without ':' "
            "(':' separates task and port in a link)",
            path,
        )
    return name


def _check_time(value: Any, path: KeyPath, what: str, positive: bool, loc: Locator) -> None:
    if type(value) is Fraction:  # the common case: its sign is its numerator's (no ABC)
        n = value.numerator
        if n > 0 or (n == 0 and not positive):
            return
    bound = "> 0" if positive else ">= 0"
    if isinstance(value, bool) or not isinstance(value, (Fraction, Integral)):
        raise loc.error(
            f"expected {what} {bound} as an exact Fraction or int, "
            f"got {type(value).__name__} {value!r}",
            path,
        )
    if value < 0 or (positive and value == 0):
        raise loc.error(f"expected {what} {bound}, got {written(Fraction(value))}", path)


def check_skeleton(sk: SkeletonShape, loc: Locator, *, values_checked: bool = False) -> None:
    """Check every rule of spec §1 on a skeleton, raising at the first broken one.

    Parameters
    ----------
    sk : SkeletonShape
        A :class:`~tegraph.model.skeleton.core.Skeleton`, or anything with its attributes.
    loc : Locator
        Maps key paths to file lines for the messages.
    values_checked : bool
        The skeleton was built by :func:`~tegraph.model.skeleton.schema.skeleton_fields`,
        which checked each value on its own (names, times, priorities, the private
        clocks of ``period``): only the rules between parts are checked again (each
        value is then known good, so no message changes; tens of thousands of names
        are not checked twice).

    Raises
    ------
    SkeletonError
    """
    if not isinstance(sk.name, str) or not sk.name:
        raise loc.error(f"expected a non-empty text as name, got {sk.name!r}", ("name",))
    if not isinstance(sk.unit, str) or not sk.unit:
        raise loc.error(f"expected a non-empty text as unit, got {sk.unit!r}", ("unit",))
    if not isinstance(sk.tasks, Mapping) or not sk.tasks:
        raise loc.error("expected a mapping from task names to at least one task", ("tasks",))
    if not isinstance(sk.clocks, Mapping):
        raise loc.error(f"expected a mapping of clocks, got {type(sk.clocks).__name__}",
                        ("clocks",))
    for part in ("links", "threads", "chains"):
        if not isinstance(getattr(sk, part), Sequence):
            raise loc.error(f"expected a list, got {type(getattr(sk, part)).__name__}", (part,))
    if not values_checked:
        for key, clock in sk.clocks.items():
            _check_clock(key, clock, sk, loc)
    ports: dict[str, tuple[set[str], set[str]]] = {}
    for key, task in sk.tasks.items():
        ports[key] = _check_task(key, task, sk, loc, values_checked)
    _check_platform(sk, loc, values_checked)
    _check_links(sk, ports, loc, values_checked)
    _check_threads(sk, loc)
    for i, chain in enumerate(sk.chains):
        check_chain(sk, chain, ("chains", i), loc)


def _check_platform(sk: SkeletonShape, loc: Locator, values_checked: bool) -> None:
    """``processors`` and ``network`` (v1.3, §4d): each entry a :class:`Processor` of a
    processor some task runs on (``default`` included), the network's delay >= 0."""
    if not isinstance(sk.processors, Mapping):
        raise loc.error(f"expected a mapping of processors, got {type(sk.processors).__name__}",
                        ("processors",))
    if sk.processors:
        used = {task.runs_on for task in sk.tasks.values()}
        for key, entry in sk.processors.items():
            path: KeyPath = ("processors", str(key))
            if not values_checked:
                check_name(key, path, "processor name", loc)
                if not isinstance(entry, Processor):
                    raise loc.error(f"expected a Processor, got {type(entry).__name__}", path)
                if entry.name != key:
                    raise loc.error(f"the key {key!r} holds the processor named "
                                    f"{entry.name!r}", path)
                if not isinstance(entry.preemptive, bool):
                    raise loc.error(f"expected true or false, got {entry.preemptive!r}",
                                    (*path, "preemptive"))
            if key not in used:
                raise loc.error(
                    f"no task runs on processor {key!r}; expected a processor that a task "
                    f"names in `processor:`, or `default` for the tasks that name none "
                    f"({_names(sorted(used))})", path)
    if sk.network_delay is not None and not values_checked:
        _check_time(sk.network_delay, ("network", "delay"), "a delay", False, loc)


def _check_entry(key: Any, entry: Any, kind: type[Clock] | type[Task], path: KeyPath,
                 loc: Locator) -> None:
    """A clock's or task's key: a valid name, holding a ``kind`` of that name."""
    word = kind.__name__.lower()
    check_name(key, path, f"{word} name", loc)
    if not isinstance(entry, kind):
        raise loc.error(f"expected a {kind.__name__}, got {type(entry).__name__}", path)
    if entry.name != key:
        raise loc.error(f"the key {key!r} holds the {word} named {entry.name!r}", path)


def _check_clock(key: Any, clock: Clock, sk: SkeletonShape, loc: Locator) -> None:
    path: KeyPath = ("clocks", str(key))
    _check_entry(key, clock, Clock, path, loc)
    _check_time(clock.period, (*path, "period"), "a period", True, loc)
    _check_time(clock.phase, (*path, "phase"), "a phase", False, loc)
    if clock.private:
        # A private clock is written back as its task's `period:` shorthand,
        # so it must be "T.clock" and activate T alone.
        owner = key[: -len(".clock")] if key.endswith(".clock") else None
        if owner is None or owner not in sk.tasks or sk.tasks[owner].clock != key:
            raise loc.error(
                f"the private clock {key!r} is not the clock of a task T named 'T.clock'; "
                "expected private clocks only from a task's 'period' shorthand",
                path,
            )


def _check_task(key: Any, task: Task, sk: SkeletonShape, loc: Locator,
                values_checked: bool = False) -> tuple[set[str], set[str]]:
    path: KeyPath = ("tasks", str(key))
    if not values_checked:
        _check_entry(key, task, Task, path, loc)
        _check_time(task.duration, (*path, "duration"), "a duration", False, loc)
    if task.clock is not None:
        clock = sk.clocks.get(task.clock) if isinstance(task.clock, str) else None
        if clock is None:
            declared = [c for c, k in sk.clocks.items() if not k.private]
            raise loc.error(
                f"no clock {task.clock!r}; expected a clock declared under clocks "
                f"({_names(declared)})",
                (*path, "clock"),
            )
        if clock.private and task.clock != f"{key}.clock":
            raise loc.error(
                f"{task.clock!r} is the private clock of another task (made by its "
                "'period'); expected a clock declared under clocks to share one",
                (*path, "clock"),
            )
    inputs, outputs = task.inputs, task.outputs
    if values_checked and type(inputs) is tuple and type(outputs) is tuple:
        # Names already checked: all that is left is their uniqueness, which sets tell
        # without a key path per port (the loop below words a duplicate).
        ins, outs = set(inputs), set(outputs)
        if len(ins) == len(inputs) and len(outs) == len(outputs) and ins.isdisjoint(outs):
            return ins, outs
    seen: dict[str, KeyPath] = {}
    sides: list[set[str]] = []
    for side in ("inputs", "outputs"):
        names = getattr(task, side)
        # A tuple (what the schema builds) is a Sequence: no abstract-class check.
        if type(names) is not tuple and (isinstance(names, str)
                                         or not isinstance(names, Sequence)):
            raise loc.error(f"expected a sequence of port names, got {names!r}", (*path, side))
        for i, port in enumerate(names):
            where = (*path, side, i)
            if not values_checked:
                check_name(port, where, "port name", loc)
            if port in seen:
                raise loc.error(
                    f"the port name {port!r} is already used at {format_path(seen[port])}; "
                    "expected port names unique within a task (inputs and outputs together)",
                    where,
                )
            seen[port] = where
        sides.append(set(names))
    if values_checked:
        return sides[0], sides[1]
    # Spec §6: optional scheduling attributes.
    if task.priority is not None and (isinstance(task.priority, bool)
                                      or not isinstance(task.priority, Integral)):
        raise loc.error(f"expected a priority (an integer; larger is more urgent), got "
                        f"{type(task.priority).__name__} {task.priority!r}", (*path, "priority"))
    if task.processor is not None:
        check_name(task.processor, (*path, "processor"), "processor name", loc)
    return sides[0], sides[1]


def _endpoint(
    link: Link, i: int, end: str, ports: dict[str, tuple[set[str], set[str]]], loc: Locator
) -> tuple[str, str]:
    path: KeyPath = ("links", i, end)
    pair = link.writer if end == "from" else link.reader
    if not (isinstance(pair, tuple) and len(pair) == 2 and isinstance(pair[0], str)
            and isinstance(pair[1], str)):
        raise loc.error(f"expected a (task, port) pair of names, got {pair!r}", path)
    task, port = pair
    if task not in ports:
        raise loc.error(f"no task {task!r}; expected one of the tasks ({_names(list(ports))})",
                        path)
    inputs, outputs = ports[task]
    wanted, other = (outputs, inputs) if end == "from" else (inputs, outputs)
    kind, other_kind = ("output", "input") if end == "from" else ("input", "output")
    if port in other:
        raise loc.error(
            f"{task}:{port} is an {other_kind} port, linked in the wrong direction; "
            f"expected an {kind} port as a link's '{end}' (the writer's output port "
            "in 'from', the reader's input port in 'to')",
            path,
        )
    if port not in wanted:
        raise loc.error(
            f"task {task!r} has no port {port!r}; expected one of its {kind} ports "
            f"({_names(sorted(wanted))})",
            path,
        )
    return task, port


def _check_links(sk: SkeletonShape, ports: dict[str, tuple[set[str], set[str]]],
                 loc: Locator, values_checked: bool = False) -> None:
    writers: dict[tuple[str, str], int] = {}
    for i, link in enumerate(sk.links):
        if _plain_link(link, ports, writers):
            writers[link.reader] = i
            if link.delay is not None:
                _check_delay(sk, link, i, loc, values_checked)
            continue
        # Not the common case: every rule in turn, the first broken one raised.
        if not isinstance(link, Link):
            raise loc.error(f"expected a Link, got {type(link).__name__}", ("links", i))
        if not isinstance(link.protocol, Protocol):
            raise loc.error(f"expected a Protocol, got {link.protocol!r}", ("links", i, "protocol"))
        writer = _endpoint(link, i, "from", ports, loc)
        reader = _endpoint(link, i, "to", ports, loc)
        if writer[0] == reader[0]:
            raise loc.error(
                f"the link joins task {writer[0]!r} to itself; expected a link between "
                "two different tasks",
                ("links", i),
            )
        if reader in writers:
            j = writers[reader]
            if sk.links[j].writer == writer:
                raise loc.error(
                    f"the same link as links[{j}] ({sk.links[j].label}); expected each link once",
                    ("links", i),
                )
            raise loc.error(
                f"the input port {reader[0]}:{reader[1]} already has a writer "
                f"(links[{j}]: {sk.links[j].label}); expected one writer per input port",
                ("links", i, "to"),
            )
        writers[reader] = i
        _check_delay(sk, link, i, loc, values_checked)
    if sk.network_delay:  # a positive network delay: each rendezvous across processors
        for i, link in enumerate(sk.links):
            if link.protocol is Protocol.SYN_SYN and link.delay is None:
                _check_delay(sk, link, i, loc, True)


def _check_delay(sk: SkeletonShape, link: Link, i: int, loc: Locator,
                 values_checked: bool) -> None:
    """A link's delay (§4d): >= 0, and none on a rendezvous, which is one event (§2)."""
    if link.delay is not None and not values_checked:
        _check_time(link.delay, ("links", i, "delay"), "a delay", False, loc)
    if link.protocol is not Protocol.SYN_SYN:
        return
    crosses = sk.tasks[link.writer[0]].runs_on != sk.tasks[link.reader[0]].runs_on
    delay = link.effective_delay(crosses, sk.network_delay)
    if delay:
        whose = ("its own" if link.delay is not None else
                 f"the network's, between processors {sk.tasks[link.writer[0]].runs_on!r} "
                 f"and {sk.tasks[link.reader[0]].runs_on!r}")
        raise loc.error(
            f"a SYN/SYN link with a delay ({_time_words(delay)}, {whose}); a rendezvous is one "
            "event of both tasks (spec §2), which no delay can separate: expected delay 0 "
            "(`delay: 0` on the link overrides the network's) or another protocol "
            "(ASYN/SYN: the reader waits for the delayed message)", ("links", i))


def _time_words(t: Fraction) -> str:
    return str(t.numerator) if t.denominator == 1 else f"{t.numerator}/{t.denominator}"


def _plain_link(link: Any, ports: dict[str, tuple[set[str], set[str]]],
                writers: dict[tuple[str, str], int]) -> bool:
    """Whether ``link`` keeps every rule of :func:`_check_links`, in one expression.

    True only for a :class:`Link` of two (task, port) pairs of texts, from an
    output port to an input port of another task that has no writer yet; anything
    else (a refusal or an unusual type) goes through the rules one by one.
    """
    if type(link) is not Link or type(link.protocol) is not Protocol:
        return False
    writer, reader = link.writer, link.reader
    if type(writer) is not tuple or type(reader) is not tuple or len(writer) != 2 \
            or len(reader) != 2:
        return False
    (w_task, w_port), (r_task, r_port) = writer, reader
    if type(w_task) is not str or type(w_port) is not str or type(r_task) is not str \
            or type(r_port) is not str or w_task == r_task or reader in writers:
        return False
    # A port among a task's outputs is none of its inputs (port names are unique within
    # a task, checked before the links): one membership test per end.
    w_ports, r_ports = ports.get(w_task), ports.get(r_task)
    return (w_ports is not None and r_ports is not None and w_port in w_ports[1]
            and r_port in r_ports[0])


def _check_threads(sk: SkeletonShape, loc: Locator) -> None:
    placed: dict[str, KeyPath] = {}
    for i, thread in enumerate(sk.threads):
        if isinstance(thread, str) or not isinstance(thread, Sequence):
            raise loc.error(f"expected a sequence of task names, got {thread!r}", ("threads", i))
        if not thread:
            raise loc.error("an empty thread; expected a list of at least one task", ("threads", i))
        for j, task in enumerate(thread):
            where: KeyPath = ("threads", i, j)
            if not isinstance(task, str) or task not in sk.tasks:
                raise loc.error(
                    f"no task {task!r}; expected one of the tasks ({_names(list(sk.tasks))})",
                    where,
                )
            if task in placed:
                again = "again in this thread" if placed[task][1] == i else "in two threads"
                raise loc.error(
                    f"the task {task!r} is {again} (also at {format_path(placed[task])}); "
                    "expected each task in at most one thread, once",
                    where,
                )
            placed[task] = where
        _check_thread_processor(sk, thread, i, loc)


def _check_thread_processor(sk: SkeletonShape, thread: Sequence[str], i: int, loc: Locator) -> None:
    # A thread is one OS thread: it runs on one processor (tasks without a
    # `processor` share the default one), or the thread places of spec §2 would
    # serialize tasks that the schedulability analysis puts on two processors.
    first = sk.tasks[thread[0]].processor
    for j, task in enumerate(thread):
        here = sk.tasks[task].processor
        if here != first and sk.tasks[task].runs_on != sk.tasks[thread[0]].runs_on:
            raise loc.error(
                f"the thread runs {thread[0]!r} on {_on(first)} and {task!r} on {_on(here)}; "
                "a thread is one OS thread: expected all its tasks on one processor",
                ("threads", i, j),
            )


def _on(processor: str | None) -> str:
    return "the default processor" if processor in (None, DEFAULT_PROCESSOR) \
        else f"processor {processor!r}"


def check_chain(sk: SkeletonShape, chain: Any, path: KeyPath, loc: Locator) -> tuple[str, ...]:
    """Refuse a latency chain (spec §6) that does not follow the skeleton's links.

    A chain names at least one task, each at most once, and every task after
    the first reads (through some link) an output of the task before it.

    Parameters
    ----------
    sk : SkeletonShape
        Its ``tasks`` and ``links`` are read.
    chain : sequence of str
    path : KeyPath
        Where the chain is (``("chains", 0)``, or ``("chain",)`` for a chain given as a parameter).
    loc : Locator

    Returns
    -------
    tuple of str

    Examples
    --------
    >>> from tegraph.model.skeleton import Skeleton
    >>> sk = Skeleton.from_dict({"tasks": {"A": {"duration": 1, "outputs": ["x"]},
    ...                                    "B": {"duration": 1, "inputs": ["x"]}},
    ...                          "links": [{"from": "A:x", "to": "B:x", "protocol": "ASYN/SYN"}]})
    >>> check_chain(sk, ["A", "B"], ("chains", 0), Locator())
    ('A', 'B')
    >>> check_chain(sk, ["B", "A"], ("chains", 0), Locator())
    Traceback (most recent call last):
    ...
    tegraph.errors.SkeletonError: chains[0][1]: no link from B to A; expected each task ...
    """
    if isinstance(chain, str) or not isinstance(chain, Sequence):
        raise loc.error(f"expected a sequence of task names, got {chain!r}", path)
    if not chain:
        raise loc.error("an empty chain; expected a list of at least one task, sensor first",
                        path)
    placed: dict[str, int] = {}
    # Each (writer, reader) pair once: a chain through every group of a large skeleton
    # would otherwise scan every link at each of its thousands of hops.
    linked = {(link.writer[0], link.reader[0]) for link in sk.links} if len(chain) > 1 else set()
    for j, task in enumerate(chain):
        where: KeyPath = (*path, j)
        if not isinstance(task, str) or task not in sk.tasks:
            raise loc.error(
                f"no task {task!r}; expected one of the tasks ({_names(list(sk.tasks))})", where)
        if task in placed:
            raise loc.error(
                f"the task {task!r} is already at {format_path((*path, placed[task]))}; "
                "expected each task once in a chain", where)
        placed[task] = j
        if j and (chain[j - 1], task) not in linked:
            raise loc.error(
                f"no link from {chain[j - 1]} to {task}; expected each task of a chain to read "
                f'an output of the task before it (a link "{chain[j - 1]}:PORT" -> '
                f'"{task}:PORT")', where)
    return tuple(chain)
