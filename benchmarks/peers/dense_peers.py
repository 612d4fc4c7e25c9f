"""maxplus.eigenvalue against the Python peers, side by side in one run (issue 13).

Random irreducible dense matrices: integers 0..1000, each entry ε with
probability 0.2 (redrawn until strongly connected), fixed seeds, n = 2, 10,
50, 200, 500, several matrices per size (Howard's iteration count varies
from matrix to matrix). For every sample the contestants run back to back in
the same process, A B C A B C ..., each on the same matrices, so that load
from other processes hits them alike; the table gives the median time per
call and the spread (min–max over the samples). A sample of a small n
repeats the matrices a batch of times (the same batch for every contestant)
so that it lasts about a millisecond.

* ours: ``maxplus.eigenvalue(A)`` on the matrix as lists of ints and None:
  exact (a Fraction) and certified, conversion included.
* eigenlag: ``eigenlag.maxplus.howard(graph)``, its float Howard, on its own
  input (a ``CondensedGraph`` with one edge per finite entry) built *before*
  the clock starts: the conversion is not charged to it.
* mplusa: ``mplusa.maxplus.karp_algorithm(A)`` on a float array (ε = -inf);
  O(n³) Python calls, so it runs only up to ``--mplusa-max`` nodes. Its
  package ``__init__`` fails to import in 0.0.5 (its plotting module), so
  the algebra module is loaded directly.

"agrees" compares a peer's float with our exact value within 1e-9 relative
(for this column only). A peer that is not installed is skipped with a
message. Peers run in the interpreter running this script (eigenlag needs
Python >= 3.12): run it there, with numpy and scipy installed, so both sides
share one interpreter.

Usage::

    python3.12 benchmarks/peers/dense_peers.py
    python3.12 benchmarks/peers/dense_peers.py --sizes 2 10 --matrices 5 --samples 11
"""

from __future__ import annotations

import argparse
import importlib
import importlib.util
import platform
import statistics
import sys
import time
import types
from pathlib import Path

import numpy as np
import scipy
from scipy.sparse import csr_matrix
from scipy.sparse.csgraph import connected_components

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

from maxplus import eigenvalue  # noqa: E402  (after the path insert: the checkout)


def random_irreducible(n: int, seed: int) -> list[list[int | None]]:
    rng = np.random.default_rng(seed)
    while True:
        A = rng.integers(0, 1001, size=(n, n)).astype(object)
        A[rng.random((n, n)) < 0.2] = None
        finite = np.array([[v is not None for v in row] for row in A.tolist()])
        if connected_components(csr_matrix(finite), directed=True, connection="strong")[0] == 1 \
                and (n > 1 or finite[0, 0]):
            return A.tolist()


def load_eigenlag():
    try:
        from eigenlag.maxplus import CondensedEdge, CondensedGraph, howard
    except ImportError as exc:
        return None, f"eigenlag not importable here ({exc})"

    def prepare(A):
        n = len(A)
        edges = tuple(CondensedEdge(str(j), str(i), float(A[i][j]), 1)
                      for i in range(n) for j in range(n) if A[i][j] is not None)
        return CondensedGraph(tuple(str(i) for i in range(n)), edges)

    def run(graph):
        return howard(graph)[0]

    return (prepare, run), ""


def load_mplusa():
    spec = importlib.util.find_spec("mplusa")
    if spec is None or not spec.submodule_search_locations:
        return None, "mplusa not installed"
    root = spec.submodule_search_locations[0]
    for name, path in (("mplusa", root), ("mplusa.maxplus", f"{root}/maxplus")):
        package = types.ModuleType(name)
        package.__path__ = [path]
        sys.modules[name] = package
    karp_algorithm = importlib.import_module("mplusa.maxplus.maxplus").karp_algorithm

    def prepare(A):
        return np.array([[-np.inf if v is None else float(v) for v in row] for row in A])

    return (prepare, karp_algorithm), ""


def agrees(exact: list, approx: list | None) -> str:
    if approx is None:
        return "-"
    exact = exact[:len(approx)]
    bad = [(e, a) for e, a in zip(exact, approx)
           if abs(float(e) - float(a)) > 1e-9 * max(1.0, abs(float(e)))]
    if not bad:
        return f"yes ({len(exact)}/{len(exact)})"
    e, a = bad[0]
    return f"NO on {len(bad)}/{len(exact)} (e.g. {a:g} for {e})"


def clock(call, args: list, batch: int) -> tuple[float, list]:
    """Seconds per call of ``call`` over every matrix, ``batch`` times."""
    start = time.perf_counter()
    for _ in range(batch):
        out = [call(arg) for arg in args]
    return (time.perf_counter() - start) / (batch * len(args)), out


def measure(n: int, samples: int, matrices: int, peers: dict, mplusa_max: int,
            mplusa_matrices: int, seed: int) -> dict:
    mats = [random_irreducible(n, seed + 1000 * k) for k in range(matrices)]
    runners = {"ours": (mats, eigenvalue)}
    for name, (prepare, run) in peers.items():
        if name == "mplusa":
            if n > mplusa_max:
                continue
            runners[name] = ([prepare(A) for A in mats[:mplusa_matrices]], run)
        else:
            runners[name] = ([prepare(A) for A in mats], run)
        if name == "eigenlag":  # the same, building its input from the matrix inside the clock
            runners["eigenlag+input"] = (mats, lambda A, prepare=prepare, run=run: run(prepare(A)))
    once = {name: clock(run, args, 1) for name, (args, run) in runners.items()}  # warm-up
    batch = max(1, int(1e-3 / max(once["ours"][0] * matrices, 1e-7)))
    times: dict[str, list[float]] = {name: [] for name in runners}
    answers = {name: out for name, (_, out) in once.items()}
    for _ in range(samples):
        for name, (args, run) in runners.items():  # A B C A B C ...
            t, answers[name] = clock(run, args, batch)
            times[name].append(t)
    return {"n": n, "batch": batch, "matrices": matrices, "times": times, "answers": answers}


def fmt(seconds: float) -> str:
    return f"{seconds * 1e3:.3f}" if seconds < 1 else f"{seconds * 1e3:.0f}"


def cell(ts: list[float] | None) -> str:
    if not ts:
        return "not run"
    return f"{fmt(statistics.median(ts))} ({fmt(min(ts))}–{fmt(max(ts))})"


def table(results: list[dict], notes: list[str]) -> str:
    lines = [
        ("| n | ours: maxplus.eigenvalue, ms | eigenlag howard, ms | ours / eigenlag | "
         "eigenlag incl. building its graph, ms | mplusa karp, ms | "
         "λ of the first matrix (ours, exact) | eigenlag agrees | mplusa agrees |"),
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for r in results:
        t, a = r["times"], r["answers"]
        ratio = (f"{statistics.median(t['ours']) / statistics.median(t['eigenlag']):.2f}"
                 if "eigenlag" in t else "-")
        lines.append(
            f"| {r['n']} | {cell(t['ours'])} | {cell(t.get('eigenlag'))} | {ratio} | "
            f"{cell(t.get('eigenlag+input'))} | {cell(t.get('mplusa'))} | {a['ours'][0]} | "
            f"{agrees(a['ours'], a.get('eigenlag'))} | "
            f"{agrees(a['ours'], a.get('mplusa'))} |"
        )
    return "\n".join(lines + [""] + [f"- {note}" for note in notes]) + "\n"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[2, 10, 50, 200, 500])
    parser.add_argument("--samples", type=int, default=0,
                        help="samples per size (default: 15 up to n=50, 5 at 200, 3 above)")
    parser.add_argument("--matrices", type=int, nargs="+", default=[20, 20, 20, 5, 3],
                        help="random matrices per size (one number, or one per size)")
    parser.add_argument("--mplusa-max", type=int, default=50)
    parser.add_argument("--mplusa-matrices", type=int, default=3,
                        help="mplusa runs on the first few matrices of a size only")
    parser.add_argument("--seed", type=int, default=13)
    parser.add_argument("--out", type=Path, default=None, help="also write the table here")
    args = parser.parse_args()

    peers, notes = {}, []
    for name, loader in (("eigenlag", load_eigenlag), ("mplusa", load_mplusa)):
        loaded, why = loader()
        if loaded is None:
            print(f"skipping {name}: {why}", file=sys.stderr)
            notes.append(f"{name} skipped: {why}")
        else:
            peers[name] = loaded
    results = []
    counts = args.matrices * len(args.sizes) if len(args.matrices) == 1 else args.matrices
    for n, matrices in zip(args.sizes, counts):
        samples = args.samples or (15 if n <= 50 else 5 if n <= 200 else 3)
        r = measure(n, samples, matrices, peers, args.mplusa_max, args.mplusa_matrices,
                    args.seed + n)
        results.append(r)
        print(f"n={n}: {samples} samples of {r['batch']} x {matrices} matrices",
              file=sys.stderr)
    notes += [
        (f"Python {platform.python_version()}, numpy {np.__version__}, scipy {scipy.__version__}; "
         "one interpreter for every contestant. Each sample runs a contestant on the same "
         f"random matrices ({', '.join(f'{m} at n = {n}' for n, m in zip(args.sizes, counts))};"
         " repeated a batch of times for small n); times are per call, median (min–max) "
         "over the samples; contestants interleaved A B C A B C. "
         "The machine's 2 cores were shared with other jobs while this ran."),
        (f"mplusa runs only up to n = {args.mplusa_max} and on the first "
         f"{args.mplusa_matrices} matrices of a size (O(n³) Python calls per matrix); its "
         "'agrees' column covers those."),
        ("'eigenlag howard' times its solver on its input graph built beforehand (the "
         "ratio uses this, the figure most favourable to it); 'incl. building its graph' "
         "adds turning the same list-of-lists matrix into that graph. Ours always includes "
         "validating and converting the list-of-lists matrix and checking the certificate."),
    ]
    text = table(results, notes)
    print(text)
    if args.out is not None:
        args.out.write_text(text)


if __name__ == "__main__":
    main()
