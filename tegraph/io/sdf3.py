"""SDF3 synchronous dataflow graphs (``<sdf3 type="sdf">`` XML), and their expansion.

An SDF graph has actors with an execution time and channels that carry
tokens at fixed rates: each firing of the source actor produces ``prod``
tokens, each firing of the destination consumes ``cons``; ``tokens`` are
there initially. What is read, as SDF3 itself reads it:

* the execution time of an actor is that of the **last** ``<processor>`` of
  its ``actorProperties`` carrying a ``default`` attribute (any value), 0 if none;
* rates come from the ``rate`` of the ports named by the channel;
  ``initialTokens`` defaults to 0;
* an actor without a self-loop channel may fire concurrently with itself
  (unbounded auto-concurrency): no self-loop is added.

The repetition vector ``q`` (the smallest positive integers with
``q[src] * prod == q[dst] * cons`` on every channel) expands the graph into
its homogeneous graph: one transition ``actor_i`` per firing
``i < q[actor]`` of an iteration, one place per dependency, holding the
execution time of the source firing (:meth:`SDFGraph.to_arcs`). Its maximum
cycle ratio is the period of the graph: the time per iteration, whose
inverse is SDF3's throughput (Sriram & Bhattacharyya, *Embedded
Multiprocessors*, 2009, ch. 3; Ghamarian et al., ACSD 2006).
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass, field
from fractions import Fraction
from pathlib import Path
from typing import Any
from xml.sax.saxutils import quoteattr

import numpy as np

from ..errors import InputError, ModelError
from ..teg import TimedEventGraph
from .edges import ArcList
from .formats import DEFAULT_MAX_BYTES, XmlNode, as_teg, parse_xml, read_limited, write_bytes

__all__ = ["SDFChannel", "SDFGraph", "dumps_sdf3", "parse_sdf3", "read_sdf3", "write_sdf3"]


@dataclass(frozen=True)
class SDFChannel:
    """A channel ``src -> dst``: ``prod`` tokens per source firing, ``cons`` per destination firing."""

    name: str
    src: str
    dst: str
    prod: int = 1
    cons: int = 1
    tokens: int = 0


@dataclass
class SDFGraph:
    """A timed SDF graph: actors with integer execution times, channels with rates.

    Attributes
    ----------
    name : str
    actors : dict of str to int
        Execution time of each actor, in file order.
    channels : list of SDFChannel

    Examples
    --------
    ``a`` fires twice per firing of ``b`` (rates 1 and 2); the two tokens on
    the way back let both firings of ``a`` start at once (no self-loop, so
    they run concurrently): the period is 2 + 3 = 5.

    >>> g = SDFGraph("g", {"a": 2, "b": 3}, [SDFChannel("ab", "a", "b", 1, 2, 0),
    ...                                     SDFChannel("ba", "b", "a", 2, 1, 2)])
    >>> g.repetition_vector()
    {'a': 2, 'b': 1}
    >>> from tegraph.cycle_time import cycle_time
    >>> str(cycle_time(g).period)
    '5'
    """

    name: str
    actors: dict[str, int]
    channels: list[SDFChannel] = field(default_factory=list)

    def repetition_vector(self) -> dict[str, int]:
        """Smallest positive firings per iteration, per actor (connected parts separately).

        Raises
        ------
        ModelError
            Inconsistent rates: the message names a channel closing an
            inconsistent cycle (such a graph needs unbounded memory or deadlocks).
        """
        adj: dict[str, list[tuple[str, Fraction, SDFChannel]]] = {a: [] for a in self.actors}
        for c in self.channels:
            adj[c.src].append((c.dst, Fraction(c.prod, c.cons), c))
            adj[c.dst].append((c.src, Fraction(c.cons, c.prod), c))
        q: dict[str, Fraction] = {}
        for start in self.actors:
            if start in q:
                continue
            part, stack = [start], [start]
            q[start] = Fraction(1)
            while stack:  # q[b] = q[a] * prod / cons along every channel a -> b
                a = stack.pop()
                for b, factor, c in adj[a]:
                    want = q[a] * factor
                    if b not in q:
                        q[b] = want
                        part.append(b)
                        stack.append(b)
                    elif q[b] != want:
                        raise ModelError(f"inconsistent rates: {c.src} x{c.prod} -> {c.dst} "
                                         f"x{c.cons} contradicts the other channels between "
                                         "these actors (no repetition vector exists)",
                                         f"channel {c.name}")
            lcm = math.lcm(*(q[a].denominator for a in part))
            ints = [int(q[a] * lcm) for a in part]
            g = math.gcd(*ints)
            for a, v in zip(part, ints):
                q[a] = Fraction(v // g)
        return {a: int(q[a]) for a in self.actors}

    def to_arcs(self) -> ArcList:
        """The homogeneous (HSDF) expansion as an arc list (transitions ``actor_i``).

        Firing ``j`` of ``dst`` in iteration ``k`` takes the tokens of absolute
        index ``N = (k q_dst + j) cons + i``, ``i < cons``; token ``N`` was made
        by firing ``f = floor((N - tokens) / prod)`` of ``src`` (initial tokens
        count as firings of earlier iterations), i.e. by ``src_(f mod q_src)``
        ``-floor(f / q_src)`` iterations before. Of the places between two
        firings only the one with fewest tokens constrains, and is kept.
        """
        q = self.repetition_vector()
        offset: dict[str, int] = {}
        names: list[str] = []
        for a in self.actors:
            offset[a] = len(names)
            names.extend(f"{a}_{i}" for i in range(q[a]))
        if len(set(names)) != len(names):
            raise ModelError("two firings get the same name actor_i; rename the actors",
                             f"graph {self.name}")
        src, dst, tok = [], [], []
        for c in self.channels:
            j = np.repeat(np.arange(q[c.dst], dtype=np.int64), c.cons)
            i = np.tile(np.arange(c.cons, dtype=np.int64), q[c.dst])
            f = (j * c.cons + i - c.tokens) // c.prod
            src.append(offset[c.src] + f % q[c.src])
            dst.append(offset[c.dst] + j)
            tok.append(-(f // q[c.src]))
        s = np.concatenate(src) if src else np.zeros(0, np.int64)
        d = np.concatenate(dst) if dst else np.zeros(0, np.int64)
        t = np.concatenate(tok) if tok else np.zeros(0, np.int64)
        order = np.lexsort((t, d, s))  # by (src, dst), fewest tokens first
        s, d, t = s[order], d[order], t[order]
        first = np.ones(len(s), dtype=bool)
        first[1:] = (s[1:] != s[:-1]) | (d[1:] != d[:-1])
        s, d, t = s[first], d[first], t[first]
        exec_time = np.array([self.actors[a] for a in self.actors for _ in range(q[a])],
                             dtype=np.int64)
        return ArcList(s, d, exec_time[s], t, 1, names, len(names), self.name)

    def to_teg(self) -> TimedEventGraph:
        """The homogeneous expansion as a :class:`~tegraph.teg.TimedEventGraph`."""
        return self.to_arcs().to_teg()

    @classmethod
    def from_teg(cls, teg: Any) -> SDFGraph:
        """The homogeneous SDF graph of a timed event graph (all rates 1).

        A transition whose places all hold one time becomes an actor of that
        execution time. When its places hold different times, the actor takes
        0 and each place becomes an actor of its own, holding its time (no
        self-loop: it serves any number of tokens at once, as a place does).
        Every circuit keeps its times and tokens, so its cycle ratio.

        Raises
        ------
        ModelError
            A time is not an integer, or initial tokens are available after 0:
            SDF3 has neither.
        """
        g = as_teg(teg)
        names = g.transition_names
        times: dict[int, set[Fraction]] = {}
        for p in g.places:
            where = f"place {p.name}"
            if p.initial != 0:
                raise ModelError("initial tokens available after 0 cannot be written to "
                                 "SDF3", where)
            if p.holding.denominator != 1:
                raise ModelError(f"SDF3 execution times are integers, got {p.holding}", where)
            times.setdefault(p.src, set()).add(p.holding)
        actors = {n: int(next(iter(times[k]))) if len(times.get(k, ())) == 1 else 0
                  for k, n in enumerate(names)}
        channels = []
        for k, p in enumerate(g.places):
            src, dst = names[p.src], names[p.dst]
            if len(times[p.src]) > 1 and p.holding:
                mid = f"place{k}"
                while mid in actors:
                    mid += "_"
                actors[mid] = int(p.holding)
                channels.append(SDFChannel(f"ch{k}a", src, mid, 1, 1, 0))
                src = mid
            channels.append(SDFChannel(f"ch{k}", src, dst, 1, 1, p.tokens))
        return cls(g.name, actors, channels)


# --------------------------------------------------------------------------- reading


def read_sdf3(path: str | os.PathLike[str], *, max_bytes: int = DEFAULT_MAX_BYTES) -> SDFGraph:
    """Read an SDF3 XML file (``<sdf3 type="sdf">``); see the module docstring."""
    file = os.fspath(path)
    return parse_sdf3(read_limited(file, max_bytes), file)


def parse_sdf3(data: bytes | str, file: str | None = None) -> SDFGraph:
    """Parse SDF3 XML text.

    Raises
    ------
    InputError
        Malformed XML, a DOCTYPE, a missing name, a channel to an unknown
        actor or port, a rate that is not a positive integer, initial tokens
        or an execution time that is not an integer >= 0, inconsistent rates.

    Examples
    --------
    >>> g = parse_sdf3('''<sdf3 type="sdf"><applicationGraph name="x"><sdf name="x">
    ...   <actor name="a"><port name="o" type="out" rate="1"/><port name="i" type="in" rate="1"/></actor>
    ...   <channel name="c" srcActor="a" srcPort="o" dstActor="a" dstPort="i" initialTokens="1"/>
    ... </sdf><sdfProperties><actorProperties actor="a">
    ...   <processor type="p" default="true"><executionTime time="5"/></processor>
    ... </actorProperties></sdfProperties></applicationGraph></sdf3>''')
    >>> g.actors, g.channels[0].tokens
    ({'a': 5}, 1)
    """
    if isinstance(data, str):
        data = data.encode("utf-8")
    root = parse_xml(data, file)
    if root.tag != "sdf3":
        raise InputError(f"the root element is <{root.tag}>, expected <sdf3>", root.tag, file,
                         root.line)
    kind = root.attrs.get("type", "sdf")
    if kind != "sdf":
        raise InputError(f"SDF3 graph type {kind!r} is not supported; expected 'sdf'", "sdf3",
                         file, root.line)
    app = root.child("applicationGraph")
    sdf = app.child("sdf") if app is not None else None
    if app is None or sdf is None:
        raise InputError("no <applicationGraph><sdf> element", "sdf3", file, root.line)
    name = sdf.attrs.get("name") or app.attrs.get("name") or Path(file or "sdf").stem
    ports: dict[tuple[str, str], tuple[str, int]] = {}
    actors: dict[str, int] = {}
    for actor in sdf.all("actor"):
        a = _required(actor, "name", file)
        if a in actors:
            raise InputError(f"duplicate actor name {a!r}", f"actor[{a}]", file, actor.line)
        actors[a] = 0
        for port in actor.all("port"):
            p = _required(port, "name", file, f"actor[{a}]/port")
            where = f"actor[{a}]/port[{p}]"
            ptype = port.attrs.get("type")
            if ptype not in ("in", "out"):
                raise InputError(f"a port type is 'in' or 'out', got {ptype!r}", where, file,
                                 port.line)
            rate = _integer(port.attrs.get("rate", "1"), "rate", where, file, port.line)
            if rate < 1:
                raise InputError(f"a rate must be an integer >= 1, got {rate}", where, file,
                                 port.line)
            ports[(a, p)] = (ptype, rate)
    channels = []
    for ch in sdf.all("channel"):
        c = _required(ch, "name", file, "channel")
        where = f"channel[{c}]"
        rates = []
        for end, ptype in (("src", "out"), ("dst", "in")):
            a = _required(ch, f"{end}Actor", file, where)
            p = _required(ch, f"{end}Port", file, where)
            if a not in actors:
                raise InputError(f"{end}Actor {a!r} is not an actor of the graph", where, file,
                                 ch.line)
            if (a, p) not in ports:
                raise InputError(f"{end}Port {p!r} is not a port of actor {a!r}", where, file,
                                 ch.line)
            if ports[(a, p)][0] != ptype:
                raise InputError(f"{end}Port {a}.{p} is an '{ports[(a, p)][0]}' port, expected "
                                 f"'{ptype}'", where, file, ch.line)
            rates.append(ports[(a, p)][1])
        tokens = _integer(ch.attrs.get("initialTokens", "0"), "initialTokens", where, file,
                          ch.line)
        channels.append(SDFChannel(c, ch.attrs["srcActor"], ch.attrs["dstActor"], rates[0],
                                   rates[1], tokens))
    props = app.child("sdfProperties")
    for ap in props.all("actorProperties") if props is not None else []:
        a = _required(ap, "actor", file, "actorProperties")
        where = f"actorProperties[{a}]"
        if a not in actors:
            raise InputError(f"actor {a!r} is not an actor of the graph", where, file, ap.line)
        for proc in ap.all("processor"):
            if "default" not in proc.attrs:
                continue
            et = proc.child("executionTime")
            if et is None or "time" not in et.attrs:
                raise InputError("a default processor needs <executionTime time=...>",
                                 f"{where}/processor", file, proc.line)
            actors[a] = _integer(et.attrs["time"], "executionTime", f"{where}/processor", file,
                                 et.line)  # the last default processor wins, as in SDF3
    graph = SDFGraph(name, actors, channels)
    try:
        graph.repetition_vector()
    except ModelError as exc:
        raise InputError(exc.reason, exc.element, file) from None
    return graph


def _required(node: XmlNode, attr: str, file: str | None, where: str | None = None) -> str:
    value = node.attrs.get(attr)
    if not value:
        raise InputError(f"<{node.tag}> has no {attr} attribute", where or node.tag, file,
                         node.line)
    return value


def _integer(text: str, what: str, where: str, file: str | None, line: int) -> int:
    try:
        value = int(text.strip())
    except ValueError:
        raise InputError(f"{what} must be an integer >= 0, got {text!r}", where, file,
                         line) from None
    if value < 0:
        raise InputError(f"{what} must be an integer >= 0, got {value}", where, file, line)
    return value


# --------------------------------------------------------------------------- writing


def write_sdf3(obj: Any, path: str | os.PathLike[str], overwrite: bool = False) -> Path:
    """Write an SDF graph, or a timed event graph as a homogeneous one, as SDF3 XML."""
    return write_bytes(path, dumps_sdf3(obj), overwrite)


def dumps_sdf3(obj: Any) -> str:
    """SDF3 XML text; one processor ``p`` marked default per actor, one port per channel end.

    Examples
    --------
    >>> g = SDFGraph("g", {"a": 3}, [SDFChannel("c", "a", "a", 1, 1, 1)])
    >>> parse_sdf3(dumps_sdf3(g)) == g
    True
    """
    g = obj if isinstance(obj, SDFGraph) else SDFGraph.from_teg(obj)
    ports: dict[str, list[str]] = {a: [] for a in g.actors}
    lines = ['<?xml version="1.0" encoding="UTF-8"?>', '<sdf3 type="sdf" version="1.0">',
             f"  <applicationGraph name={quoteattr(g.name)}>",
             f"    <sdf name={quoteattr(g.name)} type={quoteattr(g.name)}>"]
    for k, c in enumerate(g.channels):
        ports[c.src].append(f'<port name="out{k}" type="out" rate="{c.prod}"/>')
        ports[c.dst].append(f'<port name="in{k}" type="in" rate="{c.cons}"/>')
    for a in g.actors:
        lines.append(f"      <actor name={quoteattr(a)} type={quoteattr(a)}>")
        lines.extend(f"        {p}" for p in ports[a])
        lines.append("      </actor>")
    for k, c in enumerate(g.channels):
        lines.append(f"      <channel name={quoteattr(c.name)} srcActor={quoteattr(c.src)} "
                     f'srcPort="out{k}" dstActor={quoteattr(c.dst)} dstPort="in{k}" '
                     f'initialTokens="{c.tokens}"/>')
    lines += ["    </sdf>", "    <sdfProperties>"]
    for a, t in g.actors.items():
        lines += [f"      <actorProperties actor={quoteattr(a)}>",
                  '        <processor type="p" default="true">',
                  f'          <executionTime time="{t}"/>',
                  "        </processor>", "      </actorProperties>"]
    lines += ["    </sdfProperties>", "  </applicationGraph>", "</sdf3>", ""]
    return "\n".join(lines)
