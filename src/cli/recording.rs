//! The options every command that reads recordings takes (`fit`, `discover`): one clap group,
//! turned into the library's (name, value) pairs, which the library checks
//! ([`crate::recording::RecordingSettings::set`]), as it checks Python's keywords.

use crate::recording::Setting;

/// How the recordings are read and projected.
#[derive(Debug, clap::Args)]
pub struct RecordingArgs {
    /// What the columns after time hold.
    #[arg(long, value_enum, default_value_t = Kind::Midline)]
    kind: Kind,
    /// The model field the data observe (default: the lateral field for midlines, the axial
    /// one for lengths).
    #[arg(long)]
    field: Option<String>,
    /// Model points N for midlines (resampled by arc length when the data have another K),
    /// from 3 to 500.
    #[arg(long, short, default_value_t = 12, value_name = "N")]
    points: usize,
    /// Lengths only: the number of segments around the whole body when only the first K
    /// were measured (fits the lowest whole modes by least squares).
    #[arg(long, value_name = "R")]
    ring: Option<usize>,
    /// Bridge gaps of at most K lost frames linearly (0: none); longer gaps split the recording
    /// into runs (the covariance pools every usable frame, the spectra use windows inside one
    /// run).
    #[arg(long, value_name = "K", default_value_t = crate::recording::DEFAULT_FILL_GAPS)]
    fill_gaps: usize,
    /// Frames per second of a DeepLabCut file (its rows hold frame indices; without it the
    /// time unit is one frame). Refused for a file with a time column.
    #[arg(allow_hyphen_values = true, long, value_name = "F")]
    fps: Option<f64>,
    /// DeepLabCut points tracked below this likelihood make their frame lost.
    #[arg(
        allow_hyphen_values = true,
        long,
        value_name = "P",
        default_value_t = 0.6
    )]
    min_likelihood: f64,
    /// Which end the data list first: `first` (head first, as trackers write) or `last`.
    /// A WCON record's own `"head"` (`L`/`R`) is followed where it is given.
    #[arg(long, value_enum, default_value_t = HeadEnd::First)]
    head: HeadEnd,
    /// The inputs' layout (auto: `{` opens WCON, HDF5's signature a SLEAP analysis file or
    /// DeepLabCut's `.h5`, DeepLabCut's header rows mark its CSV).
    #[arg(long, value_enum, default_value_t = Format::Auto)]
    input_format: Format,
    /// The first CSV column is a track id: each track is one animal (rows may interleave).
    #[arg(long)]
    track_column: bool,
    /// Unit of the time column (e.g. `s`), printed with ω and β (a WCON file names its own).
    #[arg(long, value_name = "UNIT")]
    time_unit: Option<String>,
    /// Unit of the coordinates (e.g. `mm`), printed with the point spacing.
    #[arg(long, value_name = "UNIT")]
    length_unit: Option<String>,
}

/// Input kinds.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
enum Kind {
    Midline,
    Lengths,
}

/// Input layouts.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
enum Format {
    Auto,
    Csv,
    Wcon,
    Hdf5,
}

/// Where the head is in each frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
enum HeadEnd {
    First,
    Last,
}

/// A choice by its command-line name (clap's, which is the library's).
pub(super) fn choice(value: impl clap::ValueEnum) -> Setting {
    let name = value.to_possible_value().map(|v| v.get_name().to_string());
    Setting::Text(name.unwrap_or_default())
}

/// A count.
pub(super) fn count(n: usize) -> Setting {
    Setting::Int(n as i128)
}

impl RecordingArgs {
    /// The options as (name, value) pairs, `order` the theory's; options not given are left
    /// to the library's defaults.
    pub fn pairs(&self, order: u32) -> Vec<(&'static str, Setting)> {
        let mut pairs = vec![
            ("kind", choice(self.kind)),
            ("order", Setting::Int(order.into())),
            ("points", count(self.points)),
            ("fill_gaps", count(self.fill_gaps)),
            ("min_likelihood", Setting::Float(self.min_likelihood)),
            ("head", choice(self.head)),
            ("input_format", choice(self.input_format)),
            ("track_column", Setting::Bool(self.track_column)),
        ];
        let text = |t: &Option<String>| t.clone().map(Setting::Text);
        let optional = [
            ("field", text(&self.field)),
            ("ring", self.ring.map(count)),
            ("fps", self.fps.map(Setting::Float)),
            ("time_unit", text(&self.time_unit)),
            ("length_unit", text(&self.length_unit)),
        ];
        pairs.extend(optional.into_iter().filter_map(|(n, v)| Some((n, v?))));
        pairs
    }

    /// The options given away from their defaults, as command-line words: the commands a
    /// report prints read the same recordings the same way.
    pub fn words(&self) -> Vec<String> {
        #[derive(clap::Parser)]
        struct Defaults {
            #[command(flatten)]
            recording: RecordingArgs,
        }
        let defaults = <Defaults as clap::Parser>::try_parse_from(["defaults"])
            .map(|d| d.recording.pairs(0))
            .unwrap_or_default();
        let mut words = Vec::new();
        for (name, value) in self.pairs(0) {
            if defaults.contains(&(name, value.clone())) {
                continue;
            }
            words.push(format!("--{}", name.replace('_', "-")));
            match value {
                Setting::Bool(_) => {}
                Setting::Text(t) => words.push(t),
                Setting::Int(i) => words.push(i.to_string()),
                Setting::Float(x) => words.push(crate::report::number(x)),
            }
        }
        words
    }
}

/// The recordings as the command line named them, then the reading options given: the words
/// a report's commands start from.
pub(super) fn inputs(paths: &[std::path::PathBuf], args: &RecordingArgs) -> Vec<String> {
    let mut words: Vec<String> = paths.iter().map(|p| p.display().to_string()).collect();
    words.extend(args.words());
    words
}
