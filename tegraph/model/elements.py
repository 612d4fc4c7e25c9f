"""The elements of a synchronization skeleton: protocols, clocks, tasks and links.

Plain frozen dataclasses (``docs/skeleton.md`` §1); the skeleton that holds
them is :class:`tegraph.model.skeleton.Skeleton`. Times are exact
:class:`fractions.Fraction` values.
"""

from __future__ import annotations

import enum
from collections.abc import Iterable
from dataclasses import dataclass
from fractions import Fraction
from functools import cached_property

__all__ = ["DEFAULT_PROCESSOR", "Clock", "Link", "LinkLabel", "Processor", "Protocol", "Task",
           "flow_list", "link_name"]

DEFAULT_PROCESSOR = "default"
"""The processor of every task that declares none (spec §4b); a file may name it too."""


def link_name(writer: tuple[str, str], reader: tuple[str, str]) -> str:
    """``W:p -> R:q``: how a link is named in choices, reports, result columns and the
    owner of its delay.

    >>> link_name(("MT1", "x1"), ("MT2", "x1"))
    'MT1:x1 -> MT2:x1'
    """
    return f"{writer[0]}:{writer[1]} -> {reader[0]}:{reader[1]}"


def flow_list(names: Iterable[str]) -> str:
    """Names as a skeleton file writes a list of them: YAML flow style.

    Reports print port orders this way so that a user can paste them into the
    file; a name that YAML would misread (a comma, a leading ``*``) is quoted.

    Examples
    --------
    >>> flow_list(["a", "c"]), flow_list([]), flow_list(["x, y"])
    ('[a, c]', '[]', "['x, y']")
    """
    import yaml  # here: a JSON skeleton's reading and analysis need no PyYAML (15 ms)

    return yaml.safe_dump(list(names), default_flow_style=True, width=float("inf")).strip()


class Protocol(enum.Enum):
    """Link protocol, writer side first (spec §1).

    The four protocols of section 2.3 of the ORCCAD paper [1]_: ASYN/ASYN
    adds no synchronization; ASYN/SYN blocks the reader until a new message
    is posted; SYN/ASYN blocks the writer until the next read request; SYN/SYN is a
    rendezvous.

    See Also
    --------
    Link : a link and its protocol.
    tegraph.build_teg : the places (or merged event) each protocol adds.

    References
    ----------
    .. [1] D. Simon et al., "Design and analysis of synchronization for
       real-time closed-loop control in robotics", IEEE Transactions on Control
       Systems Technology, 1998.

    Examples
    --------
    >>> Protocol("ASYN/SYN"), Protocol.ASYN_SYN.synchronizing
    (<Protocol.ASYN_SYN: 'ASYN/SYN'>, True)
    """

    ASYN_ASYN = "ASYN/ASYN"
    ASYN_SYN = "ASYN/SYN"
    SYN_ASYN = "SYN/ASYN"
    SYN_SYN = "SYN/SYN"

    @property
    def synchronizing(self) -> bool:
        """True when the link adds a place or merges events (not ASYN/ASYN)."""
        return self is not Protocol.ASYN_ASYN


@dataclass(frozen=True)
class Clock:
    """A real-time clock: ticks at ``phase + (k-1) * period``, k >= 1.

    Attributes
    ----------
    name : str
        The clock's name (``T.clock`` for a task's ``period:`` shorthand).
    period, phase : Fraction
        Time between two ticks, and time of the first tick.
    private : bool
        Made by a task's ``period:`` shorthand.

    See Also
    --------
    Task : a task activated by a clock.
    tegraph.Skeleton : the skeleton that holds the clocks.

    Examples
    --------
    >>> Clock("rtc", Fraction(10), Fraction(1)).phase
    Fraction(1, 1)
    """

    name: str
    period: Fraction
    phase: Fraction = Fraction(0)
    private: bool = False
    """True for the clock ``T.clock`` made by a task's ``period:`` shorthand."""


@dataclass(frozen=True)
class Task:
    """A module task: read inputs in order, compute, write outputs in order.

    ``priority`` and ``processor`` are the optional scheduling attributes of
    spec §4b (a larger priority is more urgent; ``None``: not declared, all
    such tasks share the processor :data:`DEFAULT_PROCESSOR`, :attr:`runs_on`).
    The timed event graph ignores them, but for the links that cross processors
    (a network delay, §4d).

    Attributes
    ----------
    name : str
        The task's name.
    duration : Fraction
        Worst-case execution time of one activation.
    clock : str or None
        The clock that activates it, if any.
    inputs, outputs : tuple of str
        Port names, in the order they are read and written.
    priority : int or None
        Declared priority (larger is more urgent).
    processor : str or None
        Declared processor.

    See Also
    --------
    Clock : what activates a clocked task.
    Link : what joins two tasks' ports.
    tegraph.Skeleton : the skeleton that holds the tasks.

    Examples
    --------
    >>> Task("A", Fraction(2), clock="rtc", outputs=("x",)).inputs
    ()
    """

    name: str
    duration: Fraction
    clock: str | None = None
    inputs: tuple[str, ...] = ()
    outputs: tuple[str, ...] = ()
    priority: int | None = None
    processor: str | None = None

    @property
    def runs_on(self) -> str:
        """The processor it runs on: the declared one, else :data:`DEFAULT_PROCESSOR`.

        >>> Task("A", Fraction(1)).runs_on, Task("B", Fraction(1), processor="cpu1").runs_on
        ('default', 'cpu1')
        """
        return DEFAULT_PROCESSOR if self.processor is None else self.processor


@dataclass(frozen=True)
class Processor:
    """The declared properties of one processor (spec §1 ``processors``, §4d).

    A processor that no ``processors`` entry names has the default properties.

    Attributes
    ----------
    name : str
    preemptive : bool
        True (the default): a release of a more urgent job preempts the running one
        (§4b); False: a running job is never interrupted (a bus, a cooperative
        executor, §4d).

    Examples
    --------
    >>> Processor("can0", preemptive=False)
    Processor(name='can0', preemptive=False)
    """

    name: str
    preemptive: bool = True


@dataclass(frozen=True)
class Link:
    """A link from the output port ``writer`` to the input port ``reader``.

    Ports are ``(task, port)`` pairs.

    Attributes
    ----------
    writer, reader : (str, str)
        The ``(task, port)`` written and read.
    protocol : Protocol
        How the two sides synchronize.
    delay : Fraction or None
        The declared delay (spec §4d): a message is readable this long after its
        write. None: not declared; the network's delay then applies when the two
        tasks run on different processors (:meth:`effective_delay`).

    See Also
    --------
    Protocol : the four protocols.
    LinkLabel : the link's text in reports.

    Examples
    --------
    >>> Link(("A", "x"), ("B", "y"), Protocol.SYN_SYN).label
    'A:x -> B:y (SYN/SYN)'
    """

    writer: tuple[str, str]
    reader: tuple[str, str]
    protocol: Protocol
    delay: Fraction | None = None

    def effective_delay(self, crosses: bool, network_delay: Fraction | None) -> Fraction:
        """The link's delay (spec §4d): its own when it declares one (0 included),
        else the network's when it ``crosses`` processors, else 0.

        Which links cross is the platform's to say
        (:func:`tegraph.model.platform.link_delay` reads the declared processors).

        >>> link = Link(("A", "x"), ("B", "y"), Protocol.ASYN_SYN)
        >>> link.effective_delay(True, Fraction(1, 5)), link.effective_delay(False, Fraction(1))
        (Fraction(1, 5), Fraction(0, 1))
        >>> Link(("A", "x"), ("B", "y"), Protocol.ASYN_SYN, Fraction(0)).effective_delay(
        ...     True, Fraction(1))
        Fraction(0, 1)
        """
        if self.delay is not None:
            return self.delay
        if crosses and network_delay is not None:
            return network_delay
        return _NO_DELAY

    @cached_property
    def label(self) -> LinkLabel:
        """``W:p -> R:q (PROTO)``, the link as the user wrote it."""
        # Cached in the instance's __dict__ (beside, not among, the fields:
        # equality and hashing are unchanged): the advice and the reports ask
        # for the same link's label again and again (27,340 texts made on
        # 10,000 tasks).
        return LinkLabel(self.writer, self.reader, self.protocol)


_NO_DELAY = Fraction(0)


class LinkLabel(str):
    """A link's text ``W:p -> R:q (PROTO)`` that also knows its two ports and protocol.

    Findings, deadlocks and latency hops name links by this text in reports
    and messages; the JSON reports give each as an object (:meth:`document`),
    which a reader need not parse. Task and port names may hold any character
    but ``:``, so the text alone is not always unambiguous.

    Examples
    --------
    >>> label = LinkLabel(("A", "x"), ("B", "y"), Protocol.ASYN_SYN)
    >>> label, label.document()
    ('A:x -> B:y (ASYN/SYN)', {'from': 'A:x', 'to': 'B:y', 'protocol': 'ASYN/SYN'})
    """

    __slots__ = ("writer", "reader", "protocol")
    writer: tuple[str, str]
    reader: tuple[str, str]
    protocol: Protocol

    def __new__(cls, writer: tuple[str, str], reader: tuple[str, str],
                protocol: Protocol) -> LinkLabel:
        text = f"{link_name(writer, reader)} ({protocol.value})"
        self = super().__new__(cls, text)
        self.writer, self.reader, self.protocol = writer, reader, protocol
        return self

    def __reduce__(self) -> tuple:
        # Results travel between processes (tegraph explore on Dask workers).
        return (LinkLabel, (self.writer, self.reader, self.protocol))

    def document(self) -> dict[str, str]:
        """``{"from": "W:p", "to": "R:q", "protocol": "PROTO"}``, as the skeleton file writes it."""
        return {"from": ":".join(self.writer), "to": ":".join(self.reader),
                "protocol": self.protocol.value}
