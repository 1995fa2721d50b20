"""LAPACK's dense eigvalsh (through numpy) on the larva's three operators, for comparison with
`cargo bench --bench modes`. Usage: python3 benches/lapack_eigvalsh.py [N]  (needs numpy)."""
import sys
import time

import numpy as np

n = int(sys.argv[1]) if len(sys.argv) > 1 else 2000


def op(k, periodic, points):
    size = points - 1 if periodic else points
    w = np.array([1.0])
    for _ in range(k):
        w = np.convolve(w, [-1.0, 1.0])
    positions = range(size) if periodic else range(size - k)
    d = np.zeros((size, size))
    for p in positions:
        idx = [(p + j) % size for j in range(k + 1)]
        d[np.ix_(idx, idx)] += np.outer(w, w)
    return d


mats = [op(1, True, n), op(1, False, n), op(2, False, n)]
best = float("inf")
for _ in range(5):
    t = time.perf_counter()
    for m in mats:
        np.linalg.eigvalsh(m)
    best = min(best, time.perf_counter() - t)
print(f"numpy {np.__version__}: eigvalsh of D2,c, D2,f, D4 at N = {n}: {best * 1e3:.1f} ms (best of 5)")
