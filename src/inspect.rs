//! `pelt inspect`: prints `pelt_bake::inspect`'s report of a file, as text or JSON.

use std::process::ExitCode;

use pelt_bake::inspect;

use crate::InspectArgs;

/// Runs `pelt inspect`.
pub fn run(args: &InspectArgs) -> anyhow::Result<ExitCode> {
    let report = pelt_io::load(&args.file).and_then(|doc| inspect::describe(&doc));
    let info = match report {
        Ok(v) => v,
        Err(e) => {
            eprintln!("pelt: {e}");
            return Ok(ExitCode::from(1));
        }
    };
    if args.json {
        println!("{}", serde_json::to_string_pretty(&info)?);
    } else {
        print!("{}", inspect::text(&info));
    }
    Ok(ExitCode::SUCCESS)
}
