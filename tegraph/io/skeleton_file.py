"""Read and write skeleton files (spec §1): YAML or JSON, every refusal located.

A YAML document is read (and a YAML file written) by :mod:`tegraph.io._skeleton_yaml`,
imported for YAML text only. The checks themselves live in the model
(:mod:`tegraph.model.skeleton.schema` and :mod:`tegraph.model.skeleton.checks`),
shared with skeletons built in code.
"""

from __future__ import annotations

import json
import os
import re
from decimal import Decimal
from pathlib import Path
from typing import Any

from ..errors import InputError, SkeletonError
from ..model.limits import text_problem
from ..model.skeleton import Skeleton
from ..model.skeleton.checks import KeyPath, Locator
from ._files import DEFAULT_MAX_BYTES, check_size
from .formats import FORMATS, sniff_format

__all__ = ["SKELETON_EXTENSIONS", "dump_skeleton", "load_skeleton", "read_skeleton_file",
           "write_skeleton_file"]

SKELETON_EXTENSIONS = FORMATS["skeleton"].extensions()
"""The extensions of skeleton files: ``.json`` is JSON, the others YAML."""


def _read_yaml(text: str, loc: Locator) -> Any:
    # PyYAML is imported for YAML text only: a JSON skeleton's reading (and its
    # analysis) does without importing it.
    from ._skeleton_yaml import read_yaml

    return read_yaml(text, loc)


class _DuplicateKey(Exception):
    def __init__(self, key: str) -> None:
        super().__init__(key)
        self.key = key


def _unique_pairs(pairs: list[tuple[str, Any]]) -> dict[str, Any]:
    # dict() builds the object in C; a duplicate shows as a shorter dict (a
    # 10,000-task file holds some 20,000 objects).
    out = dict(pairs)
    if len(out) < len(pairs):
        seen: set[str] = set()
        for key, _ in pairs:  # the first key met twice, as the message names it
            if key in seen:
                raise _DuplicateKey(key)
            seen.add(key)
    return out


def _read_json(text: str, loc: Locator) -> Any:
    try:
        # Decimal keeps "0.1" exact and never overflows to inf.
        return json.loads(text, object_pairs_hook=_unique_pairs, parse_float=Decimal)
    except _DuplicateKey as dup:
        # Composing the text as YAML (most JSON is YAML) finds the line of the
        # duplicate; when it cannot, the message goes without a line.
        try:
            _read_yaml(text, Locator(file=loc.file))
        except SkeletonError as err:
            if err.reason.startswith("duplicate key"):
                raise err from None
        raise SkeletonError(f"duplicate key {dup.key!r}; expected each key once",
                            file=loc.file) from None
    except json.JSONDecodeError as err:
        raise SkeletonError(f"not valid JSON: {err.msg} (column {err.colno}); expected a "
                            "JSON object as in the skeleton format",
                            file=loc.file, line=err.lineno) from None
    except (ValueError, RecursionError) as err:
        raise SkeletonError(f"not valid JSON: {err or 'nested too deeply'}; expected a JSON "
                            "object as in the skeleton format", file=loc.file) from None


def _json_lines(text: str, loc: Locator) -> None:
    """Fill ``loc`` with the line of every key path, by composing the JSON as YAML."""
    probe = Locator(file=loc.file)
    try:
        _read_yaml(text, probe)
    except SkeletonError:
        return
    loc.lines.update(probe.lines)


def load_skeleton(path: str | os.PathLike[str]) -> Skeleton:
    """Read a skeleton file and check every rule of spec §1.

    Parameters
    ----------
    path : str or path-like
        A ``.json`` file is read as JSON, anything else (``.yaml``, ``.yml``)
        as YAML.

    Returns
    -------
    Skeleton
        Named by the file's ``name`` key, else by the file's stem; ``source``
        is ``path`` as given.

    Raises
    ------
    SkeletonError
        The file does not exist, is empty, is not valid YAML/JSON, or breaks a
        rule of the format; the message names the file, the key path, the line
        when known, and what is expected.

    See Also
    --------
    dump_skeleton : the converse.
    tegraph.io.read : any supported file.
    tegraph.model.skeleton.Skeleton.from_dict : a skeleton from a mapping.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> f = pathlib.Path(tempfile.mkdtemp()) / "demo.yaml"
    >>> _ = f.write_text("tasks:\\n  A: {duration: 0.1, period: '7/3'}\\n")
    >>> sk = load_skeleton(f)
    >>> sk.name, sk.tasks["A"].duration, sk.clocks["A.clock"].period
    ('demo', Fraction(1, 10), Fraction(7, 3))
    """
    file = os.fspath(path)
    where = Path(file)
    loc = Locator(file=file)
    try:
        raw = where.read_bytes()
    except FileNotFoundError:
        raise SkeletonError("no such file; expected an existing skeleton file "
                            "(.yaml, .yml or .json)", file=file) from None
    except IsADirectoryError:
        raise SkeletonError("is a directory; expected a skeleton file", file=file) from None
    except OSError as err:
        raise SkeletonError(f"cannot be read ({err.strerror}); expected a readable "
                            "skeleton file", file=file) from None
    try:
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError as err:
        raise SkeletonError(f"not UTF-8 text (byte 0x{raw[err.start]:02x} at offset "
                            f"{err.start}); expected a YAML or JSON text file", file=file,
                            line=raw[:err.start].count(b"\n") + 1) from None
    data = None
    as_json = where.suffix.lower() == ".json"
    if text.strip():
        try:
            if not as_json and text.lstrip().startswith("{"):
                # JSON is YAML, and JSON's parser is some twenty times faster than YAML's
                # on a large file (a generated skeleton of 100,000 tasks): try it first.
                try:
                    data, as_json = _read_json(text, loc), True
                except SkeletonError:
                    data = _read_yaml(text, loc)
            else:
                data = _read_json(text, loc) if as_json else _read_yaml(text, loc)
        except SkeletonError:
            _other_format(raw, file)  # an XML net read as YAML fails: say what it is
            raise
    if not isinstance(data, dict) or "tasks" not in data:
        _other_format(raw, file, data)
    if data is None:  # nothing but blanks or comments
        raise SkeletonError("the file is empty; expected a skeleton with at least 'tasks'",
                            file=file)
    if _SURROGATE_ESCAPE.search(text):
        _refuse_surrogates(data, loc)
    if not as_json:
        return Skeleton.from_dict(data, where.stem, file, locator=loc)
    try:
        return Skeleton.from_dict(data, where.stem, file, locator=loc)
    except SkeletonError:
        # Lines of a JSON file are looked up only when there is an error to place.
        _json_lines(text, loc)
        return Skeleton.from_dict(data, where.stem, file, locator=loc)


def _other_format(raw: bytes, file: str, data: Any = None) -> None:
    """Refuse a file of another format that tegraph reads, saying which commands read it.

    Called only when the file is no skeleton anyway (it does not parse, or
    holds no ``tasks`` mapping), so a skeleton is never refused for how it looks.
    """
    fmt = sniff_format(raw[:4096])
    if fmt is None and isinstance(data, dict) and isinstance(data.get("nets"), list):
        fmt = "tpne-json"
    if fmt is None:
        return
    readers = ("tegraph writes DOT drawings but reads none" if fmt == "dot" else
               "`tegraph cycle-time` and `tegraph reach` read it (tegraph.io.read in Python)")
    raise SkeletonError(f"this is {FORMATS[fmt].holds}, not a skeleton file; {readers}",
                        file=file)


# JSON's "\ud800" and YAML's "\ud800" or "\U0000d800": a surrogate written as an escape
_SURROGATE_ESCAPE = re.compile(r"\\(u|U0000)[dD][89a-fA-F]")


def _refuse_surrogates(data: Any, loc: Locator) -> None:
    """Refuse the first key or text holding a lone surrogate, at its key path.

    Such a name is read without complaint and fails only when a report or a
    file is written (UnicodeEncodeError); it is refused where it is read.
    """
    stack: list[tuple[KeyPath, Any]] = [((), data)]
    while stack:
        path, value = stack.pop()
        if isinstance(value, str):
            why = text_problem(value)
            if why is not None:
                raise loc.error(why, path)
        elif isinstance(value, dict):
            for key, item in reversed(list(value.items())):
                why = text_problem(key)
                if why is not None:  # the key path shows the surrogate escaped
                    raise loc.error(f"the key {why}",
                                    (*path, key.encode("utf-8", "backslashreplace").decode()))
                stack.append(((*path, key), item))
        elif isinstance(value, list):
            stack.extend(((*path, i), item) for i, item in reversed(list(enumerate(value))))


def dump_skeleton(sk: Skeleton, path: str | os.PathLike[str], overwrite: bool = False) -> Path:
    """Write a skeleton file that :func:`load_skeleton` reads back equal.

    Parameters
    ----------
    sk : Skeleton
        The skeleton to write.
    path : str or path-like
        ``.json`` writes JSON, ``.yaml`` and ``.yml`` YAML; any other
        extension is refused (nothing is written).
    overwrite : bool
        Replace an existing file; without it an existing file is never touched.

    Returns
    -------
    pathlib.Path
        The file written.

    Raises
    ------
    FileExistsError
        ``path`` exists and ``overwrite`` is False.
    SkeletonError
        ``sk`` breaks a rule of spec §1, or ``path`` has no skeleton extension
        (nothing is written).

    See Also
    --------
    load_skeleton : the converse.
    tegraph.write : any model to any format.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> sk = Skeleton.from_dict({"tasks": {"A": {"duration": "7/3", "period": 4}}}, "s")
    >>> f = dump_skeleton(sk, pathlib.Path(tempfile.mkdtemp()) / "s.yaml")
    >>> print(f.read_text(), end="")
    name: s
    unit: ms
    tasks:
      A:
        duration: 7/3
        period: 4
    >>> load_skeleton(f) == sk
    True
    """
    target = Path(os.fspath(path))
    if target.suffix.lower() not in SKELETON_EXTENSIONS:
        raise SkeletonError(f"a skeleton file is .yaml, .yml or .json, not "
                            f"{target.suffix or 'a name without extension'!r}; name the file "
                            "accordingly (other formats take a timed event graph: "
                            "tegraph.io.write)", file=str(target))
    data = sk.to_dict()
    if target.suffix.lower() == ".json":
        text = json.dumps(data, indent=2, ensure_ascii=False) + "\n"
    else:
        from ._skeleton_yaml import dump_yaml

        text = dump_yaml(data)
    try:
        # Mode "x" refuses an existing file atomically (no check-then-write race).
        with open(target, "w" if overwrite else "x", encoding="utf-8") as out:
            out.write(text)
    except FileExistsError:
        raise FileExistsError(f"{target}: the file exists already; pass overwrite=True "
                              "to replace it") from None
    return target


def read_skeleton_file(path: str | os.PathLike[str], *, max_bytes: int = DEFAULT_MAX_BYTES
                       ) -> Skeleton:
    """The reader of the ``skeleton`` format for :func:`tegraph.io.read`: the size, then the file.

    See Also
    --------
    load_skeleton : the same without the size limit.
    """
    check_size(path, max_bytes)
    return load_skeleton(path)


def write_skeleton_file(obj: Any, path: str | os.PathLike[str], overwrite: bool = False) -> Path:
    """The writer of the ``skeleton`` format for :func:`tegraph.io.write`: a skeleton only.

    See Also
    --------
    dump_skeleton : writes a skeleton.
    """
    if not isinstance(obj, Skeleton):
        raise InputError(f"a skeleton file holds a skeleton; a {type(obj).__name__} cannot "
                         "become one (a skeleton becomes a timed event graph, not the other "
                         "way round)", file=os.fspath(path))
    return dump_skeleton(obj, path, overwrite=overwrite)
