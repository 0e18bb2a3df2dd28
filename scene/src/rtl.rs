//! RTL in the loop: every box test of a render answered by the Verilated
//! `silhouette` unit instead of its golden model.
//!
//! 1. **Record**: the golden render runs with a [`Recorder`], which answers
//!    from the golden model ([`Golden`]) and keeps every box-test input (the
//!    unit's [`BundleIn`] record, binary32 bits), split by unit: single rays
//!    and shared-origin bundles go to the shared-origin unit, the other
//!    bundles to the bounded-origin unit (the same split as [`Golden`]).
//! 2. **Run**: the recorded inputs of each unit, duplicates included, in
//!    recording order, are written as one `rtlvec` stream and run through
//!    the unit's Verilated harness ([`sim::Harness::run`], back to back, one
//!    transaction per clock). Configurations: binary32, conservative
//!    rounding, `origin=shared stages=4` and `origin=bounded stages=2`, the
//!    parameters of `tests/silhouette_rtl.rs`, so the harness builds are
//!    shared through the cache (`target/rtl-cache`).
//! 3. **Replay**: the render runs again with an [`RtlTester`], which answers
//!    every box test from the RTL outputs, looked up by the exact input bits
//!    (tiles run in parallel, so the order is not replayed). A box test whose
//!    input was not recorded is counted as missing (and answered
//!    conservatively: hit / Mixed); the loop fails if any is missing.
//! 4. **Check**: the replayed image is compared with the golden one (primary
//!    hit ids, `t` bits, colour bits of every pixel), the replay must make
//!    exactly as many box tests as were recorded, and the RTL outputs are also
//!    compared with the golden model vector by vector (all five output bits).

use crate::bvh::Accel;
use crate::render::{render, Frame};
use crate::scene::Scene;
use crate::tester::{ray_input, BoxTester, BundleBox, Golden, RayBox};
use crate::trace::TraceOpts;
use golden_model::silhouette::{eval, BundleIn, Verdict};
use rtl_gen::flow::silhouette::SilhouetteBench;
use rtl_gen::flow::{self, Generated};
use sim::{BinReader, BinWriter, Harness};
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Mutex;
use std::time::{Duration, Instant};

/// Unit parameters of the shared-origin unit (single rays, shared-origin
/// bundles): those of `tests/silhouette_rtl.rs`.
pub const SHARED_PARAMS: [&str; 4] = ["exp_bits=8", "frac_bits=23", "origin=shared", "stages=4"];
/// Unit parameters of the bounded-origin unit (other bundles): those of
/// `tests/silhouette_rtl.rs`.
pub const BOUNDED_PARAMS: [&str; 4] = ["exp_bits=8", "frac_bits=23", "origin=bounded", "stages=2"];

/// The unit's output ports, in the bit order of `Out::to_bits`.
pub const OUTPUTS: [&str; 5] = ["all_hit", "any_hit", "nan", "invalid", "mixed_sign"];

/// Which silhouette unit a box test goes to.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Unit {
    /// shared origin: single rays and shared-origin bundles
    Shared,
    /// bounded origin: bundles with different origins
    Bounded,
}

/// All the inputs of a record as one hashable key.
fn key(b: &BundleIn) -> [u64; 20] {
    let mut k = [0u64; 20];
    k[0..3].copy_from_slice(&b.p_min);
    k[3..6].copy_from_slice(&b.p_max);
    k[6..9].copy_from_slice(&b.o_lo);
    k[9..12].copy_from_slice(&b.o_hi);
    k[12..15].copy_from_slice(&b.d_lo);
    k[15..18].copy_from_slice(&b.d_hi);
    k[18] = b.t_min;
    k[19] = b.t_max;
    k
}

/// Answers from the golden model and records every box-test input.
#[derive(Default)]
pub struct Recorder {
    golden: Golden,
    shared: Mutex<Vec<BundleIn>>,
    bounded: Mutex<Vec<BundleIn>>,
}

impl Recorder {
    /// The recorded inputs of each unit (recording order).
    pub fn into_inputs(self) -> (Vec<BundleIn>, Vec<BundleIn>) {
        (
            self.shared.into_inner().unwrap(),
            self.bounded.into_inner().unwrap(),
        )
    }
}

impl BoxTester for Recorder {
    fn ray(&self, x: &RayBox) -> bool {
        self.shared.lock().unwrap().push(ray_input(x));
        self.golden.ray(x)
    }
    fn bundle(&self, x: &BundleBox) -> Verdict {
        let list = if x.shared {
            &self.shared
        } else {
            &self.bounded
        };
        list.lock().unwrap().push(x.input);
        self.golden.bundle(x)
    }
    fn supports_bundles(&self) -> bool {
        true
    }
    fn name(&self) -> &'static str {
        "golden (recording)"
    }
}

/// Answers every box test from the RTL outputs (packed as
/// `golden_model::silhouette::Out::to_bits`: bit 0 all_hit, 1 any_hit).
pub struct RtlTester {
    shared: HashMap<[u64; 20], u8>,
    bounded: HashMap<[u64; 20], u8>,
    answered: AtomicU64,
    missing: AtomicU64,
}

impl RtlTester {
    /// A tester answering from the given outputs.
    pub fn new(shared: HashMap<[u64; 20], u8>, bounded: HashMap<[u64; 20], u8>) -> RtlTester {
        RtlTester {
            shared,
            bounded,
            answered: AtomicU64::new(0),
            missing: AtomicU64::new(0),
        }
    }
    /// Box tests answered from the RTL outputs.
    pub fn answered(&self) -> u64 {
        self.answered.load(Ordering::Relaxed)
    }
    /// Box tests whose input had not been run through the RTL.
    pub fn missing(&self) -> u64 {
        self.missing.load(Ordering::Relaxed)
    }
    fn lookup(&self, unit: Unit, b: &BundleIn) -> Option<u8> {
        let map = match unit {
            Unit::Shared => &self.shared,
            Unit::Bounded => &self.bounded,
        };
        match map.get(&key(b)) {
            Some(&bits) => {
                self.answered.fetch_add(1, Ordering::Relaxed);
                Some(bits)
            }
            None => {
                self.missing.fetch_add(1, Ordering::Relaxed);
                None
            }
        }
    }
}

impl BoxTester for RtlTester {
    fn ray(&self, x: &RayBox) -> bool {
        self.lookup(Unit::Shared, &ray_input(x))
            .is_none_or(|bits| bits & 2 != 0)
    }
    fn bundle(&self, x: &BundleBox) -> Verdict {
        let unit = if x.shared {
            Unit::Shared
        } else {
            Unit::Bounded
        };
        match self.lookup(unit, &x.input) {
            None => Verdict::Mixed,
            Some(bits) if bits & 1 != 0 => Verdict::AllHit,
            Some(bits) if bits & 2 == 0 => Verdict::AllMiss,
            Some(_) => Verdict::Mixed,
        }
    }
    fn supports_bundles(&self) -> bool {
        true
    }
    fn name(&self) -> &'static str {
        "rtl"
    }
}

/// One silhouette unit generated and its harness built (or found in the cache).
pub struct UnitHarness {
    /// the generated unit
    pub generated: Generated,
    /// its testbench (port mapping)
    pub bench: SilhouetteBench,
    /// the Verilated harness
    pub harness: Harness,
}

impl UnitHarness {
    /// Generates `silhouette` with `params` into `dir` and builds its harness
    /// under [`sim::default_cache_root`].
    pub fn build(params: &[&str], dir: &Path) -> Result<UnitHarness, String> {
        let given: Vec<String> = params.iter().map(|s| s.to_string()).collect();
        let g = flow::generate("silhouette", &given).map_err(|e| e.to_string())?;
        let dir = dir.join(&g.module.name);
        g.write(&dir, 10.0).map_err(|e| e.to_string())?;
        let harness = Harness::build(&g.ports, &dir, &sim::default_cache_root())
            .map_err(|e| e.to_string())?;
        let outs: Vec<&str> = g.ports.outputs.iter().map(|p| p.name.as_str()).collect();
        if outs != OUTPUTS {
            return Err(format!(
                "{}: output ports {outs:?}, expected {OUTPUTS:?} (the packing of Out::to_bits)",
                g.module.name
            ));
        }
        let bench = SilhouetteBench::new(&g.params);
        Ok(UnitHarness {
            generated: g,
            bench,
            harness,
        })
    }

    /// Runs `inputs` as one stream through the RTL; returns the outputs
    /// packed as `Out::to_bits`, one per input, and the cycles simulated.
    pub fn run(&self, inputs: &[BundleIn], dir: &Path) -> Result<(Vec<u8>, u64), String> {
        let ports = &self.generated.ports;
        let name = &self.generated.module.name;
        let (fin, fout) = (
            dir.join(format!("{name}.in.rtlvec")),
            dir.join(format!("{name}.out.rtlvec")),
        );
        let e = |e: sim::SimError| e.to_string();
        let mut w = BinWriter::create(&fin, &ports.inputs).map_err(e)?;
        let mut v = vec![0u64; ports.inputs.len()];
        for b in inputs {
            self.bench.to_ports(b, &mut v);
            w.write_record(&v).map_err(e)?;
        }
        w.finish().map_err(e)?;
        let stats = self
            .harness
            .run(&fin, &fout, &sim::RunOptions::default())
            .map_err(e)?;
        let mut r = BinReader::open(&fout).map_err(e)?;
        r.expect_ports(&ports.outputs).map_err(e)?;
        let mut o = vec![0u64; ports.outputs.len()];
        let mut out = Vec::with_capacity(inputs.len());
        while r.read_record(&mut o).map_err(e)? {
            out.push(
                o.iter()
                    .enumerate()
                    .fold(0u8, |a, (i, &b)| a | ((b as u8 & 1) << i)),
            );
        }
        if out.len() != inputs.len() {
            return Err(format!(
                "{name}: {} inputs, {} outputs from the harness",
                inputs.len(),
                out.len()
            ));
        }
        let _ = std::fs::remove_file(&fin);
        let _ = std::fs::remove_file(&fout);
        Ok((out, stats.cycles))
    }
}

/// Per unit: what went through the RTL.
#[derive(Debug, Clone, Default)]
pub struct UnitReport {
    /// harness top module
    pub top: String,
    /// box tests run through the RTL (the stream's length, duplicates included)
    pub vectors: u64,
    /// distinct inputs among them
    pub distinct: u64,
    /// clock cycles the harness simulated (reset and drain included)
    pub cycles: u64,
    /// RTL outputs (all five bits) differing from the golden model
    pub mismatches: u64,
    /// harness build time (cache lookup included) and whether it was cached
    pub build: (Duration, bool),
    /// time of the harness run
    pub run: Duration,
}

/// The outcome of an RTL-in-the-loop render.
pub struct LoopReport {
    /// the golden render (recording)
    pub golden: Frame,
    /// the render answered by the RTL
    pub rtl: Frame,
    /// shared-origin unit
    pub shared: UnitReport,
    /// bounded-origin unit
    pub bounded: UnitReport,
    /// box tests the replay answered from the RTL outputs
    pub answered: u64,
    /// box tests of the replay whose input had not been run (should be 0)
    pub missing: u64,
    /// pixels whose hit id, `t` bits or colour bits differ
    pub differing_pixels: u64,
}

impl LoopReport {
    /// Box tests that went through the RTL (both units).
    pub fn box_tests(&self) -> u64 {
        self.shared.vectors + self.bounded.vectors
    }
    /// Everything agrees: no RTL/golden mismatch, nothing missing, as many
    /// box tests replayed as recorded, identical images.
    pub fn ok(&self) -> bool {
        self.shared.mismatches == 0
            && self.bounded.mismatches == 0
            && self.missing == 0
            && self.answered == self.box_tests()
            && self.differing_pixels == 0
    }
}

impl std::fmt::Display for LoopReport {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        writeln!(
            f,
            "| unit | box tests through the RTL | distinct | cycles | RTL ≠ golden | harness build | run |\n|---|---|---|---|---|---|---|"
        )?;
        for u in [&self.shared, &self.bounded] {
            writeln!(
                f,
                "| {} | {} | {} | {} | {} | {:.1} s{} | {:.2} s |",
                u.top,
                u.vectors,
                u.distinct,
                u.cycles,
                u.mismatches,
                u.build.0.as_secs_f64(),
                if u.build.1 { " (cached)" } else { "" },
                u.run.as_secs_f64()
            )?;
        }
        writeln!(
            f,
            "\n{} box tests through the RTL; replay answered {} from the RTL outputs ({} missing); \
             {} of {} pixels differ from the golden image: {}",
            self.box_tests(),
            self.answered,
            self.missing,
            self.differing_pixels,
            self.golden.ids.len(),
            if self.ok() { "IDENTICAL" } else { "FAILED" }
        )
    }
}

/// Pixels whose primary hit, `t` bits or colour bits differ.
pub fn differing_pixels(a: &Frame, b: &Frame) -> u64 {
    (0..a.ids.len())
        .filter(|&p| {
            a.ids[p] != b.ids[p]
                || a.t[p] != b.t[p]
                || a.color[p].map(f32::to_bits) != b.color[p].map(f32::to_bits)
        })
        .count() as u64
}

fn run_unit(
    params: &[&str],
    inputs: &[BundleIn],
    dir: &Path,
) -> Result<(UnitReport, HashMap<[u64; 20], u8>), String> {
    let started = Instant::now();
    let u = UnitHarness::build(params, dir)?;
    let build = (started.elapsed(), u.harness.was_cached());
    let started = Instant::now();
    let (outs, cycles) = u.run(inputs, dir)?;
    let run = started.elapsed();
    let cfg = u.bench.config();
    let mut map = HashMap::with_capacity(inputs.len());
    let mut mismatches = 0;
    for (b, &bits) in inputs.iter().zip(&outs) {
        if eval(cfg, b).to_bits() != bits {
            mismatches += 1;
        }
        if let Some(prev) = map.insert(key(b), bits) {
            if prev != bits {
                return Err(format!(
                    "{}: the RTL answered the same input twice differently",
                    u.generated.module.name
                ));
            }
        }
    }
    Ok((
        UnitReport {
            top: u.generated.module.name.clone(),
            vectors: inputs.len() as u64,
            distinct: map.len() as u64,
            cycles,
            mismatches,
            build,
            run,
        },
        map,
    ))
}

/// Renders `w`×`h` with the golden model (recording every box test), runs
/// the box tests through the Verilated shared- and bounded-origin units (one
/// stream each; `work` holds the generated Verilog and the vector files),
/// renders again answering from the RTL outputs and compares.
pub fn rtl_loop(
    scene: &Scene,
    accel: &Accel,
    opts: TraceOpts,
    w: u32,
    h: u32,
    work: &Path,
    progress: bool,
) -> Result<LoopReport, String> {
    let rec = Recorder::default();
    let golden = render(scene, accel, &rec, opts, w, h, progress);
    let (shared_in, bounded_in) = rec.into_inputs();
    std::fs::create_dir_all(work).map_err(|e| format!("{}: {e}", work.display()))?;
    // the two Verilator builds/runs are independent
    let (a, b) = rayon::join(
        || run_unit(&SHARED_PARAMS, &shared_in, work),
        || run_unit(&BOUNDED_PARAMS, &bounded_in, work),
    );
    let ((shared, shared_map), (bounded, bounded_map)) = (a?, b?);
    let tester = RtlTester::new(shared_map, bounded_map);
    let rtl = render(scene, accel, &tester, opts, w, h, progress);
    let differing = differing_pixels(&golden, &rtl);
    Ok(LoopReport {
        golden,
        rtl,
        shared,
        bounded,
        answered: tester.answered(),
        missing: tester.missing(),
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
