"""Files <-> models: :func:`read` and :func:`write` through one table of formats.

Every reader returns the model its format holds, most faithfully:

=============  ================================  =========================================
format         files                             :func:`read` returns
=============  ================================  =========================================
``skeleton``   ``.yaml``, ``.yml``, ``.json``    :class:`~tegraph.model.skeleton.Skeleton`
``pnml``       ``.pnml``, ``.xml``               :class:`~tegraph.model.petri.PetriNet`
``sdf3``       ``.sdf3``, ``.xml``               :class:`~tegraph.model.sdf.SDFGraph`
``edges``      ``.edges``                        :class:`~tegraph.model.arcs.ArcList`
``tpne-json``  ``.json`` (TimedPetriNetEditor)   :class:`~tegraph.model.petri.PetriNet`
``tpne-teg``   ``.teg`` (TimedPetriNetEditor)    :class:`~tegraph.model.teg.TimedEventGraph`
``dot``        ``.dot``, ``.gv`` (write only)    --
``teg-dot``    (write only)                      --
=============  ================================  =========================================

:func:`write` accepts any of these models (and a
:class:`~tegraph.model.teg.TimedEventGraph`)
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

The formats are the records of :data:`~tegraph.io.formats.FORMATS`
(:mod:`tegraph.io.formats`): extensions, how a file's first bytes tell it apart,
reader and writer. This package turns files into models and models into files,
nothing more: what a model means is the job of :mod:`tegraph.analysis`.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

from .formats import FORMATS

# name -> module that defines it. Each is imported on first use, and each format's
# module when one of its files is read or written: a skeleton's analysis reads none
# of the other formats, and the command line's help reads the table of formats alone.
_WHERE = {
    "DEFAULT_MAX_BYTES": "tegraph.io._files",
    "FORMATS": "tegraph.io.formats",
    "FileFormat": "tegraph.io.formats",
    "detect_format": "tegraph.io.formats",
    "dump_skeleton": "tegraph.io.skeleton_file",
    "format_for_writing": "tegraph.io.formats",
    "input_as_output": "tegraph.io._files",
    "load_skeleton": "tegraph.io.skeleton_file",
    "read": "tegraph.io.formats",
    "same_file": "tegraph.io._files",
    "sniff_format": "tegraph.io.formats",
    "write": "tegraph.io.formats",
}
_FORMAT_MODULES = tuple(sorted({
    target.partition(":")[0].rpartition(".")[2]
    for f in FORMATS.values() for target in (f.reader, f.writer) if target is not None
} - {"skeleton_file"}))

__all__ = [
    "DEFAULT_MAX_BYTES",
    "FORMATS",
    "FileFormat",
    "detect_format",
    "dump_skeleton",
    "format_for_writing",
    "input_as_output",
    "load_skeleton",
    "read",
    "same_file",
    "sniff_format",
    "write",
]


def __getattr__(name: str) -> Any:
    if name in _WHERE:
        value = getattr(importlib.import_module(_WHERE[name]), name)
        globals()[name] = value  # later lookups skip this function
        return value
    if name in _FORMAT_MODULES:  # `tegraph.io.pnml` after `import tegraph.io`
        return importlib.import_module(f"{__name__}.{name}")
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted({*globals(), *_WHERE, *_FORMAT_MODULES})


if TYPE_CHECKING:  # static tools see the names where they are defined
    from . import dot, edges, pnml, sdf3, tpne  # noqa: F401  (attributes of the package)
    from ._files import DEFAULT_MAX_BYTES, input_as_output, same_file
    from .formats import FileFormat, detect_format, format_for_writing, read, sniff_format, write
    from .skeleton_file import dump_skeleton, load_skeleton
