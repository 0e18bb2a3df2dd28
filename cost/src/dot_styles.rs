//! The transform unit's dot-product styles side by side (issue #16 §4): the
//! `synth_xilinx` estimate of each (binary32, RNE, `inverse=pre`, full
//! throughput) against the accuracy study's error against the real product
//! of the stored inverse (`transform::exact::stored_product`, big integers):
//! what each style's extra hardware buys. Half an ulp, about 5.96e-8 at
//! binary32, is what rounding once leaves.

use crate::synth::{self, Xilinx};
use golden_model::float::{FloatFormat, RoundingMode};
use golden_model::transform::accuracy::{default_offsets, run, StudyInverse, StudyOptions};
use golden_model::transform::DotStyle;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// One style: its cost and its accuracy.
#[derive(Debug, Clone)]
pub struct StyleRow {
    /// the style
    pub style: DotStyle,
    /// the unit's top module
    pub top: String,
    /// `synth_xilinx -flatten` estimate
    pub xilinx: Xilinx,
    /// largest normwise relative error against the stored inverse's real
    /// product, over every offset, the seed's matrices and the random set
    pub max_rel: f64,
    /// largest median of the same over the offsets (random set)
    pub med_rel: f64,
}

/// Study size.
#[derive(Debug, Clone, Copy)]
pub struct Study {
    /// random matrices
    pub matrices: usize,
    /// origins per offset for each random matrix
    pub points: usize,
    /// origins per offset for each of the seed's M1–M3
    pub seed_points: usize,
    /// seed of the matrices and origins
    pub seed: u64,
}

/// Synthesises (or finds in the cache) `transform` with every dot style at
/// `stages` and runs the accuracy study once for all styles.
pub fn run_styles(stages: u32, study: Study, cached_only: bool) -> Result<Vec<StyleRow>, String> {
    let rows = run(&StudyOptions {
        fmt: FloatFormat::BINARY32,
        mode: RoundingMode::NearestEven,
        styles: DotStyle::ALL.to_vec(),
        points: study.seed_points,
        random_matrices: study.matrices,
        random_points: study.points,
        offsets: default_offsets(),
        seed: study.seed,
        inverse: StudyInverse::Exact,
    });
    DotStyle::ALL
        .iter()
        .enumerate()
        .map(|(k, &style)| {
            let p = vec![format!("dot={}", style.word()), format!("stages={stages}")];
            let g = rtl_flow::generate("transform", &p).map_err(|e| format!("transform: {e}"))?;
            let xilinx = synth::xilinx_estimate(&g, cached_only)?;
            let max_rel = rows
                .iter()
                .map(|r| r.two_step[k].max_rel_stored)
                .fold(0.0, f64::max);
            let med_rel = rows
                .iter()
                .filter(|r| r.set == "random")
                .map(|r| r.two_step[k].med_rel_stored)
                .fold(0.0, f64::max);
            Ok(StyleRow {
                style,
                top: g.module.name.clone(),
                xilinx,
                max_rel,
                med_rel,
            })
        })
        .collect()
}

/// The markdown table.
pub fn markdown(rows: &[StyleRow], stages: u32, study: Study) -> String {
    let mut s = format!(
        "`transform` binary32, RNE, `inverse=pre`, `throughput=full`, `stages={stages}`: \
         `synth_xilinx -flatten` estimates against the error of the model-space origin with \
         respect to the real product of the stored `R⁻¹` and `O_w − T` (normwise relative; \
         {} random matrices × {} origins and M1-M3 × {} origins per offset, offsets 0 and \
         1e-3 .. 1e5, seed {}):\n\n\
         | dot | top | xc7 LUT | FF | DSP48 | CARRY4 | max error | largest median |\n\
         |---|---|---|---|---|---|---|---|\n",
        study.matrices, study.points, study.seed_points, study.seed
    );
    for r in rows {
        let x = &r.xilinx;
        let _ = writeln!(
            s,
            "| `{}` | {} | {} | {} | {} | {} | {:.3e} | {:.3e} |",
            r.style.word(),
            r.top,
            x.luts,
            x.ffs,
            x.dsps,
            x.carries,
            r.max_rel,
            r.med_rel
        );
    }
    s
}

/// xc7 LUT against the largest error, one point per style:
/// `<dir>/transform_dot_styles.png` and `.svg`.
pub fn chart(rows: &[StyleRow], dir: &Path) -> Result<Vec<PathBuf>, Box<dyn std::error::Error>> {
    use crate::charts::{write_chart, Chart, Point, Series};
    use plotters::prelude::RGBColor;
    let series = vec![Series {
        name: "dot styles (binary32)".into(),
        color: RGBColor(31, 119, 180),
        points: rows
            .iter()
            .map(|r| {
                Point::new(
                    r.max_rel * 1e8,
                    r.xilinx.luts as f64,
                    // (leading spaces: the label starts under the marker)
                    format!("  {}, {} DSP48", r.style.word(), r.xilinx.dsps),
                )
            })
            .collect(),
        hollow: false,
        line: false,
    }];
    let c = Chart::plain(
        "transform_dot_styles",
        "Two-step transform: xc7 LUT against the largest error (binary32)",
        "largest relative error against the stored inverse's real product, 1e-8",
        "xc7 LUT (synth_xilinx estimate)",
        series,
    );
    write_chart(&c, dir)
}
