"""Every compiled kernel ``setup.py`` builds is there wherever it could have been built.

The kernels are optional: ``setup.py`` goes on without a C compiler, without
Cython, or past a module that fails to compile, and each caller then runs its
reference (numpy, or the engine's Python loop), which every other test passes
too, only slower. So a kernel lost to a broken build would go unnoticed but for
this test: where a C compiler is found and Cython ran at build time, every
extension module ``setup.py`` lists must import, from this checkout. It also holds each package's
kernel switch (``maxplus._kernels``, ``tegraph.analysis.processors._loops``,
which ``tegraph --version`` reads) to the same list.
"""

from __future__ import annotations

import importlib
import importlib.util
import os
import runpy
import shlex
import shutil
import sysconfig
from pathlib import Path

import pytest

from tegraph.api import compiled_kernels
from tests.paths import REPO

SOURCES: dict[str, str] = runpy.run_path(str(REPO / "setup.py"),
                                         run_name="setup_rules")["extension_sources"]()
"""Every extension module setup.py builds (dotted name -> its ``.pyx``), by its own rule."""


def c_compiler() -> str | None:
    """The C compiler setup.py would call (``$CC``, else Python's own ``CC``), if found."""
    command = os.environ.get("CC") or sysconfig.get_config_var("CC") or ""
    words = shlex.split(command)
    return shutil.which(words[0]) if words else None


def cython_ran() -> bool:
    """Whether Cython was there at build time: the C it writes beside a ``.pyx``, or Cython
    importable here (pip's isolated build installs it for the build alone)."""
    beside = any((REPO / source).with_suffix(".c").exists() for source in SOURCES.values())
    return beside or importlib.util.find_spec("Cython") is not None


def built_here(name: str) -> bool:
    """Whether the module imports, and from this checkout (an editable install's finder
    would otherwise hand over another checkout's build of it)."""
    try:
        module = importlib.import_module(name)
    except ImportError:
        return False
    return REPO.resolve() in Path(module.__file__ or "").resolve().parents


def test_setup_py_builds_the_kernels_the_switches_know():
    # A new .pyx that no switch reads would be built and never run (nor reported).
    assert len(SOURCES) == 4
    assert sorted(compiled_kernels()) == sorted(SOURCES)


def test_every_kernel_is_built_where_a_compiler_and_cython_are_found():
    compiler = c_compiler()
    if compiler is None:
        pytest.skip("no C compiler: the kernels cannot be built here (their references run)")
    if not cython_ran():
        pytest.skip("Cython was not available at build time (no C beside the .pyx files): "
                    "the kernels could not be built")
    missing = [name for name in SOURCES if not built_here(name)]
    assert not missing, (
        f"{compiler} and Cython were found, but these compiled kernels do not import "
        f"from {REPO}: "
        f"{', '.join(missing)}; rebuild them (pip install -e . or python setup.py "
        "build_ext --inplace) and read the compiler's errors")
    # The switches found them too: what runs is what was built.
    assert all(compiled_kernels().values())


def test_the_compiler_is_looked_up_as_setup_py_would(monkeypatch):
    # $CC first, its first word the program (distutils reads it so), found on the PATH.
    monkeypatch.setenv("CC", "no-such-compiler-anywhere -O2")
    assert c_compiler() is None
    monkeypatch.setenv("CC", "sh -c")
    assert c_compiler() == shutil.which("sh")
