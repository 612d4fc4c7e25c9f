"""The design rules of section 6 of the ORCCAD paper, checked on a skeleton, with advice.

The ORCCAD paper [1]_ gives four *sufficient* (not necessary) conditions for
a deadlock-free, temporally consistent, low-latency set of module tasks:

1. one and only one synchronization per task: a clock, or one synchronizing
   port (an input read ASYN/SYN or SYN/SYN, an output posted SYN/ASYN or
   SYN/SYN);
2. cooperating tasks are synchronized with ASYN/SYN and SYN/ASYN links (a
   SYN/SYN rendezvous blocks both sides; tasks of one rate left ASYN/ASYN run
   in whatever order the scheduler picks, Figure 4);
3. one and only one clock per synchronized group;
4. one priority per group, different priorities for different groups on one
   processor, rate-monotonic order [2]_, the Robot-task automaton highest.

A synchronized group is a weakly connected part of the timed event graph
(spec §4 ``groups``): tasks joined by a synchronizing link, a thread or a
shared clock; the groups, their design periods and the links by port are
:class:`tegraph.model.structure.Structure`, computed once per analysis and
passed to every rule. Each finding names the tasks, ports and links concerned and
what to change: for Rules 1-3 a machine-applicable :class:`~.change.Change`,
chosen so that it brings no other finding of Rules 1-3, so that following the
advice never goes round in a circle. The automaton is recognized by its name
(spec §6): ``RTA``, ``automaton``, or a name ending in ``.RTA`` /
``.automaton``, any case.

Modules, and where a change goes
--------------------------------
``findings``
    :class:`RuleFinding` and :class:`FindingKind`: what a finding is and what
    identifies it (kind and key, never the message). A new kind of finding
    starts here: a member of :class:`FindingKind`, its key documented.
``synchronization``
    What a task waits for (its clock, the blocking sides of its links).
``check``
    :func:`check_rules`; Rules 1-3 (what is wrong) and the advice in words.
    A rule's condition or its message changes here.
``priorities``
    Rule 4 and the rate-monotonic proposal, one function per thing decided.
``change``
    :class:`Change`, a machine-applicable edit of a skeleton, and
    :func:`apply_change`. A new kind of edit goes here (and in the advisor's
    candidates).
``freeing``
    :class:`~.freeing.Edits`, a candidate's edits, and the search for the ways
    a task keeps one synchronization only (the first found without the others).
``candidates``
    The candidate edits for a finding of Rules 1-3, best first, by kind.
    A new way to repair a finding goes here.
``regroup``
    :class:`~.regroup.Regrouping`: the groups a candidate's edits leave, re-formed
    on the groups it touches only.
``advice``
    :class:`~.advice.Advisor`: checks each candidate where it can change the
    rules (what it would bring, liveness, the periods it changes) and
    chooses. How a change is judged goes here.
``on_processors``
    :class:`~.on_processors.ScheduleAdvice`: what an advised change does to the
    skeleton on its processors (spec §4b), before -> after, on the part it
    touches, within a stated budget of event firings. Said, never ranked.

The design section of a report (rules, schedulability, latencies together) is
:mod:`tegraph.design.section`, one floor up in the design package: it also
reads the schedulability, which itself reads the proposal of Rule 4 here.

References
----------
.. [1] D. Simon et al., "Design and analysis of synchronization for
   real-time closed-loop control in robotics", IEEE Transactions on Control
   Systems Technology, 1998.
.. [2] C. L. Liu, J. W. Layland, "Scheduling algorithms for
   multiprogramming in a hard-real-time environment", Journal of the ACM
   20(1), 46–61, 1973.
"""

from .change import Change, apply_change
from .check import check_rules
from .findings import FindingKind, RuleFinding
from .priorities import is_automaton, proposed_priorities
from .synchronization import Synchronization, synchronizations

__all__ = [
    "Change",
    "FindingKind",
    "RuleFinding",
    "Synchronization",
    "apply_change",
    "check_rules",
    "is_automaton",
    "proposed_priorities",
    "synchronizations",
]
