//! The trackers' HDF5 files, read without a C library (`hdf5-pure`):
//! * **SLEAP analysis** (`*.analysis.h5`, SLEAP's "Export Analysis HDF5" and `sleap_io`'s
//!   `save_analysis_h5`): `tracks` holds x, y per track, node and frame (NaN where lost), its
//!   axis order named by the dataset's `dims` attribute (a JSON list), or SLEAP's own
//!   `(track, xy, node, frame)` when absent; `node_names` and `track_names` name them.
//! * **DeepLabCut** (`*.h5`, pandas' `table` format under one key, `df_with_missing` as
//!   DeepLabCut writes it): a table of frame index and one block of values, the columns named by
//!   the group's `non_index_axes` attribute (a protocol-0 pickle of the column tuples: scorer,
//!   individual when multi-animal, body part, coordinate).
//!
//! Each track (SLEAP) or individual (DeepLabCut) is one animal, its body parts in the file's
//! order; time is the frame index over `--fps` (one frame a time unit without it); a point
//! below `min_likelihood` (DeepLabCut) or NaN makes its frame lost, as in the CSV readers.

use hdf5_pure::{AttrValue, Datatype, DatatypeByteOrder, File};

const LE: DatatypeByteOrder = DatatypeByteOrder::LittleEndian;

use super::read::{Frame, Track};
use super::{RecordingError, RecordingSettings};

/// The 8 bytes that open an HDF5 file (its superblock signature at offset 0).
pub(crate) const SIGNATURE: &[u8; 8] = b"\x89HDF\r\n\x1a\n";

/// Most values one file may hold (tracks × nodes × frames × 2): bounds the memory it takes.
const MAX_VALUES: u64 = 1 << 28;

fn bad(why: impl std::fmt::Display) -> RecordingError {
    let why = why.to_string();
    // The crate's own errors open with "HDF5 format error: ".
    let why = why.strip_prefix("HDF5 format error: ").unwrap_or(&why);
    RecordingError::Invalid(format!("HDF5 file: {why}"))
}

/// The tracks of an HDF5 file's bytes, SLEAP or DeepLabCut by what it holds.
pub(crate) fn parse(
    bytes: Vec<u8>,
    name: &str,
    settings: &RecordingSettings,
) -> Result<Vec<Track>, RecordingError> {
    let file = File::from_bytes(bytes).map_err(|e| bad(format!("not readable ({e})")))?;
    let clock = |frame: f64| frame / settings.fps.unwrap_or(1.0);
    if file.dataset("tracks").is_ok() {
        return sleap(&file, name, &clock);
    }
    let root = file.root();
    let keys = root.groups().map_err(bad)?;
    let key = keys
        .iter()
        .find(|k| pandas_type(&file, k).is_some_and(|t| t == "frame_table"))
        .ok_or_else(|| {
            bad("neither a SLEAP analysis file (no `tracks` dataset) nor a DeepLabCut table (no group pandas wrote in its `table` format)")
        })?;
    deeplabcut(&file, key, name, &clock, settings.min_likelihood)
}

fn text(value: Option<&AttrValue>) -> Option<String> {
    match value? {
        AttrValue::String(s) | AttrValue::AsciiString(s) | AttrValue::VarLenString(s) => {
            Some(s.clone())
        }
        _ => None,
    }
}

fn pandas_type(file: &File, key: &str) -> Option<String> {
    text(file.group(key).ok()?.attrs().ok()?.get("pandas_type"))
}

fn shape(dataset: &hdf5_pure::Dataset) -> Result<Vec<usize>, RecordingError> {
    let shape = dataset.shape().map_err(bad)?;
    let total = shape.iter().try_fold(1u64, |n, &d| n.checked_mul(d));
    if total.is_none_or(|n| n > MAX_VALUES) {
        return Err(bad(format!(
            "a dataset of shape {shape:?} is larger than {MAX_VALUES} values"
        )));
    }
    Ok(shape.into_iter().map(|d| d as usize).collect())
}

/// SLEAP's `tracks`, one animal a track.
fn sleap(
    file: &File,
    name: &str,
    clock: &dyn Fn(f64) -> f64,
) -> Result<Vec<Track>, RecordingError> {
    let tracks = file.dataset("tracks").map_err(bad)?;
    let dims = shape(&tracks)?;
    let order: Vec<String> = match text(tracks.attrs().map_err(bad)?.get("dims")) {
        Some(json) => serde_json::from_str(&json)
            .map_err(|e| bad(format!("`tracks`' dims attribute is not a JSON list ({e})")))?,
        None => ["track", "xy", "node", "frame"].map(String::from).to_vec(),
    };
    let axis = |n: &str| order.iter().position(|d| d == n);
    let (Some(track), Some(xy), Some(node), Some(frame), 4) = (
        axis("track"),
        axis("xy"),
        axis("node"),
        axis("frame"),
        dims.len(),
    ) else {
        return Err(bad(format!(
            "`tracks` has shape {dims:?} and dims {order:?}: SLEAP's are track, xy, node, frame"
        )));
    };
    if dims[xy] != 2 {
        return Err(bad(format!(
            "`tracks` has {} coordinates, not x and y",
            dims[xy]
        )));
    }
    let values = tracks.read_f64().map_err(bad)?;
    let names = file
        .dataset("track_names")
        .and_then(|d| d.read_string())
        .unwrap_or_default();
    let stride: Vec<usize> = (0..4).map(|a| dims[a + 1..].iter().product()).collect();
    let at = |i: [usize; 4]| -> f64 {
        let mut k = 0;
        for (a, &ix) in [track, xy, node, frame].iter().zip(&i) {
            k += stride[*a] * ix;
        }
        values[k]
    };
    Ok((0..dims[track])
        .map(|k| {
            let id = names.get(k).cloned().unwrap_or_else(|| k.to_string());
            let frames = (0..dims[frame])
                .map(|f| {
                    let row: Vec<f64> = (0..dims[node])
                        .flat_map(|j| [at([k, 0, j, f]), at([k, 1, j, f])])
                        .collect();
                    Frame {
                        t: clock(f as f64),
                        values: row.iter().all(|v| v.is_finite()).then_some(row),
                    }
                })
                .collect();
            Track {
                name: format!("{name}#{}", crate::markup::bound_line(&id)),
                frames,
            }
        })
        .collect())
}

/// The column tuples pandas pickled in `non_index_axes`: `[(1, [(scorer, …, coord), …])]`.
fn columns(pickled: &str) -> Result<Vec<Vec<String>>, RecordingError> {
    use serde_pickle::Value;
    let not = |why: &str| bad(format!("the table's column names {why}"));
    let value: Value = serde_pickle::value_from_slice(pickled.as_bytes(), Default::default())
        .map_err(|e| not(&format!("are not a readable pickle ({e})")))?;
    let axes = match value {
        Value::List(axes) => axes,
        _ => return Err(not("are not a list of axes")),
    };
    let labels = axes
        .into_iter()
        .find_map(|axis| match axis {
            Value::Tuple(mut pair) if pair.len() == 2 => match pair.pop() {
                Some(Value::List(labels)) => Some(labels),
                _ => None,
            },
            _ => None,
        })
        .ok_or_else(|| not("hold no (axis, labels) pair"))?;
    labels
        .into_iter()
        .map(|label| match label {
            Value::Tuple(parts) => parts
                .into_iter()
                .map(|p| match p {
                    Value::String(s) => Ok(s),
                    other => Ok(format!("{other:?}")),
                })
                .collect(),
            _ => Err(not(
                "are not tuples (DeepLabCut's scorer, body part, coordinate)",
            )),
        })
        .collect()
}

/// DeepLabCut's table under `key`, one animal an individual.
fn deeplabcut(
    file: &File,
    key: &str,
    name: &str,
    clock: &dyn Fn(f64) -> f64,
    min_likelihood: f64,
) -> Result<Vec<Track>, RecordingError> {
    let group = file.group(key).map_err(bad)?;
    let attrs = group.attrs().map_err(bad)?;
    let columns = columns(&text(attrs.get("non_index_axes")).unwrap_or_default())?;
    let table = file.dataset(&format!("{key}/table")).map_err(bad)?;
    let rows = shape(&table)?.first().copied().unwrap_or(0);
    let Datatype::Compound { size, members } = table.datatype().map_err(bad)? else {
        return Err(bad(format!("`{key}/table` is not a table of records")));
    };
    let field = |n: &str| members.iter().find(|m| m.name == n);
    let blocks = members
        .iter()
        .filter(|m| m.name.starts_with("values_block_"));
    let (Some(index), Some(block), 1) = (field("index"), field("values_block_0"), blocks.count())
    else {
        return Err(bad(format!(
            "`{key}/table` is not one frame index and one block of numbers (DeepLabCut's layout)"
        )));
    };
    let little = |t: &Datatype, float: bool| match t {
        Datatype::FixedPoint {
            size: 8,
            byte_order,
            ..
        } => !float && *byte_order == LE,
        Datatype::FloatingPoint {
            size: 8,
            byte_order,
            ..
        } => float && *byte_order == LE,
        _ => false,
    };
    let width = match &block.datatype {
        Datatype::Array {
            base_type,
            dimensions,
        } if little(base_type, true) => dimensions.iter().map(|&d| d as usize).product(),
        _ => 0,
    };
    if !little(&index.datatype, false) || width != columns.len() || width == 0 {
        return Err(bad(format!(
            "`{key}/table` holds {width} numbers a row for {} named columns, or its index is not frame numbers",
            columns.len()
        )));
    }
    let raw = table.read_raw().map_err(bad)?;
    let size = size as usize;
    let fits = |m: &hdf5_pure::CompoundMember, len: usize| m.byte_offset as usize + len <= size;
    if raw.len() != rows * size || !fits(index, 8) || !fits(block, 8 * width) {
        return Err(bad(format!(
            "`{key}/table`'s records do not hold their fields"
        )));
    }
    // Body parts with x, y and likelihood, per individual in order of first appearance.
    let mut parts: Vec<(&str, &str, [Option<usize>; 3])> = Vec::new();
    for (c, col) in columns.iter().enumerate() {
        let (who, part, coord) = match col.as_slice() {
            [_, part, coord] => ("", part, coord),
            [_, who, part, coord] => (who.as_str(), part, coord),
            _ => {
                return Err(bad(format!(
                    "column {c} is named by {} levels, not DeepLabCut's 3 or 4",
                    col.len()
                )))
            }
        };
        let Some(slot) = ["x", "y", "likelihood"].iter().position(|n| n == coord) else {
            continue;
        };
        let k = match parts.iter().position(|(w, p, _)| *w == who && p == part) {
            Some(k) => k,
            None => {
                parts.push((who, part, [None; 3]));
                parts.len() - 1
            }
        };
        parts[k].2[slot] = Some(c);
    }
    let mut individuals: Vec<(&str, Vec<[usize; 3]>)> = Vec::new();
    for (who, _, slots) in &parts {
        let [Some(x), Some(y), Some(p)] = *slots else {
            continue;
        };
        match individuals.iter_mut().find(|(w, _)| w == who) {
            Some((_, list)) => list.push([x, y, p]),
            None => individuals.push((who, vec![[x, y, p]])),
        }
    }
    if individuals.is_empty() {
        return Err(bad("no body part has x, y and likelihood columns"));
    }
    let eight = |row: &[u8], at: usize| -> [u8; 8] {
        let mut b = [0; 8];
        b.copy_from_slice(&row[at..at + 8]);
        b
    };
    let (block_at, index_at) = (block.byte_offset as usize, index.byte_offset as usize);
    Ok(individuals
        .into_iter()
        .map(|(who, list)| {
            let frames = raw
                .chunks_exact(size)
                .map(|row| {
                    let value = |c: usize| f64::from_le_bytes(eight(row, block_at + 8 * c));
                    let frame = i64::from_le_bytes(eight(row, index_at));
                    let likely = list.iter().all(|p| value(p[2]) >= min_likelihood);
                    let xy: Vec<f64> = list
                        .iter()
                        .flat_map(|p| [value(p[0]), value(p[1])])
                        .collect();
                    Frame {
                        t: clock(frame as f64),
                        values: likely.then_some(xy),
                    }
                })
                .collect();
            let label = if who.is_empty() {
                String::new()
            } else {
                format!("#{}", crate::markup::bound_line(who))
            };
            Track {
                name: format!("{name}{label}"),
                frames,
            }
        })
        .collect())
}
