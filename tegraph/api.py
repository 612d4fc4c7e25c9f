"""The few calls that cross floors: analyze with its design section, cycle time of a file,
the state-space baselines of any model, writing a drawing coloured by the analysis, and
the exploration of designs with its results file.

Everything below this module keeps to its floor (``docs/architecture.md``):
the analysis does not read files, the readers do not analyze, the report
renders what it is given. These functions put them together for a user of
the library, as the command line does.
"""

from __future__ import annotations

import os
import time
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

from maxplus.errors import MaxPlusError

from . import io
from .analysis.analyze import analyze_skeleton
from .analysis.results import Report
from .design.placement import shared_processor_candidates
from .design.section import DesignSection, design_section
from .errors import InputError, TegraphError
from .model.budgets import (
    DEFAULT_MAX_BYTES,
    DEFAULT_MAX_FIRINGS,
    DEFAULT_MAX_MEMORY,
    DEFAULT_MAX_STATES,
    MAX_EVENTS,
)
from .model.skeleton import Skeleton

if TYPE_CHECKING:  # imported when called: `analyze` need not load them
    from .analysis.cycle_time import CycleTimeResult
    from .design.explore import Exploration

__all__ = ["analyze", "compiled_kernels", "cycle_time", "explore", "reach", "rules", "to_dot",
           "write"]

#: Above this many tasks ``analyze`` leaves the duration margins to ``sensitivity``:
#: measured (benchmarks/results/sensitivity.md), they cost about as much as the
#: analysis itself on generated skeletons, and more than it as they grow.
MARGINS_MAX_TASKS = 2_000


def analyze(skeleton: Skeleton | str | os.PathLike[str], max_steps: int = 100_000,
            semiflow_budget: int = 2000,
            semiflow_max_places: int = 2_000_000, chains: Sequence[Sequence[str]] = (),
            design: bool = True, margins_max_tasks: int = MARGINS_MAX_TASKS,
            processors: bool = True, max_events: int = MAX_EVENTS) -> Report:
    """Analyze a synchronization skeleton: deadlocks, periods, overruns, slack, design.

    Parameters
    ----------
    skeleton : Skeleton or path
        From :func:`tegraph.load_skeleton` or built in code; a path (``str`` or
        ``os.PathLike``) is read with :func:`tegraph.load_skeleton` first.
    max_steps : int
        Budget on the firing index of the dater simulation; only reached for
        overruns that cannot be decided otherwise (the report says so).
    semiflow_budget : int
        Largest number of candidate rows of one p-semiflow enumeration (a batch
        of strongly connected components of a few hundred places).
    semiflow_max_places : int
        Above this many places in all, the semiflow cross-check is skipped
        (the report says so).
    chains : sequence of task-name sequences
        Sensor-to-actuator chains whose latency to report, besides the
        skeleton's own ``chains``.
    design : bool
        Add the design section (rules 1-4, schedulability, latencies); it
        never changes the exit status of spec §5.
    margins_max_tasks : int
        Up to this many tasks, each task's ``duration_margin`` (how much its
        duration may grow, its group staying consistent:
        :func:`~tegraph.analysis.sensitivity.margins.duration_margins`) is
        computed; above it, ``methods["duration_margins"]`` says it was not
        (it costs about one more analysis; ``tegraph.sensitivity`` computes them).
    processors : bool
        Decide the skeleton on its processors (``docs/skeleton.md`` §4b:
        preemptive fixed priorities, declared or rate-monotonic), which the
        verdict and :attr:`Report.exit_status` include; False: every task on a
        processor of its own, the v1.1 verdict.
    max_events : int
        Budget of event firings of the schedule on processors; past it,
        ``report.schedulable`` is None and ``report.schedule.why_undecided`` says why.

    Returns
    -------
    Report
        :func:`tegraph.report.to_json` gives the JSON of ``docs/skeleton.md`` §5,
        :func:`tegraph.report.render_text` the human report.

    Raises
    ------
    SkeletonError
        A chain of ``chains`` names an unknown task, a task twice, or two
        consecutive tasks with no link between them.
    InputError
        ``skeleton`` is a path whose file is refused (it names the file and key path).
    TypeError
        ``skeleton`` is neither a :class:`Skeleton` nor a path.

    See Also
    --------
    tegraph.analysis.analyze.analyze_skeleton : the figures of spec §4 alone.
    cycle_time : the period of any timed event graph or file.
    tegraph.check_rules : the design rules alone.

    Notes
    -----
    Liveness is decided by Commoner's theorem [1]_, [2]_ (no token-free
    circuit), the periods are the (max,+) cycle times [3]_, the design
    section follows section 6 of the ORCCAD paper [4]_ with Joseph-Pandya
    response times [5]_.

    References
    ----------
    .. [1] F. Commoner, A. W. Holt, S. Even, A. Pnueli, "Marked directed
       graphs", Journal of Computer and System Sciences 5(5), 511–523, 1971.
    .. [2] T. Murata, "Petri nets: properties, analysis and applications",
       Proceedings of the IEEE 77(4), 541–580, 1989.
    .. [3] F. Baccelli, G. Cohen, G. J. Olsder, J.-P. Quadrat, *Synchronization
       and Linearity*, Wiley, 1992.
    .. [4] D. Simon et al., "Design and analysis of synchronization for
       real-time closed-loop control in robotics", IEEE Transactions on Control
       Systems Technology, 1998.
    .. [5] M. Joseph, P. Pandya, "Finding response times in a real-time
       system", The Computer Journal 29(5), 390–395, 1986.

    Examples
    --------
    A task of duration 2 on a clock of period 10:

    >>> sk = Skeleton.from_dict({"tasks": {"A": {"duration": 2, "period": 10}}})
    >>> r = analyze(sk)
    >>> r.live, r.consistent, r.tasks["A"].period, r.tasks["A"].slack
    (True, True, Fraction(10, 1), Fraction(8, 1))
    """
    skeleton = _skeleton(skeleton)
    report = analyze_skeleton(skeleton, max_steps, semiflow_budget, semiflow_max_places,
                              processors=processors, max_events=max_events, chains=chains)
    _add_duration_margins(skeleton, report, margins_max_tasks)
    if design:
        report.design = design_section(skeleton, report, chains)
    return report


def rules(skeleton: Skeleton | str | os.PathLike[str], chains: Sequence[Sequence[str]] = (),
          processors: bool = True, max_events: int = MAX_EVENTS) -> DesignSection:
    """The design rules of ORCCAD §6, schedulability and chain latencies (``tegraph rules``).

    Parameters
    ----------
    skeleton : Skeleton or path
        From :func:`tegraph.load_skeleton` or built in code; a path is read first.
    chains : sequence of task-name sequences
        Sensor-to-actuator chains whose latency to report, besides the
        skeleton's own ``chains``.
    processors : bool
        Decide the skeleton on its processors (spec §4b), as :func:`analyze` does:
        the verdict, and what each advised change does there; False: every task on
        a processor of its own (the verdict of spec §4).
    max_events : int
        Budget of event firings of the schedule on processors, as for :func:`analyze`.

    Returns
    -------
    DesignSection
        Its ``schedulable`` is :func:`analyze`'s verdict and its ``exit_status`` the
        command's (that verdict, and the rules); :func:`tegraph.report.to_json`
        gives its JSON document, :func:`tegraph.report.render_text` its text.

    Raises
    ------
    SkeletonError
        A chain of ``chains`` names an unknown task, a task twice, or two
        consecutive tasks with no link between them.
    InputError
        ``skeleton`` is a path whose file is refused (it names the file and key path).
    TypeError
        ``skeleton`` is neither a :class:`Skeleton` nor a path.

    See Also
    --------
    analyze : the same section inside the whole analysis.
    tegraph.check_rules : the rules alone.

    Examples
    --------
    >>> sk = Skeleton.from_dict({"tasks": {"A": {"duration": 2, "period": 10}}})
    >>> section = rules(sk)
    >>> [(f.rule, f.severity) for f in section.rules], section.exit_status
    ([(4, 'info')], 0)
    """
    skeleton = _skeleton(skeleton)
    # The semiflow cross-check of liveness is not reported by the rules: skipped. The
    # chains' figures are analyze's, on the same schedule with the same budget.
    report = analyze_skeleton(skeleton, chains=chains, semiflow_max_places=0,
                              processors=processors, max_events=max_events)
    section = design_section(skeleton, report, chains, processors=processors)
    section.never_together = shared_processor_candidates(skeleton, report, max_events)
    return section


def compiled_kernels() -> dict[str, bool]:
    """Per compiled kernel (an extension module ``setup.py`` builds), whether it is built here.

    Each one is optional: where it was not built (no C compiler, no Cython, or
    it failed to compile), its reference runs instead, with the same results,
    slower (the numpy Howard kernel and certificate checks, the Python loop of
    the schedule on processors). ``tegraph --version`` prints this.

    Returns
    -------
    dict of str to bool
        The module names, ``maxplus``'s first, the schedule engine's after.

    See Also
    --------
    maxplus.max_cycle_ratio : runs Howard's kernel.

    Examples
    --------
    >>> list(compiled_kernels())[:2]
    ['maxplus._howard_kernel', 'maxplus._certificate_kernel']
    """
    from maxplus import _kernels

    from .analysis.processors import _loops

    return {**_kernels.compiled(), **_loops.compiled()}


def _skeleton(skeleton: Any) -> Skeleton:
    """``skeleton`` itself, or the skeleton its path names."""
    if isinstance(skeleton, (str, os.PathLike)):
        return io.load_skeleton(skeleton)
    if not isinstance(skeleton, Skeleton):
        raise TypeError(f"skeleton: expected a Skeleton (tegraph.load_skeleton reads one from "
                        f"a file) or a path, got {type(skeleton).__name__}")
    return skeleton


def _add_duration_margins(skeleton: Skeleton, report: Report, max_tasks: int) -> None:
    """Fill each task's ``duration_margin`` and ``duration_margin_state``; say how."""
    n = len(skeleton.tasks)
    if n > max_tasks:
        report.methods["duration_margins"] = (
            f"not computed: {n:,} tasks, more than {max_tasks:,} (they would cost about as "
            "much as the analysis again); the sensitivity analysis computes them")
        return
    # Imported here: above max_tasks (the 10,000-task files) the module is not used.
    from .analysis.sensitivity.margins import duration_margins

    margins = duration_margins(skeleton, report)
    for name, task in report.tasks.items():
        if name not in margins:
            task.duration_margin_state = "not consistent"
        elif margins[name] is None:
            task.duration_margin_state = "unbounded"
        else:
            task.duration_margin, task.duration_margin_state = margins[name], "exact"
    report.methods["duration_margins"] = (
        "how much each duration may grow alone, its group staying consistent (no "
        "overrun, every place bounded): the slack bound and longest paths to each "
        "activation's end at the nominal point in clocked groups, an exact line search "
        "otherwise")


def _check_state_budget(max_states: Any) -> None:
    """Refuse a budget of states that is no integer >= 1, naming ``max_states``.

    A search of no state decides nothing: refused, like a memory budget of 0 bytes.
    """
    if isinstance(max_states, bool) or not isinstance(max_states, int) or max_states < 1:
        raise InputError(f"expected an integer >= 1, got {max_states!r}", "max_states")


def cycle_time(source: Any, *, format: str | None = None, verify: bool = True,
               default_holding: Any = None, max_bytes: int | None = None,
               max_states: int = DEFAULT_MAX_STATES, max_seconds: float | None = None,
               max_memory: int = DEFAULT_MAX_MEMORY,
               max_firings: int = DEFAULT_MAX_FIRINGS) -> CycleTimeResult:
    """Period, throughput, critical circuit and cycle times of a timed event graph or its file.

    Parameters
    ----------
    source : path or model
        A file (read by :func:`tegraph.io.read`), or a Skeleton, TimedEventGraph,
        PetriNet, SDFGraph or ArcList.
    format : str, optional
        Force the format of a file (see :data:`tegraph.io.FORMATS`).
    verify : bool
        Check the exact certificate of the result (default True).
    default_holding : int, Fraction or str, optional
        Holding time of every place of a net that carries no timing at all
        (a plain PNML P/T net); default 0.
    max_bytes : int, optional
        Size limit when ``source`` is a path.
    max_states, max_seconds, max_memory : int, float, int, optional
        Budgets of the reachability exploration run on a P/T net that is not
        a marked graph (beyond them its deadlock verdict is inconclusive);
        ``max_states`` is checked (an integer >= 1) even when no search runs.
    max_firings : int
        Largest homogeneous expansion of an SDF graph (firings per iteration).

    Returns
    -------
    CycleTimeResult
        Period, throughput, critical circuit and cycle times, or the
        token-free circuit of a deadlock; ``source`` is the file read.

    Raises
    ------
    InputError
        The file or model is refused, or ``max_states`` is below 1.

    See Also
    --------
    tegraph.analysis.cycle_time.cycle_time : the same on a model.
    maxplus.max_cycle_ratio : the exact kernel.
    analyze : the full report of a skeleton.

    Notes
    -----
    The period is the maximum cycle ratio [1]_, computed by Howard's policy
    iteration [2]_ in exact arithmetic and certified; a token-free circuit is
    a deadlock by Commoner's theorem [3]_.

    References
    ----------
    .. [1] F. Baccelli, G. Cohen, G. J. Olsder, J.-P. Quadrat, *Synchronization
       and Linearity*, Wiley, 1992.
    .. [2] J. Cochet-Terrasson, G. Cohen, S. Gaubert, M. Mc Gettrick,
       J.-P. Quadrat, "Numerical computation of spectral elements in max-plus
       algebra", IFAC Conference on System Structure and Control, 1998.
    .. [3] F. Commoner, A. W. Holt, S. Even, A. Pnueli, "Marked directed
       graphs", Journal of Computer and System Sciences 5(5), 511–523, 1971.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> f = pathlib.Path(tempfile.mkdtemp()) / "ring.edges"
    >>> _ = f.write_text("0 1 2 0\\n1 0 3 1\\n")
    >>> r = cycle_time(f)
    >>> str(r.period), r.critical_circuit, r.source == str(f)
    ('5', ['0', '1'], True)
    """
    _check_state_budget(max_states)  # even for a model whose cycle time runs no search
    read_seconds = None
    path = None
    if isinstance(source, (str, os.PathLike)):
        path = os.fspath(source)
        t0 = time.perf_counter()
        limit = DEFAULT_MAX_BYTES if max_bytes is None else max_bytes  # 0 is no "default"
        source = io.read(path, format, max_bytes=limit)
        read_seconds = time.perf_counter() - t0
    from .analysis.cycle_time import cycle_time as cycle_time_of

    result = cycle_time_of(source, verify=verify, default_holding=default_holding,
                           max_states=max_states, max_seconds=max_seconds,
                           max_memory=max_memory, max_firings=max_firings)
    result.source = path
    if read_seconds is not None:
        result.seconds = {"read": read_seconds, **result.seconds}
    return result


def reach(model: Any, *, timed: bool = False, max_states: int = DEFAULT_MAX_STATES,
          max_seconds: float | None = None, max_memory: int = DEFAULT_MAX_MEMORY,
          max_firings: int = DEFAULT_MAX_FIRINGS, progress: Any = None,
          stop: Any = None) -> Any:
    """The state-space baseline of a model: the ORCCAD searches (spec §4, ORCCAD §5).

    A skeleton is explored group by group (its timed event graph, places bounded
    to m + 1 tokens), or, with ``timed``, by the timed exploration; any other
    model (a timed event graph, a P/T net, an SDF graph expanded to its
    homogeneous graph) by the reachability graph of its P/T net.

    Parameters
    ----------
    model : Skeleton, TimedEventGraph, PetriNet or SDFGraph
        What :func:`tegraph.io.read` or :func:`tegraph.io.load_skeleton` gives.
    timed : bool
        The timed exploration (skeletons only).
    max_states, max_seconds, max_memory : int, float, int, optional
        Budgets; beyond one the answer is inconclusive (``max_memory``: bytes of
        stored markings, untimed searches only).
    max_firings : int
        Largest homogeneous expansion of an SDF graph (firings per iteration).
    progress, stop : callable, optional
        ``progress(states, other, seconds)`` every batch; ``stop()`` true ends
        the search (its counts are then partial).

    Returns
    -------
    Reachability or TimedExploration

    Raises
    ------
    InputError
        ``timed`` for a model that is not a skeleton; ``max_states`` not an
        integer >= 1.
    TegraphError
        A model that has no P/T net within ``max_firings``.

    See Also
    --------
    tegraph.analysis.baselines.reachability.reachability_graph : the untimed search of a net.
    tegraph.analysis.baselines.timed_reachability.timed_reachability : the timed search.
    analyze : the (max,+) answers the baselines are compared with.

    Examples
    --------
    >>> sk = Skeleton.from_dict({"tasks": {"A": {"duration": 1, "period": 2}}})
    >>> reach(sk).deadlock, reach(sk, timed=True).exit_status
    (False, 0)
    """
    from .analysis.baselines.reachability import reachability_graph, skeleton_reachability
    from .analysis.baselines.timed_reachability import timed_reachability
    from .model.build import build_teg
    from .model.convert import as_petri_net

    _check_state_budget(max_states)
    budgets = {"max_states": max_states, "max_seconds": max_seconds, "progress": progress,
               "stop": stop}
    if timed:
        if not isinstance(model, Skeleton):
            raise InputError("the timed exploration needs a skeleton (tasks, clocks, "
                             f"durations), not a {type(model).__name__}", "timed")
        return timed_reachability(model, **budgets)
    if isinstance(model, Skeleton):
        return skeleton_reachability(build_teg(model), **budgets, max_memory=max_memory)
    return reachability_graph(as_petri_net(model, max_firings), **budgets,
                              max_memory=max_memory)


def write(obj: Any, path: str | os.PathLike[str], format: str | None = None,
          overwrite: bool = False) -> Path:
    """Write a model to a file; a DOT drawing colours the critical or token-free circuit.

    Parameters
    ----------
    obj : Skeleton, TimedEventGraph, PetriNet, SDFGraph or ArcList
        The model to write.
    path : str or path-like
        The file.
    format : str, optional
        A name of :data:`tegraph.io.FORMATS`; default from the extension.
    overwrite : bool
        Replace an existing file; without it an existing file is never touched.

    Returns
    -------
    pathlib.Path
        The file written.

    Raises
    ------
    InputError
        The target cannot hold the content, or the extension names no format.
    FileExistsError
        ``path`` exists and ``overwrite`` is False.

    See Also
    --------
    tegraph.io.write : the same without the analysis (a DOT drawing is then plain).
    to_dot : the coloured DOT text without a file.
    tegraph.read : the converse.

    Examples
    --------
    >>> import os, tempfile
    >>> sk = Skeleton.from_dict({"tasks": {"A": {"duration": 2, "period": 10}}})
    >>> p = write(sk, os.path.join(tempfile.mkdtemp(), "a.dot"))
    >>> p.read_text().splitlines()[1]
    '  label="skeleton: period 10 (critical circuit in red)"; rankdir=LR;'
    """
    fmt = format or io.format_for_writing(obj, os.fspath(path))
    marks = None
    record = io.FORMATS.get(fmt)
    if record is not None and record.draws:
        from .report.dot import highlights  # a drawing's colours: only drawings need them

        marks = highlights(_figures_for_drawing(obj))
    return io.write(obj, path, fmt, overwrite, highlights=marks)


def to_dot(obj: Any, view: str | None = None) -> str:
    """DOT text of a model, its critical circuit red and bold, a token-free circuit dashed.

    Parameters
    ----------
    obj : Skeleton, TimedEventGraph, PetriNet, SDFGraph or ArcList
        The model to draw.
    view : {"skeleton", "teg", "net"}, optional
        Default: ``skeleton`` for a Skeleton, ``net`` for a P/T net, ``teg`` otherwise.

    Returns
    -------
    str
        A Graphviz ``digraph``; its caption gives the period when there is one.

    Raises
    ------
    InputError
        ``obj`` is not a model this project reads.

    See Also
    --------
    tegraph.io.dot.dot_text : the drawing alone, coloured as told.
    write : the same to a file.
    cycle_time : the figures the colours come from.

    Examples
    --------
    >>> from tegraph.model.teg import TimedEventGraph
    >>> g = TimedEventGraph("ring"); _ = g.add_transition("a"); _ = g.add_transition("b")
    >>> _ = g.add_place("a", "b", 0, 2); _ = g.add_place("b", "a", 1, 3)
    >>> to_dot(g).splitlines()[1]
    '  label="ring: period 5 (critical circuit in red)"; rankdir=LR;'
    """
    from .io.dot import dot_text
    from .report.dot import highlights

    return dot_text(obj, view, highlights(_figures_for_drawing(obj)))


def _figures_for_drawing(obj: Any) -> CycleTimeResult | None:
    """The cycle time of what a drawing shows; None when it cannot be had (never a failure)."""
    from .analysis.cycle_time import cycle_time as cycle_time_of

    try:
        # No reachability search for a drawing: a net that is not a marked
        # graph gets its reason as a caption, nothing more.
        return cycle_time_of(obj, verify=False, max_states=0)
    except (TegraphError, MaxPlusError):
        return None


def explore(skeleton: Skeleton, links: Any = (), *, all_links: bool = False,
            clocks: Mapping[str, Sequence[Any]] | Sequence[Any] | None = None,
            chains: Sequence[Sequence[str]] = (), objectives: Sequence[str] | None = None,
            scheduler: str | None = None, workers: int | None = None,
            output: str | os.PathLike[str] | None = None, resume: bool = False,
            overwrite: bool = False, max_variants: int = 10_000,
            batch_size: int | None = None, progress: Any = None,
            timeout: float | str = 10.0, requires: Sequence[Any] = (),
            max_latency: Sequence[Any] = (), forbid: Sequence[Any] = (),
            max_events: int = MAX_EVENTS, free_running: bool = False,
            offer: Sequence[str] | str | None = None, allocate: str = "groups",
            pin: Sequence[Any] = ()) -> Exploration:
    """Search protocol and clock choices for the best live, consistent, schedulable designs.

    Each variant (one protocol per chosen link, one period per chosen clock) is
    analyzed exactly, repaired by reordering its ports when only the order
    deadlocks, and kept when live, consistent and schedulable; the result is the
    Pareto front of the objectives (chain latencies on processors, period, processor load),
    exhaustive up to ``max_variants`` variants, by Pareto local search beyond.

    Parameters
    ----------
    skeleton : Skeleton
        The design to vary.
    links : mapping of str to protocols, or sequence of str
        ``{"W:p -> R:q": ["ASYN/SYN", "SYN/SYN"]}``; None or a bare name: all four.
    all_links : bool
        Choose every link, with all four protocols.
    clocks : mapping of str to sequence of times, or sequence of pairs or texts
        ``{"rtc": [5, 10, 20]}``, or ``["rtc=5,10,20"]`` as the command line gives them
        (a clock named twice is refused); a task's own clock is ``"TASK.clock"``.
    chains : sequence of task-name sequences
        Chains whose latency is an objective, besides the skeleton's ``chains``.
    objectives : sequence of str, optional
        Among ``latency`` (each chain's first use on processors, spec §4c), ``age``,
        ``reaction``, ``period``, ``load``, ``utilization`` (default: ``latency`` when
        there is a chain, ``period``, ``load``, ``utilization`` on several processors).
    scheduler : str, optional
        Address of a running Dask scheduler, ``tcp://HOST:8786``.
    workers : int, optional
        0: this process; N: a local Dask cluster of N processes; None: decided
        from the measured cost.
    output : path, optional
        Results file (``.csv``, or ``.parquet`` with the ``[parquet]`` extra), one
        row per judged variant, appended as verdicts arrive.
    resume : bool
        Continue ``output``: its variants are not judged again.
    overwrite : bool
        Start ``output`` anew when it exists.
    max_variants : int
        Threshold of the exhaustive search, and budget of the local search.
    batch_size : int, optional
        Variants per batch (default adaptive).
    progress : callable, optional
        Called with a :class:`tegraph.design.explore.run.Progress` after each batch.
    timeout : float, Fraction or str
        Seconds to wait for the scheduler (> 0, at most a day), read exactly as
        every number is (``"5/2"``; ``"1e999999999"`` refused by its size).
    requires : sequence
        ``"TASK.period=P"`` or ``"TASK.period<=P"``: kept designs run the task at
        that period.
    max_latency : sequence
        ``"A,B,C=L"``: kept designs have the chain's first use on processors (exact)
        at most L.
    forbid : sequence of protocols
        Protocols no link may use (taken out of the choices).
    max_events : int
        Budget of event firings of each variant's schedule on processors (spec
        §4b); a variant undecided within it is rejected as undecided.
    free_running : bool
        Keep designs where a task runs free (no clock in its group) that the input
        design runs on a clock; by default they are not kept.
    offer : sequence of str, or a comma-separated str, optional
        Processors to put the tasks on: where each group (or task) runs becomes a
        choice (:mod:`tegraph.design.explore.allocation`).
    allocate : str
        ``groups`` (whole groups of spec §4 move together, the default) or ``tasks``.
    pin : sequence
        ``"TASK=PROCESSOR"`` texts: that task (its group, under ``groups``) stays there.

    Returns
    -------
    Exploration
        :func:`tegraph.report.explore_text.render_exploration` gives its text,
        :func:`tegraph.report.to_json` its JSON document.

    Raises
    ------
    InputError
        An unknown link, task, clock or protocol, an empty choice, a results file
        that exists (without ``resume`` or ``overwrite``) or in a directory that
        does not exist, a scheduler that does not answer.

    See Also
    --------
    tegraph.design.explore.explore_design : the search on a design space.
    analyze : the analysis of one variant.
    tegraph.fix_ports : the port reordering applied to a deadlocked variant.

    Notes
    -----
    This automates the synthesis of section 6 of the ORCCAD paper [1]_: a
    variant is live when it has no token-free circuit [2]_, schedulable when the
    exact preemptive fixed-priority schedule on its processors (spec §4b) says so
    (Joseph-Pandya response times [3]_ only as a cross-check).

    References
    ----------
    .. [1] D. Simon et al., "Design and analysis of synchronization for
       real-time closed-loop control in robotics", IEEE Transactions on Control
       Systems Technology, 1998.
    .. [2] F. Commoner, A. W. Holt, S. Even, A. Pnueli, "Marked directed
       graphs", Journal of Computer and System Sciences 5(5), 511–523, 1971.
    .. [3] M. Joseph, P. Pandya, "Finding response times in a real-time
       system", The Computer Journal 29(5), 390–395, 1986.

    Examples
    --------
    >>> sk = Skeleton.from_dict({"clocks": {"rtc": {"period": 10}}, "tasks": {
    ...     "A": {"duration": 1, "clock": "rtc", "inputs": ["s"], "outputs": ["x"]},
    ...     "B": {"duration": 2, "inputs": ["x"], "outputs": ["u"]}},
    ...     "links": [{"from": "A:x", "to": "B:x", "protocol": "ASYN/ASYN"}]})
    >>> found = explore(sk, ["A:x -> B:x"], chains=[["A", "B"]], workers=0)
    >>> [(f["links"]["A:x -> B:x"], f["objectives"]["latency:A,B"]) for f in
    ...  (found.entry(r) for r in found.front)]
    [('ASYN/SYN', '3')]

    SYN/SYN ties with ASYN/SYN on every objective; the tie goes to the design with
    fewer Rule 2 findings (a SYN/SYN rendezvous is one).
    """
    from .design.explore import explore_design
    from .design.explore.results import ResultsTable
    from .design.explore.space import design_space

    space = design_space(skeleton, links, all_links, clocks, chains, objectives,
                         requires=requires, max_latency=max_latency, forbid=forbid,
                         max_events=max_events, free_running=free_running, offer=offer,
                         allocate=allocate, pin=pin)
    if output is None and resume:
        raise InputError("nothing to resume without an `output` file", "resume")
    table = None if output is None else ResultsTable(output, space, resume, overwrite)
    try:
        found = explore_design(space, scheduler=scheduler, workers=workers,
                               max_variants=max_variants, batch_size=batch_size,
                               known=None if table is None else table.known,
                               record=None if table is None else table.append,
                               progress=progress, timeout=timeout)
    finally:
        if table is not None:
            table.close()
    found.output = None if output is None else os.fspath(output)
    return found
