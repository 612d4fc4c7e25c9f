"""End-to-end benchmark of ``tegraph analyze --json`` on generated skeletons, A/B.

Skeletons of ``generate_skeleton.py``: groups of 3 to 30 tasks (1,000, 10,000
and 100,000 tasks), and two shapes where all tasks form ONE synchronized
group: an ASYN/SYN chain on one clock (``chain``) and the same chain with a
clock per task (``chain-clocks``). Each run is a fresh process (the time
includes start-up, reading the file and writing the JSON) whose peak resident
memory is measured from inside it. With ``--base`` the runs alternate between
the base checkout (A) and this one (B), so that load from elsewhere on the
machine falls on both alike; the table gives medians with their spread
(min-max), and says whether A and B printed the same bytes.

Usage::

    git worktree add --detach /tmp/perf-base main
    python benchmarks/bench_analyze.py --base /tmp/perf-base [--runs 3]
        [--output benchmarks/results/analyze.md]
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent

CHILD = """
import atexit, resource, sys
from tegraph.cli import main
rss_file = sys.argv.pop(1)
sys.argv = ["tegraph", "analyze", *sys.argv[1:]]


def usage():  # an exit handler: main() ends the process itself once they have run
    use = resource.getrusage(resource.RUSAGE_SELF)
    # ru_maxrss keeps the pages mapped before exec (the benchmark's own, inherited by
    # fork): after the 100,000-task row every child read that row's peak. VmHWM is
    # this program's own high-water mark, reset by exec.
    peak = use.ru_maxrss
    try:
        with open("/proc/self/status") as status:
            peak = next(int(line.split()[1]) for line in status if line.startswith("VmHWM:"))
    except (OSError, StopIteration):
        pass
    with open(rss_file, "w") as fh:
        fh.write(f"{peak} {use.ru_utime + use.ru_stime}")


atexit.register(usage)
main()
"""

CASES = [("groups", 1_000, (), None), ("groups", 10_000, (), None),
         ("groups", 100_000, (), None), ("chain", 10_000, (), None),
         # main's design advice recurses once per clock and fails here (see results):
         # a short timeout, and the analysis alone on the next row.
         ("chain-clocks", 1_000, (), None), ("chain-clocks", 10_000, (), 90.0),
         ("chain-clocks", 10_000, ("--no-design",), None)]


def measure(checkout: Path, path: Path, extra: tuple[str, ...], rss_file: Path,
            timeout: float) -> dict:
    """One fresh process: wall seconds, peak RSS (MiB), exit status, stdout."""
    rss_file.unlink(missing_ok=True)
    start = time.perf_counter()
    try:
        out = subprocess.run([sys.executable, "-c", CHILD, str(rss_file), str(path), "--json",
                              *extra], cwd=checkout, capture_output=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        return {"time": None, "rss": None, "cpu": None, "rc": "timeout", "stdout": b""}
    elapsed = time.perf_counter() - start
    rss, cpu = None, None
    if rss_file.exists():
        kib, seconds = rss_file.read_text().split()
        rss, cpu = int(kib) / 1024, float(seconds)
    # An uncaught exception also exits with 1: no RSS file written means it crashed.
    rc = out.returncode if out.returncode in (0, 1, 2) and rss is not None else "crash"
    return {"time": elapsed, "rss": rss, "cpu": cpu, "rc": rc, "stdout": out.stdout,
            "error": out.stderr.decode(errors="replace").strip().splitlines()[-1:]}


def spread(values: list[float]) -> str:
    if not values:
        return "-"
    return f"{statistics.median(values):.2f} ({min(values):.2f}-{max(values):.2f})"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--base", type=Path, help="checkout of the base (A); B is this one")
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--timeout", type=float, default=600.0,
                        help="seconds per run; a variant that times out is not run again")
    parser.add_argument("--cases", nargs="*", help="e.g. groups:1000 chain:10000")
    parser.add_argument("--output", type=Path, help="write the Markdown table here too")
    args = parser.parse_args()
    cases = CASES
    if args.cases:
        cases = [(c.split(":")[0], int(c.split(":")[1]), tuple(c.split(":")[2:]), None)
                 for c in args.cases]
    variants = ([("A", args.base.resolve())] if args.base else []) + [("B", HERE.parent)]
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for shape, n, extra, limit in cases:
            path = Path(tmp) / f"{shape}-{n}.json"
            if not path.exists():
                # In a child process: a parent that held the 100,000-task document
                # would pass its RSS on through fork (Linux keeps the larger
                # high-water mark across exec), and every later child would report it.
                subprocess.run([sys.executable, str(HERE / "generate_skeleton.py"), str(n),
                                "--shape", shape, "-o", str(path)], check=True)
            results: dict[str, list[dict]] = {name: [] for name, _ in variants}
            for _ in range(args.runs):
                for name, checkout in variants:  # interleaved: A, B, A, B, ...
                    if any(r["rc"] in ("timeout", "crash") for r in results[name]):
                        continue
                    r = measure(checkout, path, extra, Path(tmp) / "rss", limit or args.timeout)
                    results[name].append(r)
                    print(f"{shape} {n} {' '.join(extra)} {name}: {r['time']} s "
                          f"cpu {r['cpu']} s {r['rss']} MiB rc {r['rc']}", file=sys.stderr,
                          flush=True)
            rows.append((shape, n, extra, results))
    lines = table(rows, [name for name, _ in variants], args.runs)
    text = "\n".join(lines) + "\n"
    print(text)
    if args.output:
        args.output.write_text(text)


def table(rows: list, names: list[str], runs: int) -> list[str]:
    head = ["# `tegraph analyze FILE --json`, whole process (fresh process per run)", "",
            f"Machine: {os.cpu_count()} cores, load average {os.getloadavg()[0]:.2f} at the "
            "end (say beside the table what else ran); A and B runs alternate, so any load "
            f"falls on both alike. Median of {runs} runs (min-max), seconds; "
            "CPU is user + system time of the process (less sensitive to the load than wall "
            "time); peak RSS is the largest of the runs; \"crash\": the time to the traceback. "
            "A = the base checkout, B = this one. "
            f"Measured {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}.", ""]
    cols = ["shape", "tasks"]
    for name in names:
        cols += [f"{name} time (s)", f"{name} CPU (s)", f"{name} peak RSS (MiB)",
                 f"{name} exit"]
    if len(names) == 2:
        cols += ["B/A", "same stdout"]
    out = head + ["| " + " | ".join(cols) + " |", "|" + "---|" * len(cols)]
    for shape, n, extra, results in rows:
        cells = [shape + (" " + " ".join(extra) if extra else ""), f"{n:,}"]
        medians = []
        for name in names:
            rs = results[name]
            times = [r["time"] for r in rs if r["time"] is not None]
            rss = [r["rss"] for r in rs if r["rss"] is not None]
            codes = sorted({str(r["rc"]) for r in rs})
            cpus = [r["cpu"] for r in rs if r["cpu"] is not None]
            cells += [spread(times) if rs and rs[-1]["rc"] not in ("timeout",) else "timeout",
                      spread(cpus), f"{max(rss):.0f}" if rss else "-", "/".join(codes)]
            medians.append(statistics.median(times) if times else None)
        if len(names) == 2:
            a, b = medians
            cells.append(f"{b / a:.2f}" if a and b else "-")
            same = {results[nm][0]["stdout"] for nm in names if results[nm]}
            cells.append("yes" if len(same) == 1 else "NO")
        out.append("| " + " | ".join(cells) + " |")
    return out


if __name__ == "__main__":
    main()
