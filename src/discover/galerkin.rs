//! Each linear library force as a matrix on the modes the recording is projected on: the
//! body's continuum modes where the field has them, else the grid's.
//!
//! **Continuum.** For a force linear in the field, f = L u + L′ u̇, the modal equations of the
//! continuum body are q̈ᵢ = Σⱼ (⟨φᵢ, L φⱼ⟩ qⱼ + ⟨φᵢ, L′ φⱼ⟩ q̇ⱼ) + …, with φⱼ the body's own
//! modes (unit mean square, body length 1; `modal::continuum_shape`). Each ⟨φᵢ, L φⱼ⟩ is the
//! engine's own force on a fine grid of n points applied to φⱼ sampled there, paired with φᵢ:
//! h^{1−p}·φᵢ·f_n(φⱼ), h = 1/(n − 1), p the coefficient's spacing power (so the coefficient is
//! the continuum's, in body lengths). The free ends' difference rows converge at first order in
//! h (the lattice's eigenvalues are low by 1.41× at 12 points, 1.10× at 41), so the matrix is
//! Richardson's (8M(h/4) − 6M(h/2) + M(h))/3 from n = [`FINE`], 2n − 1 and 4n − 3 points: the
//! first- and second-order errors cancel (a free–free beam's ⟨φ₁, ∂s⁴φ₁⟩ = β₁⁴ to 10⁻⁴
//! relative, `tests`; with the first order alone the active ⟨φ₁, ∂s³φ₄⟩ was 0.9 % off, which
//! an active beam's coupled likelihood turned into a 4 % error in a_y).
//!
//! **Grid.** Where the field has no continuum shapes (a ring, lengths, or coordinates past the
//! projector's continuum ones) the matrices are the grid's own on its unit-norm modes, and the
//! coefficients are the grid's (said in the report).

use nalgebra::DMatrix;

use crate::dynamics::{library, Candidate};
use crate::model::Model;

/// The coarsest grid's points (the others have 2·FINE − 1 and 4·FINE − 3): 125, 250 and 500
/// intervals divide the continuum shapes' 2000 samples.
pub const FINE: usize = 126;

/// One linear force on the modes: its position and velocity matrices (coefficient 1).
#[derive(Debug, Clone)]
pub(super) struct ModalForce {
    /// ⟨φᵢ, L φⱼ⟩.
    pub position: DMatrix<f64>,
    /// ⟨φᵢ, L′ φⱼ⟩.
    pub velocity: DMatrix<f64>,
}

impl ModalForce {
    /// The matrices on the first `n` modes.
    pub fn block(&self, n: usize) -> ModalForce {
        ModalForce {
            position: self.position.view((0, 0), (n, n)).into_owned(),
            velocity: self.velocity.view((0, 0), (n, n)).into_owned(),
        }
    }
}

/// Whether `c`'s force is linear in (u, u̇) on `unknowns` values: f(0) = 0 and
/// f(a + 2b) = f(a) + 2 f(b) for two fixed pseudo-random pairs, to 10⁻⁹ of their size.
pub(super) fn is_linear(c: &Candidate) -> bool {
    if c.kinetic {
        return false;
    }
    let n = c.unknowns();
    let wave = |k: f64| -> Vec<f64> {
        (0..n)
            .map(|i| (k * (i as f64 + 0.5)).sin() * 1e-2)
            .collect()
    };
    let (u1, v1, u2, v2) = (wave(0.7), wave(1.3), wave(2.1), wave(0.4));
    let mix =
        |a: &[f64], b: &[f64]| -> Vec<f64> { a.iter().zip(b).map(|(x, y)| x + 2.0 * y).collect() };
    let whole = c.force(&mix(&u1, &u2), &mix(&v1, &v2));
    let parts = mix(&c.force(&u1, &v1), &c.force(&u2, &v2));
    let zero = c.force(&vec![0.0; n], &vec![0.0; n]);
    let size = parts
        .iter()
        .chain(&whole)
        .fold(0.0f64, |m, x| m.max(x.abs()));
    let gap = whole
        .iter()
        .zip(&parts)
        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
    let offset = zero.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    gap <= 1e-9 * size.max(f64::MIN_POSITIVE) && offset <= 1e-12 * size.max(1.0)
}

/// The matrices of `c` on `shapes` (each sampled on the body's points of `c`'s grid, tail
/// first), with the pairing h^{1−p}·φᵢ·f(φⱼ) of `points` points.
fn on_shapes(c: &Candidate, shapes: &[Vec<f64>], points: usize) -> ModalForce {
    let m = shapes.len();
    let stripped: Vec<Vec<f64>> = shapes.iter().map(|s| c.strip(s)).collect();
    let zero = vec![0.0; c.unknowns()];
    let h = 1.0 / (points as f64 - 1.0);
    let scale = h.powi(1 - c.spacing_power);
    let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
    let mut position = DMatrix::zeros(m, m);
    let mut velocity = DMatrix::zeros(m, m);
    for (j, phi) in stripped.iter().enumerate() {
        let fu = c.force(phi, &zero);
        let fv = c.force(&zero, phi);
        for (i, psi) in stripped.iter().enumerate() {
            position[(i, j)] = scale * dot(psi, &fu);
            velocity[(i, j)] = scale * dot(psi, &fv);
        }
    }
    ModalForce { position, velocity }
}

/// The first `modes` continuum shapes of a field (stencil `k`, `boundary`) sampled on
/// `points` points; `None` where the field has none or `points − 1` does not divide the
/// shapes' samples.
fn sampled(
    k: u32,
    boundary: crate::boundary::Boundary,
    modes: usize,
    points: usize,
) -> Option<Vec<Vec<f64>>> {
    (1..=modes)
        .map(|i| {
            let shape = crate::modal::continuum_shape(k, boundary, i)?;
            let intervals = shape.len() - 1;
            let stride = intervals / (points - 1);
            (stride * (points - 1) == intervals)
                .then(|| (0..points).map(|p| shape[p * stride]).collect())
        })
        .collect()
}

/// The continuum matrices of the candidates named `names` of `model`'s field `field` on its
/// first `modes` continuum modes (stencil `k`, `boundary`): `None` for a candidate that is not
/// linear, and `Ok(None)` where the field has no continuum shapes.
pub(super) fn continuum(
    model: &Model,
    order: u32,
    field: &str,
    (k, boundary): (u32, crate::boundary::Boundary),
    modes: usize,
    names: &[String],
) -> Result<Option<Vec<Option<ModalForce>>>, crate::dynamics::nonlinear::NonlinearError> {
    let fine = [FINE, 2 * FINE - 1, 4 * FINE - 3];
    let mut at = Vec::new();
    for &n in &fine {
        let Some(shapes) = sampled(k, boundary, modes, n) else {
            return Ok(None);
        };
        let lib = library(model, order, n, field)?;
        let forces: Vec<Option<ModalForce>> = names
            .iter()
            .map(|name| {
                let c = lib.iter().find(|c| &c.name == name)?;
                is_linear(c).then(|| on_shapes(c, &shapes, n))
            })
            .collect();
        at.push(forces);
    }
    // Richardson over h, h/2, h/4: (8 M(h/4) − 6 M(h/2) + M(h))/3 cancels the h and h² terms.
    let mut levels = at.into_iter();
    let (Some(coarse), Some(middle), Some(finest)) = (levels.next(), levels.next(), levels.next())
    else {
        return Ok(None);
    };
    Ok(Some(
        (coarse.into_iter().zip(middle).zip(finest))
            .map(|((a, b), c)| {
                let (a, b, c) = (a?, b?, c?);
                let combine = |a: &DMatrix<f64>, b: &DMatrix<f64>, c: &DMatrix<f64>| {
                    (c * 8.0 - b * 6.0 + a) / 3.0
                };
                Some(ModalForce {
                    position: combine(&a.position, &b.position, &c.position),
                    velocity: combine(&a.velocity, &b.velocity, &c.velocity),
                })
            })
            .collect(),
    ))
}

/// The grid's matrices of `candidates` on its unit-norm `shapes` (on the body's points):
/// h^{−p}·vᵢ·f(vⱼ), `None` for a candidate that is not linear.
pub(super) fn grid(
    candidates: &[Candidate],
    shapes: &[Vec<f64>],
    points: usize,
) -> Vec<Option<ModalForce>> {
    let h = 1.0 / (points as f64 - 1.0);
    candidates
        .iter()
        .map(|c| {
            is_linear(c).then(|| {
                let f = on_shapes(c, shapes, points);
                // on_shapes pairs with weight h; unit-norm grid shapes pair with weight 1.
                ModalForce {
                    position: f.position / h,
                    velocity: f.velocity / h,
                }
            })
        })
        .collect()
}

/// The least grid the onward line replays continuum coefficients on: the lattice's lowest
/// shapes at 12 points, read through the continuum projector, kept 7 % less variance than the
/// continuum body's (a free beam's lowest mode; tests/discover_rates.rs).
pub const REPLAY_POINTS: usize = 41;

/// The field's own unit-norm shapes of its first `modes` non-zero modes at `points` points,
/// [`signed`], with its stencil and boundary.
fn own_shapes(
    model: &Model,
    (order, field): (u32, &str),
    points: usize,
    modes: usize,
) -> Option<(Vec<Vec<f64>>, u32, crate::boundary::Boundary)> {
    let index = model.fields.iter().position(|f| f.id == field)?;
    let params = crate::modal::Params::default();
    let all = crate::modal::field_modes(&model.only(index), order, points, &params, None, true);
    let fm = all.ok()?.into_iter().next()?;
    let s = fm.spectrum.shapes.as_ref()?;
    let first = fm.spectrum.nullity;
    if first + modes > s.ncols() {
        return None;
    }
    let shapes: Vec<Vec<f64>> = (0..modes)
        .map(|j| (0..s.nrows()).map(|p| s[(p, first + j)]).collect())
        .collect();
    let shapes = signed(&shapes, fm.k, fm.field.boundary);
    Some((shapes, fm.k, fm.field.boundary))
}

/// The grid's matrices of the candidates `names` of `model`'s field `field` on its own first
/// `modes` non-zero modes at `points` points, [`signed`] as the continuum shapes; `None` where
/// the field, its shapes or a candidate is missing at that size.
pub(super) fn grid_at(
    model: &Model,
    (order, field): (u32, &str),
    points: usize,
    modes: usize,
    names: &[String],
) -> Option<Vec<Option<ModalForce>>> {
    let (shapes, _, _) = own_shapes(model, (order, field), points, modes)?;
    let lib = library(model, order, points, field).ok()?;
    let picked: Vec<Candidate> = (names.iter())
        .map(|n| lib.iter().find(|c| &c.name == n).cloned())
        .collect::<Option<_>>()?;
    Some(grid(&picked, &shapes, points))
}

/// What a unit continuum amplitude of each continuum shape reads as on the unit-norm grid
/// modes at `points` points (φⱼ·vⱼ/h), over what the recording's projector read it as
/// (`coarse`, its continuum gains at N points): the onward line's variances at `points` are
/// the recording's times the square. `None` where the field has no shapes there.
pub(super) fn replay_gains(
    model: &Model,
    (order, field): (u32, &str),
    coarse: &[f64],
    points: usize,
) -> Option<Vec<f64>> {
    let (fine, k, boundary) = own_shapes(model, (order, field), points, coarse.len())?;
    let h = 1.0 / (points.max(2) - 1) as f64;
    (fine.iter().zip(coarse).enumerate())
        .map(|(i, (v, c))| Some(overlap(k, boundary, i, v)?.abs() / h / c.abs()))
        .collect()
}

/// vᵢ·φᵢ: the grid vector `v` (on equally spaced points) against the field's continuum shape
/// i + 1 (stencil `k`, `boundary`), each point at its nearest of the shape's samples; `None`
/// where the field has no continuum shapes.
fn overlap(k: u32, boundary: crate::boundary::Boundary, i: usize, v: &[f64]) -> Option<f64> {
    let shape = crate::modal::continuum_shape(k, boundary, i + 1)?;
    let last = (shape.len() - 1) as f64;
    let along = (v.len().max(2) - 1) as f64;
    let at = |p: usize| shape[(p as f64 * last / along).round() as usize];
    Some(v.iter().enumerate().map(|(p, x)| x * at(p)).sum())
}

/// The grid's unit-norm `shapes` signed as the field's first continuum shapes (stencil `k`,
/// `boundary`) sampled at the nearest of their 2000 intervals: the grid's matrices then pair
/// with the continuum's entry by entry (an odd force's off-diagonal entries follow the signs).
fn signed(shapes: &[Vec<f64>], k: u32, boundary: crate::boundary::Boundary) -> Vec<Vec<f64>> {
    (shapes.iter().enumerate())
        .map(|(i, v)| {
            let sign = match overlap(k, boundary, i, v) {
                Some(dot) if dot < 0.0 => -1.0,
                _ => 1.0,
            };
            v.iter().map(|x| sign * x).collect()
        })
        .collect()
}

/// The grid's coefficients for the `selected` candidates whose matrices `grid` (on the grid's
/// own first modes, [`signed`]) come nearest the continuum estimate Σₖ βₖ Cₖ (`continuum`):
/// least squares over every position and velocity entry, each mode's row relative to the
/// estimate's largest entry in it. This is the body `simulate --points N` runs so that the
/// modes used keep their frequencies and dampings: the N-point lattice's free ends put its
/// eigenvalues 1.41× low at 12 points, 1.18× at 25, and the continuum coefficient there would
/// replay the modes 16 % and 8 % slow. `None` where an entry is missing or the system is singular.
pub(super) fn nearest_on_grid(
    continuum: &[Option<ModalForce>],
    grid: &[Option<ModalForce>],
    selected: &[usize],
    beta: &[f64],
) -> Option<Vec<f64>> {
    let pick = |forces: &[Option<ModalForce>], k: usize| forces.get(k)?.clone();
    let cont: Vec<ModalForce> = (selected.iter())
        .map(|&k| pick(continuum, k))
        .collect::<Option<_>>()?;
    let on_grid: Vec<ModalForce> = (selected.iter())
        .map(|&k| pick(grid, k))
        .collect::<Option<_>>()?;
    let m = (cont.iter().chain(&on_grid))
        .map(|f| f.position.nrows().min(f.velocity.nrows()))
        .min()?;
    let mut rows: Vec<(Vec<f64>, f64)> = Vec::new();
    for part in [
        |f: &ModalForce| f.position.clone(),
        |f: &ModalForce| f.velocity.clone(),
    ] {
        let target = (cont.iter().zip(beta)).fold(DMatrix::zeros(m, m), |t, (f, b)| {
            t + part(f).view((0, 0), (m, m)) * *b
        });
        for i in 0..m {
            let scale = (0..m).fold(0.0f64, |a, j| a.max(target[(i, j)].abs()));
            if scale <= 0.0 {
                continue;
            }
            for j in 0..m {
                let row = on_grid.iter().map(|f| part(f)[(i, j)] / scale).collect();
                rows.push((row, target[(i, j)] / scale));
            }
        }
    }
    let a = DMatrix::from_fn(rows.len(), selected.len(), |r, c| rows[r].0[c]);
    let b = nalgebra::DVector::from_iterator(rows.len(), rows.iter().map(|r| r.1));
    let solved = a.svd(true, true).solve(&b, 1e-12).ok()?;
    solved
        .iter()
        .all(|x| x.is_finite())
        .then(|| solved.iter().copied().collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_free_beams_stiffness_is_its_continuum_eigenvalue() {
        let model = Model::from_toml(include_str!("../../tables/models/crawler.toml")).unwrap();
        let field = &model.fields[1];
        let names: Vec<String> = library(&model, 4, 12, "y")
            .unwrap()
            .iter()
            .map(|c| c.name.clone())
            .collect();
        let found = continuum(&model, 4, "y", (2, field.boundary), 4, &names)
            .unwrap()
            .unwrap();
        let c = names.iter().position(|n| n == "c_y").unwrap();
        let force = found[c].as_ref().unwrap();
        let lambda = |i: usize| {
            crate::modal::continuum_beta(2, field.boundary, i + 1)
                .unwrap()
                .powi(4)
        };
        // The second-order remainder: 3e-5 of β₁⁴, 3e-4 of β₄⁴.
        for i in 0..4 {
            for j in 0..4 {
                let got = force.position[(i, j)];
                let want = if i == j { -lambda(i) } else { 0.0 };
                let tol = 1e-3 * (lambda(i) * lambda(j)).sqrt();
                assert!((got - want).abs() < tol, "({i}, {j}): {got} against {want}");
            }
        }
        // The Kelvin damping −2c′_y ∂t∂s⁴y (as `equations` prints it): the same operator's.
        let kelvin = names.iter().position(|n| n == "c'_y").unwrap();
        let d = found[kelvin].as_ref().unwrap().velocity[(1, 1)];
        assert!((d + 2.0 * lambda(1)).abs() < 1e-3 * lambda(1), "{d}");
    }
}
