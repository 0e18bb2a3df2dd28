//! The argument groups the subcommands share.

use super::bad_usage;
use crate::{FlowError, Generated};
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct UnitArgs {
    /// Unit to generate (see `rtl-gen list`).
    pub(super) unit: String,
    /// Parameter as key=value; repeat for several. Unset parameters take their defaults.
    #[arg(short, long = "param", value_name = "KEY=VALUE")]
    pub(super) params: Vec<String>,
    /// Float units: shorthand for exp_bits/frac_bits: binary16, binary32, binary64,
    /// bfloat16, or eXmY (e.g. e6m9).
    #[arg(long, value_name = "FORMAT")]
    pub(super) format: Option<String>,
    /// Float units: shorthand for round=...: rne|rtz|rdn|rup, or TestFloat's names
    /// near_even, minMag, min, max (also nearest, zero, down, up).
    #[arg(long, value_name = "MODE")]
    pub(super) round: Option<String>,
}

impl UnitArgs {
    /// `--param` values plus the ones `--format` and `--round` stand for.
    pub(super) fn all_params(&self) -> Result<Vec<String>, FlowError> {
        let mut params = self.params.clone();
        if let Some(f) = &self.format {
            let (e, m) = float_format(f).ok_or_else(|| {
                bad_usage(format!(
                    "--format {f}: expected binary16, binary32, binary64, bfloat16 or eXmY"
                ))
            })?;
            params.push(format!("exp_bits={e}"));
            params.push(format!("frac_bits={m}"));
        }
        if let Some(r) = &self.round {
            let mode = match r.as_str() {
                "rne" | "near_even" | "nearest" => "rne",
                "rtz" | "minMag" | "zero" => "rtz",
                "rdn" | "min" | "down" => "rdn",
                "rup" | "max" | "up" => "rup",
                "dyn" => "dyn",
                other => {
                    return Err(bad_usage(format!(
                    "--round {other}: expected rne|rtz|rdn|rup (or near_even, minMag, min, max); \
                         near_maxMag and odd rounding are not implemented"
                )))
                }
            };
            params.push(format!("round={mode}"));
        }
        crate::params::given_once(&params).map_err(FlowError::Params)?;
        Ok(params)
    }

    /// Builds and emits the unit with these parameters.
    pub(super) fn generate(&self) -> Result<Generated, FlowError> {
        crate::generate(&self.unit, &self.all_params()?)
    }
}

/// (exponent bits, fraction bits) of a format name.
fn float_format(name: &str) -> Option<(u32, u32)> {
    golden_model::float::FloatFormat::parse_name(name)
}

#[derive(clap::Args)]
pub struct ScaleArgs {
    /// Harness processes run in parallel, each fed by its own golden-model threads
    /// (default: all cores).
    #[arg(long, value_name = "N")]
    pub(super) jobs: Option<usize>,
    /// Run only shard K of N (1-based): the vectors whose index i has i mod N = K-1, corner
    /// vectors included. N jobs with K = 1..N together run exactly the unsharded set; combine
    /// their --report files with `rtl-gen merge-reports`.
    #[arg(long, value_name = "K/N")]
    pub(super) shard: Option<String>,
}

#[derive(clap::Args)]
pub struct ReportArgs {
    /// Write a JSON report: unit, parameters, generator version, Verilog hash, seed, shard,
    /// vectors, mismatches with the first failing vector, vectors/s, wall time.
    #[arg(long, value_name = "FILE.json")]
    pub(super) report: Option<PathBuf>,
    /// Write the verdict as JUnit XML (one test case).
    #[arg(long, value_name = "FILE")]
    pub(super) junit: Option<PathBuf>,
}

impl ReportArgs {
    /// The report files beside a command's main output, for [`super::check_outputs`].
    pub(super) fn with<'a>(&'a self, out: &'a std::path::Path) -> [Option<&'a std::path::Path>; 3] {
        [Some(out), self.report.as_deref(), self.junit.as_deref()]
    }
}

#[derive(clap::Args)]
pub struct FileArgs {
    /// Input vectors: text (a header line of port names, one transaction a line, values in
    /// 0x-hex or decimal) or binary rtlvec, told apart by content.
    #[arg(long = "in", value_name = "FILE")]
    pub(super) input: PathBuf,
    /// Results file: inputs then outputs of every transaction; binary for .rtlvec/.bin,
    /// text for .txt/.vec/.tsv/.text, else the input's format. Written only when complete.
    #[arg(long, value_name = "FILE")]
    pub(super) out: PathBuf,
}
