//! WCON, the OpenWorm tracker-commons JSON (its `WCON_format.md`): a `units` object (`t`, `x`,
//! `y` required) and `data`, one record or an array of them. A record has an `id` (number or
//! string), `t` (a number, or an array), and `x`, `y` (one midline, or one per time), `null`
//! for a missing value; records of one id may repeat and join. Optional `head` (`"L"`: the
//! first point is the head, `"R"`: the last, `"?"`), single or per time, orients the points.
//! Origins and centroids (`ox`, `oy`, `cx`, `cy`) move a whole frame, and turning angles do
//! not see that, so they are not needed. Unknown keys are ignored, as the format requires.

use serde_json::Value;

use super::read::{Frame, Track};
use super::RecordingError;

/// Most animals one file may hold.
const MAX_IDS: usize = 100_000;

/// The tracks of a WCON text and its time and length units.
pub(crate) struct Wcon {
    pub(crate) tracks: Vec<Track>,
    pub(crate) time_unit: String,
    pub(crate) length_unit: String,
}

fn bad(why: impl Into<String>) -> RecordingError {
    RecordingError::Invalid(format!("WCON: {}", why.into()))
}

/// A length unit's size in metres: `[number*][prefix]unit`, with the format's prefixes and
/// units (m, metre/meter, micron, in/inch, plural or not).
fn metres(unit: &str) -> Option<f64> {
    let (scale, unit) = match unit.split_once('*') {
        Some((n, u)) => (n.trim().parse::<f64>().ok()?, u.trim()),
        None => (1.0, unit.trim()),
    };
    let singular = unit.strip_suffix('s').unwrap_or(unit);
    let base = |u: &str| match u {
        "m" | "metre" | "meter" => Some(1.0),
        "micron" => Some(1e-6),
        "in" | "inch" | "inche" => Some(0.0254),
        _ => None,
    };
    let prefixes: [(&str, &str, f64); 7] = [
        ("c", "centi", 1e-2),
        ("m", "milli", 1e-3),
        ("u", "micro", 1e-6),
        ("n", "nano", 1e-9),
        ("k", "kilo", 1e3),
        ("M", "mega", 1e6),
        ("G", "giga", 1e9),
    ];
    let found = base(unit).or_else(|| base(singular)).or_else(|| {
        prefixes.iter().find_map(|&(short, long, f)| {
            let abbreviated = unit.strip_prefix(short).filter(|u| *u == "m");
            let micro = ["µ", "μ"]
                .iter()
                .find_map(|p| unit.strip_prefix(p))
                .filter(|u| short == "u" && *u == "m");
            let spelled = singular
                .strip_prefix(long)
                .filter(|u| matches!(*u, "metre" | "meter"));
            abbreviated.or(micro).or(spelled).map(|_| f)
        })
    })?;
    (scale.is_finite() && scale > 0.0).then_some(scale * found)
}

/// A unit string from the file: text, printable, short.
fn unit(units: &serde_json::Map<String, Value>, key: &str) -> Result<String, RecordingError> {
    let u = units
        .get(key)
        .and_then(Value::as_str)
        .ok_or_else(|| bad(format!("units has no string for {key:?}")))?;
    super::checked_unit(u).map_err(|e| bad(e.to_string()))
}

/// A number or `null` (missing) as f64.
fn number(v: &Value) -> Result<f64, RecordingError> {
    match v {
        Value::Null => Ok(f64::NAN),
        Value::Number(n) => n.as_f64().ok_or_else(|| bad("a number out of range")),
        other => Err(bad(format!("expected a number or null, found {other}"))),
    }
}

/// A value that may be single or arrayed, as a list.
fn arrayed(v: &Value) -> Vec<&Value> {
    match v {
        Value::Array(a) => a.iter().collect(),
        single => vec![single],
    }
}

/// Parse a WCON text; `head_first` is the orientation the frames are given to the fit in.
pub(crate) fn parse(text: &str, name: &str, head_first: bool) -> Result<Wcon, RecordingError> {
    let root: Value = serde_json::from_str(text).map_err(|e| RecordingError::Line {
        line: e.line(),
        why: e.into(),
    })?;
    let top = root
        .as_object()
        .ok_or_else(|| bad("the file must hold one JSON object"))?;
    let units = top
        .get("units")
        .and_then(Value::as_object)
        .ok_or_else(|| bad("the required \"units\" object is missing"))?;
    let (t_unit, x_unit, y_unit) = (unit(units, "t")?, unit(units, "x")?, unit(units, "y")?);
    // y in x's unit: the angles need both axes on one scale.
    let y_scale = if x_unit == y_unit {
        1.0
    } else {
        match (metres(&x_unit), metres(&y_unit)) {
            (Some(x), Some(y)) => y / x,
            _ => {
                return Err(bad(format!(
                    "x is in {x_unit:?} and y in {y_unit:?}: give both one length unit"
                )))
            }
        }
    };
    let data = top
        .get("data")
        .ok_or_else(|| bad("the required \"data\" entry is missing"))?;
    let mut tracks: Vec<Track> = Vec::new();
    let mut index = std::collections::HashMap::new();
    for (r, record) in arrayed(data).into_iter().enumerate() {
        let record = record
            .as_object()
            .ok_or_else(|| bad(format!("data record {} is not an object", r + 1)))?;
        let id = match record.get("id") {
            Some(Value::String(s)) => s.clone(),
            Some(Value::Number(n)) => n.to_string(),
            _ => return Err(bad(format!("data record {} has no id", r + 1))),
        };
        let id = super::checked_name(&id).map_err(|e| bad(e.to_string()))?;
        let frames = record_frames(record, r + 1, head_first, y_scale)?;
        let k = match index.get(&id) {
            Some(&k) => k,
            None => {
                if tracks.len() == MAX_IDS {
                    return Err(bad(format!("more than {MAX_IDS} animals in one file")));
                }
                tracks.push(Track {
                    name: format!("{name}#{id}"),
                    frames: Vec::new(),
                });
                index.insert(id, tracks.len() - 1);
                tracks.len() - 1
            }
        };
        tracks[k].frames.extend(frames);
    }
    if tracks.is_empty() {
        return Err(bad("the data section is empty"));
    }
    for t in &mut tracks {
        t.frames.sort_by(|a, b| a.t.total_cmp(&b.t));
    }
    Ok(Wcon {
        tracks,
        time_unit: t_unit,
        length_unit: x_unit,
    })
}

/// The frames of one data record, oriented `head_first` or not, y scaled to x's unit.
fn record_frames(
    record: &serde_json::Map<String, Value>,
    r: usize,
    head_first: bool,
    y_scale: f64,
) -> Result<Vec<Frame>, RecordingError> {
    let get = |key: &str| {
        record
            .get(key)
            .ok_or_else(|| bad(format!("data record {r} has no {key:?}")))
    };
    let t = get("t")?;
    let single = !t.is_array();
    let times = arrayed(t);
    let per_time = |key: &str| -> Result<Vec<Vec<&Value>>, RecordingError> {
        let v = get(key)?;
        let rows: Vec<Vec<&Value>> = if single {
            vec![arrayed(v)]
        } else {
            arrayed(v).into_iter().map(arrayed).collect()
        };
        if rows.len() != times.len() {
            return Err(bad(format!(
                "data record {r}: {} times but {} midlines in {key:?}",
                times.len(),
                rows.len()
            )));
        }
        Ok(rows)
    };
    let (xs, ys) = (per_time("x")?, per_time("y")?);
    let heads: Vec<&Value> = record.get("head").map(arrayed).unwrap_or_default();
    if heads.len() > 1 && heads.len() != times.len() {
        return Err(bad(format!(
            "data record {r}: \"head\" has {} entries for {} times",
            heads.len(),
            times.len()
        )));
    }
    let mut frames = Vec::with_capacity(times.len());
    for (i, t) in times.iter().enumerate() {
        let t = number(t)?;
        if !t.is_finite() {
            continue; // a time left out: the clock sees the frame as missing
        }
        let (x, y) = (&xs[i], &ys[i]);
        if x.len() != y.len() {
            return Err(bad(format!(
                "data record {r}, t = {t}: {} x values but {} y values",
                x.len(),
                y.len()
            )));
        }
        let mut values = Vec::with_capacity(2 * x.len());
        for (a, b) in x.iter().zip(y) {
            values.push(number(a)?);
            values.push(y_scale * number(b)?);
        }
        let head = heads.get(if heads.len() > 1 { i } else { 0 });
        let listed_head_first = match head.and_then(|h| h.as_str()) {
            Some("L") => Some(true),
            Some("R") => Some(false),
            _ => None,
        };
        if listed_head_first.is_some_and(|f| f != head_first) {
            values = values.chunks(2).rev().flatten().copied().collect();
        }
        let lost = values.iter().any(|v| !v.is_finite());
        frames.push(Frame {
            t,
            values: (!lost).then_some(values),
        });
    }
    Ok(frames)
}

#[cfg(test)]
mod tests {
    use super::metres;

    #[test]
    fn length_units_of_the_format() {
        for (u, m) in [
            ("mm", 1e-3),
            ("millimetres", 1e-3),
            ("millimeter", 1e-3),
            ("um", 1e-6),
            ("µm", 1e-6),
            ("micron", 1e-6),
            ("microns", 1e-6),
            ("12*in", 12.0 * 0.0254),
            ("m", 1.0),
            ("cm", 1e-2),
        ] {
            let got = metres(u).unwrap_or_else(|| panic!("{u}"));
            assert!((got - m).abs() < 1e-15, "{u}: {got}");
        }
        for u in ["msecond", "s", "", "Mx", "-1*mm"] {
            assert_eq!(metres(u), None, "{u}");
        }
    }
}
