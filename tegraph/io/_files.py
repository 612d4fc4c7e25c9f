"""Files: a size limit before anything is read, and writes that never replace by accident."""

from __future__ import annotations

import os
from pathlib import Path

from ..errors import InputError
from ..model.budgets import DEFAULT_MAX_BYTES

__all__ = ["DEFAULT_MAX_BYTES", "check_size", "read_limited", "write_bytes"]

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
