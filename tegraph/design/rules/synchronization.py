"""What a task waits for (spec §6).

A task's *synchronizations* are its clock, each input it reads ASYN/SYN or
SYN/SYN (the reader blocks) and each output it posts SYN/ASYN or SYN/SYN (the
writer blocks). The *synchronized groups* they form are the groups of spec §4,
defined once in :class:`tegraph.model.structure.Structure`. The design rules
(:mod:`.check`) and their advice (:mod:`.advice`) read a skeleton through these.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

from ...model.skeleton import Link, Protocol, Skeleton
from ...model.structure import Structure

__all__ = ["READER_BLOCKS", "WRITER_BLOCKS", "Synchronization", "synchronizations"]

# Which side of a link blocks (spec §1): the reader of ASYN/SYN, the writer of SYN/ASYN.
READER_BLOCKS = (Protocol.ASYN_SYN, Protocol.SYN_SYN)
WRITER_BLOCKS = (Protocol.SYN_ASYN, Protocol.SYN_SYN)


@dataclass(frozen=True)
class Synchronization:
    """One thing a task waits for: its clock, or a blocking side of a link."""

    kind: Literal["clock", "input", "output"]
    clock: str | None = None
    port: str | None = None
    """``TASK:PORT``."""
    link: Link | None = None

    @property
    def label(self) -> str:
        """How messages name this synchronization."""
        if self.kind == "clock":
            return f"clock {self.clock}"
        # Type: an input or output synchronization always has its link (only a clock has none).
        return f"{self.kind} {self.port} ({self.link.label})"  # type: ignore[union-attr]


def synchronizations(sk: Skeleton, task: str,
                     structure: Structure | None = None) -> list[Synchronization]:
    """What ``task`` waits for at each activation, in chain order (Rule 1).

    ``structure`` is ``Structure.of(sk)``, if known (its links by port are read).

    Examples
    --------
    Figure 12: MT2 has a clock and also waits for MT1's message.

    >>> sk = Skeleton.from_dict({"tasks": {
    ...     "MT1": {"duration": 1, "period": 10, "outputs": ["y"]},
    ...     "MT2": {"duration": 2, "period": 4, "inputs": ["y"]}},
    ...   "links": [{"from": "MT1:y", "to": "MT2:y", "protocol": "ASYN/SYN"}]})
    >>> [s.label for s in synchronizations(sk, "MT2")]
    ['clock MT2.clock', 'input MT2:y (MT1:y -> MT2:y (ASYN/SYN))']
    """
    s = Structure.of(sk) if structure is None else structure
    by_reader, by_writer = s.by_reader, s.by_writer
    t = sk.tasks[task]
    out = [Synchronization("clock", clock=t.clock)] if t.clock else []
    for port in t.inputs:
        for link in by_reader.get((task, port), ()):
            if link.protocol in READER_BLOCKS:
                out.append(Synchronization("input", port=f"{task}:{port}", link=link))
    for port in t.outputs:
        for link in by_writer.get((task, port), ()):
            if link.protocol in WRITER_BLOCKS:
                out.append(Synchronization("output", port=f"{task}:{port}", link=link))
    return out
