//! The figure of `compare`: per quantity (κ, the compared modes' Ω and ζ, discovered
//! coefficients), every animal's own value beside its group, and each group's mean with its
//! 95 % interval.

use super::plot::*;
use super::FigureError;
use crate::compare::CompareReport;

/// The most quantities drawn: κ (or c) and the discovered coefficients first, then the modes'
/// Ω and ζ in order (three modes compared with two discovered coefficients left the
/// coefficients out).
const PANELS: usize = 6;

/// The figure, laid out at `width` pixels.
pub(super) fn compare_groups(r: &CompareReport, width: u32) -> Result<String, FigureError> {
    let names: Vec<&str> = r.groups.iter().map(|g| g.name.as_str()).collect();
    let time = r.unit.rsplit('/').next().unwrap_or("time unit");
    // (title, the value axis) per quantity.
    let modal = |q: &str| q.starts_with("Omega_") || q.starts_with("zeta_");
    let mut drawn: Vec<_> = r.differences.iter().collect();
    drawn.sort_by_key(|d| modal(&d.quantity));
    drawn.truncate(PANELS);
    let labels: Vec<(String, String)> = (drawn.iter())
        .map(|d| match d.quantity.as_str() {
            "kappa" => ("κ".into(), r.unit.clone()),
            "c" => ("c".into(), r.unit.clone()),
            q if q.starts_with("Omega_") => {
                (q.replace("Omega_", "Ω, mode "), format!("rad per {time}"))
            }
            q if q.starts_with("zeta_") => (q.replace("zeta_", "ζ, mode "), "damping ratio".into()),
            q => (
                format!("{q} (discovered)"),
                "body lengths and time units".into(),
            ),
        })
        .collect();
    let axis = format!("group: 1 = {}, 2 = {}", names[0], names[1]);
    let panels: Vec<Panel> = (drawn.iter())
        .zip(&labels)
        .map(|(d, (title, unit))| {
            let mut marks: Vec<Series> = (0..2)
                .map(|g| {
                    let mine: Vec<f64> = (r.animals.iter())
                        .filter(|a| a.quantity == d.quantity && a.group == names[g])
                        .map(|a| a.value)
                        .collect();
                    // Spread across the group's slot, in input order, so points do not overlap.
                    let n = mine.len().max(2) as f64 - 1.0;
                    let points = (mine.iter().enumerate())
                        .map(|(i, &v)| (g as f64 + 0.8 + 0.2 * i as f64 / n, v))
                        .collect();
                    series(format!("{} animals", names[g]), points, Mark::Dots)
                })
                .collect();
            let bars = (0..2)
                .flat_map(|g| {
                    let [lo, hi] = d.group_intervals[g];
                    [(g as f64 + 1.2, lo), (g as f64 + 1.2, hi)]
                })
                .collect();
            marks.push(series("group mean, 95 % interval", bars, Mark::Errors));
            let means = (0..2).map(|g| (g as f64 + 1.2, d.means[g])).collect();
            marks.push(series("group mean", means, Mark::Dots));
            panel(title, &axis, unit, marks)
        })
        .collect();
    let rows = panels.len().div_ceil(3).max(1);
    render(
        width,
        &format!(
            "{} against {}: each animal, and the groups' means",
            names[1], names[0]
        ),
        330,
        (rows, 3),
        &panels,
    )
}
