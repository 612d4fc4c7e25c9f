"""Files: a size limit before anything is read, and writes that never replace by accident."""

from __future__ import annotations

import os
from collections.abc import Iterable
from pathlib import Path

from ..errors import InputError
from ..model.budgets import DEFAULT_MAX_BYTES

__all__ = ["DEFAULT_MAX_BYTES", "check_size", "input_as_output", "read_limited", "same_file",
           "write_bytes"]

def check_size(path: str | os.PathLike[str], max_bytes: int = DEFAULT_MAX_BYTES) -> None:
    """Refuse (``InputError``) a file above ``max_bytes``, or one that cannot be read."""
    file = os.fspath(path)
    try:
        size = os.stat(file).st_size
    except OSError as exc:
        raise InputError(f"cannot read the file: {exc.strerror}", file=file) from None
    if size > max_bytes:
        raise InputError(f"the file has {size} bytes, above the limit of {max_bytes}; raise "
                         "`max_bytes` to read it", file=file)


def read_limited(path: str | os.PathLike[str], max_bytes: int = DEFAULT_MAX_BYTES) -> bytes:
    """The bytes of ``path``, refused (``InputError``) above ``max_bytes`` or when unreadable."""
    check_size(path, max_bytes)
    file = os.fspath(path)
    try:
        with open(file, "rb") as fh:
            return fh.read()
    except OSError as exc:
        raise InputError(f"cannot read the file: {exc.strerror}", file=file) from None


def write_bytes(path: str | os.PathLike[str], data: bytes | str, overwrite: bool = False) -> Path:
    """Write ``data`` to ``path``; an existing file is replaced only when ``overwrite``.

    Raises
    ------
    FileExistsError
        ``path`` exists and ``overwrite`` is False (the file is not touched).
    """
    target = Path(os.fspath(path))
    payload = data.encode("utf-8") if isinstance(data, str) else data
    # "x" mode creates atomically: no window between an exists() check and the write.
    with open(target, "wb" if overwrite else "xb") as fh:
        fh.write(payload)
    return target


def same_file(a: str | os.PathLike[str], b: str | os.PathLike[str]) -> bool:
    """Whether ``a`` and ``b`` name one existing file, whatever links lead to it
    (symbolic links resolved; a hard link has the same device and inode).

    >>> import pathlib, tempfile
    >>> d = pathlib.Path(tempfile.mkdtemp())
    >>> (d / "s.yaml").write_text("tasks: {}")
    9
    >>> (d / "link.svg").symlink_to(d / "s.yaml")
    >>> same_file(d / "link.svg", d / "s.yaml"), same_file(d / "new.svg", d / "s.yaml")
    (True, False)
    """
    try:
        return os.path.samefile(a, b)
    except OSError:  # one of them does not exist: a file to come is no input
        return False


def input_as_output(output: str | os.PathLike[str], inputs: Iterable[str | os.PathLike[str]],
                    where: str) -> None:
    """Refuse an output file that is one of the ``inputs`` (after resolving links),
    whatever the flags: a command writes its results beside its input, never over it.

    The one rule of every command that writes a file (only ``fix``, whose output is
    the repaired input, may replace it, and only when asked to).

    Raises
    ------
    InputError
        ``output`` is one of ``inputs``; ``where`` names the option that gave it.
    """
    for source in inputs:
        if same_file(output, source):
            link = Path(output).is_symlink() or os.path.realpath(output) != os.path.abspath(
                output)
            how = " (through a symbolic link)" if link else ""
            raise InputError(f"{os.fspath(output)} is the input file {os.fspath(source)}{how}; "
                             "expected another file name: the input is never written over",
                             where)
