//! `fragkit list`: the cases with their parameters and requirements.

use anyhow::Result;
use fragkit::harness::runner::{is_opt_in, select};

pub fn list(pattern: Option<String>, verbose: bool) -> Result<()> {
    let patterns: Vec<String> = pattern.into_iter().collect();
    let cases = if patterns.is_empty() {
        fragkit_cases::all().iter().collect()
    } else {
        select(fragkit_cases::all(), &patterns)?
    };
    for case in cases {
        let requires =
            if case.requires.is_empty() { String::new() } else { format!(" [requires {:?}]", case.requires) };
        let opt_in = if is_opt_in(case.name) { " [opt-in: runs only when a pattern names it]" } else { "" };
        println!("{}{requires}{opt_in}\n    {}", case.name, case.summary);
        for p in case.params {
            println!("    --set {}={}   ({})", p.name, p.default, p.help);
        }
        if verbose {
            // One hop to the code: each shader file its pipelines are built from, and the module
            // that builds them (the kit's shader table).
            for file in case.shaders {
                println!("    shaders/{:<40} {}", file.path, file.module);
            }
        }
    }
    Ok(())
}
