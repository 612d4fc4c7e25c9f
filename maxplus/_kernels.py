"""Which kernel runs, and where each kernel changes strategy: the one switch of maxplus.

Every Howard solve of :func:`maxplus.max_cycle_ratio` and every check of
:func:`maxplus.certificate.verify_cycle_ratio` reads its kernel and its
crossovers here, in the style of :mod:`scipy.sparse.csgraph`: the input is
validated once at the edge, then one compiled path runs, with one reference
beside it.

Kernels
-------
``"compiled"``
    Howard's policy iteration in C (:mod:`maxplus._howard_kernel`) and the
    certificate's arc checks in C (:mod:`maxplus._certificate_kernel`), both
    built by ``setup.py`` where a C compiler is found. Where the data leave
    their int64 bounds (numbers of any size are allowed), the numpy kernel
    takes over within the same call; the result is the same.
``"numpy"``
    The reference: the same iteration, step for step, and the same checks, on
    numpy arrays, in int64 below bounds computed from the data and in Python
    ints beyond them.

``"auto"``, the default, runs each compiled module where it is built and the
numpy kernel where it is not; ``"compiled"`` refuses to run without them
(:class:`RuntimeError` naming what is missing), so that a test that asks for
the compiled kernel is never given the reference instead.

The crossovers (:class:`KernelChoice`) decide how the numpy kernel computes
a step, never what it computes: every path gives the same policy, potentials
and iteration count (the sweep's two thresholds also fix the order of its
visits, so the compiled kernel reads them too). The tests force each path on
small graphs with :func:`use`, instead of patching module globals.
"""

from __future__ import annotations

import importlib
from collections.abc import Iterator
from contextlib import contextmanager
from contextvars import ContextVar
from dataclasses import dataclass, replace
from types import ModuleType
from typing import Literal, TypeAlias

__all__ = ["COMPILED", "Kernel", "KernelChoice", "certificate_kernel", "compiled", "current",
           "howard_kernel", "use"]

Kernel: TypeAlias = Literal["auto", "compiled", "numpy"]
"""The kernels :func:`use` accepts (see the module's docstring)."""

KERNELS: tuple[Kernel, ...] = ("auto", "compiled", "numpy")


def _load(name: str) -> ModuleType | None:
    # By importlib: a compiled module has no Python source for the import checks to
    # read, and they read `from . import` as an import of the package, the whole of
    # maxplus (a cycle through the modules that import this one).
    try:
        return importlib.import_module(name)
    except ImportError:  # pragma: no cover - depends on the build
        return None


COMPILED: dict[str, ModuleType | None] = {
    name: _load(name) for name in ("maxplus._howard_kernel", "maxplus._certificate_kernel")}
"""Every compiled module of maxplus (``setup.py`` builds one per ``.pyx``): None where
it is not built. ``_howard_kernel`` runs Howard's iteration, ``_certificate_kernel``
the certificate's arc and policy checks."""

_HOWARD, _CERTIFICATE = COMPILED.values()


def compiled() -> dict[str, bool]:
    """Per compiled module of maxplus, whether it is built (what ``tegraph --version`` says).

    >>> sorted(compiled())
    ['maxplus._certificate_kernel', 'maxplus._howard_kernel']
    """
    return {name: module is not None for name, module in COMPILED.items()}


@dataclass(frozen=True)
class KernelChoice:
    """The kernel and the crossovers between the numpy kernel's strategies.

    Each crossover is a size at which a strategy starts to pay, measured by
    the benchmarks of ``benchmarks/`` (figures in ``benchmarks/results/``). 0
    or a huge value forces one side at every size.
    """

    kernel: Kernel = "auto"

    sweep_few: int = 16
    """Sweep rounds from at most this many nodes are walked in Python (the
    compiled kernel reads it too: it fixes the order of the visits)."""

    scan_min_share: int = 16
    """Sweep rounds from more than one node in this many scan all arcs (read by
    the compiled kernel too)."""

    rows_min_level: int = 4096
    """From this many nodes on, a sweep round gathers their out-arcs by scipy's
    row selection (one C pass, faster than numpy's repeat-and-gather,
    which has less overhead on small rounds)."""

    max_degree_blocks: int = 64
    """Most distinct in-degrees for which the bias step takes its maxima by
    blocks of equal in-degree (by ``np.maximum.reduceat`` beyond)."""

    python_max_circuit_nodes: int = 256
    """Up to this many circuit nodes, policy circuits are walked in Python:
    pointer jumping costs some 40 numpy calls whatever the size."""

    walk_min_circuit_nodes: int = 2048
    """Above this many circuit nodes, circuits are walked in C (scipy's graph
    traversals and a cumulative sum) rather than by pointer jumping, whose
    ``log2`` rounds of several passes cost more on long circuits."""

    intp_max_arcs: int = 2**21
    """Up to this many arcs and nodes the numpy kernel's index arrays are
    ``intp``, above it int32 (int64 past 2**31): numpy converts an int32 index
    array to ``intp`` before each gather, and int32 halves the index arrays'
    memory where it counts (at 10^6 nodes)."""

    walk_in_python: int = 4096
    """Steps of a policy walk taken in Python (where the compiled walk does not
    run) before a depth-first search in C of the policy graph takes over."""

    scipy_coo_tocsr: bool = True
    """The counting sort by scipy's private COO to CSR routine (without the
    sparse array's checks and copies) where scipy has it; else by its public
    sparse conversion."""

    dense_lists_max_nodes: int = 16
    """Up to this many nodes the dense Howard (:mod:`maxplus._dense_howard`)
    runs on Python lists, faster than numpy there."""


DEFAULT = KernelChoice()
"""The choice outside every :func:`use`."""

_CHOICE: ContextVar[KernelChoice] = ContextVar("maxplus_kernel_choice")


def current() -> KernelChoice:
    """The kernel and crossovers in force (the defaults, or those of the innermost :func:`use`).

    >>> current().kernel
    'auto'
    """
    return _CHOICE.get(DEFAULT)


@contextmanager
def use(kernel: Kernel | None = None, **crossovers: int | bool) -> Iterator[KernelChoice]:
    """Run the block on ``kernel`` and the given crossovers (the others stay as they are).

    The choice holds in this thread and context (a :class:`contextvars.ContextVar`):
    work handed to other threads or processes runs on the defaults.

    Parameters
    ----------
    kernel : {"auto", "compiled", "numpy"}, optional
        The kernel; unchanged when omitted.
    **crossovers
        Fields of :class:`KernelChoice` to change.

    Raises
    ------
    ValueError
        An unknown kernel or field.
    RuntimeError
        ``kernel="compiled"`` where a compiled module is not built.

    Examples
    --------
    >>> from maxplus import max_cycle_ratio
    >>> with use("numpy", sweep_few=0):
    ...     max_cycle_ratio([0, 1, 1], [1, 0, 1], [5, 3, 3]).ratio
    Fraction(4, 1)
    """
    changes: dict[str, object] = dict(crossovers)
    if kernel is not None:
        if kernel not in KERNELS:
            raise ValueError(f"unknown kernel {kernel!r}; expected one of {', '.join(KERNELS)}")
        if kernel == "compiled":
            missing = [name for name, built in compiled().items() if not built]
            if missing:
                raise RuntimeError(f"the compiled kernel is not built ({', '.join(missing)} "
                                   "missing): python setup.py build_ext --inplace")
        changes["kernel"] = kernel
    try:
        choice = replace(current(), **changes)  # type: ignore[arg-type]
    except TypeError as e:
        raise ValueError(f"unknown crossover in {sorted(crossovers)}: {e}") from None
    token = _CHOICE.set(choice)
    try:
        yield choice
    finally:
        _CHOICE.reset(token)


def howard_kernel() -> ModuleType | None:
    """The compiled Howard kernel where it is built and the choice lets it run, else None."""
    return None if _CHOICE.get(DEFAULT).kernel == "numpy" else _HOWARD


def certificate_kernel() -> ModuleType | None:
    """The compiled certificate checks where they are built and the choice lets them run."""
    return None if _CHOICE.get(DEFAULT).kernel == "numpy" else _CERTIFICATE
