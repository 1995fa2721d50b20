//! The comparison's values and their forms: text for people, JSON, and a tidy CSV (one row per
//! animal and quantity, for a statistics package).

use serde::Serialize;

use crate::fit::{FitReport, TheoryTest, Verdict};
use crate::markup::clip;
use crate::report::{short, wrap_long, Report, MAX_LINE};

/// One group's animals, summarised.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct GroupSummary {
    /// Its name.
    pub name: String,
    /// Animals fitted.
    pub animals: usize,
    /// Per law (equipartition, dispersion, damping): animals consistent, rejected, undetermined.
    pub laws: Vec<LawCount>,
}

/// How a group's animals fared on one law.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LawCount {
    /// The law.
    pub law: &'static str,
    /// Animals whose own fit is consistent with it.
    pub consistent: usize,
    /// … rejects it.
    pub rejected: usize,
    /// … cannot decide.
    pub undetermined: usize,
}

impl GroupSummary {
    /// The summary of a group's animals' own fits.
    pub(super) fn of<'a>(name: &str, reports: impl Iterator<Item = &'a FitReport>) -> Self {
        let reports: Vec<&FitReport> = reports.collect();
        let law = |law: &'static str, pick: fn(&FitReport) -> &TheoryTest| {
            let count = |v: Verdict| reports.iter().filter(|r| pick(r).verdict == v).count();
            LawCount {
                law,
                consistent: count(Verdict::Consistent),
                rejected: count(Verdict::Rejected),
                undetermined: count(Verdict::Undetermined),
            }
        };
        GroupSummary {
            name: name.to_string(),
            animals: reports.len(),
            laws: vec![
                law("equipartition", |r| &r.tests.equipartition),
                law("dispersion", |r| &r.tests.dispersion),
                law("damping", |r| &r.tests.damping),
            ],
        }
    }
}

/// The difference between the groups in one quantity.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Difference {
    /// `kappa` (or `c`), `Omega_<mode>`, `zeta_<mode>`.
    pub quantity: String,
    /// Each group's mean over its animals.
    pub means: [f64; 2],
    /// Each group's 95 % interval of its mean (Student's t on its animals − 1 dof).
    pub group_intervals: [[f64; 2]; 2],
    /// The second group's mean less the first's.
    pub estimate: f64,
    /// Its 95 % interval (Welch's t).
    pub interval: [f64; 2],
    /// The second group's mean over the first's.
    pub ratio: f64,
    /// The permutation p-value of no difference.
    pub p: f64,
}

/// One animal's value of one quantity (a row of the tidy CSV).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct AnimalRow {
    /// Its group.
    pub group: String,
    /// The animal (its recording).
    pub animal: String,
    /// The quantity.
    pub quantity: String,
    /// Its value from the animal's own fit.
    pub value: f64,
}

/// An animal left out, and why.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Excluded {
    /// Its group.
    pub group: String,
    /// The animal.
    pub animal: String,
    /// Why its fit failed.
    pub why: String,
}

impl Excluded {
    pub(super) fn new(group: &str, animal: &str, why: String) -> Self {
        Excluded {
            group: group.to_string(),
            animal: animal.to_string(),
            why,
        }
    }
}

/// Two groups of animals compared.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CompareReport {
    /// The continuum constant's name (`kappa` or `c`).
    pub constant: &'static str,
    /// Its unit.
    pub unit: String,
    /// The observed field.
    pub field: String,
    /// The modes whose Ω and ζ are compared (every animal resolves them).
    pub modes: Vec<usize>,
    /// The groups.
    pub groups: Vec<GroupSummary>,
    /// Second group less first, per quantity.
    pub differences: Vec<Difference>,
    /// Every animal's values.
    pub animals: Vec<AnimalRow>,
    /// Animals left out.
    pub excluded: Vec<Excluded>,
    /// Permutations.
    pub permutations: usize,
    /// Their seed.
    pub seed: u64,
}

impl Report for CompareReport {
    fn text(&self) -> String {
        let [a, b] = [&self.groups[0], &self.groups[1]];
        let mut out = format!(
            "Compared: {} ({} animals) against {} ({} animals), each animal fitted alone (field {}).\n",
            clip(&b.name),
            b.animals,
            clip(&a.name),
            a.animals,
            self.field
        );
        out += &format!(
            "Differences ({} less {}: means over animals; Welch's 95 % interval; p from {} permutations of the animals' groups, seed {}):\n",
            clip(&b.name),
            clip(&a.name),
            self.permutations,
            self.seed
        );
        out += &format!(
            "  {:<12} {:>12} {:>12} {:>12}  {:<26} {:>7} {:>8}\n",
            "quantity", "first", "second", "difference", "95 % interval", "ratio", "p"
        );
        for d in &self.differences {
            let interval = format!("[{}, {}]", short(d.interval[0]), short(d.interval[1]));
            out += &format!(
                "  {:<12} {:>12} {:>12} {:>12}  {:<26} {:>7.3} {:>8.4}\n",
                d.quantity,
                short(d.means[0]),
                short(d.means[1]),
                short(d.estimate),
                interval,
                d.ratio,
                d.p
            );
        }
        out += &format!(
            "({} in {}; Ω in rad per time unit; modes compared: {})\n",
            self.constant,
            self.unit,
            if self.modes.is_empty() {
                "none resolved by every animal".to_string()
            } else {
                self.modes
                    .iter()
                    .map(|m| m.to_string())
                    .collect::<Vec<_>>()
                    .join(", ")
            }
        );
        out += "Laws, animals consistent / rejected / undetermined:\n";
        for g in &self.groups {
            let laws: Vec<String> = (g.laws.iter())
                .map(|l| {
                    format!(
                        "{} {}/{}/{}",
                        l.law, l.consistent, l.rejected, l.undetermined
                    )
                })
                .collect();
            out += &format!("  {}: {}\n", clip(&g.name), laws.join(", "));
        }
        for e in &self.excluded {
            out += &format!(
                "Left out: {} of {}: {}\n",
                clip(&e.animal),
                clip(&e.group),
                e.why
            );
        }
        wrap_long(&out, MAX_LINE)
    }

    fn json(&self) -> serde_json::Value {
        serde_json::to_value(self).unwrap_or(serde_json::Value::Null)
    }

    fn csv(&self) -> Option<String> {
        // Names come from the user's files: the csv writer quotes what needs quoting.
        Some(crate::report::csv_table(
            &["group", "animal", "quantity", "value"],
            self.animals.iter().map(|r| {
                vec![
                    r.group.clone(),
                    r.animal.clone(),
                    r.quantity.clone(),
                    r.value.to_string(),
                ]
            }),
        ))
    }

    fn check(&self) -> Result<(), crate::report::NonFinite> {
        crate::report::check_finite(self)
    }
}
