//! `fragkit list`: the cases with their parameters and requirements.

use anyhow::Result;
use fragkit::harness::runner::{is_opt_in, select};

pub fn list(pattern: Option<String>) -> Result<()> {
    let patterns: Vec<String> = pattern.into_iter().collect();
    let cases =
        if patterns.is_empty() { fragkit_cases::ALL.iter().collect() } else { select(fragkit_cases::ALL, &patterns)? };
    for case in cases {
        let requires =
            if case.requires.is_empty() { String::new() } else { format!(" [requires {:?}]", case.requires) };
        let opt_in = if is_opt_in(case.name) { " [opt-in: runs only when a pattern names it]" } else { "" };
        println!("{}{requires}{opt_in}\n    {}", case.name, case.summary);
        for p in case.params {
            println!("    --set {}={}   ({})", p.name, p.default, p.help);
        }
    }
    Ok(())
}
