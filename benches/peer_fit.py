"""The peer of `fit` a notebook user would write (issue 25, item 7): pandas reads the midlines,
numpy takes the turning angles and their PCA, scipy takes each component's Welch spectrum.

    python3 benches/peer_fit.py FILE.csv [--window 256]

Prints the PCA variance shares and each component's peak frequency, so that its work cannot be
skipped; time it whole (`/usr/bin/time`) beside `theory-search fit FILE.csv --window 256`.
"""

import argparse

import numpy as np
import pandas as pd
from scipy.signal import welch


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("file")
    ap.add_argument("--window", type=int, default=256)
    args = ap.parse_args()
    frame = pd.read_csv(args.file)
    t = frame.iloc[:, 0].to_numpy()
    xy = frame.iloc[:, 1:].to_numpy().reshape(len(frame), -1, 2)
    seg = np.diff(xy, axis=1)
    heading = np.arctan2(seg[..., 1], seg[..., 0])
    angles = np.angle(np.exp(1j * np.diff(heading, axis=1)))
    centred = angles - angles.mean(axis=0)
    _, s, vt = np.linalg.svd(centred, full_matrices=False)
    shares = s**2 / np.sum(s**2)
    scores = centred @ vt.T
    fs = 1.0 / np.median(np.diff(t))
    f, p = welch(scores, fs=fs, nperseg=args.window, axis=0)
    peaks = f[1:][np.argmax(p[1:], axis=0)]
    print("shares", np.round(shares, 4))
    print("peaks", np.round(peaks, 4))


if __name__ == "__main__":
    main()
