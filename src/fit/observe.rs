//! The observation map of one frame: a midline resampled to the model's points and read as
//! turning angles, or segment lengths read as strains (the `o` of the `fit` module header).

use super::InputKind;

/// Why one frame gives no modal coordinates.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub enum FrameError {
    /// Every point at one place.
    #[error("the midline has zero length")]
    ZeroLength,
    /// Two neighbours at one place: no turning angle.
    #[error("two consecutive midline points coincide")]
    Coincident,
    /// A segment length of zero or less.
    #[error("segment lengths must be positive")]
    NonPositive,
    /// Coordinates so large that the body's length overflows (or not numbers at all).
    #[error(
        "the coordinates are too large to measure (the midline's length overflows): rescale them"
    )]
    Overflow,
}

/// The angle of (dot, cross): musl's atan2 (within an ulp), which a million frames feel less
/// than the C library's correctly rounded one. Every angle of a frame is taken by it.
pub(super) fn angle(cross: f64, dot: f64) -> f64 {
    libm::atan2(cross, dot)
}

/// The length of (x, y) without overflow of the squares for coordinates up to ~1e308 (musl's
/// hypot, as [`angle`]).
pub(super) fn size(x: f64, y: f64) -> f64 {
    libm::hypot(x, y)
}

/// Resample a polyline to `n` points equally spaced in arc length.
fn resample(points: &[(f64, f64)], n: usize) -> Result<Vec<(f64, f64)>, FrameError> {
    let mut cum = vec![0.0];
    for w in points.windows(2) {
        let d = size(w[1].0 - w[0].0, w[1].1 - w[0].1);
        cum.push(cum.last().unwrap_or(&0.0) + d);
    }
    let total = *cum.last().unwrap_or(&0.0);
    if !total.is_finite() {
        return Err(FrameError::Overflow);
    }
    if total <= 0.0 {
        return Err(FrameError::ZeroLength);
    }
    let mut out = Vec::with_capacity(n);
    let mut seg = 0;
    for i in 0..n {
        let s = total * i as f64 / (n - 1) as f64;
        while seg + 2 < cum.len() && cum[seg + 1] < s {
            seg += 1;
        }
        let len = cum[seg + 1] - cum[seg];
        let u = if len > 0.0 {
            ((s - cum[seg]) / len).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let (a, b) = (points[seg], points[seg + 1]);
        out.push((a.0 + u * (b.0 - a.0), a.1 + u * (b.1 - a.1)));
    }
    Ok(out)
}

/// Turning angles between consecutive segments of a polyline (radians, in (−π, π]).
pub fn turning_angles(points: &[(f64, f64)]) -> Result<Vec<f64>, FrameError> {
    let seg: Vec<(f64, f64)> = points
        .windows(2)
        .map(|w| (w[1].0 - w[0].0, w[1].1 - w[0].1))
        .collect();
    if seg.iter().any(|s| !(s.0.is_finite() && s.1.is_finite())) {
        return Err(FrameError::Overflow);
    }
    if seg.iter().any(|s| s.0 == 0.0 && s.1 == 0.0) {
        return Err(FrameError::Coincident);
    }
    let (mut seg, mut out) = (seg, Vec::with_capacity(points.len()));
    segment_angles(&mut seg, &mut out);
    Ok(out)
}

/// The turning angles between consecutive segments (none of them zero) into `out`. Each
/// segment is scaled to unit size first, in place: the angle is scale-free, and the cross and
/// dot products of huge coordinates would overflow.
pub(super) fn segment_angles(seg: &mut [(f64, f64)], out: &mut Vec<f64>) {
    for s in seg.iter_mut() {
        let size = s.0.abs().max(s.1.abs());
        *s = (s.0 / size, s.1 / size);
    }
    out.clear();
    out.extend(seg.windows(2).map(|w| {
        let cross = w[0].0 * w[1].1 - w[0].1 * w[1].0;
        let dot = w[0].0 * w[1].0 + w[0].1 * w[1].1;
        angle(cross, dot)
    }));
}

/// The observation o of one frame: turning angles (midline) or strains (lengths).
pub(super) fn observe(
    kind: InputKind,
    values: &[f64],
    n: usize,
    reference: Option<f64>,
) -> Result<Vec<f64>, FrameError> {
    match kind {
        InputKind::Midline => {
            let pts: Vec<(f64, f64)> = values.chunks(2).map(|c| (c[0], c[1])).collect();
            let pts = if pts.len() == n {
                pts
            } else {
                resample(&pts, n)?
            };
            turning_angles(&pts)
        }
        InputKind::Lengths => {
            if values.iter().any(|&l| l <= 0.0) {
                return Err(FrameError::NonPositive);
            }
            let h = reference.unwrap_or_else(|| values.iter().sum::<f64>() / values.len() as f64);
            Ok(values.iter().map(|l| l / h - 1.0).collect())
        }
    }
}
