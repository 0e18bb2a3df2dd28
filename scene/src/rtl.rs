//! RTL in the loop: every box, transform, cull and triangle test of a render
//! answered by the Verilated units instead of their golden models.
//!
//! 1. **Generate**: the units of the loop ([`Stream`]) in the
//!    configurations of their own Verilator tests (`tests/*_rtl.rs`), so the
//!    harness builds are shared through the cache (`target/rtl-cache`); the
//!    loop checks that these are the renderer's configurations
//!    ([`GoldenUnits`]). The triangle unit has two builds, `outputs=full`
//!    for [`TriTest::Golden`] and `outputs=tnum` for [`TriTest::GoldenTnum`];
//!    a render uses one, and only used units are built.
//! 2. **Record**: the golden render runs with a [`Recorder`], which answers
//!    from the golden models and keeps every unit call as the unit's input
//!    port values (the port packing of the unit's own testbench), one
//!    stream per unit. Box tests: single rays and shared-origin bundles go
//!    to the shared-origin `silhouette`, other bundles to the bounded-origin
//!    one (the split of [`Golden`]).
//! 3. **Run**: each stream, duplicates included, in recording order, is
//!    written as one `rtlvec` file and run through the unit's Verilated
//!    harness ([`sim::Harness::run`], back to back, one transaction per
//!    clock); every output vector is also compared with the unit's golden
//!    model (all output ports; the first mismatches are kept with a replay).
//! 4. **Replay**: the render runs again with an [`RtlTester`], which answers
//!    every call from the RTL outputs, looked up by the exact input port
//!    values (tiles run in parallel, so the order is not replayed). A call
//!    whose input was not recorded is counted as missing (a box test then
//!    answers conservatively, the others from the golden model) and fails
//!    the loop.
//! 5. **Check**: the replayed image equals the golden one (primary hit ids,
//!    `t` bits, colour bits of every pixel) and every unit answered exactly as
//!    many calls as went through its RTL.
//!
//! Not through RTL: the ray set-up beside the units (the triangle test's
//! shear `kz, s` per ray, the conservative slab interval `[t_lo, t_hi]` the
//! cull unit reads, the reciprocal of the model-space direction), bundle
//! formation and traversal order.

use crate::bvh::Accel;
use crate::render::{render_with, Frame};
use crate::scene::Scene;
use crate::tester::{ray_input, BoxTester, BundleBox, Golden, RayBox};
use crate::trace::{TraceOpts, Tracer, TriTest};
use crate::units::{ChildTestIn, GoldenUnits, NodeTestIn, RayTermsIn, Units};
use crate::wide::{Boxes, WideAccel};
use golden_model::cull::tester::NormalTerm;
use golden_model::float::FloatFormat;
use golden_model::float::RoundingMode;
use golden_model::node::NodeOut;
use golden_model::node_reorigin::ReoriginParams;
use golden_model::silhouette::{BundleIn, Verdict};
use golden_model::transform::{InstanceTransform, ModelRay, WorldRay};
use golden_model::triangle::{Segment, TriIn, TriNum, TriOut};
use rtl_flow::cull::CullBench;
use rtl_flow::cull_ray::CullRayBench;
use rtl_flow::node::NodeBench;
use rtl_flow::silhouette::SilhouetteBench;
use rtl_flow::transform::TransformBench;
use rtl_flow::triangle::TriangleBench;
use rtl_flow::{self, configured, Generated};
use rtl_gen::units::{
    cull::Cull,
    cull_ray::CullRay,
    node::Node,
    silhouette::Silhouette,
    transform::Transform,
    triangle::{Outputs, Triangle},
};
use sim::Harness;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Mutex;
use std::time::{Duration, Instant};

/// The Verilated units of the loop, one input stream each.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Stream {
    /// `silhouette`, shared origin: single rays and shared-origin bundles
    BoxShared,
    /// `silhouette`, bounded origin: bundles whose rays have different origins
    BoxBounded,
    /// `transform`: world rays into an instance's model space
    Transform,
    /// `cull_ray`: the ray terms of a node's shared normals
    CullRay,
    /// `cull`: one child's cull-plane test
    Cull,
    /// `triangle`, `outputs=full`: the watertight ray/triangle test
    Triangle,
    /// `triangle`, `outputs=tnum`: the same test giving `T` and `det`, no
    /// divider (`--tri tnum`; `t` is divided in software)
    TriangleTnum,
    /// `node`: one ray against a BLAS node of the wide BVH (`--wide N`)
    Node,
    /// `node`: one ray against a TLAS node (q of the TLAS)
    NodeTlas,
}

/// The number of streams.
pub const STREAMS: usize = Stream::ALL.len();

impl Stream {
    /// Every stream, in report order.
    pub const ALL: [Stream; 9] = [
        Stream::BoxShared,
        Stream::BoxBounded,
        Stream::Transform,
        Stream::CullRay,
        Stream::Cull,
        Stream::Triangle,
        Stream::TriangleTnum,
        Stream::Node,
        Stream::NodeTlas,
    ];

    /// The generator's unit.
    pub fn unit(self) -> &'static str {
        match self {
            Stream::BoxShared | Stream::BoxBounded => "silhouette",
            Stream::Transform => "transform",
            Stream::CullRay => "cull_ray",
            Stream::Cull => "cull",
            Stream::Triangle | Stream::TriangleTnum => "triangle",
            Stream::Node | Stream::NodeTlas => "node",
        }
    }

    /// The unit's parameters: those of its Verilator test in CI
    /// (`tests/silhouette_rtl.rs`, `transform_rtl.rs` `xf_fma`,
    /// `cull_rtl.rs` K = 4, `triangle_rtl.rs` binary32 `full` and `tnum`
    /// with whole products, the build per-ray costs), same order.
    pub fn params(self, wide: WideShape) -> Vec<String> {
        const CULL: &[&str] = &[
            "exp_bits=8",
            "frac_bits=23",
            "plane_exp_bits=5",
            "plane_frac_bits=10",
            "k=4",
            "stages=4",
        ];
        let fixed: &[&str] = match self {
            Stream::BoxShared => &["exp_bits=8", "frac_bits=23", "origin=shared", "stages=4"],
            Stream::BoxBounded => &["exp_bits=8", "frac_bits=23", "origin=bounded", "stages=2"],
            Stream::Transform => &["dot=fma", "throughput=full", "round=rne", "stages=8"],
            Stream::CullRay | Stream::Cull => CULL,
            Stream::Triangle => &[
                "exp_bits=8",
                "frac_bits=23",
                "outputs=full",
                "stages=8",
                "pipeline=plan",
            ],
            Stream::TriangleTnum => rtl_flow::triangle::RENDER_TNUM,
            Stream::Node | Stream::NodeTlas => {
                // the configuration of tests/node_rtl.rs at this shape
                let (n, q) = match self {
                    Stream::Node => (wide.children, wide.box_bits),
                    _ => (wide.children, wide.tlas_box_bits),
                };
                return vec![
                    format!("children={n}"),
                    format!("box_bits={q}"),
                    "stages=4".into(),
                ];
            }
        };
        fixed.iter().map(|p| p.to_string()).collect()
    }

    /// Report name.
    pub fn label(self) -> &'static str {
        match self {
            Stream::BoxShared => "silhouette (shared origin)",
            Stream::BoxBounded => "silhouette (bounded origin)",
            Stream::Transform => "transform",
            Stream::CullRay => "cull_ray",
            Stream::Cull => "cull",
            Stream::Triangle => "triangle",
            Stream::TriangleTnum => "triangle (tnum)",
            Stream::Node => "node (BLAS)",
            Stream::NodeTlas => "node (TLAS)",
        }
    }

    /// Whether a render with `opts` (over a wide BVH if `wide`) calls this
    /// unit at all (bounded-origin bundles need bundles, the cull units need
    /// planes, the box tester is the node unit's over a wide BVH, the
    /// triangle unit is the `tnum` one with `--tri tnum`).
    pub fn used(self, opts: &TraceOpts, wide: bool) -> bool {
        match self {
            Stream::Triangle => opts.tri != TriTest::GoldenTnum,
            Stream::TriangleTnum => opts.tri == TriTest::GoldenTnum,
            Stream::BoxBounded => !wide && opts.bundles.enabled,
            Stream::BoxShared => !wide,
            Stream::CullRay | Stream::Cull => !wide && opts.planes,
            Stream::Node | Stream::NodeTlas => wide,
            _ => true,
        }
    }
}

/// The silhouette unit's output ports, in the bit order of `Out::to_bits`.
pub const BOX_OUTPUTS: [&str; 5] = ["all_hit", "any_hit", "nan", "invalid", "mixed_sign"];

/// The most input ports of a loop unit (a packing buffer's size; `node` at
/// N = 8 has 67).
const MAX_PORTS: usize = 80;

/// The wide BVH's node shapes the `node` streams are generated for (a
/// render over the binary BVH leaves them unused).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct WideShape {
    /// N
    pub children: usize,
    /// q of the BLAS nodes
    pub box_bits: u32,
    /// q of the TLAS nodes
    pub tlas_box_bits: u32,
}

impl Default for WideShape {
    fn default() -> WideShape {
        WideShape {
            children: 4,
            box_bits: 8,
            tlas_box_bits: crate::wide::TLAS_BOX_BITS,
        }
    }
}

/// The loop's units generated, with the port packing of their testbenches.
pub struct LoopUnits {
    generated: Vec<Generated>,
    shared: SilhouetteBench,
    bounded: SilhouetteBench,
    transform: TransformBench,
    cull_ray: CullRayBench,
    cull: CullBench,
    triangle: TriangleBench,
    triangle_tnum: TriangleBench,
    node: NodeBench,
    node_tlas: NodeBench,
}

impl LoopUnits {
    /// Generates every unit of [`Stream::ALL`] and checks its configuration
    /// is the renderer's ([`GoldenUnits`]) and its ports fit the loop.
    pub fn generate(wide: WideShape) -> Result<LoopUnits, String> {
        let mut generated = Vec::new();
        for s in Stream::ALL {
            let given = s.params(wide);
            let g =
                rtl_flow::generate(s.unit(), &given).map_err(|e| format!("{}: {e}", s.label()))?;
            if g.ports.inputs.len() > MAX_PORTS {
                return Err(format!("{}: more than {MAX_PORTS} input ports", s.label()));
            }
            generated.push(g);
        }
        // each unit's configuration as its description parses it
        let p = |s: Stream| &generated[s as usize].params;
        let units = LoopUnits {
            shared: SilhouetteBench::new(&configured(&Silhouette, p(Stream::BoxShared))),
            bounded: SilhouetteBench::new(&configured(&Silhouette, p(Stream::BoxBounded))),
            transform: TransformBench::new(&configured(&Transform, p(Stream::Transform))),
            cull_ray: CullRayBench::new(&configured(&CullRay, p(Stream::CullRay))),
            cull: CullBench::new(&configured(&Cull, p(Stream::Cull))),
            triangle: TriangleBench::new(&configured(&Triangle, p(Stream::Triangle))),
            triangle_tnum: TriangleBench::new(&configured(&Triangle, p(Stream::TriangleTnum))),
            node: NodeBench::new(&configured(&Node, p(Stream::Node))),
            node_tlas: NodeBench::new(&configured(&Node, p(Stream::NodeTlas))),
            generated,
        };
        units.check(wide)?;
        Ok(units)
    }

    /// The RTL computes what the renderer's golden units compute.
    fn check(&self, wide: WideShape) -> Result<(), String> {
        let golden = GoldenUnits::get();
        let box_cfg = Golden::default();
        let mismatch = |s: Stream, what: String| Err(format!("{}: {what}", s.label()));
        if *self.shared.config() != box_cfg.shared() {
            return mismatch(Stream::BoxShared, "not the renderer's box test".into());
        }
        if *self.bounded.config() != box_cfg.bounded() {
            return mismatch(Stream::BoxBounded, "not the renderer's box test".into());
        }
        if *self.transform.config() != golden.transform {
            return mismatch(Stream::Transform, "not the renderer's transform".into());
        }
        if *self.cull_ray.config() != golden.cull || *self.cull.config() != golden.cull {
            return mismatch(
                Stream::Cull,
                "not the renderer's plane configuration".into(),
            );
        }
        for (s, bench, outputs, segment) in [
            (
                Stream::Triangle,
                &self.triangle,
                Outputs::Full,
                Segment::Exact,
            ),
            (
                Stream::TriangleTnum,
                &self.triangle_tnum,
                Outputs::Tnum,
                golden.tnum_segment,
            ),
        ] {
            if bench.format() != golden.triangle
                || bench.mode() != RoundingMode::NearestEven
                || bench.outputs() != outputs
                || bench.segment() != segment
            {
                return mismatch(
                    s,
                    format!(
                        "binary32, RNE, outputs={outputs}, the renderer's segment test expected"
                    ),
                );
            }
        }
        for (s, bench, q) in [
            (Stream::Node, &self.node, wide.box_bits),
            (Stream::NodeTlas, &self.node_tlas, wide.tlas_box_bits),
        ] {
            let renderer = ReoriginParams::new(FloatFormat::BINARY32, wide.children, q);
            if *bench.params() != renderer {
                return mismatch(s, "not the renderer's node shape and precision".into());
            }
        }
        for s in [Stream::BoxShared, Stream::BoxBounded] {
            let outs: Vec<&str> = self.generated[s as usize]
                .ports
                .outputs
                .iter()
                .map(|p| p.name.as_str())
                .collect();
            if outs != BOX_OUTPUTS {
                return mismatch(
                    s,
                    format!("output ports {outs:?}, expected {BOX_OUTPUTS:?} (Out::to_bits)"),
                );
            }
        }
        Ok(())
    }

    /// The generated unit of a stream.
    pub fn generated(&self, s: Stream) -> &Generated {
        &self.generated[s as usize]
    }

    /// A call of stream `s` packed by `pack` into the unit's input ports.
    fn packed(&self, s: Stream, pack: impl FnOnce(&mut [u64])) -> Packed {
        let len = self.generated(s).ports.inputs.len();
        let mut v = [0; MAX_PORTS];
        pack(&mut v[..len]);
        Packed { stream: s, len, v }
    }

    // One packing per unit, its testbench's (the recorder and the RTL tester
    // both pack through these, so they see the same port values).
    fn pack_box(&self, x: &BundleIn, shared: bool) -> Packed {
        if shared {
            self.packed(Stream::BoxShared, |v| self.shared.to_ports(x, v))
        } else {
            self.packed(Stream::BoxBounded, |v| self.bounded.to_ports(x, v))
        }
    }
    fn pack_transform(&self, ray: &WorldRay, inst: &InstanceTransform) -> Packed {
        self.packed(Stream::Transform, |v| self.transform.to_ports(ray, inst, v))
    }
    fn pack_cull_ray(&self, x: &RayTermsIn) -> Packed {
        self.packed(Stream::CullRay, |v| {
            self.cull_ray.to_ports(x.o, x.d, x.r_min, x.normals, v)
        })
    }
    fn pack_cull(&self, x: &ChildTestIn) -> Packed {
        self.packed(Stream::Cull, |v| {
            self.cull.to_ports(x.t_lo, x.t_hi, x.w, x.terms, v)
        })
    }
    fn pack_triangle(&self, x: &TriIn) -> Packed {
        self.packed(Stream::Triangle, |v| self.triangle.to_ports(x, v))
    }
    fn pack_triangle_tnum(&self, x: &TriIn) -> Packed {
        self.packed(Stream::TriangleTnum, |v| self.triangle_tnum.to_ports(x, v))
    }
    /// A BLAS node's test goes to the BLAS stream, a TLAS node's (its q) to the TLAS one.
    fn node_bench(&self, x: &NodeTestIn) -> (Stream, &NodeBench) {
        if x.params == self.node.params() {
            (Stream::Node, &self.node)
        } else {
            (Stream::NodeTlas, &self.node_tlas)
        }
    }
    fn pack_node(&self, x: &NodeTestIn) -> Packed {
        let (s, bench) = self.node_bench(x);
        self.packed(s, |v| bench.to_ports(x.ray, x.d, x.t_start, x.node, v))
    }
}

/// A unit call packed into port values: the stream and its values.
struct Packed {
    stream: Stream,
    len: usize,
    v: [u64; MAX_PORTS],
}

impl Packed {
    fn values(&self) -> &[u64] {
        &self.v[..self.len]
    }
}

/// Answers from the golden models and records every unit call as port
/// values, one stream per unit (recording order, duplicates included).
pub struct Recorder<'u> {
    units: &'u LoopUnits,
    golden: Golden,
    streams: [Mutex<Vec<u64>>; STREAMS],
}

impl<'u> Recorder<'u> {
    /// A recorder for the loop's units.
    pub fn new(units: &'u LoopUnits) -> Recorder<'u> {
        Recorder {
            units,
            golden: Golden::default(),
            streams: Default::default(),
        }
    }
    fn record(&self, p: Packed) {
        self.streams[p.stream as usize]
            .lock()
            .unwrap()
            .extend_from_slice(p.values());
    }
    /// The recorded port values of each stream (flat, [`Stream::ALL`] order).
    pub fn into_streams(self) -> [Vec<u64>; STREAMS] {
        self.streams.map(|m| m.into_inner().unwrap())
    }
}

impl BoxTester for Recorder<'_> {
    fn ray(&self, x: &RayBox) -> bool {
        self.record(self.units.pack_box(&ray_input(x), true));
        self.golden.ray(x)
    }
    fn bundle(&self, x: &BundleBox) -> Verdict {
        self.record(self.units.pack_box(&x.input, x.shared));
        self.golden.bundle(x)
    }
    fn supports_bundles(&self) -> bool {
        true
    }
    fn name(&self) -> &'static str {
        "golden (recording)"
    }
    fn units(&self) -> &dyn Units {
        self
    }
}

impl Units for Recorder<'_> {
    fn transform(&self, ray: &WorldRay, inst: &InstanceTransform) -> ModelRay {
        self.record(self.units.pack_transform(ray, inst));
        GoldenUnits::get().transform(ray, inst)
    }
    fn cull_ray(&self, x: &RayTermsIn, terms: &mut [NormalTerm]) {
        self.record(self.units.pack_cull_ray(x));
        GoldenUnits::get().cull_ray(x, terms)
    }
    fn cull(&self, x: &ChildTestIn) -> bool {
        self.record(self.units.pack_cull(x));
        GoldenUnits::get().cull(x)
    }
    fn triangle(&self, x: &TriIn) -> TriOut {
        self.record(self.units.pack_triangle(x));
        GoldenUnits::get().triangle(x)
    }
    fn triangle_tnum(&self, x: &TriIn) -> TriNum {
        self.record(self.units.pack_triangle_tnum(x));
        GoldenUnits::get().triangle_tnum(x)
    }
    fn node(&self, x: &NodeTestIn) -> NodeOut {
        self.record(self.units.pack_node(x));
        GoldenUnits::get().node(x)
    }
}

/// RTL outputs by input port values, one table per unit.
pub type Answers = HashMap<Vec<u64>, Vec<u64>>;

/// Answers every unit call from the RTL outputs.
pub struct RtlTester<'u> {
    units: &'u LoopUnits,
    answers: [Answers; STREAMS],
    answered: [AtomicU64; STREAMS],
    missing: [AtomicU64; STREAMS],
}

impl<'u> RtlTester<'u> {
    /// A tester answering from `answers` ([`Stream::ALL`] order).
    pub fn new(units: &'u LoopUnits, answers: [Answers; STREAMS]) -> RtlTester<'u> {
        RtlTester {
            units,
            answers,
            answered: Default::default(),
            missing: Default::default(),
        }
    }
    /// Calls of a unit answered from the RTL outputs.
    pub fn answered(&self, s: Stream) -> u64 {
        self.answered[s as usize].load(Ordering::Relaxed)
    }
    /// Calls of a unit whose input had not been run through the RTL.
    pub fn missing(&self, s: Stream) -> u64 {
        self.missing[s as usize].load(Ordering::Relaxed)
    }
    fn lookup(&self, p: &Packed) -> Option<&[u64]> {
        let i = p.stream as usize;
        let found = self.answers[i].get(p.values()).map(Vec::as_slice);
        let count = if found.is_some() {
            &self.answered[i]
        } else {
            &self.missing[i]
        };
        count.fetch_add(1, Ordering::Relaxed);
        found
    }
}

/// The silhouette unit's outputs: bit 0 all_hit, bit 1 any_hit ([`BOX_OUTPUTS`]).
fn all_any(out: &[u64]) -> (bool, bool) {
    (out[0] & 1 != 0, out[1] & 1 != 0)
}

impl BoxTester for RtlTester<'_> {
    fn ray(&self, x: &RayBox) -> bool {
        self.lookup(&self.units.pack_box(&ray_input(x), true))
            .is_none_or(|out| all_any(out).1)
    }
    fn bundle(&self, x: &BundleBox) -> Verdict {
        match self
            .lookup(&self.units.pack_box(&x.input, x.shared))
            .map(all_any)
        {
            None => Verdict::Mixed,
            Some((true, _)) => Verdict::AllHit,
            Some((false, false)) => Verdict::AllMiss,
            Some(_) => Verdict::Mixed,
        }
    }
    fn supports_bundles(&self) -> bool {
        true
    }
    fn name(&self) -> &'static str {
        "rtl"
    }
    fn units(&self) -> &dyn Units {
        self
    }
}

impl Units for RtlTester<'_> {
    fn transform(&self, ray: &WorldRay, inst: &InstanceTransform) -> ModelRay {
        match self.lookup(&self.units.pack_transform(ray, inst)) {
            Some(out) => self.units.transform.model_ray_from_ports(out),
            None => GoldenUnits::get().transform(ray, inst),
        }
    }
    fn cull_ray(&self, x: &RayTermsIn, terms: &mut [NormalTerm]) {
        match self.lookup(&self.units.pack_cull_ray(x)) {
            Some(out) => self.units.cull_ray.terms_from_ports(out, terms),
            None => GoldenUnits::get().cull_ray(x, terms),
        }
    }
    fn cull(&self, x: &ChildTestIn) -> bool {
        // a missing answer keeps the child (never a wrongful cull)
        self.lookup(&self.units.pack_cull(x))
            .is_none_or(|out| self.units.cull.keep_from_ports(out))
    }
    fn triangle(&self, x: &TriIn) -> TriOut {
        match self.lookup(&self.units.pack_triangle(x)) {
            Some(out) => self.units.triangle.result_from_ports(out),
            None => GoldenUnits::get().triangle(x),
        }
    }
    fn triangle_tnum(&self, x: &TriIn) -> TriNum {
        match self.lookup(&self.units.pack_triangle_tnum(x)) {
            Some(out) => self.units.triangle_tnum.tnum_from_ports(out),
            None => GoldenUnits::get().triangle_tnum(x),
        }
    }
    fn node(&self, x: &NodeTestIn) -> NodeOut {
        let (_, bench) = self.units.node_bench(x);
        match self.lookup(&self.units.pack_node(x)) {
            Some(out) => bench.result_from_ports(out),
            None => GoldenUnits::get().node(x),
        }
    }
}

/// Per unit: what went through the RTL.
#[derive(Debug, Clone)]
pub struct UnitReport {
    /// the stream
    pub stream: Stream,
    /// the render calls this unit (see [`Stream::used`])
    pub used: bool,
    /// harness top module
    pub top: String,
    /// calls run through the RTL (the stream's length, duplicates included)
    pub vectors: u64,
    /// distinct inputs among them
    pub distinct: u64,
    /// clock cycles the harness simulated (reset and drain included)
    pub cycles: u64,
    /// RTL output vectors differing from the golden model (any output port)
    pub mismatches: u64,
    /// the first [`SHOWN_MISMATCHES`] of them: the vector, both results and
    /// how to replay it
    pub shown: Vec<sim::Mismatch>,
    /// calls the replay answered from the RTL outputs
    pub answered: u64,
    /// calls of the replay whose input had not been run (should be 0)
    pub missing: u64,
    /// harness build time (cache lookup included) and whether it was cached
    pub build: (Duration, bool),
    /// time of the harness run
    pub run: Duration,
}

impl UnitReport {
    /// A report of `vectors` calls (`distinct` inputs) of stream `s` run
    /// through harness `top`, before the comparison and the replay.
    fn new(
        s: Stream,
        top: &str,
        vectors: u64,
        distinct: u64,
        build: (Duration, bool),
        run: Duration,
    ) -> UnitReport {
        UnitReport {
            stream: s,
            used: true,
            top: top.to_string(),
            vectors,
            distinct,
            cycles: 0,
            mismatches: 0,
            shown: Vec::new(),
            answered: 0,
            missing: 0,
            build,
            run,
        }
    }
    /// The unit agreed everywhere: no RTL/golden mismatch, nothing missing,
    /// as many calls replayed as recorded, and exercised if the render uses it.
    pub fn ok(&self) -> bool {
        self.mismatches == 0
            && self.missing == 0
            && self.answered == self.vectors
            && (self.vectors > 0 || !self.used)
    }
    /// `<unit>: N tests through RTL, identical` (or `DIFFERENT`, or
    /// `not exercised`).
    pub fn line(&self) -> String {
        let verdict = if !self.used {
            "not used by this render"
        } else if self.vectors == 0 {
            "NOT EXERCISED"
        } else if self.ok() {
            "identical"
        } else {
            "DIFFERENT"
        };
        format!(
            "{}: {} tests through RTL, {verdict}",
            self.stream.label(),
            self.vectors
        )
    }
}

/// The outcome of an RTL-in-the-loop render.
pub struct LoopReport {
    /// the golden render (recording)
    pub golden: Frame,
    /// the render answered by the RTL
    pub rtl: Frame,
    /// per unit, [`Stream::ALL`] order
    pub units: Vec<UnitReport>,
    /// pixels whose hit id, `t` bits or colour bits differ
    pub differing_pixels: u64,
}

impl LoopReport {
    /// The report of one unit.
    pub fn unit(&self, s: Stream) -> &UnitReport {
        &self.units[s as usize]
    }
    /// Box tests that went through the RTL (both silhouette units).
    pub fn box_tests(&self) -> u64 {
        self.unit(Stream::BoxShared).vectors + self.unit(Stream::BoxBounded).vectors
    }
    /// Every unit agreed and the images are identical.
    pub fn ok(&self) -> bool {
        self.units.iter().all(UnitReport::ok) && self.differing_pixels == 0
    }
}

impl std::fmt::Display for LoopReport {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        writeln!(
            f,
            "| unit | harness top | tests through the RTL | distinct | cycles | RTL ≠ golden | replay answered (missing) | harness build | run |\n|---|---|---|---|---|---|---|---|---|"
        )?;
        for u in &self.units {
            writeln!(
                f,
                "| {} | {} | {} | {} | {} | {} | {} ({}) | {:.1} s{} | {:.2} s |",
                u.stream.label(),
                u.top,
                u.vectors,
                u.distinct,
                u.cycles,
                u.mismatches,
                u.answered,
                u.missing,
                u.build.0.as_secs_f64(),
                if u.build.1 { " (cached)" } else { "" },
                u.run.as_secs_f64()
            )?;
        }
        writeln!(f)?;
        for u in &self.units {
            writeln!(f, "{}", u.line())?;
        }
        for u in self.units.iter().filter(|u| !u.shown.is_empty()) {
            writeln!(
                f,
                "\n{} (`{}`), {} of {} mismatches:",
                u.stream.label(),
                u.top,
                u.shown.len(),
                u.mismatches
            )?;
            for m in &u.shown {
                write!(f, "{m}")?;
            }
        }
        writeln!(
            f,
            "image: {} of {} pixels differ from the golden render: {}",
            self.differing_pixels,
            self.golden.ids.len(),
            if self.differing_pixels == 0 {
                "IDENTICAL"
            } else {
                "DIFFERENT"
            }
        )?;
        let unexercised = self.units.iter().any(|u| u.used && u.vectors == 0);
        writeln!(
            f,
            "RTL in the loop: {}",
            if self.ok() {
                "passed"
            } else if unexercised && self.units.iter().all(|u| u.vectors == 0 || u.ok()) {
                "FAILED: a unit the render uses got no test (render larger, or turn its \
                 feature off: --bundle 0, --no-planes)"
            } else {
                "FAILED"
            }
        )
    }
}

/// Pixels whose primary hit, `t` bits or colour bits differ.
pub fn differing_pixels(a: &Frame, b: &Frame) -> u64 {
    (0..a.ids.len())
        .filter(|&p| a.ids[p] != b.ids[p] || a.t[p] != b.t[p] || a.color_bits(p) != b.color_bits(p))
        .count() as u64
}

/// Mismatches described per unit (the vector, both results, a replay).
pub const SHOWN_MISMATCHES: usize = 3;

/// One stream run through its unit's RTL.
struct StreamRun {
    report: UnitReport,
    answers: Answers,
}

/// Builds the harness of `g` (or finds it in the cache), runs the flat
/// port values `inputs` through it as one stream and compares every output
/// vector with the unit's golden model.
fn run_stream(s: Stream, g: &Generated, inputs: &[u64], dir: &Path) -> Result<StreamRun, String> {
    let e = |e: sim::SimError| format!("{}: {e}", s.label());
    let name = &g.module.name;
    let dir = dir.join(name);
    let (n_in, n_out) = (g.ports.inputs.len(), g.ports.outputs.len());
    let vectors = inputs.len() / n_in;
    let mut answers = Answers::with_capacity(vectors);
    if inputs.is_empty() {
        return Ok(StreamRun {
            report: UnitReport::new(s, name, 0, 0, (Duration::ZERO, false), Duration::ZERO),
            answers,
        });
    }
    let started = Instant::now();
    g.write(&dir, 10.0).map_err(|e| e.to_string())?;
    let harness = Harness::build(&g.ports, &dir, &sim::default_cache_root()).map_err(e)?;
    let build = (started.elapsed(), harness.was_cached());
    let started = Instant::now();
    let (stats, outputs) = harness
        .run_records(
            inputs.chunks(n_in),
            &dir.join(name),
            &sim::RunOptions::default(),
        )
        .map_err(e)?;
    let run = started.elapsed();
    let bench = g.testbench();
    let mut golden = vec![0u64; n_out];
    let (mut mismatches, mut shown) = (0, Vec::new());
    for (index, (v, out)) in inputs.chunks(n_in).zip(outputs.chunks(n_out)).enumerate() {
        bench.eval(v, &mut golden);
        if golden != out {
            mismatches += 1;
            if shown.len() < SHOWN_MISMATCHES {
                // vector `index` of the stream, written alone for a traced replay
                let stem = format!("{name}-vec{index}");
                shown.push(sim::describe_mismatch(
                    &harness,
                    &dir,
                    &stem,
                    None,
                    index as u64,
                    v,
                    &golden,
                    out,
                ));
            }
        }
        if let Some(prev) = answers.insert(v.to_vec(), out.to_vec()) {
            if prev != out {
                return Err(format!(
                    "{name}: the RTL answered the same input twice differently"
                ));
            }
        }
    }
    let mut report = UnitReport::new(s, name, vectors as u64, answers.len() as u64, build, run);
    report.cycles = stats.cycles;
    report.mismatches = mismatches;
    report.shown = shown;
    Ok(StreamRun { report, answers })
}

/// Renders `w`×`h` with the golden models (recording every unit call),
/// runs the calls through the Verilated units (one stream each; `work`
/// holds the generated Verilog and the vector files), renders again
/// answering from the RTL outputs and compares. The triangle test is the
/// `triangle` unit's: the `outputs=tnum` unit if `opts.tri` is
/// [`TriTest::GoldenTnum`], else the `outputs=full` one (`opts.tri` is set
/// to [`TriTest::Golden`]); rays are transformed by the `transform` unit. With `wide`, the rays traverse the
/// wide BVH and every node test is the `node` unit's (its TLAS and BLAS
/// shapes two streams).
#[allow(clippy::too_many_arguments)]
pub fn rtl_loop(
    scene: &Scene,
    accel: &Accel,
    wide: Option<&WideAccel>,
    mut opts: TraceOpts,
    w: u32,
    h: u32,
    work: &Path,
    progress: bool,
) -> Result<LoopReport, String> {
    if opts.tri != TriTest::GoldenTnum {
        opts.tri = TriTest::Golden;
    }
    opts.f32_transform = false;
    let shape = wide.map_or_else(WideShape::default, |wa| WideShape {
        children: wa.format.children(),
        box_bits: wa.format.box_bits(),
        tlas_box_bits: wa.tlas.format.box_bits(),
    });
    let units = LoopUnits::generate(shape)?;
    let frame = |tester: &dyn BoxTester| {
        let tracer = Tracer::new(scene, accel, tester, opts);
        let tracer = match wide {
            Some(wa) => tracer.with_wide(wa, Boxes::Node),
            None => tracer,
        };
        render_with(scene, accel, &tracer, w, h, progress)
    };
    let rec = Recorder::new(&units);
    let golden = frame(&rec);
    let streams = rec.into_streams();
    std::fs::create_dir_all(work).map_err(|e| format!("{}: {e}", work.display()))?;
    // the Verilator builds and runs are independent: two at a time (the
    // machines this runs on have two cores)
    let runs: Vec<Result<StreamRun, String>> = {
        use rayon::prelude::*;
        Stream::ALL
            .par_iter()
            .map(|&s| run_stream(s, units.generated(s), &streams[s as usize], work))
            .collect()
    };
    let mut reports = Vec::new();
    let mut answers: [Answers; STREAMS] = Default::default();
    for (s, r) in Stream::ALL.into_iter().zip(runs) {
        let r = r?;
        reports.push(r.report);
        answers[s as usize] = r.answers;
    }
    let tester = RtlTester::new(&units, answers);
    let rtl = frame(&tester);
    for r in &mut reports {
        r.used = r.stream.used(&opts, wide.is_some());
        r.answered = tester.answered(r.stream);
        r.missing = tester.missing(r.stream);
    }
    let differing = differing_pixels(&golden, &rtl);
    Ok(LoopReport {
        golden,
        rtl,
        units: reports,
        differing_pixels: differing,
    })
}

/// A default working directory: `<target>/rtl-loop/<pid>` next to the
/// harness cache.
pub fn default_work_dir() -> PathBuf {
    sim::default_cache_root()
        .parent()
        .map(|p| p.join("rtl-loop"))
        .unwrap_or_else(|| std::env::temp_dir().join("rtl-loop"))
        .join(std::process::id().to_string())
}
