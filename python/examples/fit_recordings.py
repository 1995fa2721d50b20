"""A notebook-style example: fit the C. elegans recordings beside the repository and plot the
principal components over the theory's mode shapes and the variance shares.

Run: python python/examples/fit_recordings.py [DATA_DIR] [OUT_DIR]
"""

import pathlib
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import theory_search as ts  # noqa: E402

here = pathlib.Path(__file__).resolve().parent
data = pathlib.Path(sys.argv[1]) if len(sys.argv) > 1 else here.parents[1] / ".." / "shared" / "data"
out = pathlib.Path(sys.argv[2]) if len(sys.argv) > 2 else pathlib.Path(".")
out.mkdir(parents=True, exist_ok=True)

for path in sorted(data.glob("*.csv")):
    r = ts.fit(str(path), window=64, bootstrap=200, seed=1)
    # The bootstrap needs a recording long enough for its correlation time; the fit says why
    # when it draws none.
    boot = getattr(r, "intervals", None)
    omega = (f"[{boot['omega'][0]:.4f}, {boot['omega'][1]:.4f}]" if boot
             else "(" + next((w for w in r.warnings if "bootstrap" in w), "no bootstrap") + ")")
    verdicts = ", ".join(f"{name} {t['verdict']}" for name, t in r.tests.items())
    print(f"{path.name}: {r.frames} frames, ω = {r.omega:.4f} {omega}, "
          f"overlaps {np.round(r.mode_overlap[:3], 3)}; {verdicts}")
    fig, (left, right) = plt.subplots(1, 2, figsize=(9, 3.5))
    s = np.linspace(0, 1, r.shapes.shape[0])
    for k in range(3):
        # The principal component k drawn on the mode shapes (columns) it is made of.
        pc = r.shapes @ r.components[k]
        sign = np.sign(pc @ r.shapes[:, k]) or 1.0
        left.plot(s, sign * pc, label=f"PC {k + 1}")
        left.plot(s, r.shapes[:, k], "k:", lw=1, label="mode shapes 2–4" if k == 0 else None)
    left.set_xlabel("arc length (tail → head)")
    left.set_ylabel("component and mode shape")
    left.legend(frameon=False, loc="upper left", bbox_to_anchor=(1, 1))
    # The fit numbers the bending modes from 2 (mode 1 is the rigid turn), as the command line does.
    modes = np.arange(2, len(r.pca_variance_share) + 2)
    right.semilogy(modes, r.pca_variance_share, "o-", label="PCA")
    right.semilogy(modes, r.theory_variance_share, "s--", label="equipartition")
    right.set_xlabel("mode")
    right.set_ylabel("share of the variance")
    right.legend(frameon=False)
    fig.tight_layout()
    target = out / f"{path.stem}.png"
    fig.savefig(target, dpi=100)
    print(f"wrote {target}")
