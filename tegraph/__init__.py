"""tegraph: deadlock, period and overrun analysis of synchronized real-time
task sets, through timed event graphs and (max,+) algebra.

The floors (``docs/architecture.md``), lowest first: :mod:`tegraph.errors`,
:mod:`tegraph.model`, :mod:`tegraph.io` and :mod:`tegraph.analysis`,
:mod:`tegraph.design`, :mod:`tegraph.report`, :mod:`tegraph.api` and the
command line. The names below are the ones a design tool needs.
"""

from importlib.metadata import PackageNotFoundError, version

from .analysis.cycle_time import CycleTimeResult
from .analysis.results import Report
from .analysis.sensitivity import duration_margins, sensitivity
from .analysis.sensitivity_results import SensitivityResult
from .api import analyze, cycle_time, to_dot, write
from .design.fix import FixResult, fix_ports
from .design.rules import RuleFinding, check_rules
from .design.timeline import Timeline, simulate_timeline
from .errors import InputError, ModelError, NotLiveError, SkeletonError, TegraphError
from .io import dump_skeleton, load_skeleton, read
from .model.build import build_teg
from .model.petri import PetriNet
from .model.skeleton import Clock, Link, Protocol, Skeleton, Task
from .model.teg import TimedEventGraph
from .report import render_text, to_json

try:
    __version__ = version("tegraph")
except PackageNotFoundError:  # a checkout used without installing it
    __version__ = "0+unknown"

__all__ = [
    # the model
    "Clock",
    "Link",
    "PetriNet",
    "Protocol",
    "Skeleton",
    "Task",
    "TimedEventGraph",
    "build_teg",
    # files
    "dump_skeleton",
    "load_skeleton",
    "read",
    "write",
    # analysis
    "CycleTimeResult",
    "Report",
    "SensitivityResult",
    "analyze",
    "cycle_time",
    "duration_margins",
    "sensitivity",
    # design
    "FixResult",
    "RuleFinding",
    "Timeline",
    "check_rules",
    "fix_ports",
    "simulate_timeline",
    # output
    "render_text",
    "to_dot",
    "to_json",
    # errors
    "InputError",
    "ModelError",
    "NotLiveError",
    "SkeletonError",
    "TegraphError",
]
