//! Figures of the behaviour models: self-righting, rearing and hunching, asymmetry,
//! equipartition, peristalsis and rolling, free energy, the 3-point bend, the Mathieu chart.

use plotters::prelude::*;

use super::plot::*;
use super::script::{sub, symbols};
use super::{err, FigureError, FigureSettings};
use crate::behaviour::{self, PairKind, RightingSettings};
use crate::theory::Theory;

pub(super) fn bh(e: behaviour::BehaviourError) -> FigureError {
    FigureError::Behaviour(e)
}

/// Fig. 3: the two stages of self-righting.
pub(super) fn self_righting(theory: &Theory, width: u32) -> Result<String, FigureError> {
    let n = theory.points;
    let settings = RightingSettings::default();
    let r = behaviour::self_righting(theory, &settings).map_err(bh)?;
    let pick = |g: &dyn Fn(&behaviour::RightingFrame) -> f64| -> Vec<(f64, f64)> {
        r.frames.iter().map(|f| (f.t, g(f))).collect()
    };
    let attach = vec![(r.attachment_time, "mouth hooks attach".to_string())];
    // Times in units of 1/ωₜ: the torque in rad per that unit squared, angles in rad.
    let t = "time t (1/ωₜ)";
    let mut panels = vec![
        panel(
            "generalised torque on the first torsional mode",
            t,
            "Q (rad·ωₜ²)",
            vec![series("", pick(&|f| f.torque), Mark::Line)],
        ),
        panel(
            "first twisting mode",
            t,
            "Θ₁ (rad)",
            vec![series("", pick(&|f| f.mode), Mark::Line)],
        ),
        panel(
            "mean rotation along the body",
            t,
            "mean θ (rad)",
            vec![series("", pick(&|f| f.mean_rotation), Mark::Line)],
        ),
    ];
    let segments = (0..n)
        .filter(|j| n <= 8 || j % (n / 6).max(1) == 0 || *j == n - 1)
        .map(|j| {
            let name = if j == n - 1 {
                "head".to_string()
            } else if j == 0 {
                "tail".to_string()
            } else {
                format!("point {j}")
            };
            series(name, pick(&|f| f.angles[j]), Mark::Line)
        })
        .collect();
    panels.push(panel("rotation at each point", t, "θⱼ (rad)", segments));
    let align = r
        .alignment_times
        .iter()
        .enumerate()
        .map(|(j, &a)| (j as f64, a))
        .collect();
    let align_title = format!("time to align within δ = {} rad", settings.tolerance);
    panels.push(panel(
        &align_title,
        "point j (0 = tail)",
        "alignment time (1/ωₜ)",
        vec![series("", align, Mark::Dots)],
    ));
    let zs: Vec<f64> = curve(0.3, 3.0, 18, |z| z).iter().map(|p| p.0).collect();
    let points = behaviour::righting_sweep(theory, &settings, &zs).map_err(bh)?;
    let attach_at = points
        .iter()
        .map(|p| (p.mode_damping, p.attachment_time))
        .collect();
    let righted_at = points
        .iter()
        .map(|p| (p.mode_damping, p.righting_time))
        .collect();
    let mut sweep = panel(
        "righting time against the first mode's damping",
        "damping ratio ζ₁",
        "time (1/ωₜ)",
        vec![
            series("body aligned", righted_at, Mark::Line),
            series("hooks attach", attach_at, Mark::Dashed),
        ],
    );
    sweep.markers = vec![(1.0, "critical damping".into())];
    sweep.zero = true;
    panels.push(sweep);
    for p in panels.iter_mut().take(4) {
        p.markers = attach.clone();
        p.zero = true;
    }
    panels[4].zero = true;
    render(
        width,
        &format!(
            "Self-righting, N = {n}, ζ₁ = {} (paper Fig. 3); attach at {:.1}, righted at {:.1}",
            r.damping_ratio, r.attachment_time, r.righting_time
        ),
        360,
        (3, 2),
        &panels,
    )
}

/// Fig. 4: a constant force on the first dorsoventral bending mode (rearing) and on the first
/// axial mode (hunching): the transient and the shifted equilibrium shape.
pub(super) fn rearing_hunching(theory: &Theory, width: u32) -> Result<String, FigureError> {
    let n = theory.points;
    let mut panels = Vec::new();
    let field = |behaviour: &str| -> Result<(usize, String), FigureError> {
        let i = behaviour::role_fields(&theory.model, behaviour)
            .map_err(behaviour::BehaviourError::from)?[0];
        let f = &theory.model.fields[i];
        let role = f.role.map(|r| r.name()).unwrap_or_default();
        Ok((i, format!("{role} {}", f.symbol)))
    };
    let (rear, hunch) = (field("behave rearing")?, field("behave hunching")?);
    let labels = [("rearing", rear.0, rear.1), ("hunching", hunch.0, hunch.1)];
    // Each run again over its own settling time, so a fast mode's panel shows its settling
    // at the same resolution (400 samples) as a slow one's.
    let runs = labels
        .iter()
        .map(|(what, index, _)| {
            let r = behaviour::step_response(theory, what, *index, 0.02, 2000.0)?;
            match settling_end(&r.transient, r.equilibrium) {
                end if end > 0.0 && end < 1500.0 => {
                    behaviour::step_response(theory, what, *index, 0.02, end)
                }
                _ => Ok(r),
            }
        })
        .collect::<Result<Vec<_>, _>>()
        .map_err(bh)?;
    let titles: Vec<(String, String)> = labels
        .iter()
        .zip(&runs)
        .map(|((what, _, _), r)| {
            (
                format!("{what}: force 0.02 on mode {}", r.mode),
                format!("{what}: shifted equilibrium Q*·vᵢ"),
            )
        })
        .collect();
    for (((_, _, axis), r), (t1, t2)) in labels.iter().zip(&runs).zip(&titles) {
        let q = vec![
            (0.0, r.equilibrium),
            (r.transient.last().map_or(1.0, |x| x.0), r.equilibrium),
        ];
        let mut a = panel(
            t1,
            "time t (1/ω)",
            "modal coordinate Q",
            vec![
                series("transient", r.transient.clone(), Mark::Line),
                series("Q* = F/ωᵢ²", q, Mark::Dashed),
            ],
        );
        a.zero = true;
        let shape = r
            .shape
            .iter()
            .enumerate()
            .map(|(j, v)| (j as f64, *v))
            .collect();
        let mut b = panel(
            t2,
            "point j (0 = tail)",
            axis,
            vec![series("", shape, Mark::Line)],
        );
        b.zero = true;
        panels.push(a);
        panels.push(b);
    }
    render(
        width,
        &format!("Rearing and hunching, N = {n} (paper §3.3.2, Fig. 4)"),
        380,
        (2, 2),
        &panels,
    )
}

/// A third past the transient's settling time (the last moment it is more than 1 % of Q* away
/// from Q*): a fast mode settles in a tenth of a slow one's time, and its panel should show the
/// settling, not a flat line.
pub(super) fn settling_end(transient: &[(f64, f64)], equilibrium: f64) -> f64 {
    let tolerance = 0.01 * equilibrium.abs();
    transient
        .iter()
        .rev()
        .find(|&&(_, q)| (q - equilibrium).abs() > tolerance)
        .map_or(0.0, |p| p.0 * 4.0 / 3.0)
}

/// App. C: forward and backward frequencies of the self-interacting axial pair against the
/// amplitude, with the nonlinear pair's simulated frequencies.
pub(super) fn asymmetry(width: u32) -> Result<String, FigureError> {
    let c = -std::f64::consts::FRAC_1_SQRT_2;
    let roots = |a: f64| behaviour::asymmetry_roots(c, a, 1.0);
    let mut sim = (Vec::new(), Vec::new());
    for a in [0.25, 0.5, 0.75, 1.0, 1.25, 1.5] {
        let x = behaviour::asymmetry(c, a, 1.0).map_err(bh)?;
        sim.0.push((a, x.simulated_forward));
        sim.1.push((a, x.simulated_backward));
    }
    let mut p = panel(
        "roots of ωₛ² + cA²ωₛ − ω² = 0, c = −√2/2, ω = 1",
        "wave amplitude A",
        "travelling-wave frequency ωₛ (units of ω)",
        vec![
            series(
                "forward root",
                curve(0.0, 1.6, 160, |a| roots(a).0),
                Mark::Line,
            ),
            series(
                "backward root",
                curve(0.0, 1.6, 160, |a| roots(a).1),
                Mark::Line,
            ),
            series("simulated forward", sim.0, Mark::Dots),
            series("simulated backward", sim.1, Mark::Dots),
        ],
    );
    p.zero = true;
    render(
        width,
        "Forward/backward asymmetry of the axial pair (paper App. C, corrected cA²)",
        520,
        (1, 1),
        &[p],
    )
}

/// App. B: PCA of Langevin postures against the modes and the equipartition shares.
pub(super) fn equipartition(
    theory: &Theory,
    settings: &FigureSettings,
) -> Result<String, FigureError> {
    let n = theory.points;
    let width = settings.page.canvas_width();
    let kt = 0.5;
    // 200 000 steps, fewer on long bodies so that the figure takes seconds (the title says how
    // many postures went in).
    let steps = ((2e9 / (n as f64).powi(2)) as u64).clamp(1000, 200_000);
    let c = behaviour::equipartition_from_dynamics(theory, None, steps, kt, settings.seed)
        .map_err(bh)?;
    let k = |v: &[f64], f: fn(f64) -> f64| -> Vec<(f64, f64)> {
        v.iter()
            .enumerate()
            .map(|(i, x)| ((i + 1) as f64, f(*x)))
            .collect()
    };
    let mut shares = panel(
        "variance share of each principal component",
        "component k (k-th non-zero mode)",
        "log₁₀ share",
        vec![
            series(
                "PCA of simulated postures",
                k(&c.pca_variance_share, f64::log10),
                Mark::Dots,
            ),
            series(
                "equipartition λₖ⁻¹/Σλ⁻¹",
                k(&c.theory_variance_share, f64::log10),
                Mark::Line,
            ),
        ],
    );
    shares.zero = true;
    let mut overlap = panel(
        "|cos| between principal component k and mode k",
        "component k",
        "overlap",
        vec![series("", k(&c.overlap, |x| x), Mark::Dots)],
    );
    overlap.zero = true;
    render(
        width,
        &format!(
            "Equipartition from Langevin dynamics: {} postures of y, N = {n}, kT = {kt} (paper App. B)",
            c.frames
        ),
        400,
        (1, 2),
        &[shares, overlap],
    )
}

/// Figs. 6–7: a degenerate pair's minimum-energy orbit, the body it moves, and its densities.
pub(super) fn pair(
    theory: &Theory,
    kind: PairKind,
    settings: &FigureSettings,
) -> Result<String, FigureError> {
    let n = theory.points;
    let width = settings.page.canvas_width();
    let m = 0.1;
    let o = behaviour::pair_orbit(theory, kind, m, 2.0).map_err(bh)?;
    let orbit: Vec<(f64, f64)> = o.trajectory.iter().map(|&(_, a, b)| (a, b)).collect();
    let postures = o
        .postures
        .iter()
        .map(|(t, a, b)| {
            let pts = match kind {
                PairKind::Peristalsis => {
                    a.iter().enumerate().map(|(j, v)| (j as f64, *v)).collect()
                }
                PairKind::Rolling => a.iter().zip(b).map(|(y, z)| (*y, *z)).collect(),
            };
            series(format!("t = {t:.2}"), pts, Mark::Line)
        })
        .collect();
    // p(A) ∝ exp(−β(M²/A² + ω²A²)/2) on A > 0, normalised by quadrature.
    let beta: f64 = 100.0;
    let w = o.omega;
    let amax = (0.4 / w).sqrt() + 5.0 / (w * beta.sqrt());
    let mut dens = Vec::new();
    for (k, mm) in [0.0, 0.05, 0.1, 0.2].iter().enumerate() {
        let g = |a: f64| behaviour::pair_amplitude_weight(w, beta, *mm, a);
        let z = behaviour::integrate(&g, 0.0, amax * 2.0, 1e-12);
        dens.push(series(
            format!("M = {mm}"),
            curve(0.0, amax, 200, |a| g(a) / z),
            if k == 2 { Mark::Line } else { Mark::Dashed },
        ));
    }
    let s = behaviour::sample_pair(w, beta, m, settings.samples, settings.seed).map_err(bh)?;
    let (hist, bw) = histogram(&s.amplitude, 40);
    dens.push(series(format!("Metropolis, M = {m}"), hist, Mark::Bars(bw)));
    let (what, pfield, title) = match kind {
        PairKind::Peristalsis => (
            "Peristalsis",
            "axial displacement x",
            "travelling compression wave",
        ),
        PairKind::Rolling => (
            "Rolling",
            "dorsoventral z",
            "midline seen along the axis: a C-bend turning",
        ),
    };
    let px = match kind {
        PairKind::Peristalsis => "point j (0 = tail)",
        PairKind::Rolling => "mediolateral y",
    };
    let mut orbit_panel = panel(
        "minimum-energy orbit A* = √(|M|/ω)",
        "Q₁ of the pair",
        "Q₂ of the pair",
        vec![series("", orbit, Mark::Line)],
    );
    orbit_panel.zero = true;
    let mut dens_panel = panel("amplitude density at β = 100", "amplitude A", "p(A)", dens);
    dens_panel.zero = true;
    render(
        width,
        &format!(
            "{what}: pair frequency ω = {:.4}, M = {m}, N = {n} (paper Figs. 6–7)",
            o.omega
        ),
        420,
        (1, 3),
        &[orbit_panel, panel(title, px, pfield, postures), dens_panel],
    )
}

/// Fig. 8A: the free energy of a pair across M = 0.
pub(super) fn free_energy(theory: &Theory, width: u32) -> Result<String, FigureError> {
    let o = behaviour::pair_orbit(theory, PairKind::Peristalsis, 0.1, 1.0).map_err(bh)?;
    let mut lines = Vec::new();
    for beta in [1.0, 3.0, 10.0] {
        let mut pts = Vec::new();
        for (m, _) in curve(-1.0, 1.0, 200, |m| m) {
            pts.push((
                m,
                behaviour::pair_statistics(o.omega, beta, m)
                    .map_err(bh)?
                    .free_energy,
            ));
        }
        lines.push(series(format!("β = {beta}"), pts, Mark::Line));
    }
    render(
        width,
        &format!(
            "Free energy of the first axial pair, ω = {:.4} (paper Fig. 8A)",
            o.omega
        ),
        480,
        (1, 1),
        &[panel(
            "F(M) = ln(βω/2π²)/β + |M|ω: a kink at M = 0",
            "conserved momentum M",
            "free energy F",
            lines,
        )],
    )
}

/// Fig. 8D: the 3-point bend angle of unbiased exploration against its linearised Gaussian.
pub(super) fn bend_angle(
    theory: &Theory,
    settings: &FigureSettings,
) -> Result<String, FigureError> {
    let n = theory.points;
    let width = settings.page.canvas_width();
    let beta = 10_000.0;
    let e = behaviour::explore(theory, beta, settings.samples, settings.seed).map_err(bh)?;
    let deg: Vec<f64> = e.bend.iter().map(|b| b.to_degrees()).collect();
    let (hist, w) = histogram(&deg, 60);
    let sd = e.bend_sd_linear.to_degrees();
    let lim = 4.0 * sd;
    let gauss = curve(-lim, lim, 200, |x| {
        (-0.5 * (x / sd).powi(2)).exp() / (sd * (2.0 * std::f64::consts::PI).sqrt())
    });
    render(
        width,
        &format!("3-point body bend in unbiased exploration, β = {beta}, N = {n} (paper Fig. 8D)"),
        480,
        (1, 1),
        &[panel(
            "tail–midpoint–head turning angle",
            "bend angle (degrees)",
            "density (1/degree)",
            vec![
                series(
                    format!("{} sampled postures", e.bend.len()),
                    hist,
                    Mark::Bars(w),
                ),
                series("linearised Gaussian", gauss, Mark::Line),
            ],
        )],
    )
}

/// App. D: the Mathieu stability chart with the first tongue's small-ε edges.
pub(super) fn mathieu(width: u32) -> Result<String, FigureError> {
    let (nx, ny, emax) = (161usize, 61usize, 0.6);
    let (lo, hi) = (0.5, 4.5);
    let chart_points = behaviour::stability_chart(1.0, (lo, hi), emax, (nx, ny)).map_err(bh)?;
    let mut svg = String::new();
    let mut curves = Curves::new(0);
    {
        let root = SVGBackend::with_string(&mut svg, (width, 560)).into_drawing_area();
        root.fill(&WHITE).map_err(err)?;
        let root = headed(
            &root,
            "Mathieu stability: Φ̈ + λ²[1 − 2ε cos ωt]Φ = 0 (paper App. D)",
            TITLE,
        )?;
        // The key is a caption: a legend box would hide a tongue at any width.
        let root = headed(
            &root,
            "shaded: unstable (|tr M| > 2); lines: the first tongue's edges ω/λ = 2√(1 ± ε)",
            CAPTION,
        )?;
        let mut chart = chart_builder(&root, (1, 1))
            .build_cartesian_2d(lo..hi, 0.0..emax)
            .map_err(err)?;
        chart
            .configure_mesh()
            .x_desc("drive frequency ω/λ")
            .y_desc("modulation depth ε")
            .label_style(("sans-serif", TEXT))
            .axis_desc_style(("sans-serif", TEXT))
            .light_line_style(WHITE)
            .draw()
            .map_err(err)?;
        let (dx, dy) = ((hi - lo) / (nx - 1) as f64, emax / (ny - 1) as f64);
        chart
            .draw_series(chart_points.iter().filter(|p| !p.stable).map(|p| {
                let (x, y) = (p.frequency_ratio, p.epsilon);
                Rectangle::new(
                    [(x - dx / 2.0, y - dy / 2.0), (x + dx / 2.0, y + dy / 2.0)],
                    RGBColor(214, 39, 40).mix(0.5).filled(),
                )
            }))
            .map_err(err)?;
        let pixels = chart.plotting_area().get_pixel_range();
        for sign in [-1.0, 1.0] {
            let edge: Vec<(f64, f64)> = curve(0.0, emax, 100, |e| e)
                .into_iter()
                .map(|(e, _)| (2.0 * (1.0 + sign * e).sqrt(), e))
                .collect();
            curves.add(&edge, &pixels, (&(lo..hi), &(0.0..emax)), (BLACK, false));
        }
        chart
            .draw_series(std::iter::once(Rectangle::new(
                [(lo, 0.0), (lo, 0.0)],
                curves.marker.filled(),
            )))
            .map_err(err)?;
        root.present().map_err(err)?;
    }
    curves.splice(&mut svg);
    Ok(svg)
}

/// Fig. 11: forward and backward peristalsis against the gyroscopic coupling, simulated, with
/// the dispersion relation's curves and the 1 : 2 point against App. C's.
pub(super) fn forward_backward(theory: &Theory, width: u32) -> Result<String, FigureError> {
    let couplings: Vec<f64> = (0..=12).map(|i| 0.125 * f64::from(i)).collect();
    let r = behaviour::forward_backward(theory, &couplings).map_err(bh)?;
    let pick = |g: &dyn Fn(&behaviour::Split) -> f64| -> Vec<(f64, f64)> {
        r.sweep.iter().map(|s| (s.coupling, g(s))).collect()
    };
    let lines = |g: &dyn Fn((f64, f64)) -> f64| {
        curve(0.0, 1.5, 150, |c| {
            g(behaviour::forward_backward::analytic(c))
        })
    };
    let x = "coupling G = −g sin k/ω₁ (App. C: −cA²/ω)";
    let backward_over_forward = format!("ω{}/ω{}", sub("b"), sub("f"));
    let mut ratio = panel(
        "backward : forward",
        x,
        &backward_over_forward,
        vec![
            series("simulated", pick(&|s| s.backward / s.forward), Mark::Dots),
            series("dispersion relation", lines(&|(f, b)| b / f), Mark::Line),
            series("1 : 2", vec![(0.0, 0.5), (1.5, 0.5)], Mark::Dashed),
        ],
    );
    ratio.markers = vec![
        (r.half, format!("simulated 1 : 2 at G = {:.4}", r.half)),
        (behaviour::PAPER_COUPLING, "App. C: √2/2".into()),
    ];
    let frequencies = panel(
        "frequencies",
        x,
        "ω/ω₁",
        vec![
            series(
                "forward (towards the head)",
                pick(&|s| s.forward),
                Mark::Dots,
            ),
            series("backward", pick(&|s| s.backward), Mark::Dots),
            series("(√(G²+4) + G)/2", lines(&|(f, _)| f), Mark::Line),
            series("(√(G²+4) − G)/2", lines(&|(_, b)| b), Mark::Line),
        ],
    );
    // Two lines at 85 mm: the force by its coefficient, typeset (g_x as g with a subscript x).
    render(
        width,
        &format!(
            "Forward and backward peristalsis of {} under {}, simulated (paper Fig. 11)",
            r.field,
            symbols(&r.coefficient)
        ),
        420,
        (1, 2),
        &[frequencies, ratio],
    )
}

#[cfg(test)]
mod tests {
    use super::settling_end;

    #[test]
    fn a_transient_ends_a_third_past_its_settling_time() {
        // Q(t) = 1 − e^{−t}cos t settles within 1 % at t ≈ ln 100 ≈ 4.6, sampled to t = 100.
        let transient: Vec<(f64, f64)> = (0..=10_000)
            .map(|i| {
                let t = i as f64 / 100.0;
                (t, 1.0 - (-t).exp() * t.cos())
            })
            .collect();
        let end = settling_end(&transient, 1.0);
        assert!(end > 4.0 * 4.0 / 3.0 && end < 4.7 * 4.0 / 3.0, "{end}");
        // One that never leaves its equilibrium has nothing to show; one that never settles, all.
        assert_eq!(settling_end(&[(0.0, 1.0), (1.0, 1.0)], 1.0), 0.0);
        assert_eq!(settling_end(&transient, 5.0), 100.0 * 4.0 / 3.0);
    }
}
