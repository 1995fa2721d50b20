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
pub(crate) fn angle(cross: f64, dot: f64) -> f64 {
    libm::atan2(cross, dot)
}

/// The length of (x, y) without overflow of the squares for coordinates up to ~1e308 (musl's
/// hypot, as [`angle`]).
pub(crate) fn size(x: f64, y: f64) -> f64 {
    libm::hypot(x, y)
}

/// Pairs taken at once by [`angles`] and [`sizes`]: fixed-size arrays, which the compiler
/// turns into vector instructions (two divisions or square roots for one).
const LANES: usize = 8;

/// musl's atan polynomial for |r| < 7/16: r − r(s₁ + s₂), s₁ and s₂ its odd and even halves in
/// z = r², w = z² (coefficients and order of operations as musl's); r itself below 2⁻²⁷.
fn atan_small(r: f64) -> f64 {
    // musl's coefficients, by their bits.
    const AT: [u64; 11] = [
        0x3FD5_5555_5555_550D,
        0xBFC9_9999_9998_EBC4,
        0x3FC2_4924_9200_83FF,
        0xBFBC_71C6_FE23_1671,
        0x3FB7_45CD_C54C_206E,
        0xBFB3_B0F2_AF74_9A6D,
        0x3FB1_0D66_A0D0_3D51,
        0xBFAD_DE2D_52DE_FD9A,
        0x3FA9_7B4B_2476_0DEB,
        0xBFA2_B444_2C6A_6C2F,
        0x3F90_AD3A_E322_DA11,
    ];
    let at = |i: usize| f64::from_bits(AT[i]);
    let z = r * r;
    let w = z * z;
    let s1 = z * (at(0) + w * (at(2) + w * (at(4) + w * (at(6) + w * (at(8) + w * at(10))))));
    let s2 = w * (at(1) + w * (at(3) + w * (at(5) + w * (at(7) + w * at(9)))));
    if r.abs() < 1.0 / 134_217_728.0 {
        r
    } else {
        r - r * (s1 + s2)
    }
}

/// [`angle`] of each (cross, dot), bit for bit, into `out`. A smooth body turns little: with
/// dot > 0 and r = cross/dot below 7/16 in size, musl's atan2 is its atan polynomial of r
/// alone, taken here for [`LANES`] pairs at once; any other pair is handed to [`angle`].
pub(crate) fn angles(pairs: impl Iterator<Item = (f64, f64)>, out: &mut Vec<f64>) {
    out.clear();
    let mut pairs = pairs.peekable();
    while pairs.peek().is_some() {
        let (mut cross, mut dot) = ([0.0; LANES], [1.0; LANES]);
        let mut n = 0;
        for ((c, d), p) in cross.iter_mut().zip(&mut dot).zip(&mut pairs) {
            (*c, *d) = p;
            n += 1;
        }
        let mut r = [0.0; LANES];
        for ((r, c), d) in r.iter_mut().zip(&cross).zip(&dot) {
            *r = c / d;
        }
        let mut a = [0.0; LANES];
        for (a, r) in a.iter_mut().zip(&r) {
            *a = atan_small(*r);
        }
        for i in 0..n {
            if !(dot[i] > 0.0 && r[i].abs() < 0.4375) {
                a[i] = angle(cross[i], dot[i]);
            }
        }
        out.extend_from_slice(&a[..n]);
    }
}

/// Dekker's split of x² into a head and an exact tail (musl's `sq`).
fn square(x: f64) -> (f64, f64) {
    const SPLIT: f64 = 134_217_728.0 + 1.0;
    let xc = x * SPLIT;
    let xh = x - xc + xc;
    let xl = x - xh;
    let hi = x * x;
    (hi, xh * xh - hi + 2.0 * xh * xl + xl * xl)
}

/// [`size`] of each (x, y), bit for bit, into `out`: musl's hypot without its rescaling, for
/// [`LANES`] pairs at once, where both parts lie in [2⁻⁴⁵⁰, 2⁵¹¹) within 2⁶⁴ of each other
/// (neither the squares nor their tails leave the doubles); any other pair is handed to
/// [`size`].
pub(crate) fn sizes(pairs: impl Iterator<Item = (f64, f64)>, out: &mut Vec<f64>) {
    out.clear();
    let mut pairs = pairs.peekable();
    while pairs.peek().is_some() {
        let (mut big, mut small) = ([1.0; LANES], [1.0; LANES]);
        let mut given = [(1.0, 1.0); LANES];
        let mut n = 0;
        for (((b, s), g), (x, y)) in big
            .iter_mut()
            .zip(&mut small)
            .zip(&mut given)
            .zip(&mut pairs)
        {
            // musl orders the magnitudes by their bits: by value, for numbers (a NaN fails the
            // range test below either way).
            let (a, c) = (x.abs(), y.abs());
            (*b, *s) = if a < c { (c, a) } else { (a, c) };
            *g = (x, y);
            n += 1;
        }
        let mut h = [0.0; LANES];
        for ((h, b), s) in h.iter_mut().zip(&big).zip(&small) {
            let (hx, lx) = square(*b);
            let (hy, ly) = square(*s);
            *h = (ly + lx + hy + hx).sqrt();
        }
        for i in 0..n {
            let (eb, es) = (big[i].to_bits() >> 52, small[i].to_bits() >> 52);
            if !(es >= 0x3ff - 450 && eb <= 0x3ff + 510 && eb.wrapping_sub(es) <= 64) {
                h[i] = size(given[i].0, given[i].1);
            }
        }
        out.extend_from_slice(&h[..n]);
    }
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
pub(crate) fn segment_angles(seg: &mut [(f64, f64)], out: &mut Vec<f64>) {
    for s in seg.iter_mut() {
        let size = s.0.abs().max(s.1.abs());
        *s = (s.0 / size, s.1 / size);
    }
    angles(
        seg.windows(2).map(|w| {
            let cross = w[0].0 * w[1].1 - w[0].1 * w[1].0;
            let dot = w[0].0 * w[1].0 + w[0].1 * w[1].1;
            (cross, dot)
        }),
        out,
    );
}

/// A midline's points (tail first) on `n` points: as given when it has `n`, else resampled.
pub(crate) fn on_points(values: &[f64], n: usize) -> Result<Vec<(f64, f64)>, FrameError> {
    let pts: Vec<(f64, f64)> = values.chunks(2).map(|c| (c[0], c[1])).collect();
    if pts.len() == n {
        Ok(pts)
    } else {
        resample(&pts, n)
    }
}

/// The observation o of one frame: turning angles (midline, with `held` points put in) or
/// strains (lengths).
pub(crate) fn observe(
    kind: InputKind,
    values: &[f64],
    n: usize,
    reference: Option<f64>,
    held: Option<&super::held::HeldPoints>,
) -> Result<Vec<f64>, FrameError> {
    match kind {
        InputKind::Midline => {
            let mut pts = on_points(values, n)?;
            if let Some(h) = held {
                h.hold(&mut pts);
            }
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

#[cfg(test)]
mod tests {
    use super::*;

    /// The batched angles and sizes are musl's, bit for bit: small and large turns, both signs,
    /// every quadrant, tiny and huge parts, zeros, infinities and NaN.
    #[test]
    fn batched_angles_and_sizes_are_musls() {
        let mut next = crate::recording::xorshift(0x2545_F491_4F6C_DD1Du64);
        let special = [
            0.0,
            -0.0,
            1.0,
            -1.0,
            0.4375,
            1e-9,
            3e-300,
            1e300,
            f64::MIN_POSITIVE / 4.0,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NAN,
        ];
        let mut pairs = Vec::new();
        for _ in 0..200_000 {
            // A random double of any exponent, or a turn near the fast path's edge.
            let any = |bits: u64| f64::from_bits(bits);
            let near = |u: u64| (u % 2_000_000) as f64 * 1e-6 - 1.0;
            let (a, b) = (next(), next());
            pairs.push((any(a), any(b)));
            pairs.push((near(a), 1.0 + near(b).abs()));
            pairs.push((0.4375 * (1.0 + near(a) * 1e-12), 1.0));
            pairs.push((near(a) * 1e-8, near(b)));
        }
        for &x in &special {
            for &y in &special {
                pairs.push((x, y));
            }
        }
        let mut got = Vec::new();
        angles(pairs.iter().copied(), &mut got);
        let want: Vec<f64> = pairs.iter().map(|&(c, d)| angle(c, d)).collect();
        for (i, (g, w)) in got.iter().zip(&want).enumerate() {
            assert_eq!(g.to_bits(), w.to_bits(), "angle {:?}: {g} vs {w}", pairs[i]);
        }
        sizes(pairs.iter().copied(), &mut got);
        let want: Vec<f64> = pairs.iter().map(|&(x, y)| size(x, y)).collect();
        for (i, (g, w)) in got.iter().zip(&want).enumerate() {
            assert_eq!(g.to_bits(), w.to_bits(), "size {:?}: {g} vs {w}", pairs[i]);
        }
    }
}
