//! The options synopsis in docs/commands.md names every long option of every subcommand, as
//! clap knows them, so a new option cannot be left out of it.

use clap::CommandFactory;

#[test]
fn the_synopsis_names_every_option() {
    let docs = std::fs::read_to_string(format!("{}/docs/commands.md", env!("CARGO_MANIFEST_DIR")))
        .unwrap();
    let synopsis = docs
        .split("## Options")
        .nth(1)
        .and_then(|s| s.split("```").nth(1))
        .expect("the Options synopsis block");
    // Each subcommand's synopsis: from its `theory-search NAME` line to the next one.
    let section = |name: &str| -> String {
        let start = synopsis
            .find(&format!("theory-search {name}"))
            .or_else(|| synopsis.find(&format!("theory-search [{name}]")))
            .unwrap_or_else(|| panic!("no synopsis for {name}"));
        let rest = &synopsis[start + 1..];
        let end = rest.find("theory-search ").map_or(rest.len(), |e| e);
        rest[..end].to_string()
    };
    let mut missing = Vec::new();
    let cli = theory_search::cli::Cli::command();
    let mut check = |name: String, cmd: &clap::Command| {
        let text = section(&name);
        for arg in cmd.get_arguments() {
            if let Some(long) = arg.get_long() {
                if long != "help" && !text.contains(&format!("--{long}")) {
                    missing.push(format!("{name}: --{long}"));
                }
            }
        }
    };
    for sub in cli.get_subcommands() {
        let name = sub.get_name().to_string();
        if sub.get_subcommands().next().is_some() {
            for inner in sub.get_subcommands() {
                check(format!("{name} {}", inner.get_name()), inner);
            }
        } else {
            check(name, sub);
        }
    }
    assert!(
        missing.is_empty(),
        "missing from the synopsis: {}",
        missing.join(", ")
    );
}
