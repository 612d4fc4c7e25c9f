"""tegraph: deadlock, period and overrun analysis of synchronized real-time
task sets, through timed event graphs and (max,+) algebra."""

from .errors import InputError, ModelError, NotLiveError, SkeletonError, TegraphError
from .io.skeleton_file import load_skeleton
from .skeleton import Clock, Link, Protocol, Skeleton, Task

__all__ = [
    "TegraphError",
    "InputError",
    "SkeletonError",
    "ModelError",
    "NotLiveError",
    "Skeleton",
    "Task",
    "Clock",
    "Link",
    "Protocol",
    "load_skeleton",
]

from .teg import TimedEventGraph  # noqa: E402
from .build import build_teg  # noqa: E402

__all__ += ["TimedEventGraph", "build_teg"]

from .analysis import analyze  # noqa: E402
from .report import Report  # noqa: E402

__all__ += ["analyze", "Report"]

from .io.formats import read, write  # noqa: E402

__all__ += ["read", "write"]
