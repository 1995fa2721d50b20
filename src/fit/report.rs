//! What a fit reports (pooled, per animal, per mode) and how it is written: text, JSON, CSV.

use super::animal::AnimalFit;
use super::bootstrap::Intervals;
use super::verdict::{self, ModeSpectralFit, TheoryTests, WindowChoice};
use crate::recording::{InputKind, Units};
use crate::report::{check_finite, csv_numbers, fixed, number, to_json, NonFinite, Report};

/// How complete a recording was.
#[derive(Debug, Clone, Default, PartialEq, serde::Serialize)]
pub struct Recording {
    /// Recordings (animals) pooled.
    pub recordings: usize,
    /// Rows read (frames, lost or not).
    pub frames_read: usize,
    /// Frames the tracker lost (rows with a missing value, and frames the time steps skip).
    pub frames_lost: usize,
    /// Lost frames bridged linearly (`--fill-gaps`).
    pub frames_filled: usize,
    /// The longest gap bridged (`--fill-gaps`; longer ones split the runs).
    pub fill_gaps: usize,
    /// Gaps that split the recording.
    pub gaps: usize,
    /// Runs of consecutive frames between gaps.
    pub runs: usize,
    /// The longest run, in frames.
    pub longest_run: usize,
}

/// One mode's fit.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct ModeFit {
    /// Mode index (zero modes included).
    pub index: usize,
    /// λᵢ.
    pub eigenvalue: f64,
    /// Variance of Qᵢ.
    pub variance: f64,
    /// Peak frequency (cycles per time unit).
    pub peak_frequency: f64,
    /// Spectral centroid (cycles per time unit).
    pub centroid_frequency: f64,
    /// Measured angular frequency used in the fit, 2π × the chosen estimate.
    pub angular_frequency: f64,
    /// The fitted theory's ω√λᵢ.
    pub theory_angular_frequency: f64,
}

/// The result of a fit. The JSON contract's keys come first.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct FitReport {
    /// Frames used (read and usable, plus any bridged).
    pub frames: usize,
    /// Points (midline) or segments (lengths) per frame in the input.
    pub points: usize,
    /// PCA variance shares, descending, over the non-zero modes.
    pub pca_variance_share: Vec<f64>,
    /// Equipartition shares λᵢ⁻¹/Σλⱼ⁻¹, ascending λ.
    pub theory_variance_share: Vec<f64>,
    /// |cos| between principal component i and non-zero mode shape j.
    pub overlap: Vec<Vec<f64>>,
    /// The fitted (or fixed) frequency scale.
    pub omega: f64,
    /// ω was given (`--omega`), not fitted.
    #[serde(skip)]
    pub omega_given: bool,
    /// The fitted inverse temperature, lengths in units of the spacing.
    pub beta: f64,
    /// The theory's constant in body units, independent of the number of model points: the
    /// flexural constant κ of a beam (ωᵢ = κ(βᵢL)²) or the wave speed c of a string or ring
    /// (ωᵢ = c·βᵢ), lengths in body lengths; `None` where the field has no continuum roots.
    pub continuum: Option<Continuum>,
    /// Each mode's own spectral fit (see [`super::verdict`]).
    pub modes_fit: Vec<ModeSpectralFit>,
    /// The theory's three predictions tested over the voting modes.
    pub tests: TheoryTests,
    /// The white floor ν (variance per frame of the modal coordinates), measured from
    /// the highest modes.
    pub noise_floor: Option<f64>,
    /// The Welch window used, and why.
    pub window: WindowChoice,
    /// The tracking noise σ measured at the tracked points (midlines; see `fit::jitter`).
    pub tracking_noise: Option<crate::recording::TrackingNoise>,
    /// Input kind.
    pub kind: InputKind,
    /// Observed field.
    pub field: String,
    /// The observed field's scale suffix (its `omega_<scale>` parameter).
    pub scale: String,
    /// Model points N.
    pub model_points: usize,
    /// Sampling interval.
    pub sample_interval: f64,
    /// Welch window used (frames) and segments averaged.
    pub welch: (usize, usize),
    /// For principal component k: the length of its projection onto the eigenspace of mode k
    /// (the whole degenerate pair when λₖ is shared, so a rotated cos/sin pair still scores 1).
    pub mode_overlap: Vec<f64>,
    /// Variance shares of the PCA of the plain angles (or strains).
    pub angle_pca_variance_share: Vec<f64>,
    /// Per non-zero mode.
    pub modes: Vec<ModeFit>,
    /// Modes used for ω and β.
    pub fitted_modes: usize,
    /// Frequencies of the spectra (cycles per time unit).
    #[serde(skip)]
    pub frequencies: Vec<f64>,
    /// Welch PSD of each non-zero modal coordinate.
    #[serde(skip)]
    pub psd: Vec<Vec<f64>>,
    /// Principal components as columns over the mode shapes: `components[i][j]` = component of
    /// PC i along mode j.
    #[serde(skip)]
    pub components: Vec<Vec<f64>>,
    /// The non-zero mode shapes on the model's points, `shapes[j][p]`.
    #[serde(skip)]
    pub shapes: Vec<Vec<f64>>,
    /// What the recording held: frames read, lost, bridged; gaps and runs.
    pub recording: Recording,
    /// Cautions about what the numbers can mean for this input.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub warnings: Vec<String>,
    /// Where the model holds an end: its rms displacement from the first frame over the whole
    /// midline's ([`crate::recording::Movement`]); `null` where no end is held.
    pub held_movement: Option<f64>,
    /// With several animals: each one's own fit, beside the pooled one above.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub animals: Vec<AnimalFit>,
    /// With several animals: how much their constants differ, and what the pool makes of it.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub spread: Option<super::spread::Spread>,
    /// With animals sampled at several rates: each rate group's pooled fit (the first is the
    /// one above), summarised.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub rate_groups: Vec<super::rates::RateGroup>,
    /// The continuum constant across the rate groups.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub across_rates: Option<super::rates::AcrossRates>,
    /// Units of the recording's columns.
    pub units: Units,
    /// The mean model point spacing h = (body length)/(N − 1) (midlines) or rest segment
    /// length (lengths), in the coordinates' unit: modal amplitudes are in units of h.
    pub spacing: f64,
    /// The first k principal components against the first k modes, k = 1, 2, ….
    pub subspace: Vec<Subspace>,
    /// 95 % bootstrap intervals (`--bootstrap`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub intervals: Option<Intervals>,
    /// What would decide the undetermined tests (`advice`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub advice: Option<super::advice::Advice>,
    /// The arguments that make `simulate` use the fitted scales (see [`FitReport::onward`]).
    pub onward: Vec<String>,
    /// The recordings as the command line named them and the reading options it gave (`--fps
    /// 15`…): the commands the report prints start from them.
    #[serde(skip)]
    pub inputs: Vec<String>,
    /// Which spectral estimate the measured frequencies are (`--estimator`).
    #[serde(skip)]
    pub estimator: super::settings::Estimator,
    /// The model has an `[active]` section (`discover --active` takes it).
    #[serde(skip)]
    pub active_allowed: bool,
    /// `--model`'s argument as given (the embedded larva without), for the same commands.
    #[serde(skip)]
    pub model_argument: Option<String>,
}

/// The continuum constant of a fit.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Continuum {
    /// `kappa` (beam) or `c` (string, ring).
    pub name: &'static str,
    /// Its value, lengths in body lengths and time in the data's unit.
    pub constant: f64,
    /// Its 95 % interval: from the modes' standard errors, or the bootstrap's when one was
    /// drawn (`--bootstrap B`).
    pub interval: Option<[f64; 2]>,
    /// `mode errors` or `bootstrap`.
    pub interval_from: Option<&'static str>,
    /// The unit, e.g. `body length²/s`.
    pub unit: String,
    /// The continuum roots βᵢL of the fitted modes (body length 1).
    pub roots: Vec<f64>,
    /// The mean body length L in the data's length unit (the model's spacing times N − 1).
    pub body_length: f64,
    /// The constant in the data's units: κL² (length²/time) or cL (length/time).
    pub in_data_units: f64,
}

impl Continuum {
    /// Its symbol: κ for a beam's flexural constant, c for a string's or ring's wave speed.
    pub fn symbol(&self) -> &'static str {
        if self.name == "kappa" {
            "κ"
        } else {
            "c"
        }
    }
}

/// The first k principal components against the first k theory modes.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Subspace {
    /// k.
    pub k: usize,
    /// The smallest cosine of the principal angles between the two k-dimensional subspaces
    /// (1: the same subspace).
    pub cosine: f64,
    /// Variance share the first k theory modes capture.
    pub modes_capture: f64,
    /// Variance share the first k principal components capture (the most any k directions can).
    pub components_capture: f64,
}

/// The recording's own warnings: bridging ([`super::bridging::warning`]), and a DeepLabCut export read without
/// `--fps`, whose time unit is a frame.
pub(super) fn recording_notes(report: &FitReport) -> Vec<String> {
    let mut notes: Vec<String> = super::bridging::warning(report).into_iter().collect();
    if report.units.time.as_deref() == Some(crate::recording::FRAME_UNIT) {
        notes.push("a DeepLabCut export without --fps: times are in frames (ω in rad/frame, β in frame²); --fps F gives them in seconds".into());
    }
    notes
}

impl Report for FitReport {
    fn check(&self) -> Result<(), NonFinite> {
        check_finite(self)
    }

    fn json(&self) -> serde_json::Value {
        to_json(self)
    }

    fn csv(&self) -> Option<String> {
        let r = self;
        Some(csv_numbers(
            &[
                "mode",
                "eigenvalue",
                "pca_share",
                "theory_share",
                "overlap",
                "variance",
                "peak_frequency",
                "centroid_frequency",
                "angular_frequency",
                "theory_angular_frequency",
            ],
            r.modes.iter().enumerate().map(|(k, m)| {
                vec![
                    m.index as f64,
                    m.eigenvalue,
                    r.pca_variance_share[k],
                    r.theory_variance_share[k],
                    r.overlap[k][k],
                    m.variance,
                    m.peak_frequency,
                    m.centroid_frequency,
                    m.angular_frequency,
                    m.theory_angular_frequency,
                ]
            }),
        ))
    }

    fn text(&self) -> String {
        let r = self;
        let what = match r.kind {
            InputKind::Midline => format!("{}-point midlines", r.points),
            InputKind::Lengths => format!("{} segment lengths", r.points),
        };
        let time = r.units.time.as_deref().unwrap_or("time unit");
        let length = r.units.length.as_deref().unwrap_or("length unit");
        let mut t = format!(
            "{}\nFit of {} frames of {what} (sampling interval {} {time}) to field {} on N = {}\n\
             \x20 ω = {} rad/{time} ({}), β = {} {time}² (amplitudes in point spacings h = {} {length}; β/h² = {} {time}²/{length}²)\n",
            super::gist::text(r),
            r.frames,
            number((r.sample_interval * 1e9).round() / 1e9),
            r.field,
            r.model_points,
            fixed(r.omega, 6),
            omega_from(r),
            fixed(r.beta, 6),
            fixed(r.spacing, 6),
            {
                // β/h² is printed only when it is a float; h² overflows for absurd coordinates.
                let ratio = r.beta / (r.spacing * r.spacing);
                if ratio.is_normal() {
                    fixed(ratio, 6)
                } else {
                    "out of range".into()
                }
            },
        );
        if let Some(c) = &r.continuum {
            let symbol = c.symbol();
            let law = if c.name == "kappa" {
                "ωᵢ = κ(βᵢL)²"
            } else {
                "ωᵢ = c·βᵢL"
            };
            let power = if c.name == "kappa" { "²" } else { "" };
            let interval = c
                .interval
                .map(|[lo, hi]| {
                    format!(
                        " [{}, {}] (95 %, {})",
                        fixed(lo, 6),
                        fixed(hi, 6),
                        c.interval_from.unwrap_or("")
                    )
                })
                .unwrap_or_default();
            t += &format!(
                "  continuum: {symbol} = {}{interval} {} = {} {length}{power}/{time} with the mean body length L = {} {length} ({law} over the same modes, βᵢL the continuum roots; independent of N, where ω is the N-point value)\n",
                fixed(c.constant, 6),
                c.unit,
                fixed(c.in_data_units, 6),
                fixed(c.body_length, 6),
            );
        }
        if let Some(i) = &r.intervals {
            let moving = i
                .moving
                .map(|(l, b)| format!(" of about {b} frames, drawn {l} consecutive at a time"))
                .unwrap_or_default();
            t += &format!(
                "  95 % intervals ({} replicates over {} {}{moving}, {} fitted): ω [{}, {}], β [{}, {}]\n",
                i.replicates,
                i.units,
                i.resampled,
                i.fitted,
                fixed(i.omega[0], 6),
                fixed(i.omega[1], 6),
                fixed(i.beta[0], 6),
                fixed(i.beta[1], 6)
            );
        }
        let rec = &r.recording;
        t += &format!(
            "  recording: {} animal(s), {} frames read, {} lost ({}), {} gaps, {} runs, longest {} frames\n",
            rec.recordings, rec.frames_read, rec.frames_lost, super::bridging::clause(rec, r.frames), rec.gaps, rec.runs, rec.longest_run
        );
        t += &format!(
            "  Welch: window {} frames, {} segments; f in cycles/{time}, ω in rad/{time} (peak f: the spectrum's highest bin, centroid f: its mean; measured ω = 2π × one of them, theory ω√λ: the fitted line)\n  mode        λ   PCA share  equipartition  overlap with mode   peak f  centroid f   measured ω  theory ω√λ\n",
            r.welch.0, r.welch.1
        );
        for (k, m) in r.modes.iter().enumerate() {
            t += &format!(
                "  {:>4} {:>8.5} {:>9.3} % {:>12.3} % {:>18.5} {:>8.5} {:>11.5} {:>12.5} {:>11.5}\n",
                m.index,
                m.eigenvalue,
                100.0 * r.pca_variance_share[k],
                100.0 * r.theory_variance_share[k],
                r.mode_overlap[k],
                m.peak_frequency,
                m.centroid_frequency,
                m.angular_frequency,
                m.theory_angular_frequency,
            );
        }
        t += "  overlap: |cos(PCₖ, vₖ)|, or the projection onto the pair's plane when λₖ is degenerate\n";
        t += &verdict::text(
            &r.modes_fit,
            (r.noise_floor, r.tracking_noise.as_ref()),
            &r.tests,
            &r.window,
        );
        t += &subspace_text(r);
        for w in &r.warnings {
            t += &format!("  warning: {w}\n");
        }
        if let Some(a) = &r.advice {
            t += &format!("  {a}\n");
        }
        t += &animals_text(&r.animals);
        t += &super::spread::text(r);
        t += &super::rates::text(r);
        let shares: Vec<String> = r
            .angle_pca_variance_share
            .iter()
            .map(|s| format!("{:.1}", 100.0 * s))
            .collect();
        t += &format!(
            "  PCA of the plain angles (%, the paper's eigenmaggots; equipartition makes them equal): {}\n",
            shares.join(" ")
        );
        t += &format!(
            "  onward (times in {time}, lengths in point spacings): {}\n",
            r.simulate_line()
        );
        crate::report::wrap_long(&t, crate::report::MAX_LINE)
    }
}

/// Where ω comes from: the least squares over the modes that vote (named, as they may skip
/// some), or the spectral estimates of every mode fitted when none votes.
fn omega_from(r: &FitReport) -> String {
    let voting: Vec<usize> = r
        .modes_fit
        .iter()
        .take(r.fitted_modes)
        .filter(|f| f.votes && f.omega_error.is_some())
        .map(|f| f.mode)
        .collect();
    let modes = |m: &[usize]| -> String {
        let contiguous = m.windows(2).all(|w| w[1] == w[0] + 1);
        match m {
            [] => String::new(),
            [one] => format!("mode {one}"),
            [first, .., last] if contiguous => format!("modes {first}–{last}"),
            _ => format!(
                "modes {}",
                m.iter()
                    .map(usize::to_string)
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        }
    };
    if r.omega_given {
        "given by --omega".to_string()
    } else if voting.is_empty() {
        let all: Vec<usize> = r
            .modes
            .iter()
            .take(r.fitted_modes)
            .map(|m| m.index)
            .collect();
        format!("spectral estimates of {}: none votes", modes(&all))
    } else {
        format!("least squares over the voting {}", modes(&voting))
    }
}

impl FitReport {
    /// The per-animal table as CSV (the `csv` crate's writer): animal, frames, lost, ω, β, then
    /// each component's share and overlap, then its continuum constant and that one's interval
    /// (`spread` compares them); empty cells for an animal not fitted alone.
    pub fn animals_csv(&self) -> String {
        let m = self.modes.len();
        let mut w = csv::Writer::from_writer(Vec::new());
        let mut header: Vec<String> = ["animal", "frames", "frames_lost", "omega", "beta", "note"]
            .iter()
            .map(|s| s.to_string())
            .collect();
        header.extend((1..=m).map(|k| format!("pca_share_{k}")));
        header.extend((1..=m).map(|k| format!("overlap_{k}")));
        header.extend(["continuum", "continuum_low", "continuum_high"].map(String::from));
        let opt = |v: Option<f64>| v.map(|x| x.to_string()).unwrap_or_default();
        let mut rows = vec![header];
        for a in &self.animals {
            let mut row = vec![
                a.recording.clone(),
                a.frames.to_string(),
                a.frames_lost.to_string(),
                opt(a.omega),
                opt(a.beta),
                a.note.clone().unwrap_or_default(),
            ];
            for list in [&a.pca_variance_share, &a.mode_overlap] {
                row.extend((0..m).map(|k| opt(list.get(k).copied())));
            }
            let [lo, hi] = a.continuum_interval.map_or([None; 2], |i| i.map(Some));
            row.extend([opt(a.continuum), opt(lo), opt(hi)]);
            rows.push(row);
        }
        for r in rows {
            // Writing to memory cannot fail.
            w.write_record(&r).ok();
        }
        String::from_utf8(w.into_inner().unwrap_or_default()).unwrap_or_default()
    }

    /// The onward `simulate` line: the fitted body on the model's points.
    pub fn simulate_line(&self) -> String {
        let mut line = String::from("theory-search simulate");
        if let Some(m) = &self.model_argument {
            line += " --model ";
            line += &crate::markup::shell_word(m);
        }
        line + &format!(" --points {} {}", self.model_points, self.onward.join(" "))
    }

    /// The arguments that make `simulate` (and, without `--temperature`, `behave` and `modes`)
    /// use the fitted scales: `--param omega_<scale>=ω --temperature 1/β`.
    pub fn onward_arguments(&self) -> Vec<String> {
        let mut args = vec![
            "--param".into(),
            format!(
                "{}={}",
                crate::params::Params::omega_name(&self.scale),
                number(self.omega)
            ),
        ];
        // A temperature that is not a finite number is left out, never printed as `inf`.
        let temperature = 1.0 / self.beta;
        if temperature.is_finite() {
            args.extend(["--temperature".into(), number(temperature)]);
        }
        args
    }
}

/// The subspace agreement lines: first k components against first k modes.
fn subspace_text(r: &FitReport) -> String {
    let row = |f: &dyn Fn(&Subspace) -> String| -> String {
        r.subspace.iter().map(f).collect::<Vec<_>>().join(" ")
    };
    let mut t = format!(
        "  first k = 1…{}: cos of the widest principal angle between components and modes: {}\n",
        r.subspace.len(),
        row(&|s| format!("{:.4}", s.cosine))
    );
    t += &format!(
        "    variance captured by the first k modes: {} %; by the first k components: {} %\n",
        row(&|s| format!("{:.1}", 100.0 * s.modes_capture)),
        row(&|s| format!("{:.1}", 100.0 * s.components_capture))
    );
    if let Some(i) = &r.intervals {
        let span = |v: &[[f64; 2]], scale: f64| -> String {
            v.iter()
                .map(|[a, b]| format!("[{:.3}, {:.3}]", scale * a, scale * b))
                .collect::<Vec<_>>()
                .join(" ")
        };
        t += &format!(
            "    95 %: PCA shares (%) {}\n    95 %: overlaps {}\n    95 %: subspace cosines {}\n",
            span(&i.pca_variance_share, 100.0),
            span(&i.mode_overlap, 1.0),
            span(&i.subspace_cosine, 1.0)
        );
    }
    t
}

/// Each animal's own fit, one line each.
fn animals_text(animals: &[AnimalFit]) -> String {
    if animals.is_empty() {
        return String::new();
    }
    let mut t = format!(
        "  each animal alone ({} pooled above):\n  {:<40} {:>7} {:>6} {:>10} {:>12} {:>9}\n",
        animals.iter().filter(|a| a.note.is_none()).count(),
        "animal",
        "frames",
        "lost",
        "ω",
        "β",
        "PC 1"
    );
    for a in animals {
        match (a.omega, a.beta, a.first_share) {
            (Some(w), Some(b), Some(p)) => {
                t += &format!(
                    "  {:<40} {:>7} {:>6} {:>10.5} {:>12.5} {:>7.2} %\n",
                    a.recording,
                    a.frames,
                    a.frames_lost,
                    w,
                    b,
                    100.0 * p
                )
            }
            _ => {
                t += &format!(
                    "  {:<40} {:>7} {:>6}  not fitted alone: {}\n",
                    a.recording,
                    a.frames,
                    a.frames_lost,
                    a.note.as_deref().unwrap_or("")
                )
            }
        }
    }
    t
}
