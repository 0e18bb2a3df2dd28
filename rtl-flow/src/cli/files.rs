//! Vector and report files: `vectors` (the unit's own stimulus), `convert`
//! (text and rtlvec), `merge-reports` (the shards of one check).

use super::args::{ReportArgs, UnitArgs};
use super::check::write_reports;
use super::{bad_usage, format_word};
use crate::report::{self, RunReport};
use crate::{byo, FlowError};
use std::path::PathBuf;

pub(super) fn write_vectors(
    unit: &UnitArgs,
    count: u64,
    first: u64,
    seed: u64,
    out: &std::path::Path,
) -> Result<bool, FlowError> {
    if first.checked_add(count).is_none() {
        return Err(super::bad_usage(format!(
            "--first {first} --count {count}: the vector indices pass 2^64 - 1"
        )));
    }
    let g = unit.generate()?;
    let tb = g.testbench();
    let format = byo::write_stimulus(&g, tb.as_ref(), seed, first, count, out)?;
    let word = format_word(format);
    println!(
        "wrote {} ({word}, {count} vectors of {})",
        out.display(),
        g.module.name
    );
    Ok(true)
}

pub(super) fn convert(
    input: &std::path::Path,
    output: &std::path::Path,
    unit: Option<String>,
    params: &[String],
    results: bool,
) -> Result<bool, FlowError> {
    let ports = match unit {
        Some(u) => {
            crate::params::given_once(params).map_err(FlowError::Params)?;
            let g = crate::generate(&u, params)?;
            let mut p = g.ports.inputs.clone();
            if results {
                p.extend(g.ports.outputs.iter().cloned());
            }
            Some(p)
        }
        None => None,
    };
    let (format, n) = sim::convert_file(input, output, ports.as_deref())?;
    let word = format_word(format);
    println!("wrote {} ({word}, {n} records)", output.display());
    Ok(true)
}

pub(super) fn merge_reports(
    paths: &[PathBuf],
    out: Option<PathBuf>,
    junit: Option<PathBuf>,
) -> Result<bool, FlowError> {
    crate::check_outputs(&[out.as_deref(), junit.as_deref()])?;
    let mut loaded = Vec::new();
    for p in paths {
        loaded.push((
            p.display().to_string(),
            RunReport::load(p).map_err(bad_usage)?,
        ));
    }
    let merged = report::merge(&loaded).map_err(bad_usage)?;
    for (name, r) in &loaded {
        println!(
            "  shard {:<7} {}  ({name})",
            r.shard.to_string(),
            r.headline()
        );
    }
    print!("{}", merged.failure_text());
    if let Some(e) = &merged.error {
        println!("errors in shards:\n{e}");
    }
    write_reports(&merged, &ReportArgs { report: out, junit })?;
    if merged.error.is_some() {
        return Err(bad_usage("a shard stopped with an error".into()));
    }
    Ok(merged.passed)
}
