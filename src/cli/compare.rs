//! `theory-search compare`: two groups of animals, each animal fitted alone, compared.

use std::io::Write;
use std::path::PathBuf;

use super::{emit, CliError, ModelArgs};
use crate::compare::{compare, CompareError, CompareSettings, Group};
use crate::fit::Input;
use crate::modal::Params;
use crate::recording::Setting;
use crate::report::Output;

/// Arguments of `compare`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The first group (the reference, such as the wild type): a directory, a pattern with `*`
    /// and `?` in the file name, or one file; each recording is one animal.
    #[arg(value_name = "FIRST")]
    first: PathBuf,
    /// The second group, likewise; differences are the second's mean less the first's.
    #[arg(value_name = "SECOND")]
    second: PathBuf,
    #[command(flatten)]
    recording: super::recording::RecordingArgs,
    /// Permutations of the animals' group labels for the p-values.
    #[arg(long, value_name = "P", default_value_t = 9999)]
    permutations: usize,
    /// Seed of the permutations.
    #[arg(long, value_name = "S", default_value_t = 1)]
    seed: u64,
    /// Also discover each animal's equation and compare its coefficients (a term an animal's
    /// selection left out counts as 0).
    #[arg(long)]
    discover: bool,
    /// Also write the comparison's figure (each animal's values, the groups' means with their
    /// 95 % intervals) into this directory.
    #[arg(long, value_name = "DIR")]
    figures: Option<PathBuf>,
    #[command(flatten)]
    page: super::options::FitPageArgs,
    #[command(flatten)]
    model: ModelArgs,
    /// Output format (csv: one row per animal and quantity).
    #[arg(long, value_enum, default_value_t = Output::Text)]
    format: Output,
}

/// Compare and print.
pub fn run(args: &Args, out: &mut dyn Write) -> Result<(), CliError> {
    let model = args.model.load()?;
    let page = args.page.page()?;
    let mut pairs = args.recording.pairs(args.model.order);
    pairs.extend([
        ("permutations", super::recording::count(args.permutations)),
        ("seed", Setting::Int(args.seed.into())),
        ("discover", Setting::Bool(args.discover)),
    ]);
    let settings = CompareSettings::from_pairs(pairs)?;
    let mut groups = Vec::new();
    for path in [&args.first, &args.second] {
        let inputs = crate::recording::recordings(std::slice::from_ref(path))?
            .into_iter()
            .map(Input::File)
            .collect();
        groups.push(Group {
            name: path.display().to_string(),
            inputs,
        });
    }
    let report = compare(groups, &model, &Params::default(), &settings)?;
    if let Some(dir) = &args.figures {
        crate::figures::write_compare(dir, &report, &page).map_err(super::figures::usage)?;
    }
    emit(out, &report, args.format)
}

impl From<CompareError> for CliError {
    fn from(e: CompareError) -> Self {
        CliError::Compare(Box::new(e))
    }
}
