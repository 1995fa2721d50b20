//! A nonlinear body's linearisation: each field's equilibrium u* (∇V(u*) = 0, by Newton's method
//! from rest with a least-squares step, so zero modes such as a translation do no harm) and the
//! modes of ∇²V(u*) with the unit mass of the standard kinetic term, frequencies √λ.

use super::nonlinear::{FieldSystem, NonlinearBody, NonlinearError};

/// One field's linearisation.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct LinearisedField {
    /// Field id.
    pub field: String,
    /// u* at each point (zero where held; around a ring at each unknown).
    pub equilibrium: Vec<f64>,
    /// |∇V(u*)| reached.
    pub residual: f64,
    /// Eigenvalues of ∇²V(u*), ascending.
    pub eigenvalues: Vec<f64>,
    /// √λ, or `None` where λ < 0 (an unstable direction).
    pub frequencies: Vec<Option<f64>>,
    /// Unit-norm shapes, one per eigenvalue (when asked for), on the points as `equilibrium`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub shapes: Option<Vec<Vec<f64>>>,
    /// With damping: the roots λ = −σ ± iω of det(λ²M + λC + K) = 0, one per conjugate pair
    /// (an over-damped mode gives two real roots), slowest first; with active forces, of
    /// det(λ²M + λ(C − ∂f/∂v) + K − ∂f/∂u) = 0, where σ < 0 is growth.
    pub damped: Vec<DampedMode>,
    /// Whether active forces act on the field (then `damped` holds them).
    pub active: bool,
    /// When a root grows: its fastest growth on N points against 2N ([`check_growth`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub growth: Option<GrowthCheck>,
    /// Whether the stiffness with the active forces is a centred stencil past its grid Péclet
    /// number ([`sign_changing_stencil`]).
    #[serde(skip)]
    pub peclet: bool,
}

/// A field's fastest growth rate −σ on N points against the same body on 2N: past a grid
/// Péclet number a centred stencil makes growth the continuum does not have (a ∂s x + c ∂s² x
/// on a free-ended body: a Sturm–Liouville problem with weight e^{as/c}, a real spectrum), and
/// that growth changes with N.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct GrowthCheck {
    /// The points compared against (2N).
    pub points: usize,
    /// The fastest growth rate on N points (> 0).
    pub growth: f64,
    /// On 2N points (0 when no root grows there); `None` when 2N could not be solved (over
    /// the points or the eigen-solves' budget).
    pub doubled: Option<f64>,
    /// Whether the two agree within 20 % of the larger.
    pub converged: bool,
    /// Whether the field's stencil is past its grid Péclet number: then the growth is the
    /// stencil's at every N (lattice units keep |a|h/2c as N doubles).
    pub grid_peclet: bool,
}

impl LinearisedField {
    /// The fastest growth rate −σ of the damped roots, if a root grows faster than the printed
    /// precision (5·10⁻⁷).
    pub fn fastest_growth(&self) -> Option<f64> {
        self.damped
            .iter()
            .map(|d| -d.decay_rate)
            .filter(|&g| g >= 5e-7)
            .max_by(f64::total_cmp)
    }
}

/// Set each growing field's [`GrowthCheck`] of `fields` (on N points) against `doubled`, the
/// same body's fields on `points` = 2N (`None`: not solved).
pub fn check_growth(
    fields: &mut [LinearisedField],
    points: usize,
    doubled: Option<&[LinearisedField]>,
) {
    for f in fields.iter_mut() {
        let Some(growth) = f.fastest_growth() else {
            continue;
        };
        let doubled = doubled.map(|d| {
            d.iter()
                .find(|g| g.field == f.field)
                .and_then(LinearisedField::fastest_growth)
                .unwrap_or(0.0)
        });
        f.growth = Some(GrowthCheck {
            points,
            growth,
            doubled,
            converged: doubled.is_some_and(|g| (g - growth).abs() <= 0.2 * g.max(growth)),
            grid_peclet: f.peclet,
        });
    }
}

impl GrowthCheck {
    /// One line under the roots: converged, or the grid's (compare at 2N); then whether the
    /// stencil is past its grid Péclet number.
    fn text(&self, points: usize) -> String {
        let line = self.convergence(points);
        if self.grid_peclet {
            return format!("{line}\n  the stencil is past its grid Péclet number (off-diagonals of opposite signs: |a|h/2c > 1): a centred ∂s this strong against ∂s² grows where the continuum (weight e^{{as/c}}, a real spectrum on a free-ended body) does not, at every N: the growth is the grid's");
        }
        line
    }

    fn convergence(&self, points: usize) -> String {
        let n = self.points;
        match self.doubled {
            None => format!(
                "fastest growth −σ = {:.6} on {points} points, not compared on {n} (over the limits): it may be the grid's",
                self.growth
            ),
            Some(g) if self.converged => format!(
                "fastest growth −σ = {:.6} on {points} points, {g:.6} on {n}: the same within 20 %",
                self.growth
            ),
            Some(g) => format!(
                "fastest growth −σ = {:.6} on {points} points, {g:.6} on {n}: not converged in N: compare --points {n} (growth that moves with N is the grid's or rounding's, not the body's)",
                self.growth
            ),
        }
    }
}

/// One root of the quadratic eigenproblem (λ²M + λC + K)x = 0, λ = −σ ± iω.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct DampedMode {
    /// σ = −Re λ, the decay rate of the amplitude (per unit time).
    pub decay_rate: f64,
    /// ω = |Im λ|, the damped angular frequency (0 for an over-damped root).
    pub frequency: f64,
}

/// The budget of a linearisation's quadratic eigenproblems: Σ(2n)³ over the fields whose damped
/// roots are solved (a 2n × 2n real Schur form each), checked before any of them; four fields of
/// 400 unknowns (about two seconds on two loaded cores).
pub const MAX_DAMPED_WORK: f64 = 2.1e9;

impl FieldSystem {
    pub(super) fn gradient_at(&self, u: &[f64]) -> Vec<f64> {
        let mut g = vec![0.0; self.unknowns];
        for p in &self.potential {
            p.gradient(u, 1.0, &mut g);
        }
        g
    }

    /// ∇²V(u), refused when not finite: nalgebra's SVD and eigensolvers never return on one.
    pub(super) fn hessian_at(&self, u: &[f64]) -> Result<nalgebra::DMatrix<f64>, NonlinearError> {
        let mut h = nalgebra::DMatrix::zeros(self.unknowns, self.unknowns);
        for p in &self.potential {
            p.hessian(u, 1.0, &mut |i, j, x| h[(i, j)] += x);
        }
        self.finite(h, "the potential's Hessian ∇²V")
    }

    /// `m` when every entry is finite.
    pub(super) fn finite(
        &self,
        m: nalgebra::DMatrix<f64>,
        what: &'static str,
    ) -> Result<nalgebra::DMatrix<f64>, NonlinearError> {
        if m.iter().all(|x| x.is_finite()) {
            Ok(m)
        } else {
            Err(NonlinearError::Overflow {
                field: self.id.clone(),
                what,
            })
        }
    }

    /// u* with ∇V(u*) = 0, from rest: Newton's least-squares steps, halved while |∇V| grows.
    pub fn equilibrium(&self) -> Result<(Vec<f64>, f64), NonlinearError> {
        let norm = |g: &[f64]| g.iter().map(|x| x * x).sum::<f64>().sqrt();
        let scale = self
            .potential
            .iter()
            .map(|p| p.coefficient.abs())
            .fold(0.0, f64::max)
            .max(f64::MIN_POSITIVE);
        let mut u = vec![0.0; self.unknowns];
        let mut g = self.gradient_at(&u);
        let mut r = norm(&g);
        for _ in 0..200 {
            if r <= 1e-12 * scale * (self.unknowns as f64).sqrt() {
                return Ok((u, r));
            }
            let step = self
                .hessian_at(&u)?
                .svd(true, true)
                .solve(&nalgebra::DVector::from_column_slice(&g), 1e-12 * scale);
            let Ok(step) = step else { break };
            let mut t = 1.0;
            loop {
                let trial: Vec<f64> = u.iter().zip(step.iter()).map(|(a, d)| a - t * d).collect();
                let gt = self.gradient_at(&trial);
                if norm(&gt) < r || t < 1e-6 {
                    (u, g, r) = (trial, gt.clone(), norm(&gt));
                    break;
                }
                t *= 0.5;
            }
            if !r.is_finite() {
                break;
            }
        }
        Err(NonlinearError::NoEquilibrium {
            field: self.id.clone(),
            residual: r,
        })
    }

    /// The linearisation about the equilibrium: eigenvalues ascending, shapes unit norm with
    /// their first significant component positive (as `modes` prints them); with kinetic terms
    /// beyond ½|v|², the modes of K x = λ M x, M = ∇²T(0), shapes of unit M-norm.
    pub fn linearise(&self, shapes: bool) -> Result<LinearisedField, NonlinearError> {
        self.linearise_with(shapes, true)
    }

    /// [`Self::linearise`] without the damped roots (`damped` empty): the modes and the
    /// equilibrium alone, for a modal initial state or force (their quadratic eigenproblem is
    /// the linearisation's costliest part, (2n)³).
    pub fn undamped(&self, shapes: bool) -> Result<LinearisedField, NonlinearError> {
        self.linearise_with(shapes, false)
    }

    fn linearise_with(
        &self,
        shapes: bool,
        damped: bool,
    ) -> Result<LinearisedField, NonlinearError> {
        let (equilibrium, residual) = self.equilibrium()?;
        // With a mass M = ∇²T(0) other than I: K x = λ M x through M = LLᵀ, the symmetric
        // problem L⁻¹KL⁻ᵀ y = λ y, x = L⁻ᵀ y (so xᵀMx = 1).
        let stiffness = self.hessian_at(&equilibrium)?;
        let mass = self.finite(self.mass(&vec![0.0; self.unknowns]), "the mass ∇²T(0)")?;
        // M = LLᵀ, factored once for the modes and the damped roots.
        let factor = if self.kinetic.is_empty() {
            None
        } else {
            Some(
                mass.clone()
                    .cholesky()
                    .ok_or_else(|| NonlinearError::NotPositiveMass {
                        field: self.id.clone(),
                    })?,
            )
        };
        let (damped, peclet) = if damped {
            self.damped_modes(&stiffness, &equilibrium, factor.as_ref())?
        } else {
            (Vec::new(), false)
        };
        let cholesky = factor.map(|c| c.l());
        let (reduced, back) = match &cholesky {
            None => (stiffness, None),
            Some(l) => {
                let inv =
                    l.clone()
                        .try_inverse()
                        .ok_or_else(|| NonlinearError::NotPositiveMass {
                            field: self.id.clone(),
                        })?;
                (&inv * stiffness * inv.transpose(), Some(inv.transpose()))
            }
        };
        let eigen = self
            .finite(reduced, "the reduced stiffness")?
            .symmetric_eigen();
        let mut order: Vec<usize> = (0..self.unknowns).collect();
        order.sort_by(|&a, &b| eigen.eigenvalues[a].total_cmp(&eigen.eigenvalues[b]));
        // A zero mode (a translation) comes out as ±1e-16: it is zero, not unstable.
        let top = eigen
            .eigenvalues
            .iter()
            .map(|l| l.abs())
            .fold(0.0, f64::max);
        let eigenvalues: Vec<f64> = order
            .iter()
            .map(|&k| eigen.eigenvalues[k])
            .map(|l| if l.abs() <= 1e-10 * top { 0.0 } else { l })
            .collect();
        let shape = |k: usize| -> Vec<f64> {
            let y = eigen.eigenvectors.column(k);
            let v: Vec<f64> = match &back {
                None => y.iter().copied().collect(),
                Some(b) => (b * y).iter().copied().collect(),
            };
            let first = v.iter().find(|x| x.abs() > 1e-12).copied().unwrap_or(1.0);
            v.iter().map(|x| x * first.signum()).collect()
        };
        Ok(LinearisedField {
            field: self.id.clone(),
            equilibrium: self.embed(&equilibrium),
            residual,
            damped,
            active: !self.active.is_empty(),
            growth: None,
            peclet,
            frequencies: eigenvalues
                .iter()
                .map(|&l| (l >= 0.0).then(|| l.sqrt()))
                .collect(),
            eigenvalues,
            shapes: shapes.then(|| order.iter().map(|&k| self.embed(&shape(k))).collect()),
        })
    }
}

impl FieldSystem {
    /// ∇²R(v), dense.
    pub(super) fn damping_at(&self, v: &[f64]) -> nalgebra::DMatrix<f64> {
        let mut c = nalgebra::DMatrix::zeros(self.unknowns, self.unknowns);
        for p in &self.dissipation {
            p.hessian(v, 1.0, &mut |i, j, x| c[(i, j)] += x);
        }
        c
    }

    /// The roots of det(λ²M + λC + K) = 0 with C = ∇²R(0), from the companion matrix
    /// [[0, I], [−M⁻¹K, −M⁻¹C]] (its real Schur form): none without damping or active forces,
    /// where they are ±i√λ of the modes above. Active forces enter as −∂f/∂u in K and −∂f/∂v
    /// in C: neither is symmetric, so a travelling pair splits into two roots of different
    /// frequency, and a root may grow (a negative decay rate).
    fn damped_modes(
        &self,
        stiffness: &nalgebra::DMatrix<f64>,
        equilibrium: &[f64],
        mass: Option<&nalgebra::linalg::Cholesky<f64, nalgebra::Dyn>>,
    ) -> Result<(Vec<DampedMode>, bool), NonlinearError> {
        let n = self.unknowns;
        if self.damped_work() == 0.0 {
            return Ok((Vec::new(), false));
        }
        let mut damping = self.damping_at(&vec![0.0; n]);
        let mut stiffness = stiffness.clone();
        let (mut du, mut dv) = (
            nalgebra::DMatrix::zeros(n, n),
            nalgebra::DMatrix::zeros(n, n),
        );
        for a in &self.active {
            a.jacobians((equilibrium, &vec![0.0; n]), &mut du, &mut dv);
        }
        stiffness -= du;
        damping -= dv;
        let stiffness = &self.finite(stiffness, "the stiffness with the active forces")?;
        let damping = self.finite(damping, "the damping ∇²R(0)")?;
        let (mk, mc) = match mass {
            None => (stiffness.clone(), damping),
            Some(chol) => (chol.solve(stiffness), chol.solve(&damping)),
        };
        // λ = sμ with s a power of two near the roots' size (√‖M⁻¹K‖, ‖M⁻¹C‖): the companion
        // of μ²M + μC/s + K/s² has entries of order one, where [[0, I], [−M⁻¹K, −M⁻¹C]]
        // mixes 1 with ‖K‖ and its QR iteration loses the decay rates to ε‖K‖ (exact scaling).
        let size = mk.amax().sqrt().max(mc.amax());
        let s = if size.is_finite() && size > 0.0 {
            2f64.powi(size.log2().round() as i32)
        } else {
            1.0
        };
        let a = faer::Mat::<f64>::from_fn(2 * n, 2 * n, |i, j| match (i < n, j < n) {
            (true, true) => 0.0,
            (true, false) => f64::from(u8::from(j - n == i)),
            (false, true) => -mk[(i - n, j)] / s / s,
            (false, false) => -mc[(i - n, j - n)] / s,
        });
        if !a.col_iter().all(|c| c.iter().all(|x| x.is_finite())) {
            return Err(NonlinearError::Overflow {
                field: self.id.clone(),
                what: "the companion matrix of λ²M + λC + K",
            });
        }
        // faer's blocked Hessenberg–QR (nalgebra's unblocked Schur took 8 s at n = 400).
        let scaled = a.eigenvalues().map_err(|_| NonlinearError::Overflow {
            field: self.id.clone(),
            what: "the quadratic eigenproblem's QR iteration (it did not converge)",
        })?;
        let eigenvalues: Vec<_> = scaled.iter().map(|l| (l.re * s, l.im * s)).collect();
        // A root within rounding of the origin is on it (a double root at 0 splits by about
        // √ε·‖A‖, 1.5·10⁻⁸ of the roots' size s); of a conjugate pair the upper one is kept, and
        // every real root (a double root may come as a pair ±ε·i). A real part within 10⁻¹⁰·s
        // is 0 (a simple root's rounding is ε·s times its condition).
        let tol = 1e-7 * s;
        let roots: Vec<DampedMode> = eigenvalues
            .iter()
            .filter(|l| l.1 > -tol)
            .map(|&(re, im)| DampedMode {
                decay_rate: if re.abs() <= tol && im.abs() <= tol || re.abs() <= 1e-10 * s {
                    0.0
                } else {
                    -re
                },
                frequency: if im <= tol { 0.0 } else { im },
            })
            .collect();
        let roots = self.trusted(roots, -(0..n).map(|i| mc[(i, i)]).sum::<f64>(), s)?;
        Ok((roots, sign_changing_stencil(&mk)))
    }

    /// `roots` if their real parts (a conjugate pair's twice) add up to the companion matrix's
    /// trace −tr(M⁻¹C) within 10⁻³ of it and 10⁻⁶ per root (the printed precision): where
    /// the coefficients dwarf the damping, the decay rates are lost to rounding in ε·s.
    fn trusted(
        &self,
        mut roots: Vec<DampedMode>,
        trace: f64,
        size: f64,
    ) -> Result<Vec<DampedMode>, NonlinearError> {
        let sum: f64 = roots
            .iter()
            .map(|r| -r.decay_rate * if r.frequency > 0.0 { 2.0 } else { 1.0 })
            .sum();
        let allowed = 1e-3 * trace.abs() + 1e-6 * 2.0 * self.unknowns as f64;
        if (sum - trace).abs() > allowed || !sum.is_finite() {
            return Err(NonlinearError::Untrusted {
                field: self.id.clone(),
                sum,
                trace,
                size,
            });
        }
        roots.sort_by(|a, b| {
            a.decay_rate
                .hypot(a.frequency)
                .total_cmp(&b.decay_rate.hypot(b.frequency))
        });
        Ok(roots)
    }
}

impl FieldSystem {
    /// (2n)³ of the field's quadratic eigenproblem, 0 without one (no damping or active forces).
    fn damped_work(&self) -> f64 {
        let quiet = self.dissipation.is_empty() && self.active.is_empty();
        if quiet {
            0.0
        } else {
            (2.0 * self.unknowns as f64).powi(3)
        }
    }
}

impl NonlinearBody {
    /// Every field's linearisation, its damped roots' budget ([`MAX_DAMPED_WORK`]) checked first.
    pub fn linearise(&self, shapes: bool) -> Result<Vec<LinearisedField>, NonlinearError> {
        let work: f64 = self.fields.iter().map(FieldSystem::damped_work).sum();
        if work > MAX_DAMPED_WORK {
            return Err(NonlinearError::DampedBudget {
                fields: self.fields.iter().filter(|f| f.damped_work() > 0.0).count(),
                work,
                budget: MAX_DAMPED_WORK,
            });
        }
        self.fields.iter().map(|f| f.linearise(shapes)).collect()
    }
}

/// Whether `k` is tridiagonal with a pair of off-diagonals of opposite signs: a centred ∂s
/// stencil a∂s against c∂s² past the grid Péclet number |a|h/2c = 1 (lattice units: |a| > 2c).
/// A tridiagonal matrix whose pairs have one sign is similar to a symmetric one (real
/// spectrum, as the continuum's Sturm–Liouville problem with weight e^{as/c}); past it, it is
/// not, and its complex roots grow where the continuum does not.
fn sign_changing_stencil(k: &nalgebra::DMatrix<f64>) -> bool {
    let n = k.nrows();
    let tridiagonal = (0..n).all(|i| (0..n).all(|j| i.abs_diff(j) <= 1 || k[(i, j)] == 0.0));
    tridiagonal && (1..n).any(|i| k[(i - 1, i)] * k[(i, i - 1)] < 0.0)
}

/// `modes` of a nonlinear body: each field's linearisation about its equilibrium.
#[derive(Debug, Clone, serde::Serialize)]
pub struct LinearisedReport {
    /// Model name.
    pub model: String,
    /// Order of the theory.
    pub order: u32,
    /// Points along the body.
    pub points: usize,
    /// Always true: these are the modes of a linearisation (or of a linear body whose damping
    /// is not modal).
    pub linearised: bool,
    /// Whether the equations are nonlinear (false: linear, with damping that is not modal).
    pub nonlinear: bool,
    /// The fields.
    pub fields: Vec<LinearisedField>,
}

impl crate::report::Report for LinearisedReport {
    fn text(&self) -> String {
        use std::fmt::Write as _;
        let mut s = if self.fields.iter().any(|f| f.active) {
            format!(
                "Modes of the {} model at order {} on {} points with active forces on: their operator is not symmetric, so these are the modes of K = ∇²V (frequency √λ) and then the complex roots λ = −σ ± iω the active forces give (σ < 0 grows; a travelling pair splits).\n",
                self.model, self.order, self.points
            )
        } else if self.nonlinear {
            format!(
                "Linearised modes of the {} model at order {} on {} points: the equations are nonlinear, so these are the modes of ∇²V about each field's equilibrium (unit mass; frequency √λ).\n",
                self.model, self.order, self.points
            )
        } else {
            format!(
                "Modes of the {} model at order {} on {} points: the equations are linear, but a field's damping is not on its stiffness operator (not modal), so these are the modes of K = ∇²V (frequency √λ) and, with damping, the roots λ = −σ ± iω of λ²M + λC + K.\n",
                self.model, self.order, self.points
            )
        };
        for f in &self.fields {
            let (lo, hi) = f
                .equilibrium
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| {
                    (a.min(x), b.max(x))
                });
            let at = if lo == 0.0 && hi == 0.0 {
                "at rest (u = 0)".to_string()
            } else {
                format!("u* from {lo:.6} to {hi:.6} (|∇V| = {:.1e})", f.residual)
            };
            let _ = writeln!(s, "\nfield {}: equilibrium {at}", f.field);
            let _ = writeln!(s, "  mode  eigenvalue      frequency");
            for (i, (l, w)) in f.eigenvalues.iter().zip(&f.frequencies).enumerate() {
                let w = w.map_or("unstable".to_string(), |w| format!("{w:.6}"));
                let _ = writeln!(s, "  {i:>4}  {l:<14.6}  {w}");
            }
            if !f.damped.is_empty() {
                let _ = match f.active {
                    true => writeln!(s, "  with the active forces (roots of λ²M + λ(C − ∂f/∂v) + K − ∂f/∂u, slowest first; σ < 0 grows):"),
                    false => writeln!(s, "  damped (roots of λ²M + λC + K, slowest first):"),
                };
                let _ = writeln!(s, "  root  decay rate σ   frequency ω");
                for (i, d) in f.damped.iter().enumerate() {
                    let _ = writeln!(s, "  {i:>4}  {:<13.6}  {:.6}", d.decay_rate, d.frequency);
                }
                if let Some(g) = &f.growth {
                    let _ = writeln!(s, "  {}", g.text(self.points));
                }
            }
            if let Some(shapes) = &f.shapes {
                for (i, v) in shapes.iter().enumerate() {
                    let cells: Vec<String> = v.iter().map(|x| format!("{x:.6}")).collect();
                    let _ = writeln!(s, "  shape {i}: {}", cells.join(" "));
                }
            }
        }
        s
    }

    fn json(&self) -> serde_json::Value {
        serde_json::to_value(self).unwrap_or_default()
    }

    fn check(&self) -> Result<(), crate::report::NonFinite> {
        crate::report::check_finite(self)
    }
}
