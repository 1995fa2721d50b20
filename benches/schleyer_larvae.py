"""Convert the Schleyer lab's exploration midlines (38 Drosophila larvae, 16 fps, 12 points, mm),
shipped in the larvaworld wheel on PyPI (MIT), to the plain CSV `fit` and `discover` read.

    pip download --no-deps larvaworld==2.5.1 -d WHEELDIR
    python3 benches/schleyer_larvae.py WHEELDIR/larvaworld-2.5.1-py3-none-any.whl OUTDIR

Nothing is committed: the recordings stay where the wheel put them. Each raw row is `Step`,
the 12 midline points from tail to head (larvaworld's `nam.midline_xy(12, reverse=True)`), the
contour and blob columns, and `collision_flag` last. A row with a collision or an unreadable
coordinate becomes a lost frame (a row of NaN, where the tracker lost it), as larvaworld's own
import drops collisions. Point 1 is written as the head; t = (Step − 1)/16 s.
"""

import csv
import io
import math
import sys
import zipfile
from pathlib import Path

PREFIX = "larvaworld/data/SchleyerGroup/raw/exploration/"
POINTS = 12
FPS = 16.0


def number(cell: str) -> float:
    try:
        return float(cell)
    except ValueError:
        return math.nan


def convert(raw: str) -> str:
    out = io.StringIO()
    out.write("t," + ",".join(f"x{k},y{k}" for k in range(1, POINTS + 1)) + "\n")
    for row in csv.reader(io.StringIO(raw)):
        if not row:
            continue
        step = int(number(row[0]))
        tail_first = [number(c) for c in row[1 : 1 + 2 * POINTS]]
        xy = []
        for k in reversed(range(POINTS)):
            xy += tail_first[2 * k : 2 * k + 2]
        if row[-1].strip() != "0" or any(math.isnan(v) for v in xy):
            xy = [math.nan] * (2 * POINTS)
        cells = ("NaN" if math.isnan(v) else repr(v) for v in xy)
        out.write(f"{(step - 1) / FPS:.4f}," + ",".join(cells) + "\n")
    return out.getvalue()


def main() -> int:
    if len(sys.argv) != 3:
        print(__doc__, file=sys.stderr)
        return 2
    wheel, target = Path(sys.argv[1]), Path(sys.argv[2])
    target.mkdir(parents=True, exist_ok=True)
    count = 0
    with zipfile.ZipFile(wheel) as z:
        for name in sorted(z.namelist()):
            if name.startswith(PREFIX) and name.endswith(".csv"):
                dish, animal = name[len(PREFIX) :].split("/")
                text = convert(z.read(name).decode("utf-8", "replace"))
                (target / f"{dish}_{animal}").write_text(text)
                count += 1
    print(f"{count} larvae written to {target}")
    return 0 if count else 1


if __name__ == "__main__":
    sys.exit(main())
