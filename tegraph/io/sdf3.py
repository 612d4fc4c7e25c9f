"""SDF3 synchronous dataflow graphs (``<sdf3 type="sdf">`` XML), and their expansion.

An SDF graph has actors with an execution time and channels that carry
tokens at fixed rates: each firing of the source actor produces ``prod``
tokens, each firing of the destination consumes ``cons``; ``tokens`` are
there initially. What is read, as SDF3 [4]_ itself reads it:

* the execution time of an actor is that of the **last** ``<processor>`` of
  its ``actorProperties`` carrying a ``default`` attribute (any value), 0 if none;
* rates come from the ``rate`` of the ports named by the channel;
  ``initialTokens`` defaults to 0;
* an actor without a self-loop channel may fire concurrently with itself
  (unbounded auto-concurrency): no self-loop is added.

The repetition vector ``q`` [3]_ (the smallest positive integers with
``q[src] * prod == q[dst] * cons`` on every channel) expands the graph into
its homogeneous graph: one transition ``actor_i`` per firing
``i < q[actor]`` of an iteration, one place per dependency, holding the
execution time of the source firing (:meth:`SDFGraph.to_arcs`). Its maximum
cycle ratio is the period of the graph: the time per iteration, whose
inverse is SDF3's throughput ([1]_, ch. 3; [2]_).

References
----------
.. [1] S. Sriram, S. S. Bhattacharyya, *Embedded Multiprocessors: Scheduling
   and Synchronization*, 2nd ed., CRC Press, 2009.
.. [2] A. H. Ghamarian et al., "Throughput analysis of synchronous data flow
   graphs", International Conference on Application of Concurrency to
   System Design (ACSD), 2006.
.. [3] E. A. Lee, D. G. Messerschmitt, "Synchronous data flow", Proceedings
   of the IEEE 75(9), 1235–1245, 1987.
.. [4] S. Stuijk, M. Geilen, T. Basten, "SDF³: SDF For Free", International
   Conference on Application of Concurrency to System Design (ACSD), 2006.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

from maxplus.scalar import size_problem

from ..errors import InputError, ModelError
from ..model.convert import as_teg
from ..model.limits import count_problem, shown
from ..model.sdf import SDFChannel, SDFGraph
from ._files import DEFAULT_MAX_BYTES, read_limited, write_bytes
from ._xml import XmlNode, parse_xml

__all__ = ["dumps_sdf3", "parse_sdf3", "read_sdf3", "write_sdf3"]


# --------------------------------------------------------------------------- reading


def read_sdf3(path: str | os.PathLike[str], *, max_bytes: int = DEFAULT_MAX_BYTES) -> SDFGraph:
    """Read an SDF3 XML file (``<sdf3 type="sdf">``); see the module docstring.

    Parameters
    ----------
    path : str or os.PathLike
        The file.
    max_bytes : int
        Larger files are refused before they are read.

    Returns
    -------
    SDFGraph
        Actors with their execution times, channels with rates and tokens.

    Raises
    ------
    InputError
        The file is unreadable or too large, or its content is refused (see
        :func:`parse_sdf3`).

    See Also
    --------
    parse_sdf3 : the same from text.
    write_sdf3 : the converse.

    Examples
    --------
    >>> import os, tempfile
    >>> g = SDFGraph("g", {"a": 3}, [SDFChannel("c", "a", "a", 1, 1, 1)])
    >>> with tempfile.TemporaryDirectory() as folder:
    ...     read_sdf3(write_sdf3(g, os.path.join(folder, "g.xml"))) == g
    True
    """
    file = os.fspath(path)
    return parse_sdf3(read_limited(file, max_bytes), file)


def parse_sdf3(data: bytes | str, file: str | None = None) -> SDFGraph:
    """Parse SDF3 XML text.

    Parameters
    ----------
    data : bytes or str
        The XML (str is encoded as UTF-8).
    file : str, optional
        File name, for the messages of refused input.

    Returns
    -------
    SDFGraph
        Actors with their execution times, channels with rates and tokens.

    Raises
    ------
    InputError
        Malformed XML, a DOCTYPE, a missing name, a channel to an unknown
        actor or port, a rate that is not a positive integer, initial tokens
        or an execution time that is not an integer >= 0, inconsistent rates.

    See Also
    --------
    read_sdf3 : the same from a file.
    dumps_sdf3 : the converse.
    tegraph.model.sdf.SDFGraph.to_arcs : the homogeneous expansion.

    Examples
    --------
    >>> g = parse_sdf3('''<sdf3 type="sdf"><applicationGraph name="x"><sdf name="x">
    ...   <actor name="a"><port name="o" type="out" rate="1"/>
    ...     <port name="i" type="in" rate="1"/></actor>
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
            rate = _integer(port.attrs.get("rate", "1"), "rate", where, file, port.line,
                            count=True)
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
                          ch.line, count=True)
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
    graph = SDFGraph(name, actors, channels, source=file)
    try:
        graph.repetition_vector()
    except ModelError as exc:
        raise InputError(exc.reason, exc.where, file) from None
    return graph


def _required(node: XmlNode, attr: str, file: str | None, where: str | None = None) -> str:
    value = node.attrs.get(attr)
    if not value:
        raise InputError(f"<{node.tag}> has no {attr} attribute", where or node.tag, file,
                         node.line)
    return value


def _integer(text: str, what: str, where: str, file: str | None, line: int,
             count: bool = False) -> int:
    """An integer >= 0 as SDF3 writes it; a ``count`` (rate, tokens) also below 2**63."""
    why = size_problem(text)
    if why is not None:
        raise InputError(f"{what} must be an integer within the limits: {why}", where, file,
                         line)
    try:
        value = int(text.strip())
    except ValueError:
        raise InputError(f"{what} must be an integer >= 0, got {shown(text)}", where, file,
                         line) from None
    if value < 0:
        raise InputError(f"{what} must be an integer >= 0, got {value}", where, file, line)
    why = count_problem(value, what) if count else None
    if why is not None:
        raise InputError(why, where, file, line)
    return value


# --------------------------------------------------------------------------- writing


def write_sdf3(obj: Any, path: str | os.PathLike[str], overwrite: bool = False) -> Path:
    """Write an SDF graph, or a timed event graph as a homogeneous one, as SDF3 XML.

    Parameters
    ----------
    obj : SDFGraph or any model :func:`tegraph.model.convert.as_teg` takes
        What to write; anything but an SDF graph is written as its timed
        event graph, one actor per transition.
    path : str or os.PathLike
        The file.
    overwrite : bool
        Replace an existing file (default False).

    Returns
    -------
    pathlib.Path
        The file written.

    Raises
    ------
    FileExistsError
        ``path`` exists and ``overwrite`` is False (the file is not touched).
    InputError
        ``obj`` is not a model this project reads.

    See Also
    --------
    dumps_sdf3 : the text written.
    read_sdf3 : the converse.

    Examples
    --------
    >>> import os, tempfile
    >>> g = SDFGraph("g", {"a": 3}, [SDFChannel("c", "a", "a", 1, 1, 1)])
    >>> with tempfile.TemporaryDirectory() as folder:
    ...     write_sdf3(g, os.path.join(folder, "g.xml")).name
    'g.xml'
    """
    return write_bytes(path, dumps_sdf3(obj), overwrite)


def dumps_sdf3(obj: Any) -> str:
    """SDF3 XML text; one processor ``p`` marked default per actor, one port per channel end.

    Parameters
    ----------
    obj : SDFGraph or any model :func:`tegraph.model.convert.as_teg` takes
        What to write, as for :func:`write_sdf3`.

    Returns
    -------
    str
        The XML document that SDF3 [1]_ and :func:`parse_sdf3` read.

    Raises
    ------
    InputError
        ``obj`` is not a model this project reads.

    See Also
    --------
    write_sdf3 : the same to a file.
    parse_sdf3 : the converse.

    References
    ----------
    .. [1] S. Stuijk, M. Geilen, T. Basten, "SDF³: SDF For Free", International
       Conference on Application of Concurrency to System Design (ACSD), 2006.

    Examples
    --------
    >>> g = SDFGraph("g", {"a": 3}, [SDFChannel("c", "a", "a", 1, 1, 1)])
    >>> parse_sdf3(dumps_sdf3(g)) == g
    True
    """
    # Here, not at the top: xml.sax.saxutils loads urllib.request, http and ssl,
    # which every command would pay for at start-up.
    from xml.sax.saxutils import quoteattr

    g = obj if isinstance(obj, SDFGraph) else SDFGraph.from_teg(as_teg(obj))
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
