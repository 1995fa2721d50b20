"""The peer of `theory-search discover`: PySINDy's weak-form PDE library (a generic polynomial
library in the field and its derivatives) on the same midline recordings.

Usage: python benches/peer_discover.py RECORDING [--threshold T] [--json]

The midlines (t, x1, y1, …, head first) become the lateral displacement y(s, t) (tail first,
each frame's least-squares line removed, s in body lengths); the state is (y, v = ∂t y) with v
from centred differences, since PySINDy's weak form takes first-order systems. The library:
polynomials up to `--degree` (3) in (y, v) and their derivatives in s up to order 4, with
interactions when the degree is above 1, as PySINDy's WeakPDELibrary builds it; STLSQ with normalised columns at the given threshold (0.1 by default). It prints the
terms of v's equation (∂t v = ∂t² y) and the time the fit took.
"""

import argparse
import json
import time

import numpy as np
import pysindy as ps


def lateral(path):
    d = np.loadtxt(path, delimiter=",")
    t = d[:, 0]
    p = d[:, 1:].reshape(len(t), -1, 2)[:, ::-1, :]  # tail first
    x, y = p[..., 0], p[..., 1]
    s = x.mean(axis=0) - x.mean(axis=0)[0]
    s = s / s[-1]
    a = np.vstack([np.ones_like(s), s]).T
    bend = y - (y @ np.linalg.pinv(a).T) @ a.T
    return t, s, bend


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("recording")
    ap.add_argument("--threshold", type=float, default=0.1)
    ap.add_argument("--degree", type=int, default=3)
    ap.add_argument("--json", action="store_true")
    args = ap.parse_args()
    t, s, y = lateral(args.recording)
    start = time.perf_counter()
    dt = t[1] - t[0]
    v = np.gradient(y, dt, axis=0)
    u = np.stack([y.T, v.T], axis=-1)  # (space, time, 2)
    grid = np.stack(np.meshgrid(s, t, indexing="ij"), axis=-1)
    lib = ps.WeakPDELibrary(
        function_library=ps.PolynomialLibrary(degree=args.degree, include_bias=False),
        derivative_order=4,
        spatiotemporal_grid=grid,
        is_uniform=True,
        include_interaction=args.degree > 1,
        K=2000,
    )
    model = ps.SINDy(feature_library=lib, optimizer=ps.STLSQ(threshold=args.threshold, normalize_columns=True))
    model.fit(u, t=dt, feature_names=["y", "v"])
    seconds = time.perf_counter() - start
    names = model.get_feature_names()
    coef = model.coefficients()[1]
    terms = {n: float(c) for n, c in zip(names, coef) if c != 0.0}
    if args.json:
        print(json.dumps({"terms": terms, "seconds": seconds}))
    else:
        print(f"∂t v = " + " + ".join(f"{c:.6g} {n}" for n, c in terms.items()))
        print(f"{seconds:.2f} s")


if __name__ == "__main__":
    main()
