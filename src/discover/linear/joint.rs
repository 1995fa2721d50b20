//! The joint estimator's run: the start from each mode's own fit, the tracking noise's shape
//! from the projection, the exact fit of the whole library, the selection by the Wald
//! distance and the selected set refitted (`coupled`).

use nalgebra::DVector;

use super::super::coupled::{Joint, Layout};
use super::super::exact::Quadratic;
use super::super::galerkin::ModalForce;
use super::super::report::Method;
use super::super::wald::Wald;
use super::super::DiscoverError;
use super::{set_draws, Estimate, NotExact, Problem};
use crate::statespace::Oscillator;

impl Problem<'_> {
    /// The modes' joint exact likelihood: forces that couple the modes (`coupled`).
    pub(super) fn coupled(
        &self,
        forces: &[ModalForce],
        cols: &[Vec<[f64; 2]>],
    ) -> Result<Result<Estimate, NotExact>, DiscoverError> {
        // The resolved modes that were fitted (fewer than the forces' when a later one failed).
        let m = self.fits.len();
        let all: Vec<usize> = (0..forces.len())
            .filter(|&i| {
                let f = &forces[i];
                f.position
                    .iter()
                    .chain(f.velocity.iter())
                    .any(|x| *x != 0.0)
            })
            .collect();
        let k = all.len();
        let estimates: Vec<Oscillator> = self.fits.iter().map(|f| f.fit.estimate).collect();
        let mean = |f: &dyn Fn(&Oscillator) -> f64| estimates.iter().map(f).sum::<f64>() / m as f64;
        let rates = [
            mean(&|p| p.omega * p.omega),
            mean(&|p| 2.0 * p.zeta * p.omega),
        ];
        let chosen: Vec<&ModalForce> = all.iter().map(|&i| &forces[i]).collect();
        // Start: the diagonal entries' minimum distance on the terms that have them, the rest 0.
        let largest =
            |a: &nalgebra::DMatrix<f64>, b: &nalgebra::DMatrix<f64>| a.amax().max(b.amax());
        let on_diagonal: Vec<usize> = (all.iter().copied())
            .filter(|&i| {
                let f = &forces[i];
                let diagonal = f
                    .position
                    .diagonal()
                    .amax()
                    .max(f.velocity.diagonal().amax());
                diagonal > 1e-3 * largest(&f.position, &f.velocity)
            })
            .collect();
        // The tracking noise's covariance between the used coordinates up to its scale, from
        // the projection (white noise of one size on every tracked coordinate).
        let shape = (self.noise)
            .filter(|c| c.nrows() >= m)
            .map(|c| c.view((0, 0), (m, m)).into_owned())
            .filter(|c| c.diagonal().iter().all(|v| *v > 0.0));
        let layout = Layout::new(k, m, shape.is_some());
        let mut start = DVector::zeros(layout.len());
        if let Ok(d) = self.distance(cols) {
            if let Some((b, _, _)) = d.fit(&on_diagonal) {
                for (&i, v) in on_diagonal.iter().zip(b) {
                    start[all.iter().position(|&a| a == i).unwrap_or(0)] = v;
                }
            }
        }
        // A resolved mode whose own fit found no tracking noise does not say its size.
        let seen = |j: usize| self.fits[j].free.contains(&3);
        for (j, p) in estimates.iter().enumerate() {
            start[k + j] = (4.0 * p.zeta * p.omega.powi(3) * p.variance)
                .max(f64::MIN_POSITIVE)
                .ln();
        }
        let own = |j: usize| estimates[j].noise.max(1e-12 * estimates[j].variance);
        let tracking: Vec<usize> = match &shape {
            // σ² as the recording's tracked points measure it, held there (the modes see it
            // only near Nyquist, where their own force noise looks the same: left free, it went
            // to zero on 2 of 3 active beams at 14 frames a period and took a_y −21 % with
            // it); else estimated from the modes that saw their noise (their median), else
            // from the largest.
            Some(shape) => {
                let mut sizes: Vec<f64> = (0..m)
                    .filter(|&j| seen(j))
                    .map(|j| own(j) / shape[(j, j)])
                    .collect();
                sizes.sort_by(f64::total_cmp);
                let measured = self.sigma.map(|s| s * s).filter(|v| *v > 0.0);
                let size = match (measured, sizes.get(sizes.len() / 2)) {
                    (Some(v), _) | (None, Some(&v)) => v,
                    (None, None) => (0..m).map(|j| own(j) / shape[(j, j)]).fold(0.0, f64::max),
                };
                start[layout.tracking().start] = size.max(f64::MIN_POSITIVE).ln();
                match measured {
                    Some(_) => Vec::new(),
                    None => layout.tracking().collect(),
                }
            }
            // Each mode's own; one that did not see it keeps it (the likelihood is flat there).
            None => {
                for j in 0..m {
                    start[layout.tracking().start + j] = own(j).ln();
                }
                layout.tracking().filter(|&i| seen(i - k - m)).collect()
            }
        };
        let nuisance: Vec<usize> = (layout.forces())
            .chain(tracking)
            .chain(layout.correlations())
            .collect();
        let Some(joint) = Joint::new(&self.data[..m], &chosen, rates, &start, shape.as_ref())
        else {
            return Ok(Err(NotExact::Mixed));
        };
        let every: Vec<usize> = (0..k).chain(nuisance.iter().copied()).collect();
        let Some(full) = joint.fit(start, &every) else {
            return Ok(Err(NotExact::Singular));
        };
        let Some(wald) = Wald::new(full.theta.clone(), full.information.clone(), all.clone())
        else {
            return Ok(Err(NotExact::Singular));
        };
        let whole: Vec<f64> = full.theta.iter().take(k).copied().collect();
        let resamples: Vec<Wald> = (self.counts().iter())
            .filter_map(|count| full.drawn(count))
            .filter_map(|(theta, h)| Wald::new(theta, h, all.clone()))
            .collect();
        let chosen = self.choose_terms(&wald, &resamples, all.clone(), whole, forces.len());
        let selected = chosen.selected.clone();
        let Some((mut beta, mut covariance, _)) = wald.fit(&selected) else {
            return Err(DiscoverError::Degenerate {
                terms: selected.len(),
            });
        };
        // The selected set refitted by the exact likelihood (the Wald step is its first
        // approximation); where that fails (no stable system), the Wald step stands.
        let kept: Vec<usize> = (0..k).filter(|&p| selected.contains(&all[p])).collect();
        let mut at = full.theta.clone();
        for p in 0..k {
            at[p] = kept.iter().position(|&q| q == p).map_or(0.0, |r| beta[r]);
        }
        let free: Vec<usize> = kept
            .iter()
            .copied()
            .chain(nuisance.iter().copied())
            .collect();
        let refit = (!selected.is_empty())
            .then(|| joint.fit(at, &free))
            .flatten();
        let noise_of = |theta: &DVector<f64>| {
            theta.iter().skip(k).take(m).map(|l| l.exp()).sum::<f64>() / m as f64
        };
        let mut noise = noise_of(&full.theta);
        if let Some(r) = &refit {
            if let Some(c) = r.information.clone().cholesky() {
                let inv = c.inverse();
                beta = kept.iter().map(|&p| r.theta[p]).collect();
                covariance = inv.view((0, 0), (kept.len(), kept.len())).into_owned();
                noise = noise_of(&r.theta);
            }
        }
        let draws = set_draws(&resamples, &selected);
        Ok(Ok(Estimate {
            chosen,
            fitted: (beta, covariance, draws),
            scored: Box::new(wald),
            noise,
            goodness: None,
            method: Method::Joint,
        }))
    }
}
