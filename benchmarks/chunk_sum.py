"""The sum of the streamed stiffness's chunks: the compiled merge of
``efgkit.system.streamed.chunk_sum`` against scipy's sums of the same chunks, in one process.

Run:  PYTHONPATH=. python benchmarks/chunk_sum.py --nodes 2e4 1e5 --rounds 5
      PYTHONPATH=. python benchmarks/chunk_sum.py --allocation 233 --rounds 6

``--allocation MB``: instead, an array of MB megabytes allocated and written once, by numpy
and by ``efgkit.memory.fresh_array`` in turns, in this (fresh) process: the first write of
fresh memory, which numpy's huge-page advice can make wait for the kernel's compaction.

The edge-cracked plate of ``benchmarks/scaling.py`` at about ``--nodes`` nodes is discretised
once and its chunks' K_c formed once (``chunk_stiffness``, chunks of 2**18 points); then the
three sums take turns in each round: ``merge`` (``chunk_sum``, the code now), ``pairwise``
(scipy sums of the chunks placed on all DOFs, partial sums of equal numbers of chunks added
as a binary counter: the code before) and ``running`` (scipy's running sum in chunk order,
the reference the merge must equal bit for bit: the same additions in the same order). The
memory of the arrays is fresh or reused as the allocator decides; the stage as a solve sees it
is measured by ``benchmarks/stage_times.py`` in fresh processes.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
from pathlib import Path

import numpy as np
from scipy.sparse import csr_array
from turns import take_turns

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "benchmarks"))


def on_all_dofs(parts, n):
    """The chunks (dof, K_c) as CSR on all n DOFs."""
    out = []
    for dof, K in parts:
        indptr = np.zeros(n + 1, np.int64)
        indptr[dof + 1] = np.diff(K.indptr)
        np.cumsum(indptr, out=indptr)
        out.append(csr_array((K.data, dof.astype(np.int32)[K.indices], indptr), shape=(n, n)))
    return out


def pairwise(parts):
    """The sum before: partial sums of 2**j chunks meet the next of 2**j chunks."""
    stack = []
    for p in parts:
        level, acc = 0, p
        while stack and stack[-1][0] == level:
            acc, level = csr_array(stack.pop()[1] + acc), level + 1
        stack.append((level, acc))
    total = stack.pop()[1]
    while stack:
        total = csr_array(stack.pop()[1] + total)
    total.sort_indices()
    return total


def running(parts):
    total = parts[0]
    for p in parts[1:]:
        total = csr_array(total + p)
    total.sort_indices()
    return total


def measure(nodes: float, rounds: int) -> dict:
    import scaling

    from efgkit.jit import resolve_backend
    from efgkit.methods.discretize import discretize
    from efgkit.problem.graded import modulus_weights
    from efgkit.system.streamed import chunk_stiffness, chunk_sum

    scene, method = scaling.scaled(math.sqrt(nodes / scaling.BASE_NODES), bc="lagrange")
    disc = discretize(scene, method.for_scene(scene), chunked=True)
    w = modulus_weights(disc.scene, disc.points.x, disc.points.w)
    ps, D = disc.shape, scene.material.D
    backend = resolve_backend("auto", ps.n_points)
    parts = [chunk_stiffness(ps.chunk(s, e, derivatives=True), w[s:e], D, backend)
             for s, e in ps.bounds()]
    n = ps.n_dofs
    chunk_sum(list(parts[:1]), n)  # compiled or loaded from the cache
    sums = {"merge": lambda: chunk_sum(list(parts), n),
            "pairwise": lambda: pairwise(on_all_dofs(parts, n)),
            "running": lambda: running(on_all_dofs(parts, n))}
    times = take_turns(sums, rounds)
    m, p, r = (sums[k]() for k in ("merge", "pairwise", "running"))  # once more, to compare
    same = np.array_equal(m.indptr, r.indptr) and np.array_equal(m.indices, r.indices)
    return {"nodes": disc.nodes.n, "points": ps.n_points, "chunks": len(parts),
            "chunk_nnz": int(sum(K.nnz for _, K in parts)), "nnz": int(m.nnz),
            "median_s": {k: float(np.median(v)) for k, v in times.items()},
            "range_s": {k: [float(min(v)), float(max(v))] for k, v in times.items()},
            "merge_equals_running_bitwise": bool(same and np.array_equal(m.data, r.data)),
            "merge_vs_pairwise_rel": float(abs(m - p).max() / abs(p).max())}


def allocation(megabytes: float, rounds: int) -> dict:
    """Seconds to allocate and write ``megabytes`` once, numpy and fresh_array taking turns."""
    from efgkit.memory import fresh_array

    n = int(megabytes * 2**20) // 8

    def written(a):
        a[:] = 1.0

    times = take_turns({"numpy": lambda: written(np.empty(n)),
                        "fresh_array": lambda: written(fresh_array(n, np.float64))}, rounds)
    return {"megabytes": megabytes, "seconds": {k: [round(s, 4) for s in v] for k, v in times.items()}}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--nodes", type=float, nargs="+", default=[2e4, 1e5])
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--allocation", type=float, metavar="MB")
    args = ap.parse_args(argv)
    if args.allocation:
        out = allocation(args.allocation, args.rounds)
        print(json.dumps(out))
        return out
    out = [measure(n, args.rounds) for n in args.nodes]
    for r in out:
        print(json.dumps(r))
    return out


if __name__ == "__main__":
    main()
