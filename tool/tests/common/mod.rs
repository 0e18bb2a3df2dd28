//! Running `rtl-gen` as a user would, for the command-line tests.

use std::process::{Command, Output};

/// Runs `rtl-gen args` in the package directory.
pub fn rtl_gen(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_rtl-gen"))
        .args(args)
        .output()
        .expect("rtl-gen runs")
}

/// Its standard output, then its standard error.
pub fn text(o: &Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    )
}
