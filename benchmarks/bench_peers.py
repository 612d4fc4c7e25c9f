"""maxplus.max_cycle_ratio against the C++ Howard codes, side by side.

Peers: Boost Graph's ``maximum_cycle_ratio`` (Howard's policy iteration, in
``boost/graph/howard_cycle_ratio.hpp``) and LEMON's ``HowardMmc``. Both are
built from ``benchmarks/peers/*.cpp`` with g++ when a compiler and the headers
are there (``apt-get install libboost-graph-dev liblemon-dev``); otherwise they
are skipped with a message. LEMON computes minimum cycle *means* only, so it
runs only on the families whose arcs all carry the same token count.

Every solver reads the same ``.edges`` file in a fresh process; each reports
its solve time (file reading excluded), its Howard iterations, its peak
resident memory and its ratio. The runs are interleaved (A B C A B C ...), so
that a busy machine slows every solver alike; the table gives medians, the
spread (min-max), and maxplus's median time over Boost's ("ratio").

Exactness: maxplus's ratio is exact and certified (``verify()`` is run and
timed in every run). The peers use doubles; Boost's critical cycle and LEMON's
cycle are summed exactly in integers, and the "agrees" column says whether
that exact value equals maxplus's. Their float ratio is compared within
float precision for the column only; no float enters a maxplus verdict.

Other checkouts of maxplus can join the same interleaved run, to measure a
change against its parent: ``--maxplus main=/work/main`` (label=path; a
``@numba`` suffix sets ``MAXPLUS_ENGINE=numba`` for checkouts that still had
that kernel).

Usage::

    python benchmarks/bench_peers.py                 # all families, 5 runs each
    python benchmarks/bench_peers.py --quick         # small smoke run
    python benchmarks/bench_peers.py --families sprand-1e5-s1-canon ring --runs 3
    python benchmarks/bench_peers.py --maxplus before=../main --families ring

SPRAND families come in both layouts of the Hamiltonian cycle, side by side:
``-canon`` is SPRAND's own ``0 -> 1 -> ... -> n-1 -> 0`` and ``-permu`` the
cycle along a random permutation (same random arcs, weights and tokens; see
``sprand.py``). The *layout* column of every row says which one it used.

Writes ``benchmarks/results/peers.table.md`` and ``benchmarks/results/peers.json``
(``--out`` to change; ``--no-write`` to only print); ``peers.md`` is the reading.
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from fractions import Fraction
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
REPO = HERE.parent
PEERS = HERE / "peers"
sys.path.insert(0, str(HERE))

from sprand import LAYOUTS, equal_weights, ring_with_chords, sprand, torus_grid  # noqa: E402


def _sprand_families() -> dict:
    """SPRAND n = 10^4..10^6, seeds 1 and 2, in both layouts of the Hamiltonian cycle."""
    out = {}
    for exp in (4, 5, 6):
        for seed in (1, 2):
            for layout in LAYOUTS:
                out[f"sprand-1e{exp}-s{seed}-{layout[:5]}"] = (
                    lambda exp=exp, seed=seed, layout=layout: sprand(10**exp, seed=seed,
                                                                     layout=layout),
                    f"SPRAND n=10^{exp}, seed {seed}", layout)
    return out


# name -> (generator, description, layout of the Hamiltonian cycle); "canon" is
# SPRAND's own 0 -> 1 -> ... -> n-1 -> 0, "permu" a random permutation (sprand.py).
FAMILIES = {
    **_sprand_families(),
    "ring": (lambda: ring_with_chords(10**5), "ring 10^5 + chords i->i+5", "canonical"),
    "torus": (lambda: torus_grid(316), "torus grid 316x316", "canonical"),
    "equal-canon": (lambda: equal_weights(10**5, layout="canonical"),
                    "SPRAND 10^5, all w=7, t=3", "canonical"),
    "equal-permu": (lambda: equal_weights(10**5), "SPRAND 10^5, all w=7, t=3", "permuted"),
    "sprand-1e5-t1-canon": (lambda: sprand(10**5, max_tokens=1, seed=1, layout="canonical"),
                            "SPRAND n=10^5, tokens 1", "canonical"),
    "sprand-1e5-t1-permu": (lambda: sprand(10**5, max_tokens=1, seed=1),
                            "SPRAND n=10^5, tokens 1", "permuted"),
}
QUICK = ["sprand-1e4-s1-canon", "sprand-1e4-s1-permu", "equal-small", "ring-small"]
SMALL = {
    "equal-small": (lambda: equal_weights(2000), "SPRAND 2000, all w=7, t=3", "permuted"),
    "ring-small": (lambda: ring_with_chords(5000), "ring 5000 + chords", "canonical"),
}


def layout_of(name: str) -> str:
    """The Hamiltonian-cycle layout a family was generated with (ring and torus: node order)."""
    return {**FAMILIES, **SMALL}[name][2]


# --------------------------------------------------------------------------- files


def write_edges(path: Path, graph) -> None:
    """The project's ``.edges`` text: ``# nodes N`` then ``src dst holding tokens`` lines."""
    src, dst, w, t = graph
    n = int(max(src.max(), dst.max())) + 1
    table = np.column_stack([src, dst, w, t]).astype(np.int64)
    with open(path, "w") as f:
        f.write(f"# nodes {n}\n")
        np.savetxt(f, table, fmt="%d")


def read_edges(path: Path):
    """Integer ``.edges`` file -> (src, dst, weight, tokens, n).

    numpy parses the numbers in C straight from the file's bytes: the reader's
    own peak (text plus arrays, about 3x the file) must not pass for the
    solver's. (Splitting the text into a list of Python byte strings first
    peaked at 1.28 GiB on a 10^6-node file, more than any solver.)
    """
    text = Path(path).read_bytes()
    n = None
    start = 0
    while text.startswith(b"#", start):  # "# nodes N" sits in the header
        end = text.index(b"\n", start)
        if text.startswith(b"# nodes", start):
            n = int(text[start:end].split()[2])
        start = end + 1
    if b"#" in text[start:]:  # comments further down: drop those lines first
        body = b"\n".join(x.split(b"#", 1)[0] for x in text[start:].split(b"\n"))
    else:
        body = text[start:]
    del text
    data = np.fromstring(body, dtype=np.int64, sep=" ").reshape(-1, 4)
    return data[:, 0], data[:, 1], data[:, 2], data[:, 3], n


def family_file(cache: Path, name: str) -> Path:
    path = cache / f"{name}.edges"
    if not path.exists():
        make = {**FAMILIES, **SMALL}[name][0]
        tmp = path.with_suffix(".tmp")
        write_edges(tmp, make())
        tmp.rename(path)
    return path


# --------------------------------------------------------------------------- solvers


def build_peers(build: Path) -> dict[str, Path]:
    """Compile the C++ peers; returns the programs that could be built."""
    programs = {}
    compiler = shutil.which("g++")
    if compiler is None:
        print("g++ not found: the C++ peers are skipped", file=sys.stderr)
        return programs
    for name, header in [("boost", "/usr/include/boost/graph/howard_cycle_ratio.hpp"),
                         ("lemon", "/usr/include/lemon/howard_mmc.h")]:
        if not Path(header).exists():
            print(f"{header} not found: {name} is skipped (apt-get install "
                  f"{'libboost-graph-dev' if name == 'boost' else 'liblemon-dev'})",
                  file=sys.stderr)
            continue
        exe = build / f"{name}_howard"
        src = PEERS / f"{name}_howard.cpp"
        out = subprocess.run([compiler, "-O2", "-std=c++17", "-o", str(exe), str(src)],
                             capture_output=True, text=True, check=False)
        if out.returncode != 0:
            print(f"{name}: build failed, skipped:\n{out.stderr[-2000:]}", file=sys.stderr)
            continue
        programs[name] = exe
    return programs


def child_maxplus(path: str, checkout: str) -> None:
    """One fresh-process run of maxplus: read, solve, verify; print JSON."""
    start = time.perf_counter()
    sys.path.insert(0, checkout)
    from maxplus.cycle_ratio import max_cycle_ratio

    imported = time.perf_counter()
    src, dst, w, t, n = read_edges(Path(path))
    t0 = time.perf_counter()
    result = max_cycle_ratio(src, dst, w, t, n_nodes=n)
    t1 = time.perf_counter()
    result.verify()
    t2 = time.perf_counter()
    import resource

    print(json.dumps({
        "solver": "maxplus", "seconds": t1 - t0, "verify_seconds": t2 - t1,
        "import_seconds": imported - start, "iterations": result.iterations,
        "ratio": str(result.ratio), "cycle_arcs": len(result.circuit),
        "peak_kib": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss,
    }))


def run_solver(kind: str, path: Path, programs: dict, checkouts: dict) -> dict:
    env = dict(os.environ)
    if kind in checkouts:
        checkout, _, engine = checkouts[kind].partition("@")
        if engine:
            env["MAXPLUS_ENGINE"] = engine
        cmd = [sys.executable, __file__, "--child", str(path), "--checkout", checkout]
    else:
        cmd = [str(programs[kind]), str(path)]
    start = time.perf_counter()
    out = subprocess.run(cmd, capture_output=True, text=True, env=env, check=False)
    wall = time.perf_counter() - start
    if out.returncode != 0:
        return {"solver": kind, "error": out.stderr.strip()[-300:] or f"exit {out.returncode}"}
    row = json.loads(out.stdout.strip().splitlines()[-1])
    row["process_seconds"] = wall
    return row


# --------------------------------------------------------------------------- report


def summarize(name: str, runs: list[dict]) -> dict:
    by: dict[str, list[dict]] = {}
    for r in runs:
        by.setdefault(r["label"], []).append(r)
    out = {"family": name}
    for label, rows in by.items():
        good = [r for r in rows if "error" not in r]
        if not good:
            out[label] = {"error": rows[0]["error"]}
            continue
        secs = [r["seconds"] for r in good]
        entry = {
            "median_s": statistics.median(secs), "min_s": min(secs), "max_s": max(secs),
            "process_median_s": statistics.median(r["process_seconds"] for r in good),
            "iterations": good[-1].get("iterations"),
            "peak_mib": max(r["peak_kib"] for r in good) / 1024,
            "ratio": good[-1]["ratio"], "runs": len(good),
        }
        if "verify_seconds" in good[0]:
            entry["verify_median_s"] = statistics.median(r["verify_seconds"] for r in good)
            entry["import_median_s"] = statistics.median(r["import_seconds"] for r in good)
        if "float_ratio" in good[-1]:
            entry["float_ratio"] = good[-1]["float_ratio"]
        if "capped" in good[-1]:
            entry["capped"] = good[-1]["capped"]
        out[label] = entry
    return out


def agrees(exact: str, peer: dict) -> str:
    if "error" in peer:
        return "n/a"
    mine = Fraction(exact)
    theirs = Fraction(peer["ratio"]) if peer["ratio"].split("/")[1] != "0" else None
    exact_ok = theirs == mine
    close = abs(peer["float_ratio"] - float(mine)) <= 1e-12 * max(1.0, abs(float(mine)))
    return ("exact" if exact_ok else "NO (exact cycle differs)") + ("" if close else ", float off")


def table(summary: list[dict], labels: list[str]) -> str:
    lines = [
        ("| family | layout | solver | median solve (s) | spread (s) | process (s) | iterations | "
         "peak (MiB) | verify (% of solve) | time / Boost | agrees |"),
        "|---|---|---|---:|---:|---:|---:|---:|---:|---:|---|",
    ]
    for s in summary:
        exact = next((s[x]["ratio"] for x in labels if x.startswith("maxplus") and x in s
                      and "ratio" in s[x]), None)
        boost = s.get("boost", {})
        for label in labels:
            e = s.get(label)
            if e is None:
                continue
            if "error" in e:
                lines.append(f"| {s['family']} | {layout_of(s['family'])} | {label} "
                             "| - | - | - | - | - | - | - | "
                             f"skipped: {e['error'][:60]} |")
                continue
            rel = (f"{e['median_s'] / boost['median_s']:.2f}"
                   if "median_s" in boost and label != "boost" else "")
            verify = (f"{100 * e['verify_median_s'] / e['median_s']:.0f} %"
                      if "verify_median_s" in e else "")
            its = "" if e["iterations"] is None else str(e["iterations"])
            if e.get("capped"):
                its += " (cap)"
            agree = agrees(exact, e) if "float_ratio" in e and exact else (
                f"exact {e['ratio']}" if label.startswith("maxplus") else "")
            lines.append(
                f"| {s['family']} | {layout_of(s['family'])} | {label} | {e['median_s']:.3f} "
                f"| {e['min_s']:.3f}-{e['max_s']:.3f} "
                f"| {e['process_median_s']:.2f} | {its} | {e['peak_mib']:.0f} | {verify} | {rel} "
                f"| {agree} |")
    return "\n".join(lines)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--families", nargs="+", default=None)
    parser.add_argument("--runs", type=int, default=5)
    parser.add_argument("--quick", action="store_true", help="three small graphs, 2 runs")
    parser.add_argument("--maxplus", nargs="+", default=[], metavar="LABEL=PATH[@ENGINE]",
                        help="other checkouts of maxplus to run in the same interleaving")
    parser.add_argument("--cache", type=Path, default=None,
                        help="directory for the generated .edges files (default: a temporary one)")
    parser.add_argument("--out", type=Path, default=HERE / "results" / "peers")
    parser.add_argument("--no-write", action="store_true")
    parser.add_argument("--child", help=argparse.SUPPRESS)
    parser.add_argument("--checkout", default=str(REPO), help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.child:
        child_maxplus(args.child, args.checkout)
        return
    names = args.families or (QUICK if args.quick else list(FAMILIES))
    unknown = [x for x in names if x not in FAMILIES and x not in SMALL]
    if unknown:
        parser.error(f"--families: unknown {', '.join(unknown)}; expected some of "
                     f"{', '.join([*FAMILIES, *SMALL])}")
    runs = 2 if args.quick else args.runs
    checkouts = {"maxplus": str(REPO)}
    for spec in args.maxplus:
        label, _, where = spec.partition("=")
        checkouts[f"maxplus-{label}"] = str(Path(where.split("@")[0]).resolve()) + (
            "@" + where.split("@")[1] if "@" in where else "")
    with tempfile.TemporaryDirectory() as tmp:
        cache = args.cache or Path(tmp)
        cache.mkdir(parents=True, exist_ok=True)
        programs = build_peers(Path(tmp))
        labels = list(checkouts) + list(programs)
        summary = []
        for name in names:
            path = family_file(cache, name)
            rows = []
            for _ in range(runs):  # interleaved: A B C, A B C, ...
                for label in labels:
                    row = run_solver(label, path, programs, checkouts)
                    row["label"] = label
                    rows.append(row)
            summary.append(summarize(name, rows))
            print("\n".join(table(summary[-1:], labels).splitlines()[2:]), file=sys.stderr,
                  flush=True)
    text = table(summary, labels)
    print(text)
    if not args.no_write:
        args.out.parent.mkdir(parents=True, exist_ok=True)
        args.out.with_suffix(".json").write_text(json.dumps(summary, indent=1) + "\n")
        args.out.with_suffix(".table.md").write_text(text + "\n")


if __name__ == "__main__":
    main()
