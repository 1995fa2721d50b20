//! The figure of `discover`: the discovered equation simulated and read back, against the
//! recording: each used mode's Welch spectrum, and every used mode's variance, in the data's
//! time unit and the fit's amplitude unit (point spacings); the equation's coefficients set
//! with their subscripts (c_y as c with a subscript y).

use super::plot::*;
use super::script::symbols;
use super::FigureError;
use crate::discover::{DiscoverReport, Replay};

/// The figure, laid out at `width` pixels.
pub(super) fn discover_spectra(
    r: &DiscoverReport,
    p: &Replay,
    width: u32,
) -> Result<String, FigureError> {
    let titles: Vec<String> = p.modes.iter().map(|m| format!("mode {m}")).collect();
    // The fit's units: amplitudes in point spacings, a density per cycle per time unit.
    let unit = r.time_unit.as_deref().unwrap_or("time unit");
    let frequency = format!("frequency (cycles per {unit})");
    let density = format!("log₁₀ PSD (point spacings²·{unit})");
    let mut panels: Vec<Panel> = p
        .modes
        .iter()
        .enumerate()
        .take(4)
        .map(|(k, _)| {
            panel(
                &titles[k],
                &frequency,
                &density,
                vec![
                    series(
                        "recording",
                        log_spectrum(&p.frequencies, &p.observed[k]),
                        Mark::Line,
                    ),
                    series(
                        "discovered equation, simulated",
                        log_spectrum(&p.simulated_frequencies, &p.simulated[k]),
                        Mark::Dashed,
                    ),
                ],
            )
        })
        .collect();
    let variance = |v: &[f64]| -> Vec<(f64, f64)> {
        p.modes
            .iter()
            .zip(v)
            .filter(|(_, x)| **x > 0.0)
            .map(|(m, x)| (*m as f64, x.log10()))
            .collect()
    };
    let title = format!("{}, simulated, against the recording", symbols(&r.equation));
    let caption = format!(
        "modal variances ({} frames simulated at kT = {:.4}, mode {}'s)",
        p.frames,
        p.temperature,
        p.modes.first().copied().unwrap_or(0)
    );
    panels.push(panel(
        &caption,
        "mode index i",
        "log₁₀ σᵢ² (point spacings²)",
        vec![
            series("recording", variance(&p.observed_variance), Mark::Dots),
            series(
                "discovered equation, simulated",
                variance(&p.simulated_variance),
                Mark::Line,
            ),
        ],
    ));
    // The title holds the equation alone (two lines at 85 mm); the run's numbers are the
    // variances' caption.
    render(width, &title, 330, (2, 3), &panels)
}
