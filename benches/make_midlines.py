"""Write the 10⁶-frame recording that `fit` and its peer are timed on (issue 25, item 7):
12-point midlines of a thermally bending body, plain CSV with six decimals, about 233 MB.

    python3 benches/make_midlines.py OUT.csv [--frames 1000000]

Five bending modes, each a damped oscillator driven by white noise (an AR(2) filter), on
cosine shapes; x carries a little tracking noise. Seeded: the same file every time.
"""

import argparse

import numpy as np
from scipy.signal import lfilter


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("out")
    ap.add_argument("--frames", type=int, default=1_000_000)
    args = ap.parse_args()
    rng = np.random.default_rng(1)
    n, k = args.frames, 12
    s = np.linspace(0, 1, k)
    shapes = np.array([np.cos((m + 1) * np.pi * s) for m in range(5)])
    amplitudes = np.zeros((n, 5))
    for m in range(5):
        w, z = 0.05 * (m + 1) ** 2, 0.05
        a1, a2 = 2 * np.exp(-z * w) * np.cos(w), -np.exp(-2 * z * w)
        noise = rng.normal(0, 0.01 / (m + 1) ** 2, n)
        amplitudes[:, m] = lfilter([1], [1, -a1, -a2], noise)
    y = amplitudes @ shapes
    x = np.tile(s * 11, (n, 1)) + rng.normal(0, 1e-4, (n, k)) + 1.0
    xy = np.empty((n, 2 * k))
    xy[:, 0::2], xy[:, 1::2] = x, y
    with open(args.out, "w") as f:
        f.write("t," + ",".join(f"x{i},y{i}" for i in range(k)) + "\n")
        data = np.column_stack([np.arange(n) * 0.04, xy])
        np.savetxt(f, data, fmt=["%.2f"] + ["%.6f"] * (2 * k), delimiter=",")


if __name__ == "__main__":
    main()
