//! The float operators in Verilator against the golden model (issue #3).
//!
//! Verilator builds dominate the time (20-70 s each, vectors run at ~2 M/s),
//! so each test builds ONE harness per operator: a top module that holds the
//! operator in several configurations side by side (binary32, binary16,
//! bfloat16 and the odd format (6,9); conversions between such pairs), each
//! slot with its own ports and its own stage count; the shorter pipelines
//! are delayed to the longest. Rounding modes are covered with `round=dyn`:
//! every vector carries its mode on the `rm` input, cycling through RNE,
//! RTZ, RDN, RUP, so one build checks all four. Each slot's stimulus and
//! golden model are its unit's testbench (`rtl-gen check <op>` runs the
//! same): special-value corners first, then exponent-biased random vectors.
//! 1,000,000 vectors per test means 1,000,000 per slot (≥ 250,000 per mode).
//! The IR evaluator runs the first 20,000 vectors as a third opinion.

mod common;

use common::scratch;
use rtl_flow::{self, Generated, Testbench};
use rtl_gen::builder::ModuleBuilder;
use rtl_gen::emit::emit;
use rtl_gen::ir::control;
use rtl_gen::params::Params;
use std::sync::Arc;

const VECTORS: u64 = 1_000_000;

/// One configuration of a unit inside the composite top.
struct Slot {
    tb: Box<dyn Testbench>,
    n_in: usize,
    n_out: usize,
}

/// The slots' testbenches side by side: vector `i` of the composite is
/// vector `i` of every slot (each with its own seed).
struct Multi {
    slots: Vec<Slot>,
}

impl sim::Golden for Multi {
    fn eval(&self, inputs: &[u64], outputs: &mut [u64]) {
        let (mut i, mut o) = (0, 0);
        for s in &self.slots {
            s.tb.eval(&inputs[i..i + s.n_in], &mut outputs[o..o + s.n_out]);
            i += s.n_in;
            o += s.n_out;
        }
    }
}

impl sim::Stimulus for Multi {
    fn vector(&self, seed: u64, index: u64, inputs: &mut [u64]) {
        let mut i = 0;
        for (k, s) in self.slots.iter().enumerate() {
            let slot_seed = seed ^ (k as u64).wrapping_mul(0x9e37_79b9_7f4a_7c15);
            s.tb.vector(slot_seed, index, &mut inputs[i..i + s.n_in]);
            i += s.n_in;
        }
    }
}

impl Testbench for Multi {}

/// Builds the composite of `configs` (unit, parameters), lints it, checks
/// 20,000 vectors in the IR evaluator and `VECTORS` in Verilator.
fn check(test: &str, configs: &[(&str, &[&str])]) {
    let mut m = ModuleBuilder::with_handshake(format!("float_{test}"));
    m.describe(format!("Test composite of float operators ({test})."));
    let mut slots = Vec::new();
    let mut outs = Vec::new();
    let mut latency = 0;
    let mut described = Vec::new();
    for (k, (unit, params)) in configs.iter().enumerate() {
        let params: Vec<String> = params.iter().map(|s| s.to_string()).collect();
        let g =
            rtl_flow::generate(unit, &params).unwrap_or_else(|e| panic!("{unit} {params:?}: {e}"));
        let op = Arc::clone(&g.module.instances[0].module);
        let conn: Vec<(String, _)> = op
            .inputs
            .iter()
            .map(|p| (p.name.clone(), m.input(&format!("{}_{k}", p.name), p.ty)))
            .collect();
        let conn: Vec<(&str, _)> = conn.iter().map(|(n, s)| (n.as_str(), *s)).collect();
        let o = m.instance(&format!("u_{k}"), &op, &conn);
        for (name, value) in o.named() {
            outs.push((format!("{name}_{k}"), value));
        }
        latency = latency.max(op.latency);
        described.push(format!("{k}: {}", op.name));
        slots.push(Slot {
            n_in: op.inputs.len(),
            n_out: op.outputs.len(),
            tb: g.testbench(),
        });
    }
    for _ in 0..latency {
        m.stage();
    }
    for (n, s) in &outs {
        m.output(n, *s);
    }
    let module = m.finish().expect("composite builds");
    let files = emit(&module, rtl_gen::GENERATOR);
    let port = |p: &rtl_gen::ir::Port| sim::Port::new(p.name.clone(), p.ty.width());
    let ports = sim::PortList {
        top: module.name.clone(),
        files: files.iter().map(|f| f.file_name.clone()).collect(),
        generator: rtl_gen::GENERATOR.to_string(),
        unit: format!("float_{test}"),
        params: described
            .iter()
            .enumerate()
            .map(|(k, d)| (format!("slot{k}"), d.clone()))
            .collect(),
        latency: module.latency,
        clock: control::CLOCK.into(),
        reset: control::RESET.into(),
        in_valid: control::IN_VALID.into(),
        out_valid: control::OUT_VALID.into(),
        ready: None,
        inputs: module.data_inputs().iter().map(port).collect(),
        outputs: module.data_outputs().iter().map(|(p, _)| port(p)).collect(),
    };
    let g = Generated {
        unit: format!("float_{test}"),
        params: Params::defaults(&[]),
        module,
        files,
        ports,
        balance: None,
    };
    let dir = scratch(&format!("float_rtl/{test}"));
    g.write(&dir, 10.0).expect("write");
    let tb = Multi { slots };
    let ev = g.evaluate(&tb, 20_000, 11);
    assert_eq!(ev.mismatches, 0, "IR evaluator: {ev}");
    sim::lint(&g.ports, &dir).unwrap_or_else(|e| panic!("lint {test}: {e}"));
    let h = sim::Harness::build(&g.ports, &dir, &sim::default_cache_root()).expect("build harness");
    let opts = sim::CheckOptions {
        vectors: VECTORS,
        seed: 11,
        progress: false,
        ..Default::default()
    };
    let report = sim::cross_check(&h, &tb, &tb, &opts).expect("cross-check runs");
    assert_eq!(report.vectors, VECTORS);
    assert_eq!(report.mismatches, 0, "{test}:\n{report}");
    eprintln!("float_rtl {test} ({}): {report}", described.join(", "));
}

const B32: &[&str] = &["exp_bits=8", "frac_bits=23"];
const B16: &[&str] = &["exp_bits=5", "frac_bits=10"];
const BF16: &[&str] = &["exp_bits=8", "frac_bits=7"];
const ODD: &[&str] = &["exp_bits=6", "frac_bits=9"];

/// `base` with `extra` appended (a leaked slice: tests build a handful).
fn with(base: &[&'static str], extra: &[&'static str]) -> &'static [&'static str] {
    Box::leak([base, extra].concat().into_boxed_slice())
}

/// The four formats with their stage counts, plus `extra` parameters.
fn four(
    unit: &'static str,
    extra: &[&'static str],
) -> Vec<(&'static str, &'static [&'static str])> {
    vec![
        (unit, with(B32, &[extra, &["stages=2"]].concat())),
        (unit, with(B16, &[extra, &["stages=0"]].concat())),
        (unit, with(BF16, &[extra, &["stages=3"]].concat())),
        (unit, with(ODD, &[extra, &["stages=1"]].concat())),
    ]
}

#[test]
fn fadd_and_fsub_all_modes() {
    let mut c = four("fadd", &["round=dyn"]);
    c.push(("fadd", with(B32, &["round=dyn", "op=sub", "stages=5"])));
    c.push(("fadd", with(ODD, &["round=dyn", "op=sub", "stages=0"])));
    check("fadd", &c);
}

#[test]
fn fadd_down_up() {
    check("fadd_down_up", &four("fadd_down_up", &[]));
}

#[test]
fn fmul_all_modes() {
    check("fmul", &four("fmul", &["round=dyn"]));
}

#[test]
fn fmul_exact() {
    check("fmul_exact", &four("fmul_exact", &[]));
}

#[test]
fn fcmp_and_fminmax() {
    let mut c = four("fcmp", &[]);
    c.extend(four("fminmax", &[]));
    check("fcmp_minmax", &c);
}

#[test]
fn fcvt_all_modes() {
    let cvt = |from: &[&'static str], to: &[&'static str], st: &'static str| {
        let to: Vec<&'static str> = to
            .iter()
            .map(|p| -> &'static str { Box::leak(format!("to_{p}").into_boxed_str()) })
            .collect();
        ("fcvt", with(from, &[&to[..], &["round=dyn", st]].concat()))
    };
    let b64: &[&str] = &["exp_bits=11", "frac_bits=52"];
    check(
        "fcvt",
        &[
            cvt(B32, B16, "stages=2"),
            cvt(B16, B32, "stages=0"),
            cvt(B32, BF16, "stages=1"),
            cvt(BF16, ODD, "stages=3"),
            cvt(ODD, B16, "stages=2"),
            cvt(b64, B32, "stages=4"),
            cvt(B16, BF16, "stages=1"),
        ],
    );
}

#[test]
fn ffma_all_modes() {
    check("ffma", &four("ffma", &["round=dyn"]));
}

#[test]
fn fdot3_all_modes() {
    check("fdot3", &four("fdot3", &["round=dyn"]));
}

#[test]
fn funpack() {
    let mut c = four("funpack", &[]);
    c.push(("funpack", &["exp_bits=11", "frac_bits=52", "stages=1"]));
    check("funpack", &c);
}

#[test]
fn frecip_every_mode() {
    // one fixed mode per module (the divider has no rm port): the four
    // formats spread over the four modes, plus binary32 in the two the
    // slab baselines use (RNE for the nearest slab, RTZ for the conservative)
    let mut c: Vec<(&str, &[&str])> = Vec::new();
    for (fmt, (round, stages)) in [B32, B16, BF16, ODD].into_iter().zip([
        ("round=rup", "stages=2"),
        ("round=rdn", "stages=0"),
        ("round=rne", "stages=3"),
        ("round=rtz", "stages=1"),
    ]) {
        c.push(("frecip", with(fmt, &[round, stages])));
    }
    c.push(("frecip", with(B32, &["round=rne", "stages=4"])));
    c.push(("frecip", with(B32, &["round=rtz", "stages=4"])));
    check("frecip", &c);
}
