"""The trackers' own in-memory formats as midlines: a ``movement`` poses dataset, a
``sleap_io.Labels``, and a DeepLabCut DataFrame (multi-index columns, single or multi-animal).
Each becomes one array per animal (frames × keypoints × 2, NaN where a point was lost or tracked
below ``min_likelihood``) and its frames' times; none of the libraries is imported here (the
objects are read through their own attributes), so none is needed to use the others."""

from __future__ import annotations

from typing import Any, Dict, List, Optional, Sequence, Tuple

import numpy as np

from ._errors import UsageError

Animals = Tuple[List[np.ndarray], List[np.ndarray], Dict[str, Any]]


def is_tracker_object(x: Any) -> bool:
    return _is_movement(x) or _is_sleap(x) or _is_dlc_frame(x)


def _is_movement(x: Any) -> bool:
    return hasattr(x, "data_vars") and "position" in getattr(x, "data_vars", {})


def _is_sleap(x: Any) -> bool:
    return type(x).__name__ == "Labels" and hasattr(x, "numpy") and hasattr(x, "skeletons")


def _is_dlc_frame(x: Any) -> bool:
    columns = getattr(x, "columns", None)
    return getattr(columns, "nlevels", 1) >= 3 and hasattr(x, "to_numpy")


def _order(names: Sequence[str], wanted: Optional[Sequence[str]], what: str) -> List[int]:
    """Indices of ``wanted`` among ``names`` (all of them, in order, when None)."""
    names = [str(n) for n in names]
    if wanted is None:
        return list(range(len(names)))
    if isinstance(wanted, str):
        wanted = [wanted]
    missing = [w for w in wanted if str(w) not in names]
    if missing:
        shown = ", ".join(repr(str(m))[:40] for m in missing[:5])
        raise UsageError(f"no {what} {shown} in the data ({what}s: {', '.join(names[:20])})")
    return [names.index(str(w)) for w in wanted]


def _times(frames: int, index: Optional[np.ndarray], fps: Optional[float]) -> np.ndarray:
    """Frame numbers (the rows' own, else 0, 1, …) over ``fps`` (one unit per frame without)."""
    n = np.arange(frames, dtype=float) if index is None else np.asarray(index, dtype=float)
    return n / fps if fps else n


def _lost_below(xy: np.ndarray, confidence: Optional[np.ndarray], least: float) -> np.ndarray:
    """``xy`` (frames × points × 2) with points whose confidence is below ``least`` as NaN."""
    if confidence is None:
        return xy
    out = xy.copy()
    out[np.asarray(confidence, dtype=float) < least] = np.nan
    return out


def midlines(
    data: Any,
    t: Any,
    fps: Optional[float],
    keypoints: Optional[Sequence[str]],
    individuals: Optional[Sequence[str]],
    min_likelihood: float,
) -> Animals:
    """One array per animal, its times, and the options the format itself states (its time
    unit)."""
    if _is_movement(data):
        return _from_movement(data, t, fps, keypoints, individuals, min_likelihood)
    if _is_sleap(data):
        return _from_sleap(data, t, fps, keypoints, individuals, min_likelihood)
    return _from_dlc(data, t, fps, keypoints, individuals, min_likelihood)


def _from_movement(ds, t, fps, keypoints, individuals, least) -> Animals:
    position = ds["position"]
    dims = set(position.dims)
    if not {"time", "space", "keypoints"} <= dims:
        raise UsageError(f"a movement dataset's position has time, space and keypoints, not {sorted(dims)}")
    if "individuals" not in dims:
        position = position.expand_dims(individuals=["animal"])
    space = [str(s) for s in position.coords["space"].values]
    if space[:2] != ["x", "y"]:
        raise UsageError(f"a movement dataset's space must be x, y (planar midlines), not {space}")
    keys = _order(position.coords["keypoints"].values, keypoints, "keypoint")
    who = _order(position.coords["individuals"].values, individuals, "individual")
    xy = position.transpose("individuals", "time", "keypoints", "space").values[..., :2]
    confidence = None
    if "confidence" in ds.data_vars:
        c = ds["confidence"]
        if "individuals" not in c.dims:
            c = c.expand_dims(individuals=["animal"])
        confidence = c.transpose("individuals", "time", "keypoints").values
    seconds = str(ds.attrs.get("time_unit", "")).lower() in ("seconds", "s")
    stamps = np.asarray(position.coords["time"].values, dtype=float)
    if t is None:
        t = stamps if seconds or not fps else stamps / fps
    animals = [
        _lost_below(xy[i][:, keys], None if confidence is None else confidence[i][:, keys], least)
        for i in who
    ]
    return animals, [np.asarray(t, dtype=float)] * len(animals), ({"time_unit": "s"} if seconds or fps else {})


def _from_sleap(labels, t, fps, keypoints, individuals, least) -> Animals:
    if not labels.skeletons:
        raise UsageError("a SLEAP Labels without a skeleton has no keypoints")
    arr = np.asarray(labels.numpy(return_confidence=True), dtype=float)  # frames × tracks × nodes × 3
    if arr.ndim != 4 or arr.shape[-1] != 3:
        raise UsageError(f"SLEAP's Labels.numpy gave an array of shape {arr.shape}, not frames × tracks × nodes × 3")
    keys = _order(labels.skeletons[0].node_names, keypoints, "node")
    names = [tr.name for tr in labels.tracks] or [f"animal {i + 1}" for i in range(arr.shape[1])]
    who = _order(names, individuals, "track")
    animals = [_lost_below(arr[:, i][:, keys, :2], arr[:, i][:, keys, 2], least) for i in who]
    times = _times(arr.shape[0], None, fps) if t is None else np.asarray(t, dtype=float)
    return animals, [times] * len(animals), ({"time_unit": "s"} if fps else {})


def _from_dlc(frame, t, fps, keypoints, individuals, least) -> Animals:
    columns = frame.columns
    names = [str(n).lower() if n is not None else "" for n in columns.names]
    coords = columns.get_level_values(columns.nlevels - 1).astype(str)
    if not {"x", "y"} <= set(coords):
        raise UsageError("a DeepLabCut DataFrame's last column level holds x, y (and likelihood)")
    parts_level = names.index("bodyparts") if "bodyparts" in names else columns.nlevels - 2
    who_level = names.index("individuals") if "individuals" in names else None
    parts = list(dict.fromkeys(columns.get_level_values(parts_level).astype(str)))
    keys = [parts[i] for i in _order(parts, keypoints, "body part")]
    if who_level is None:
        groups = [None]
    else:
        present = list(dict.fromkeys(columns.get_level_values(who_level).astype(str)))
        groups = [present[i] for i in _order(present, individuals, "individual")]
    values = frame.to_numpy(dtype=float)
    level = lambda k: columns.get_level_values(k).astype(str)  # noqa: E731
    animals = []
    for who in groups:
        mine = np.ones(len(columns), dtype=bool) if who is None else (level(who_level) == who)
        xy = np.full((len(frame), len(keys), 2), np.nan)
        confidence = np.ones((len(frame), len(keys)))
        for j, key in enumerate(keys):
            here = mine & (level(parts_level) == key)
            for c, name in enumerate(("x", "y")):
                col = np.flatnonzero(here & (coords == name))
                if col.size:
                    xy[:, j, c] = values[:, col[0]]
            col = np.flatnonzero(here & (coords == "likelihood"))
            if col.size:
                confidence[:, j] = values[:, col[0]]
        animals.append(_lost_below(xy, confidence, least))
    try:
        index = np.asarray(frame.index, dtype=float)
    except (TypeError, ValueError):
        index = None
    times = _times(len(frame), index, fps) if t is None else np.asarray(t, dtype=float)
    return animals, [times] * len(animals), ({"time_unit": "s"} if fps else {})
