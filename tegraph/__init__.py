"""tegraph: deadlock, period and overrun analysis of synchronized real-time
task sets, through timed event graphs and (max,+) algebra.

The floors (``docs/architecture.md``), lowest first: :mod:`tegraph.errors`,
:mod:`tegraph.model`, :mod:`tegraph.io` and :mod:`tegraph.analysis`,
:mod:`tegraph.design`, :mod:`tegraph.report`, :mod:`tegraph.api` and the
command line. The names below are the ones a design tool needs; each is
imported on first use, so that ``import tegraph`` (and every command of the
command line) loads only what it uses.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

# name -> module that defines it
_WHERE = {
    # the model
    "Clock": "tegraph.model.skeleton",
    "Link": "tegraph.model.skeleton",
    "PetriNet": "tegraph.model.petri",
    "Protocol": "tegraph.model.skeleton",
    "Skeleton": "tegraph.model.skeleton",
    "Task": "tegraph.model.skeleton",
    "TimedEventGraph": "tegraph.model.teg",
    "build_teg": "tegraph.model.build",
    # files
    "dump_skeleton": "tegraph.io",
    "load_skeleton": "tegraph.io",
    "read": "tegraph.io",
    "write": "tegraph.api",
    # analysis
    "CycleTimeResult": "tegraph.analysis.cycle_time",
    "Report": "tegraph.analysis.results",
    "analyze": "tegraph.api",
    "cycle_time": "tegraph.api",
    "explore": "tegraph.api",
    "reach": "tegraph.api",
    "rules": "tegraph.api",
    "SensitivityResult": "tegraph.analysis.sensitivity.results",
    "duration_margins": "tegraph.analysis.sensitivity",
    "sensitivity": "tegraph.analysis.sensitivity",
    # design
    "FixResult": "tegraph.analysis.repair",
    "RuleFinding": "tegraph.design.rules",
    "Timeline": "tegraph.design.timeline",
    "check_rules": "tegraph.design.rules",
    "fix_ports": "tegraph.analysis.repair",
    "simulate_timeline": "tegraph.design.timeline",
    # output
    "render_text": "tegraph.report",
    "to_dot": "tegraph.api",
    "to_json": "tegraph.report",
    # errors
    "InputError": "tegraph.errors",
    "ModelError": "tegraph.errors",
    "NotLiveError": "tegraph.errors",
    "SkeletonError": "tegraph.errors",
    "TegraphError": "tegraph.errors",
}

__all__ = list(_WHERE)


def _version() -> str:
    # importlib.metadata and the look-up of the installed distribution are paid when
    # the version is asked for, not by every command at start-up.
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("tegraph")
    except PackageNotFoundError:  # a checkout used without installing it
        return "0+unknown"


def __getattr__(name: str) -> Any:
    if name == "__version__":
        value: Any = _version()
        globals()[name] = value
        return value
    if name in _WHERE:
        value = getattr(importlib.import_module(_WHERE[name]), name)
        globals()[name] = value  # later lookups skip this function
        return value
    raise AttributeError(f"module 'tegraph' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted({*globals(), *_WHERE, "__version__"})


if TYPE_CHECKING:  # static tools see the names where they are defined
    from .analysis.cycle_time import CycleTimeResult
    from .analysis.repair import FixResult, fix_ports
    from .analysis.results import Report
    from .analysis.sensitivity import duration_margins, sensitivity
    from .analysis.sensitivity.results import SensitivityResult
    from .api import analyze, cycle_time, explore, reach, rules, to_dot, write
    from .design.rules import RuleFinding, check_rules
    from .design.timeline import Timeline, simulate_timeline
    from .errors import InputError, ModelError, NotLiveError, SkeletonError, TegraphError
    from .io import dump_skeleton, load_skeleton, read
    from .model.build import build_teg
    from .model.petri import PetriNet
    from .model.skeleton import Clock, Link, Protocol, Skeleton, Task
    from .model.teg import TimedEventGraph
    from .report import render_text, to_json
