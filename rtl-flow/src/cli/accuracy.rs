//! `transform-accuracy`: the inverse transform's accuracy study (seed 003,
//! FIG. 7) from the command line.

use super::bad_usage;
use crate::FlowError;

pub(super) fn transform_accuracy(
    format: &str,
    dot: &str,
    points: usize,
    random: usize,
    random_points: usize,
    seed: u64,
    inverse: &str,
) -> Result<bool, FlowError> {
    use golden_model::transform::{accuracy, DotStyle};
    let fmt = golden_model::float::FloatFormat::from_name(format)
        .map_err(|e| bad_usage(format!("--format {e}")))?;
    let styles = match dot {
        "all" => DotStyle::ALL.to_vec(),
        w => vec![DotStyle::parse(w)
            .ok_or_else(|| bad_usage(format!("--dot {w}: expected separate, fma, dot3 or all")))?],
    };
    let inverse = match inverse {
        "exact" => accuracy::StudyInverse::Exact,
        "hw" => accuracy::StudyInverse::Hardware,
        w => return Err(bad_usage(format!("--inverse {w}: expected exact or hw"))),
    };
    let opts = accuracy::StudyOptions {
        fmt,
        styles,
        inverse,
        points,
        random_matrices: random,
        random_points,
        seed,
        ..Default::default()
    };
    let rows = accuracy::run(&opts);
    print!("{}", accuracy::table(&opts, &rows));
    Ok(true)
}
