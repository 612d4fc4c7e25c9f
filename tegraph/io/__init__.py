"""Files <-> models: format detection and :func:`read` / :func:`write`, one module per format.

Every reader returns the model its format holds, most faithfully:

=============  ==============================  =========================================
format         files                           :func:`read` returns
=============  ==============================  =========================================
``skeleton``   ``.yaml``, ``.yml``, ``.json``  :class:`~tegraph.model.skeleton.Skeleton`
``pnml``       ``.pnml``, ``.xml``             :class:`~tegraph.model.petri.PetriNet`
``sdf3``       ``.sdf3``, ``.xml``             :class:`~tegraph.model.sdf.SDFGraph`
``edges``      ``.edges``                      :class:`~tegraph.model.arcs.ArcList`
``tpne-json``  ``.json`` (TimedPetriNetEditor)  :class:`~tegraph.model.petri.PetriNet`
``tpne-teg``   ``.teg`` (TimedPetriNetEditor)   :class:`~tegraph.model.teg.TimedEventGraph`
``dot``        ``.dot``, ``.gv`` (write only)   --
``teg-dot``    (write only)                     --
=============  ==============================  =========================================

:func:`write` accepts any of these models (and a :class:`TimedEventGraph`)
wherever the target can hold the content: a skeleton becomes a timed event
graph, never the other way round; a P/T net that is not a marked graph can
only go to net formats (PNML, TimedPetriNetEditor JSON, DOT).

Safety: a file larger than ``max_bytes`` (default :data:`DEFAULT_MAX_BYTES`)
is refused before it is read, and XML is parsed by expat with every document
type declaration refused, so no entity is ever expanded and no external file
is ever fetched (an entity-expansion bomb is refused at its first line).
Every reader applies the stated limits of :mod:`tegraph.model.limits` (digits
and exponent of a number, 64-bit token counts, node counts against the file's
size, names that can be written): a value is read exactly or refused naming
it and the limit, with one :class:`~tegraph.errors.InputError` (the fuzz test
``tests/tegraph/io/test_fuzz_readers.py`` holds every reader to it).

This package turns files into models and models into files, nothing more:
what a model means is the job of :mod:`tegraph.analysis`.
"""

from __future__ import annotations

import importlib
import os
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any

from ..errors import InputError, ModelError
from ..model.skeleton import Skeleton
from ._detect import FORMATS, detect_format, sniff_format
from ._files import DEFAULT_MAX_BYTES, check_size, input_as_output, same_file
from .skeleton_file import dump_skeleton, load_skeleton

if TYPE_CHECKING:  # static tools see the format modules; at run time see __getattr__
    from . import dot, edges, pnml, sdf3, tpne  # noqa: F401  (attributes of the package)

# The modules of the other formats (and the nets and SDF graphs they hold) are
# imported when a file of theirs is read or written: a skeleton's analysis uses
# none of them (some 25 ms of every `tegraph analyze`).
_FORMAT_MODULES = ("dot", "edges", "pnml", "sdf3", "tpne")


def __getattr__(name: str) -> Any:
    if name in _FORMAT_MODULES:  # `tegraph.io.pnml` after `import tegraph.io`, as before
        return importlib.import_module(f"{__name__}.{name}")
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted({*globals(), *_FORMAT_MODULES})

__all__ = [
    "DEFAULT_MAX_BYTES",
    "FORMATS",
    "detect_format",
    "format_for_writing",
    "input_as_output",
    "same_file",
    "sniff_format",
    "dump_skeleton",
    "load_skeleton",
    "read",
    "write",
]

# --------------------------------------------------------------------------- coercions


# --------------------------------------------------------------------------- read / write


def _readers() -> dict[str, Callable[..., Any]]:
    from . import edges, pnml, sdf3, tpne

    return {"pnml": pnml.read_pnml, "sdf3": sdf3.read_sdf3, "edges": edges.read_edges,
            "tpne-json": tpne.read_tpne_json, "tpne-teg": tpne.read_tpne_teg,
            "skeleton": _read_skeleton}  # DOT: no reader


def _writers() -> dict[str, Callable[..., Any]]:
    from . import dot, edges, pnml, sdf3, tpne

    return {"pnml": pnml.write_pnml, "sdf3": sdf3.write_sdf3, "edges": edges.write_edges,
            "tpne-json": tpne.write_tpne_json, "tpne-teg": tpne.write_tpne_teg,
            "dot": dot.write_dot, "teg-dot": dot.write_teg_dot, "skeleton": _write_skeleton}


def _read_skeleton(path: str | os.PathLike[str], *, max_bytes: int = DEFAULT_MAX_BYTES) -> Any:
    check_size(path, max_bytes)
    return load_skeleton(path)


def _write_skeleton(obj: Any, path: str | os.PathLike[str], overwrite: bool = False) -> Path:
    if not isinstance(obj, Skeleton):
        raise InputError(f"a skeleton file holds a skeleton; a {type(obj).__name__} cannot "
                         "become one (a skeleton becomes a timed event graph, not the other "
                         "way round)", file=os.fspath(path))
    return dump_skeleton(obj, path, overwrite=overwrite)


def read(path: str | os.PathLike[str], format: str | None = None, *,
         max_bytes: int = DEFAULT_MAX_BYTES) -> Any:
    """Read any supported file; the reader is picked from the file (see the module table).

    Parameters
    ----------
    path : str or path-like
        The file.
    format : str, optional
        Force a format name of :data:`FORMATS` instead of detecting it.
    max_bytes : int
        Refuse larger files (default :data:`DEFAULT_MAX_BYTES`).

    Returns
    -------
    Skeleton, PetriNet, SDFGraph, ArcList or TimedEventGraph
        The model the format holds (see the module table).

    Raises
    ------
    InputError
        Unknown format, file too large, or a malformed file (the message
        names the file, the line when known, and the element).

    See Also
    --------
    write : the converse.
    load_skeleton : a skeleton file, checked against spec §1.
    detect_format : the format :func:`read` picks.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> f = pathlib.Path(tempfile.mkdtemp()) / "ring.edges"
    >>> _ = f.write_text("0 1 2 0\\n1 0 3 1\\n")
    >>> g = read(f); g.n_transitions, g.n_places
    (2, 2)
    """
    readers = _readers()
    fmt = format or detect_format(path)
    if fmt not in readers:
        raise InputError(f"format {fmt!r} cannot be read; readable: {', '.join(sorted(readers))}",
                         file=os.fspath(path))
    return readers[fmt](path, max_bytes=max_bytes)


def write(obj: Any, path: str | os.PathLike[str], format: str | None = None,
          overwrite: bool = False, *, highlights: dot.Highlights | None = None) -> Path:
    """Write ``obj`` in the format of ``path`` (or ``format``) when it can hold it.

    Parameters
    ----------
    obj : Skeleton, TimedEventGraph, PetriNet, SDFGraph or ArcList
    path : str or path-like
    format : str, optional
        A name of :data:`FORMATS`; default from the extension (``.json`` is
        TimedPetriNetEditor JSON for a net or graph, a skeleton file for a skeleton).
    overwrite : bool
        Replace an existing file; without it an existing file is never touched.
    highlights : tegraph.io.dot.Highlights, optional
        Circuits to colour in a DOT drawing (``tegraph.write`` computes them).

    Returns
    -------
    pathlib.Path

    Raises
    ------
    InputError
        The target cannot hold the content (e.g. a timed event graph to a
        skeleton file, a non-marked-graph net to an arc list).
    FileExistsError
        ``path`` exists and ``overwrite`` is False.
    """
    file = os.fspath(path)
    fmt = format or format_for_writing(obj, file)
    writers = _writers()
    if fmt not in writers:
        raise InputError(f"format {fmt!r} cannot be written; writable: "
                         f"{', '.join(sorted(writers))}", file=file)
    try:
        if fmt in ("dot", "teg-dot"):
            return writers[fmt](obj, path, overwrite=overwrite, highlights=highlights)
        return writers[fmt](obj, path, overwrite=overwrite)
    except ModelError as exc:
        raise InputError(f"cannot be written as {fmt}: {exc}", file=file) from None


def format_for_writing(obj: Any, file: str) -> str:
    ext = Path(file).suffix.lower()
    if ext == ".json":
        return "skeleton" if isinstance(obj, Skeleton) else "tpne-json"
    if ext == ".xml":
        from ..model.sdf import SDFGraph

        return "sdf3" if isinstance(obj, SDFGraph) else "pnml"
    for name, exts in FORMATS.items():
        if ext in exts:
            return name
    raise InputError(f"cannot tell the format from the extension {ext!r}; use one of "
                     + ", ".join(e for exts in FORMATS.values() for e in exts)
                     + ", .xml, or give the format", file=file)


