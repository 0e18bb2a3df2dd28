//! The hybrid renderer's ray-cull unit in the loop (`rtl-gen hybrid --rtl`):
//! every cull and contribution check of an asynchronous render answered by
//! the Verilated `raycull` unit.
//!
//! 1. **Record**: the render runs with the golden model
//!    ([`golden_model::raycull::cull`]) and keeps every transaction as the
//!    unit's input port values (the packing of its testbench).
//! 2. **Run**: the transactions, in order, through the Verilated unit (one
//!    per clock); every output vector is compared with the golden model.
//! 3. **Replay**: the render runs again answering transaction `i` from the
//!    RTL's output `i` (the render is deterministic, so the `i`-th question
//!    is the recorded one; a different question is an error), and its image
//!    and counts must equal the recorded render's.

use crate::bvh::Accel;
use crate::hybrid::{render_async_with, world_triangles, HybridCounts, HybridOpts};
use crate::render::Frame;
use crate::scene::Scene;
use crate::tester::BoxTester;
use crate::trace::TraceOpts;
use golden_model::raycull::cull;
use rtl_flow::raycull::{from_out_record, to_record, unit_config};
use rtl_gen::units::ports;
use rtl_gen::units::raycull::RayCullOut;
use std::path::Path;

/// Transactions through the RTL so far and how many differed (from the
/// golden model, or in the replayed render).
#[derive(Debug, Clone, Copy, Default)]
pub struct RtlTally {
    /// transactions run through the Verilated unit
    pub tests: u64,
    /// output vectors that differ from the golden model's
    pub mismatches: u64,
    /// replayed renders whose image or counts differ from the golden one
    pub renders_differ: u64,
}

/// One asynchronous render with every ray-cull transaction answered by the
/// Verilated `raycull` (generated into `work`); returns the replayed frame
/// and counts, and adds to `tally`.
#[allow(clippy::too_many_arguments)]
pub fn hybrid_rtl(
    scene: &Scene,
    accel: &Accel,
    tester: &dyn BoxTester,
    opts: TraceOpts,
    w: u32,
    h: u32,
    hopts: &HybridOpts,
    work: &Path,
    tally: &mut RtlTally,
) -> Result<(Frame, HybridCounts), String> {
    let mcfg = hopts.unit_config(world_triangles(scene, accel).len());
    let ucfg = unit_config(&mcfg, 1);
    let params = vec![
        format!("depth={}", ucfg.depth.word()),
        format!("compare={}", ucfg.compare.word()),
        format!("gen_bits={}", ucfg.gen_bits),
        format!("prim_bits={}", ucfg.prim_bits),
        format!("group={}", ucfg.group),
        format!("stages={}", ucfg.stages),
    ];
    let g = rtl_flow::generate("raycull", &params).map_err(|e| e.to_string())?;
    let (n_in, n_out) = (g.ports.inputs.len(), g.ports.outputs.len());
    // 1. record
    let mut inputs: Vec<u64> = Vec::new();
    let (gold, gold_counts) =
        render_async_with(scene, accel, tester, opts, w, h, hopts, &mut |x| {
            let start = inputs.len();
            inputs.resize(start + n_in, 0);
            ports::pack(&ucfg, &to_record(x), &mut inputs[start..]);
            cull(&mcfg, x)
        });
    let vectors = inputs.len() / n_in;
    // 2. run
    let dir = work.join(&g.module.name);
    g.write(&dir, 10.0).map_err(|e| e.to_string())?;
    let e = |e: sim::SimError| format!("raycull: {e}");
    let harness = sim::Harness::build(&g.ports, &dir, &sim::default_cache_root()).map_err(e)?;
    let (_, outputs) = harness
        .run_records(
            inputs.chunks(n_in),
            &dir.join(&g.module.name),
            &sim::RunOptions::default(),
        )
        .map_err(e)?;
    if outputs.len() != vectors * n_out {
        return Err(format!(
            "raycull: {} output vectors for {vectors} inputs",
            outputs.len() / n_out.max(1)
        ));
    }
    let bench = g.testbench();
    let mut golden = vec![0u64; n_out];
    for (v, out) in inputs.chunks(n_in).zip(outputs.chunks(n_out)) {
        bench.eval(v, &mut golden);
        tally.mismatches += (golden != out) as u64;
    }
    tally.tests += vectors as u64;
    // 3. replay
    let mut next = 0usize;
    let mut wrong_question = None;
    let mut asked = vec![0u64; n_in];
    let (f, c) = render_async_with(scene, accel, tester, opts, w, h, hopts, &mut |x| {
        ports::pack(&ucfg, &to_record(x), &mut asked);
        let i = next;
        next += 1;
        if i >= vectors || asked[..] != inputs[i * n_in..(i + 1) * n_in] {
            wrong_question.get_or_insert(i);
            return cull(&mcfg, x);
        }
        let r: RayCullOut<u64> = ports::unpack(&ucfg, &outputs[i * n_out..(i + 1) * n_out]);
        from_out_record(&r)
    });
    if let Some(i) = wrong_question {
        return Err(format!(
            "raycull: the replayed render asked transaction {i} differently from the recorded one"
        ));
    }
    let same = f.same_image(&gold) && c == gold_counts && next == vectors;
    tally.renders_differ += (!same) as u64;
    Ok((f, c))
}
