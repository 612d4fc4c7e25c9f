"""tegraph: deadlock, period and overrun analysis of synchronized real-time
task sets, through timed event graphs and (max,+) algebra."""

from .errors import InputError, ModelError, NotLiveError, SkeletonError, TegraphError
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
]
