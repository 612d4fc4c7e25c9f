"""The synchronization skeleton: module tasks, clocks, links and threads (the class).

This is the in-memory form of a skeleton file (``docs/skeleton.md`` §1). A
design tool builds one in code with :meth:`Skeleton.from_dict` (the same
dictionary a YAML file holds) or from the dataclasses directly followed by
:meth:`Skeleton.validate`; both refuse what the file format refuses, with the
key path of the offending element.

Times are exact :class:`fractions.Fraction` values.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any

from ..elements import Clock, Link, Processor, Task
from .checks import Locator, check_skeleton
from .schema import skeleton_fields, skeleton_to_data

__all__ = ["Skeleton"]


@dataclass
class Skeleton:
    """A synchronization skeleton (spec §1).

    Attributes
    ----------
    name : str
    unit : str
        Label of every time value (default ``"ms"``).
    clocks : dict of str to Clock
        All clocks, the private ``T.clock`` ones included, in file order.
    tasks : dict of str to Task
        In file order (groups and reports follow this order).
    links : list of Link
    threads : list of tuple of str
    source : str or None
        The file it was read from.
    chains : list of tuple of str
        Sensor-to-actuator chains of tasks for the latency report (spec §6).
    processors : dict of str to Processor
        The declared properties of processors (spec §1 ``processors``, §4d), in file
        order; a processor named by no entry has the default ones.
    network_delay : Fraction or None
        ``network.delay`` (§4d): the delay of every link between two processors that
        declares none of its own; None when not declared.

    See Also
    --------
    tegraph.load_skeleton : a skeleton from its file.
    tegraph.build_teg : its timed event graph.
    tegraph.analyze : its analysis.

    Notes
    -----
    A skeleton describes the module tasks of the ORCCAD paper [1]_, their
    clocks and their synchronizing links.

    References
    ----------
    .. [1] D. Simon et al., "Design and analysis of synchronization for
       real-time closed-loop control in robotics", IEEE Transactions on Control
       Systems Technology, 1998.

    Examples
    --------
    >>> sk = Skeleton.from_dict({"tasks": {"A": {"duration": 2, "period": 10}}})
    >>> sk.name, sk.unit, list(sk.clocks), list(sk.tasks)
    ('skeleton', 'ms', ['A.clock'], ['A'])
    """

    name: str
    tasks: dict[str, Task]
    clocks: dict[str, Clock] = field(default_factory=dict)
    links: list[Link] = field(default_factory=list)
    threads: list[tuple[str, ...]] = field(default_factory=list)
    unit: str = "ms"
    source: str | None = field(default=None, compare=False)
    """Where it was read from: not part of the skeleton, so a copy read from
    another file (``load_skeleton(dump_skeleton(sk, path))``) compares equal."""
    extra: dict[str, Any] = field(default_factory=dict)
    """Keys of future format extensions; the writer refuses them (spec §6 keys
    have their own fields: ``Task.priority``, ``Task.processor``, ``chains``)."""
    chains: list[tuple[str, ...]] = field(default_factory=list)
    """Chains of tasks, sensor first, whose latency is reported (spec §6)."""
    processors: dict[str, Processor] = field(default_factory=dict)
    """Declared processor properties (spec §4d): read them through
    :func:`tegraph.model.platform.platform_of`, which gives every processor its own."""
    network_delay: Fraction | None = None
    """``network.delay`` (spec §4d); None: not declared."""

    @classmethod
    def from_dict(cls, data: Mapping[str, Any], name: str = "skeleton",
                  source: str | None = None, *, locator: Locator | None = None) -> Skeleton:
        """Build and validate a skeleton from the dictionary a skeleton file holds.

        Parameters
        ----------
        data : mapping
            As in ``docs/skeleton.md`` §1.
        name : str
            Default name when ``data`` has no ``name`` key.
        source : str, optional
            File name to put in error messages.
        locator : Locator, optional
            Lines and source texts of a parsed file (:mod:`tegraph.io.skeleton_file`
            passes one), so that refusals name their line.

        Returns
        -------
        Skeleton

        Raises
        ------
        SkeletonError
            With the key path of the first refused element.

        Examples
        --------
        >>> sk = Skeleton.from_dict({"tasks": {"A": {"duration": 1, "period": 4}}})
        >>> sk.tasks["A"].clock, sk.clocks["A.clock"].period
        ('A.clock', Fraction(4, 1))
        """
        loc = locator if locator is not None else Locator(file=source)
        sk = cls(**skeleton_fields(data, default_name=name, source=source, locator=loc))
        check_skeleton(sk, loc, values_checked=True)
        return sk

    def validate(self) -> Skeleton:
        """Check the cross references of a skeleton built in code (spec §1).

        Returns
        -------
        Skeleton
            The skeleton itself.

        Raises
        ------
        SkeletonError
            At the first broken rule, with the key path of the dictionary form
            (``tasks.X.clock``, ``links[2].to``...) and ``source`` as file.

        Examples
        --------
        >>> from fractions import Fraction
        >>> Skeleton("s", {"A": Task("A", Fraction(1), clock="rtc")}).validate()
        Traceback (most recent call last):
        ...
        tegraph.errors.SkeletonError: tasks.A.clock: no clock 'rtc'; expected a clock declared ...
        """
        check_skeleton(self, Locator(file=self.source))
        return self

    def to_dict(self) -> dict[str, Any]:
        """The dictionary form (as written to a skeleton file), times as exact strings."""
        return skeleton_to_data(self)

    def restricted_to(self, tasks: Sequence[str]) -> Skeleton:
        """The skeleton of ``tasks`` alone: their clocks, the links between two of them
        and the threads that start with one of them (a thread lies in one group), in
        file order; ``self`` when ``tasks`` are all of them.

        Cut along groups, its timed event graph is those groups' part of this one
        (spec §2: no place crosses from a group to another), so their figures are
        the same; cut along parts of the schedule on processors (no link or
        processor shared with the rest), so is their schedule (§4b).

        >>> sk = Skeleton.from_dict({"tasks": {"A": {"duration": 1, "period": 2},
        ...                                    "B": {"duration": 1, "period": 3}}})
        >>> list(sk.restricted_to(["B"]).tasks), list(sk.restricted_to(["B"]).clocks)
        (['B'], ['B.clock'])
        """
        if len(tasks) == len(self.tasks):
            return self
        keep = set(tasks)
        used = {self.tasks[t].clock for t in tasks}
        clocks = {c: clock for c, clock in self.clocks.items() if c in used}
        # The processors' properties and the network go with the tasks: a link keeps its
        # delay (§4d), a processor its kind; an entry naming no task left is dropped.
        runs_on = {self.tasks[t].runs_on for t in tasks}
        return dataclasses.replace(
            self, tasks={t: self.tasks[t] for t in tasks}, clocks=clocks,
            links=[x for x in self.links if x.writer[0] in keep and x.reader[0] in keep],
            threads=[th for th in self.threads if th[0] in keep], chains=[],
            processors={p: q for p, q in self.processors.items() if p in runs_on})

    def link_of_port(self, task: str, port: str) -> Link | None:
        """The link that ends or starts at ``task:port``, if any."""
        for link in self.links:
            if link.writer == (task, port) or link.reader == (task, port):
                return link
        return None
