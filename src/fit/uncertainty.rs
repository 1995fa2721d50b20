//! The standard errors of a mode's spectral fit (`spectrum`): the inverse Fisher information
//! widened by the taper's and the overlap's correlations, with the bounds and a white level
//! the data cannot see handled as stated below; and the 95 % interval of a scale fitted over
//! several modes (`weighted_scale`).

/// ν under this share of σ² is a white level the data cannot see.
const UNSEEN_NOISE: f64 = 1e-6;

/// The standard errors of ln θ from the information `a` at `t` within bounds `(lo, hi)`,
/// scaled by `scale` (b·o/M), or `None` when Ω or σ² is at a bound or the information is
/// singular. A parameter at its bound is held there, out of the information: ν at zero (no
/// tracking noise), ζ at its floor (a line narrower than the window resolves: its width
/// unknown, ζ_error none). A white level under 10⁻⁶ of σ² is no noise the data can see, yet
/// one they cannot exclude either: its row enters in linear ν (below).
pub(super) fn standard_errors(
    a: &[[f64; 4]; 4],
    t: &[f64; 4],
    (lo, hi): (&[f64; 4], &[f64; 4]),
    scale: f64,
) -> Option<[f64; 4]> {
    let free: Vec<usize> = (0..4)
        .filter(|&i| t[i] > lo[i] + 1e-6 && t[i] < hi[i] - 1e-6)
        .filter(|&i| i != 3 || t[3] > t[2] + UNSEEN_NOISE.ln())
        .collect();
    if !(free.contains(&0) && free.contains(&2)) {
        return None;
    }
    // A white level the data do not see (ν ≪ σ²) still trades against σ² and ζ at the band's
    // edges: its row in linear ν (∂ln E/∂ν = Z/E, not ν·Z/E, which vanishes with ν) keeps that
    // trade in the others' errors, as if ν could be anything the data allow near zero.
    let mut a = *a;
    let mut free = free;
    let unseen = !free.contains(&3) && t[3] < t[2] + UNSEEN_NOISE.ln();
    if unseen {
        let nu = t[3].exp();
        a[3].iter_mut().for_each(|x| *x /= nu);
        a.iter_mut().for_each(|row| row[3] /= nu);
        free.push(3);
    }
    let errors = |free: &[usize]| -> Option<[f64; 4]> {
        let sub = nalgebra::DMatrix::from_fn(free.len(), free.len(), |i, j| a[free[i]][free[j]]);
        let inv = sub.try_inverse()?;
        let mut se = [f64::INFINITY, f64::INFINITY, f64::INFINITY, 0.0];
        for (r, &i) in free
            .iter()
            .enumerate()
            .filter(|&(_, &i)| !(unseen && i == 3))
        {
            se[i] = (inv[(r, r)] * scale).sqrt();
        }
        (se[0].is_finite() && se[2].is_finite()).then_some(se)
    };
    // Should that information still be singular, ν is held where it is.
    let without_noise: Vec<usize> = free.iter().copied().filter(|&i| i != 3).collect();
    errors(&free).or_else(|| errors(&without_noise))
}

/// The weighted least-squares C of Ωᵢ = C·xᵢ over `(mode, Ω, σ_Ω)` and its 95 % interval,
/// widened by the Birge ratio √(χ²/(n − 1)) when the modes scatter more than their errors.
pub(super) fn weighted_scale(
    used: &[(usize, f64, f64)],
    x: &[f64],
) -> Option<(f64, Option<[f64; 2]>)> {
    let (mut num, mut den) = (0.0, 0.0);
    for (&(_, o, e), &x) in used.iter().zip(x) {
        let w = 1.0 / (e * e);
        num += w * o * x;
        den += w * x * x;
    }
    let c = num / den;
    if !(c.is_finite() && c > 0.0) {
        return None;
    }
    let mut se = den.sqrt().recip();
    let q = 1.959_963_984_540_054;
    let n = used.len();
    if n > 1 {
        let chi2: f64 = used
            .iter()
            .zip(x)
            .map(|(&(_, o, e), &x)| ((o - c * x) / e).powi(2))
            .sum();
        let ratio = chi2 / (n - 1) as f64;
        if ratio > 1.0 {
            se *= ratio.sqrt();
        }
    }
    let interval = se.is_finite().then_some([c - q * se, c + q * se]);
    Some((c, interval))
}
