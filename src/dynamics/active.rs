//! A model's active forces on the grid: f = a·Π (∂tᵃ∂sᵇφ)ᵖ at each point, per unit mass, as
//! `equations` prints them (`a_y ∂s³ y`).
//!
//! **Discretisation.** Each factor's derivative is the centred difference at the point, in
//! units of the point spacing like the potential's stencils: ∂s²ᵐ the m-fold (1, −2, 1), ∂s²ᵐ⁺¹
//! that convolved with (−½, 0, ½), on the unknowns (u) or the velocities (v = ∂tφ). Around a
//! ring every point has its stencil. With ends, the stated rule: **a point whose centred stencil
//! would leave the body feels no active force** (a free end's natural conditions make ∂s φ,
//! and for a beam ∂s²φ and ∂s³φ, vanish there; held points are zeros and may be read), but for
//! the gyroscopic g∂t∂sᵇφ, b odd (`closes_skew`): there it reads its stencil on the points
//! whose stencil fits, so its matrix B is skew, v·Bv = 0, and it does no work at the ends. No
//! force is a gradient here, so the Newton matrix of a step does not hold it (the matrices are
//! symmetric): its part of the step converges at the rate h²‖∂f/∂u‖/4 + h‖∂f/∂v‖/2 against the
//! rest, and a step too large for that says so (`NoConvergence`).
//!
//! **Power.** In the average-vector-field step the force enters at the midpoint
//! (ū = u₀ + Δ/2, v̄ = Δ/h), so the discrete energy balance is exact:
//! E₁ − E₀ = −h v̄·∇R(v̄) + h v̄·f(ū, v̄), the second term the work the active forces inject
//! (zero, to rounding, for a skew force).

use crate::boundary::Boundary;
use crate::discretise::centred;
use crate::term::Term;

/// One factor (∂tᵃ∂sᵇφ)ᵖ: its stencil row at each unknown.
#[derive(Debug, Clone)]
struct Factor {
    /// Read the velocities (a = 1) or the field (a = 0).
    velocity: bool,
    power: i32,
    /// The row at each unknown (empty where the force is off).
    rows: Vec<Vec<(usize, f64)>>,
}

/// One active force term on one field's unknowns.
#[derive(Debug, Clone)]
pub struct ActiveForce {
    coefficient: f64,
    factors: Vec<Factor>,
    /// The unknowns the force acts at (every factor's stencil on the body).
    live: Vec<bool>,
}

impl ActiveForce {
    /// The force `coefficient · term` (placeholder field 0, time derivatives ≤ 1) on a field of
    /// `points` points with `boundary`, `held` points at its ends and `unknowns` unknowns.
    /// `None` for a factor with two time derivatives or more (inertia: OST keeps it out).
    pub fn new(
        term: &Term,
        coefficient: f64,
        (points, unknowns): (usize, usize),
        boundary: Boundary,
        held: (usize, usize),
    ) -> Option<ActiveForce> {
        let mut live = vec![true; unknowns];
        let skew = crate::active::closes_skew(term);
        let mut factors = Vec::new();
        for f in term.factors() {
            if f.deriv.t > 1 {
                return None;
            }
            let w = centred(f.deriv.s);
            let r = w.len() / 2;
            let rows = (0..unknowns)
                .map(|i| {
                    if boundary == Boundary::Periodic {
                        let at = |k: usize| (i + unknowns * (r + 1) + k - r) % unknowns;
                        return w.iter().enumerate().map(|(k, &x)| (at(k), x)).collect();
                    }
                    let p = i + held.0;
                    let fits = |q: usize| q >= r && q + r < points;
                    if !fits(p) && !skew {
                        live[i] = false;
                        return Vec::new();
                    }
                    // Where the stencil leaves the body, a skew force reads it where it fits.
                    w.iter()
                        .enumerate()
                        .filter_map(|(k, &x)| {
                            let q = (p + k).checked_sub(r)?;
                            let on = (held.0..held.0 + unknowns).contains(&q);
                            (x != 0.0 && on && (fits(p) || fits(q))).then(|| (q - held.0, x))
                        })
                        .collect()
                })
                .collect();
            factors.push(Factor {
                velocity: f.deriv.t == 1,
                power: f.power as i32,
                rows,
            });
        }
        Some(ActiveForce {
            coefficient,
            factors,
            live,
        })
    }

    fn factor_value(f: &Factor, i: usize, u: &[f64], v: &[f64]) -> f64 {
        let w = if f.velocity { v } else { u };
        f.rows[i].iter().map(|&(j, x)| x * w[j]).sum()
    }

    /// Adds `scale` × f(u, v) into `out`.
    pub fn add(&self, u: &[f64], v: &[f64], scale: f64, out: &mut [f64]) {
        let c = scale * self.coefficient;
        for (i, o) in out.iter_mut().enumerate() {
            if self.live[i] {
                let product: f64 = self
                    .factors
                    .iter()
                    .map(|f| Self::factor_value(f, i, u, v).powi(f.power))
                    .product();
                *o += c * product;
            }
        }
    }

    /// Adds ∂f/∂u into `du` and ∂f/∂v into `dv` at (u, v), dense.
    pub fn jacobians(
        &self,
        (u, v): (&[f64], &[f64]),
        du: &mut nalgebra::DMatrix<f64>,
        dv: &mut nalgebra::DMatrix<f64>,
    ) {
        for i in (0..u.len()).filter(|&i| self.live[i]) {
            let values: Vec<f64> = self
                .factors
                .iter()
                .map(|f| Self::factor_value(f, i, u, v))
                .collect();
            for (k, f) in self.factors.iter().enumerate() {
                // ∂/∂(row·w) of Π (row·w)ᵖ: p (row·w)ᵖ⁻¹ times the other factors.
                let others: f64 = values
                    .iter()
                    .zip(&self.factors)
                    .enumerate()
                    .filter(|&(m, _)| m != k)
                    .map(|(_, (x, g))| x.powi(g.power))
                    .product();
                let d =
                    self.coefficient * f64::from(f.power) * values[k].powi(f.power - 1) * others;
                let into = if f.velocity { &mut *dv } else { &mut *du };
                for &(j, x) in &f.rows[i] {
                    into[(i, j)] += d * x;
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::DMatrix;

    #[test]
    fn a_cubic_is_differentiated_exactly_inside_and_off_near_free_ends() {
        // ∂s³ of s³ is 6 at every point whose stencil fits; the two points at each end are off.
        let term: Term = "(∂sss φ)".parse().unwrap();
        let f = ActiveForce::new(&term, 1.0, (9, 9), Boundary::FREE, (0, 0)).unwrap();
        let u: Vec<f64> = (0..9).map(|i| f64::from(i).powi(3)).collect();
        let mut out = vec![0.0; 9];
        f.add(&u, &[0.0; 9], 1.0, &mut out);
        let expect = [0.0, 0.0, 6.0, 6.0, 6.0, 6.0, 6.0, 0.0, 0.0];
        assert!(out.iter().zip(&expect).all(|(a, b)| (a - b).abs() < 1e-12));
    }

    #[test]
    fn gyroscopic_forces_are_skew_at_every_end() {
        // ∂v f = B: skew for ∂ts and ∂tsss at free ends and with held points; off at free ends
        // (B's end rows empty) it would not be.
        for (term, held) in [
            ("(∂ts φ)", (0, 0)),
            ("(∂tsss φ)", (0, 0)),
            ("(∂tsss φ)", (1, 1)),
        ] {
            let term: Term = term.parse().unwrap();
            let n = 9 - held.0 - held.1;
            let f = ActiveForce::new(&term, 0.7, (9, n), Boundary::FREE, held).unwrap();
            let (mut du, mut b) = (DMatrix::zeros(n, n), DMatrix::zeros(n, n));
            f.jacobians((&vec![0.0; n], &vec![0.0; n]), &mut du, &mut b);
            assert!((&b + b.transpose()).amax() < 1e-15, "{term:?}: {b}");
            assert!(b.row(0).amax() > 0.0 && du.amax() == 0.0);
        }
    }
}
