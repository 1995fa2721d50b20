"""The trackers' own formats, made here by the trackers' own libraries from one recording (the
shipped example beam): a ``movement`` dataset, a SLEAP file written and read by ``sleap_io``, and
DeepLabCut's HDF5 layout (single and multi-animal) written by pandas as DeepLabCut writes it,
each fitted to the CSV's κ within 1e-9."""

import pathlib

import numpy as np
import pandas as pd
import pytest

import theory_search as ts

ROOT = pathlib.Path(__file__).resolve().parents[2]
EXAMPLE = ROOT / "tables" / "examples" / "midlines.csv"


@pytest.fixture(scope="module")
def beam(tmp_path_factory):
    frame = pd.read_csv(EXAMPLE, comment="#")
    # SLEAP stores positions as float32: every format gets the float32 values, and the CSV they
    # are compared with holds those exactly.
    values = frame.iloc[:, 1:].to_numpy().astype(np.float32).astype(np.float64)
    xy = values.reshape(len(frame), -1, 2)
    t = frame["t"].to_numpy()
    assert np.allclose(np.diff(t), 1.0)  # one frame per time unit: fps = 1
    path = tmp_path_factory.mktemp("beam") / "beam.csv"
    np.savetxt(path, np.column_stack([t, values]), delimiter=",", fmt="%.17g",
               header=",".join(frame.columns), comments="")
    want = ts.fit(str(path), time_unit="s").continuum
    return xy, want


def _same_kappa(got, want):
    assert got.continuum["constant"] == pytest.approx(want["constant"], rel=1e-9)
    assert got.continuum["interval"] == pytest.approx(want["interval"], rel=1e-9)


def _names(k):
    return [f"p{j}" for j in range(k)]


def test_a_movement_dataset(beam):
    from movement.io import load_poses

    xy, want = beam
    frames, k, _ = xy.shape
    position = np.transpose(xy, (0, 2, 1))[..., None]  # time × space × keypoints × individuals
    ds = load_poses.from_numpy(position, np.ones((frames, k, 1)), ["larva"], _names(k), fps=1.0)
    got = ts.fit(ds)
    _same_kappa(got, want)
    assert got.units["time"] == "s"  # the dataset's own unit
    # Keypoints are chosen by name: the body's head-first order, here the same.
    _same_kappa(ts.fit(ds, keypoints=_names(k), individuals=["larva"]), want)
    with pytest.raises(ts.UsageError, match="no keypoint 'tail'"):
        ts.fit(ds, keypoints=["tail"])
    # A point tracked below min_likelihood is lost.
    low = np.ones((frames, k, 1))
    low[100, 3] = 0.1
    lossy = load_poses.from_numpy(position, low, ["larva"], _names(k), fps=1.0)
    assert ts.fit(lossy).recording["frames_lost"] == 1


def _labels(xy):
    import sleap_io as sio

    return sio.Labels.from_numpy(
        xy[:, None], videos=[sio.Video(filename="larva.mp4", open_backend=False)],
        skeletons=sio.Skeleton(_names(xy.shape[1])), tracks=[sio.Track("larva")],
    )


def test_a_sleap_file(beam, tmp_path):
    import sleap_io as sio

    xy, want = beam
    labels = _labels(xy)
    path = tmp_path / "larva.slp"
    sio.save_slp(labels, str(path))
    _same_kappa(ts.fit(sio.load_slp(str(path)), fps=1.0), want)


def _dlc_frame(xy, individuals):
    frames, k, _ = xy.shape
    levels = ["scorer"] + (["individuals"] if individuals else []) + ["bodyparts", "coords"]
    columns, values = [], []
    for who in individuals or [None]:
        for j, part in enumerate(_names(k)):
            for c, coord in enumerate(("x", "y", "likelihood")):
                columns.append(("DLC_resnet50", *([who] if who else []), part, coord))
                values.append(xy[:, j, c] if c < 2 else np.ones(frames))
    index = pd.MultiIndex.from_tuples(columns, names=levels)
    return pd.DataFrame(np.column_stack(values), columns=index)


def test_deeplabcut_hdf5_single_and_multi_animal(beam, tmp_path):
    xy, want = beam
    path = tmp_path / "larvaDLC_resnet50.h5"
    _dlc_frame(xy, None).to_hdf(path, key="df_with_missing", format="table", mode="w")
    _same_kappa(ts.fit(pd.read_hdf(path), fps=1.0), want)
    # The CSV DeepLabCut writes, read as its three header rows.
    csv = tmp_path / "larvaDLC_resnet50.csv"
    _dlc_frame(xy, None).to_csv(csv)
    _same_kappa(ts.fit(pd.read_csv(csv, header=[0, 1, 2], index_col=0), fps=1.0), want)
    # Multi-animal: each individual one animal; one chosen is the single animal's fit.
    both = tmp_path / "twoDLC.h5"
    _dlc_frame(xy, ["a", "b"]).to_hdf(both, key="df_with_missing", format="table", mode="w")
    two = pd.read_hdf(both)
    _same_kappa(ts.fit(two, fps=1.0, individuals=["b"]), want)
    assert len(ts.fit(two, fps=1.0).animals) == 2
    found = ts.discover(two, fps=1.0, individuals=["a"], bootstrap=0)
    assert found["selected"]


def test_the_library_reads_the_trackers_hdf5_files_by_path(beam, tmp_path):
    # The command line's reader (no h5py, no pandas): a SLEAP analysis file written by
    # sleap_io, and DeepLabCut's .h5 written by pandas as DeepLabCut writes it, single and
    # multi-animal, each the CSV's κ.
    import sleap_io as sio

    xy, want = beam
    labels = _labels(xy)
    for preset in ("matlab", "standard"):
        path = tmp_path / f"larva.{preset}.analysis.h5"
        sio.save_analysis_h5(labels, str(path), preset=preset)
        got = ts.fit(str(path), fps=1.0)
        _same_kappa(got, want)
        assert got.units["time"] == "s"  # frames per second: the clock is in seconds
    one = tmp_path / "larvaDLC_resnet50.h5"
    _dlc_frame(xy, None).to_hdf(one, key="df_with_missing", format="table", mode="w")
    _same_kappa(ts.fit(str(one), fps=1.0), want)
    assert ts.fit(str(one)).units["time"] == "frame"
    two = tmp_path / "twoDLC.h5"
    _dlc_frame(xy, ["a", "b"]).to_hdf(two, key="df_with_missing", format="table", mode="w")
    both = ts.fit(str(two), fps=1.0)
    assert [a["recording"].rsplit("#", 1)[1] for a in both.animals] == ["a", "b"]
    # A directory's .h5 files are its recordings, as its CSVs are.
    assert len(ts.fit(str(tmp_path), fps=1.0).animals) == 5
    # A point below min_likelihood loses its frame, as in DeepLabCut's CSV.
    low = _dlc_frame(xy, None)
    low.iloc[100, 2] = 0.1
    lossy = tmp_path / "lossy" / "larvaDLC.h5"
    lossy.parent.mkdir()
    low.to_hdf(lossy, key="df_with_missing", format="table", mode="w")
    assert ts.fit(str(lossy), fps=1.0).recording["frames_lost"] == 1


def test_compare_takes_arrays_and_trackers_objects(beam, tmp_path):
    # Four animals as arrays, two a group: pieces of one beam (one κ), so the difference's
    # interval holds 0; each array is one animal, as each file is.
    xy, _ = beam
    pieces = [xy[i * 700:(i + 1) * 700 + 600] for i in range(4)]
    got = ts.compare(pieces[:2], pieces[2:], fps=1.0, permutations=99)
    assert [g["animals"] for g in got["groups"]] == [2, 2]
    kappa = got["differences"][0]
    assert kappa["quantity"] == "kappa"
    lo, hi = kappa["interval"]
    assert lo < 0 < hi
    # The same animals as a multi-animal DeepLabCut frame: each individual one animal.
    frames = [_dlc_frame(p, [f"a{i}"]) for i, p in enumerate(pieces[:2])]
    two = pd.concat(frames, axis=1)
    by_frame = ts.compare(two, pieces[2:], fps=1.0, permutations=99)
    assert by_frame["differences"][0]["estimate"] == pytest.approx(kappa["estimate"], rel=1e-9)
    # The figure, as the command line's --figures writes it.
    drawn = ts.compare(pieces[:2], pieces[2:], fps=1.0, permutations=99, figures=tmp_path)
    assert [pathlib.Path(p).name for p in drawn["figures"]] == ["compare_groups.svg"]
