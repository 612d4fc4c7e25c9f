"""The skeleton on its processors (``docs/skeleton.md`` v1.2 §4b).

:func:`platform_of` gives each task its processor and priority (declared, or
the rate-monotonic proposal); :func:`schedule_on_processors` decides the
preemptive fixed-priority schedule exactly (``docs/analysis.md``, *The
schedule on processors*).
"""

from ...model.platform import (
    DEFAULT_PROCESSOR,
    Platform,
    ProcessorInfo,
    is_automaton,
    platform_of,
    processor_of,
    processor_parts,
)
from .schedule import (
    MAX_EVENTS,
    GrowingPlace,
    JobInterval,
    Problem,
    ProcessorSchedule,
    TaskOnProcessors,
    schedule_on_processors,
)

__all__ = ["DEFAULT_PROCESSOR", "MAX_EVENTS", "GrowingPlace", "JobInterval", "Platform",
           "Problem", "ProcessorInfo", "ProcessorSchedule", "TaskOnProcessors", "is_automaton",
           "platform_of", "processor_of", "processor_parts", "schedule_on_processors"]
