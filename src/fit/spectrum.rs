//! One mode's spectrum fitted by its own model, as optical-tweezers calibration fits a power
//! spectrum (Berg-Sørensen & Flyvbjerg 2004), for a thermally driven damped mode seen through
//! white tracking noise.
//!
//! **Model.** Qᵢ obeys Q̈ + 2ζΩQ̇ + Ω²Q = (white force), stationary variance σ², and is
//! observed with white noise of variance ν per frame. Its autocovariance at lag t (γ = ζΩ,
//! Ω_d² = Ω² − γ²) is c(t) = σ² e^{−γt}(cos Ω_d t + γ sin(Ω_d t)/Ω_d) (cosh and sinh when
//! over-damped) plus ν at t = 0. A Welch segment of W frames tapered by w has the expected
//! one-sided ordinate at bin k
//!
//! E Pₖ = 2/(f_s Σw²) · Σ_{|τ|<W} c(τ/f_s) r(τ) cos(2πkτ/W),  r(τ) = Σₙ wₙwₙ₊τ,
//!
//! exactly, for the sampled process: aliasing and the taper's leakage are in the model, not
//! corrections to it. One W-point FFT evaluates every bin.
//!
//! **Likelihood.** An average of M periodograms is E Pₖ times a Gamma variable of mean 1, so
//! the parameters θ = (ln Ω, ln ζ, ln σ², ln ν) minimise Whittle's Σₖ P̄ₖ/E Pₖ + ln E Pₖ over
//! bins 1 … W/2 − 1 (bin 0 holds nothing once each segment's mean is removed, which the
//! model also carries into bin 1; the Nyquist bin has other statistics), by Levenberg–Marquardt steps on the Fisher information
//! A = Σₖ ∂ln E Pₖ ∂ln E Pₖᵀ.
//!
//! **Errors.** Cov θ = (b·o/M)·A⁻¹: the inverse Fisher information of M independent
//! periodograms, widened by the taper's correlation of neighbouring bins
//! b = 1 + 2Σⱼ ρⱼ (ρⱼ = |Σₙwₙ²e^{−2πijn/W}|²/(Σw²)²; 1.94 for Hann) and of half-overlapping
//! segments o = 1 + 2ρ_{W/2}² (ρ_{W/2} = r(W/2)/r(0); 1.06 for Hann), as a sandwich estimator
//! gives for slowly varying ∂ln E Pₖ.

use std::rc::Rc;
use std::sync::Arc;

use rustfft::num_complex::Complex;
use rustfft::{Fft, FftPlanner};

/// The taper's lag products and FFT, and the two factors of the error model.
#[derive(Clone)]
pub(super) struct Taper {
    /// r(τ), τ = 0 … W − 1.
    lags: Vec<f64>,
    fft: Arc<dyn Fft<f64>>,
    /// wₙe^{−2πin/W}, and its sum W₁ (the taper's transform at bin 1).
    phase: Vec<Complex<f64>>,
    first: Complex<f64>,
    /// b·o of the module header.
    widening: f64,
}

impl Taper {
    /// The Hann taper of `len` frames (the Welch estimate's), made once per length and shared:
    /// an animal alone and every bootstrap resample reuse it.
    pub(super) fn hann(len: usize) -> Taper {
        static MADE: std::sync::OnceLock<
            std::sync::Mutex<std::collections::HashMap<usize, Taper>>,
        > = std::sync::OnceLock::new();
        let made = MADE.get_or_init(Default::default);
        if let Some(t) = made.lock().ok().and_then(|m| m.get(&len).cloned()) {
            return t;
        }
        let t = Taper::new(&super::welch::Plan::new(len).window);
        if let Ok(mut m) = made.lock() {
            m.insert(len, t.clone());
        }
        t
    }

    /// The error model and lag products of the taper `window`.
    pub(super) fn new(window: &[f64]) -> Taper {
        let len = window.len();
        let lags = super::welch::lag_products(window);
        let squares: Vec<f64> = window.iter().map(|w| w * w).collect();
        let total: f64 = squares.iter().sum();
        // Σⱼ |Σₙ wₙ² e^{−2πijn/W}|² over 0 < j < W/2: one transform of the squares.
        let mut z: Vec<Complex<f64>> = squares.iter().map(|&s| Complex::new(s, 0.0)).collect();
        FftPlanner::new().plan_fft_forward(len).process(&mut z);
        let bins: f64 = z
            .iter()
            .take(len / 2)
            .skip(1)
            .map(|z| z.norm_sqr() / (total * total))
            .sum();
        let half = lags.get(len / 2).copied().unwrap_or(0.0) / lags[0];
        let phase: Vec<Complex<f64>> = window
            .iter()
            .enumerate()
            .map(|(n, w)| {
                let a = -2.0 * std::f64::consts::PI * n as f64 / len as f64;
                Complex::new(w * a.cos(), w * a.sin())
            })
            .collect();
        Taper {
            first: phase.iter().sum(),
            phase,
            lags,
            fft: FftPlanner::new().plan_fft_forward(len),
            widening: (1.0 + 2.0 * bins) * (1.0 + 2.0 * half * half),
        }
    }

    fn len(&self) -> usize {
        self.lags.len()
    }

    /// E Pₖ for k = 0 … W/2 at sampling rate `fs` (one-sided, per cycle per time unit), each
    /// segment's mean removed: that changes bin k by −(Wₖ/W)·Σxₙ, Wₖ the taper's own
    /// transform, which for a Hann taper vanishes from k = 2 on; bin 1 is corrected exactly.
    fn expected(&self, p: &Params, fs: f64) -> Vec<f64> {
        self.expected_with(p, fs, true)
    }

    /// E Pₖ with or without each segment's mean removed.
    fn expected_with(&self, p: &Params, fs: f64, mean_removed: bool) -> Vec<f64> {
        let len = self.len();
        let mut c = p.autocovariances(len, 1.0 / fs);
        c[0] += p.noise;
        let mut h: Vec<Complex<f64>> = (0..len)
            .map(|t| {
                let back = if t == 0 {
                    0.0
                } else {
                    c[len - t] * self.lags[len - t]
                };
                Complex::new(c[t] * self.lags[t] + back, 0.0)
            })
            .collect();
        self.fft.process(&mut h);
        if mean_removed {
            self.remove_mean(&c, &mut h[1]);
        }
        let scale = 2.0 / (fs * self.lags[0]);
        h[..=len / 2].iter().map(|z| scale * z.re).collect()
    }

    /// Bin 1's change when each segment's mean is removed, from the autocovariance `c`.
    fn remove_mean(&self, c: &[f64], bin: &mut Complex<f64>) {
        let len = self.len();
        // g(n) = Σₘ c(n − m) over the segment, from the running sums C(j) = Σ_{τ≤j} c(τ).
        let mut run = Vec::with_capacity(len);
        let mut acc = 0.0;
        for v in c {
            acc += v;
            run.push(acc);
        }
        let g: Vec<f64> = (0..len).map(|n| run[n] + run[len - 1 - n] - c[0]).collect();
        let total: f64 = g.iter().sum();
        let cross: Complex<f64> = (0..len).map(|n| self.phase[n] * g[n]).sum();
        let shift = self.first / len as f64;
        *bin += -2.0 * (shift.conj() * cross).re + shift.norm_sqr() * total;
    }
}

/// One damped mode's parameters.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Params {
    omega: f64,
    zeta: f64,
    variance: f64,
    noise: f64,
}

impl Params {
    fn from_log(t: &[f64; 4]) -> Params {
        Params {
            omega: t[0].exp(),
            zeta: t[1].exp(),
            variance: t[2].exp(),
            noise: t[3].exp(),
        }
    }

    /// The oscillator's autocovariance at lags 0, dt, … (len of them), by recurrence: the
    /// under-damped e^{−γt}(cos Ω_d t + γ sin(Ω_d t)/Ω_d) is Re[(1 − iγ/Ω_d) zᵗ] with
    /// z = e^{(−γ + iΩ_d)dt}; the over-damped one is a sum of two decaying exponentials.
    fn autocovariances(&self, len: usize, dt: f64) -> Vec<f64> {
        let g = self.zeta * self.omega;
        let s = self.omega * self.omega * (1.0 - self.zeta * self.zeta);
        let d = s.abs().sqrt();
        let mut out = Vec::with_capacity(len);
        if s > 0.0 && d > 1e-6 * g {
            let step = Complex::from_polar((-g * dt).exp(), d * dt);
            let mut z = Complex::new(self.variance, -self.variance * g / d);
            for _ in 0..len {
                out.push(z.re);
                z *= step;
            }
        } else if s < 0.0 && d > 1e-6 * g {
            // (1 + g/d)/2·e^{−(g−d)t} + (1 − g/d)/2·e^{−(g+d)t}; g − d = Ω²/(g + d) without
            // cancellation.
            let slow = self.omega * self.omega / (g + d);
            let (a, b) = (0.5 * (1.0 + g / d), 0.5 * (1.0 - g / d));
            for t in 0..len {
                let t = t as f64 * dt;
                out.push(self.variance * (a * (-slow * t).exp() + b * (-(g + d) * t).exp()));
            }
        } else {
            // Critical (or nearly): e^{−γt}(1 + γt).
            for t in 0..len {
                let t = t as f64 * dt;
                out.push(self.variance * (-g * t).exp() * (1.0 + g * t));
            }
        }
        out
    }
}

/// One mode's maximum-likelihood spectral fit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct ModeSpectrum {
    /// Natural angular frequency Ω (rad per time unit).
    pub omega: f64,
    /// Its standard error.
    pub omega_error: f64,
    /// Damping ratio ζ.
    pub zeta: f64,
    /// Its standard error.
    pub zeta_error: f64,
    /// The oscillator's variance σ² (tracking noise removed).
    pub variance: f64,
    /// Its standard error.
    pub variance_error: f64,
    /// White tracking-noise variance per frame ν.
    pub noise: f64,
    /// Whether the optimiser converged with a finite, positive-definite information.
    pub converged: bool,
}

/// Lowest fitted bin: bin 0 holds nothing once each segment's mean is removed.
const FIRST_BIN: usize = 1;

/// Whittle's −log-likelihood (up to a constant) of `psd` under `model` over the fitted bins.
fn whittle(psd: &[f64], model: &[f64], bins: std::ops::Range<usize>) -> f64 {
    bins.map(|k| psd[k] / model[k] + model[k].ln()).sum()
}

/// How much better (in −ln L) an optimum above Nyquist must fit than the best one below it to
/// be kept: the χ²₁ 95 % point over 2. Whittle's sum over an average of M periodograms is
/// −ln L divided by M/(b·o) (the taper's and the overlap's correlation, module header).
const ALIAS_MARGIN: f64 = 1.92;

/// Fit one mode's Welch density `psd` (bins 0 … W/2), averaged over `segments` segments at
/// sampling rate `fs`, over the frequency band `band` (cycles per time unit; widened to 8 bins
/// at least), starting from each of `starts` (Ω, ζ) with variance `variance` (the mode's total
/// variance); the best likelihood wins. `None` when no bins can be fitted.
///
/// The band keeps other modes out: a coordinate also holds a little of its neighbours (the
/// N-point modes are not quite the body's), and a far tail of a narrow resonance is so low that
/// such a trace, fitted as this mode's own, would widen it.
pub(super) fn fit_mode(
    taper: &Taper,
    (fs, segments): (f64, f64),
    psd: &[f64],
    starts: &[(f64, f64)],
    variance: f64,
    band: (f64, f64),
) -> Option<ModeSpectrum> {
    let len = taper.len();
    let df = fs / len as f64;
    let last = len / 2;
    if psd.len() != last + 1 || last < FIRST_BIN + 5 || variance.is_nan() || variance <= 0.0 {
        return None;
    }
    // In bins, clamped to the spectrum first (a band of 1e300 bins saturates `as usize`, and
    // the widening below would then step from usize::MAX): at most `last` widening steps.
    let (mut lo, mut hi) = (
        ((band.0 / df).floor() as usize).clamp(FIRST_BIN, last),
        ((band.1 / df).ceil() as usize).clamp(FIRST_BIN, last),
    );
    while hi.saturating_sub(lo) < 8 && (lo > FIRST_BIN || hi < last) {
        lo = (lo - 1).max(FIRST_BIN);
        hi = (hi + 1).min(last);
    }
    let bins = lo..hi;
    // The white level from the highest quarter of the band: where a mode's own spectrum has
    // fallen off, what is left is the tracking noise (or the mode's aliased tail).
    let top = &psd[(3 * len / 8).max(FIRST_BIN)..len / 2];
    let floor = top.iter().sum::<f64>() / top.len().max(1) as f64 * fs / 2.0;
    let nu0 = floor.clamp(variance * 1e-6, variance * 0.5);
    // Bounds on ln θ: Ω from a tenth of a bin to twice the sampling rate; ζ over 1e-4 … 1e3;
    // ν from 1e-12 of the variance (no noise) up.
    let lo = [
        (0.2 * std::f64::consts::PI * df).ln(),
        (1e-4f64).ln(),
        (variance * 1e-8).ln(),
        (variance * 1e-12).ln(),
    ];
    let hi = [
        (4.0 * std::f64::consts::PI * fs).ln(),
        (1e3f64).ln(),
        (variance * 1e4).ln(),
        (variance * 1e4).ln(),
    ];
    let clamp = |t: [f64; 4]| -> [f64; 4] { std::array::from_fn(|i| t[i].clamp(lo[i], hi[i])) };
    let model = Linear::new(taper, fs);
    let nll = |t: &[f64; 4]| -> f64 {
        let e = model.expected(t, &model.shape(t[0], t[1]));
        let v = whittle(psd, &e, bins.clone());
        if v.is_finite() {
            v
        } else {
            f64::INFINITY
        }
    };
    let mut best: Option<([f64; 4], f64)> = None;
    for &(omega, zeta) in starts {
        if !(omega > 0.0 && zeta > 0.0) {
            continue;
        }
        let start = clamp([
            omega.ln(),
            zeta.ln(),
            (variance - nu0).max(variance * 0.1).ln(),
            nu0.ln(),
        ]);
        let (t, v) = descend(start, &nll, &clamp, &model, psd, bins.clone());
        if best.as_ref().is_none_or(|(_, b)| v < *b) {
            best = Some((t, v));
        }
    }
    if let Some(alias) = best.filter(|(t, _)| t[0].exp() > std::f64::consts::PI * fs) {
        let margin = ALIAS_MARGIN * taper.widening / segments.max(1.0);
        let fit = Fit {
            nll: &nll,
            clamp: &clamp,
            model: &model,
            psd,
            bins: bins.clone(),
        };
        if let Some(under) =
            below_nyquist(&fit, alias, starts, fs).filter(|(_, v)| *v <= alias.1 + margin)
        {
            best = Some(under);
        }
    }
    let (t, v) = best?;
    if !v.is_finite() {
        return None;
    }
    let p = Params::from_log(&t);
    let (a, _) = information(&t, &model, psd, bins.clone());
    let scale = taper.widening / segments.max(1.0);
    let se = super::uncertainty::standard_errors(&a, &t, (&lo, &hi), scale);
    let converged = se.is_some();
    let se = se.unwrap_or([f64::INFINITY; 4]);
    Some(ModeSpectrum {
        omega: p.omega,
        omega_error: p.omega * se[0],
        zeta: p.zeta,
        zeta_error: p.zeta * se[1],
        variance: p.variance,
        variance_error: p.variance * se[2],
        noise: p.noise,
        converged,
    })
}

/// What a descent needs: the objective, the bounds, the model and the data over the bins.
struct Fit<'a> {
    nll: &'a dyn Fn(&[f64; 4]) -> f64,
    clamp: &'a dyn Fn([f64; 4]) -> [f64; 4],
    model: &'a Linear<'a>,
    psd: &'a [f64],
    bins: std::ops::Range<usize>,
}

/// The best optimum under Nyquist when the fit `alias` (ln θ, −ln L) lies above it. A start
/// can slide past Nyquist onto an alias of the line: near Nyquist the sampled spectra of a
/// mode and of its reflection about Nyquist differ only in the line's asymmetry. The search
/// starts from the reflection and from each of `starts`, held under Nyquist, then set free
/// again (an optimum under Nyquist stays; one pressed against it leaves); the caller keeps it
/// unless the alias fits better by more than a likelihood-ratio test at 95 % can tell: below
/// Nyquist is the reading a sampling rate chosen for the animal assumes.
fn below_nyquist(
    fit: &Fit<'_>,
    (t, _): ([f64; 4], f64),
    starts: &[(f64, f64)],
    fs: f64,
) -> Option<([f64; 4], f64)> {
    let nyquist = std::f64::consts::PI * fs;
    let below = (0.999 * nyquist).ln();
    let held = |x: [f64; 4]| {
        let mut x = (fit.clamp)(x);
        x[0] = x[0].min(below);
        x
    };
    let folded = t[0].exp() % (2.0 * nyquist);
    let folded = if folded > nyquist {
        2.0 * nyquist - folded
    } else {
        folded
    };
    let tries = std::iter::once((folded, t[1].exp()))
        .chain(starts.iter().copied())
        .filter(|&(omega, zeta)| omega > 0.0 && zeta > 0.0);
    let mut under: Option<([f64; 4], f64)> = None;
    for (omega, zeta) in tries {
        let start = held([omega.ln(), zeta.ln(), t[2], t[3]]);
        let (x, _) = descend(start, fit.nll, &held, fit.model, fit.psd, fit.bins.clone());
        let (x, v) = descend(x, fit.nll, fit.clamp, fit.model, fit.psd, fit.bins.clone());
        if x[0].exp() < nyquist && under.as_ref().is_none_or(|(_, b)| v < *b) {
            under = Some((x, v));
        }
    }
    under
}

/// The model spectrum as it is linear in σ² and ν: E = σ²·S(Ω, ζ) + ν·Z, S the unit-variance
/// oscillator's expected ordinates and Z the unit white noise's (fixed), so that only Ω and ζ
/// need the FFT again.
struct Linear<'a> {
    taper: &'a Taper,
    fs: f64,
    white: Vec<f64>,
    /// The last shape made, by (ln Ω, ln ζ): a descent's accepted step is asked for again at
    /// once, by the information there.
    last: std::cell::RefCell<Option<LastShape>>,
}

/// A shape S and its (ln Ω, ln ζ), by their bits.
type LastShape = ((u64, u64), Rc<Vec<f64>>);

impl<'a> Linear<'a> {
    fn new(taper: &'a Taper, fs: f64) -> Linear<'a> {
        let unit = Params {
            omega: 1.0,
            zeta: 1.0,
            variance: 0.0,
            noise: 1.0,
        };
        Linear {
            taper,
            fs,
            white: taper.expected(&unit, fs),
            last: std::cell::RefCell::new(None),
        }
    }

    /// S(Ω, ζ) at ln Ω = `a`, ln ζ = `b`.
    fn shape(&self, a: f64, b: f64) -> Rc<Vec<f64>> {
        let key = (a.to_bits(), b.to_bits());
        if let Some((k, s)) = self.last.borrow().as_ref() {
            if *k == key {
                return Rc::clone(s);
            }
        }
        let p = Params {
            omega: a.exp(),
            zeta: b.exp(),
            variance: 1.0,
            noise: 0.0,
        };
        let s = Rc::new(self.taper.expected(&p, self.fs));
        *self.last.borrow_mut() = Some((key, Rc::clone(&s)));
        s
    }

    /// E at θ = `t` from its shape `s`.
    fn expected(&self, t: &[f64; 4], s: &[f64]) -> Vec<f64> {
        let (var, nu) = (t[2].exp(), t[3].exp());
        s.iter()
            .zip(&self.white)
            .map(|(s, w)| var * s + nu * w)
            .collect()
    }
}

/// Each bin's J = ∂ln E/∂θ and residual P/E − 1 at `t`: by forward differences in ln Ω and
/// ln ζ, exactly in ln σ² and ln ν.
fn scores(
    t: &[f64; 4],
    model: &Linear<'_>,
    psd: &[f64],
    bins: std::ops::Range<usize>,
) -> Vec<([f64; 4], f64)> {
    let step = 1e-6;
    let s = model.shape(t[0], t[1]);
    let s_omega = model.shape(t[0] + step, t[1]);
    let s_zeta = model.shape(t[0], t[1] + step);
    let e = model.expected(t, &s);
    let (var, nu) = (t[2].exp(), t[3].exp());
    bins.map(|k| {
        let j = [
            var * (s_omega[k] - s[k]) / step / e[k],
            var * (s_zeta[k] - s[k]) / step / e[k],
            var * s[k] / e[k],
            nu * model.white[k] / e[k],
        ];
        (j, psd[k] / e[k] - 1.0)
    })
    .collect()
}

/// The Fisher information A = Σ JJᵀ and the score direction Σ J(P/E − 1) at `t`.
fn information(
    t: &[f64; 4],
    model: &Linear<'_>,
    psd: &[f64],
    bins: std::ops::Range<usize>,
) -> ([[f64; 4]; 4], [f64; 4]) {
    let mut a = [[0.0; 4]; 4];
    let mut b = [0.0; 4];
    for (j, r) in scores(t, model, psd, bins) {
        for i in 0..4 {
            b[i] += j[i] * r;
            for l in 0..4 {
                a[i][l] += j[i] * j[l];
            }
        }
    }
    (a, b)
}

/// Levenberg–Marquardt descent of `nll` from `start`; returns the last point and its value.
fn descend(
    start: [f64; 4],
    nll: &dyn Fn(&[f64; 4]) -> f64,
    clamp: &dyn Fn([f64; 4]) -> [f64; 4],
    model: &Linear<'_>,
    psd: &[f64],
    bins: std::ops::Range<usize>,
) -> ([f64; 4], f64) {
    let (mut t, mut v) = (start, nll(&start));
    let mut mu = 1e-3;
    for _ in 0..200 {
        let (a, b) = information(&t, model, psd, bins.clone());
        let mut moved = false;
        while mu < 1e12 {
            let mut damped = a;
            for (i, row) in damped.iter_mut().enumerate() {
                row[i] += mu * a[i][i] + 1e-12;
            }
            let Some(step) = solve4(&damped, &b) else {
                mu *= 10.0;
                continue;
            };
            let cand = clamp(std::array::from_fn(|i| t[i] + step[i]));
            let w = nll(&cand);
            if w < v {
                let size = (0..4).map(|i| (cand[i] - t[i]).abs()).fold(0.0, f64::max);
                let gain = v - w;
                (t, v) = (cand, w);
                mu = (mu / 3.0).max(1e-9);
                moved = size > 1e-9 && gain > 1e-12 * v.abs().max(1.0);
                break;
            }
            mu *= 4.0;
        }
        if !moved {
            break;
        }
    }
    (t, v)
}

/// Solve the 4 × 4 system `a x = b` (LU with partial pivoting); `None` when it is singular.
fn solve4(a: &[[f64; 4]; 4], b: &[f64; 4]) -> Option<[f64; 4]> {
    let m = nalgebra::Matrix4::from_fn(|i, j| a[i][j]);
    let x = m.lu().solve(&nalgebra::Vector4::from_column_slice(b))?;
    x.iter()
        .all(|v| v.is_finite())
        .then(|| [x[0], x[1], x[2], x[3]])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_expected_spectrum_integrates_to_the_variance() {
        // Σₖ E Pₖ·df over the whole band = σ² + ν (Parseval, the taper normalised out).
        let taper = Taper::new(&super::super::welch::Plan::new(128).window);
        let p = Params {
            omega: 1.1,
            zeta: 0.15,
            variance: 3.0,
            noise: 0.5,
        };
        let fs = 2.0;
        let e = taper.expected_with(&p, fs, false);
        let df = fs / 128.0;
        // One-sided: the end bins count once, the others twice (already doubled).
        let total: f64 = e.iter().sum::<f64>() * df - 0.5 * (e[0] + e[64]) * df;
        assert!((total - 3.5).abs() < 1e-6 * 3.5, "{total}");
    }
}
