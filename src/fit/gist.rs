//! The report's first lines, in words: whether the theory holds on this recording (the three
//! tests' verdicts over the voting modes), the body's constant, and the next command to run,
//! with this recording's numbers:
//! * a rejected dispersion (the modes do not oscillate as a passive body's): `discover --active`,
//!   which says which forces the recording needs, where the model allows active forces;
//! * another law rejected (or no `[active]` section): `discover`, which library terms it needs;
//! * nothing rejected but a test undetermined: the options the advice names (`--window`,
//!   `--fill-gaps`, `--points`), or what no option gives (a faster frame rate, more frames);
//! * every test consistent: the onward `simulate` line, the fitted body.

use super::advice::Step;
use super::report::FitReport;
use super::verdict::Verdict;
use crate::markup::command_line;
use crate::report::short;

/// The verdict block: a headline and its `next:` line.
pub(super) fn text(r: &FitReport) -> String {
    let t = &r.tests;
    let tests = [
        ("equipartition", &t.equipartition),
        ("dispersion", &t.dispersion),
        ("damping", &t.damping),
    ];
    let with = |v: Verdict| -> Vec<&str> {
        (tests.iter())
            .filter(|(_, x)| x.verdict == v)
            .map(|(n, _)| *n)
            .collect()
    };
    let (rejected, consistent, open) = (
        with(Verdict::Rejected),
        with(Verdict::Consistent),
        with(Verdict::Undetermined),
    );
    let voting: Vec<usize> = (r.modes_fit.iter())
        .filter(|m| m.votes)
        .map(|m| m.mode)
        .collect();
    let headline = if !rejected.is_empty() {
        let mut h = format!("the theory does not hold here: {} rejected", and(&rejected));
        if !consistent.is_empty() {
            h += &format!(" ({} consistent)", and(&consistent));
        }
        h
    } else if open.is_empty() {
        format!(
            "the theory holds here: {} consistent over modes {}",
            and(&consistent),
            list(&voting)
        )
    } else if consistent.is_empty() {
        format!(
            "undetermined: {} voting mode(s), a test needs 3",
            voting.len()
        )
    } else {
        format!(
            "nothing rejected: {} consistent, {} undetermined",
            and(&consistent),
            and(&open)
        )
    };
    let mut out = format!("In short: {headline}.\n");
    if let Some(c) = &r.continuum {
        let symbol = c.symbol();
        let interval = c
            .interval
            .map(|[lo, hi]| format!(" [{}, {}]", short(lo), short(hi)))
            .unwrap_or_default();
        let hedge = if rejected.is_empty() {
            ""
        } else {
            " (not a constant of this body while a law is rejected)"
        };
        out += &format!(
            "  {symbol} = {}{interval} {}{hedge}\n",
            short(c.constant),
            c.unit
        );
    }
    out += &format!("  next: {}\n", next(r, &rejected));
    out
}

/// The command (or change) to try next, and why.
fn next(r: &FitReport, rejected: &[&str]) -> String {
    let command = |sub: &str| command_line(sub, &r.inputs, r.model_argument.as_deref());
    if rejected.contains(&"dispersion") && r.active_allowed {
        return format!(
            "{} --active (which forces the recording needs: an active force, a driven rhythm)",
            command("discover")
        );
    }
    if !rejected.is_empty() {
        return format!(
            "{} (which of the library's terms the recording needs)",
            command("discover")
        );
    }
    if let Some(a) = &r.advice {
        let options: Vec<String> = a.steps.iter().filter_map(Step::option).collect();
        if !options.is_empty() {
            return format!(
                "this command again with {} (the advice below: modes into the vote)",
                options.join(" ")
            );
        }
        if !a.steps.is_empty() {
            return "a recording the advice below describes (no option of this command decides the tests)".into();
        }
    }
    format!("{} (the fitted body)", r.simulate_line())
}

/// `a`, `a and b`, `a, b and c`.
fn and(words: &[&str]) -> String {
    match words {
        [] => String::new(),
        [one] => one.to_string(),
        [head @ .., last] => format!("{} and {last}", head.join(", ")),
    }
}

fn list(modes: &[usize]) -> String {
    let words: Vec<String> = modes.iter().map(usize::to_string).collect();
    words.join(", ")
}
