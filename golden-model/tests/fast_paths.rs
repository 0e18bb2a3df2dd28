//! The fast paths (issue #20) against the generic models they replace:
//! every output bit equal on random and corner vectors, per unit and
//! format class. `FAST_CASES` sets the number of vectors per unit and class
//! (default 1,000,000; the release run uses 10^8). A disagreement is a bug in
//! the fast path: the first disagreeing input and both outputs are printed
//! in hex.

mod common;
mod silhouette_gen;

use common::{operand, operand_near, specials};
use golden_model::float::{add_down_up, add_down_up_generic, FloatFormat};
use golden_model::silhouette::{eval, eval_generic, BundleIn, Config, OriginMode, Rounding};
use silhouette_gen::{gen_bundle, realistic_scene_case, Rng, KINDS};

/// Vectors per unit and format class.
fn cases() -> u64 {
    std::env::var("FAST_CASES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(1_000_000)
}

/// Counts vectors; panics with the first disagreement.
struct Equal {
    what: String,
    checked: u64,
}

impl Equal {
    fn new(what: impl Into<String>) -> Equal {
        Equal {
            what: what.into(),
            checked: 0,
        }
    }
    fn check<T: PartialEq + std::fmt::Debug>(
        &mut self,
        fast: T,
        generic: T,
        input: impl FnOnce() -> String,
    ) {
        self.checked += 1;
        if fast != generic {
            panic!(
                "{}: fast path disagrees at vector {}\ninput: {}\nfast:    {:x?}\ngeneric: {:x?}",
                self.what,
                self.checked,
                input(),
                fast,
                generic
            );
        }
    }
    fn finish(self) {
        println!("{}: {} vectors, fast == generic", self.what, self.checked);
    }
}

#[test]
fn add_down_up_binary32() {
    let f = FloatFormat::BINARY32;
    let sp = specials(f);
    let mut eq = Equal::new("add_down_up binary32");
    let mut one = |a: u64, b: u64| {
        eq.check(add_down_up(f, a, b), add_down_up_generic(f, a, b), || {
            format!("a = {a:#010x}, b = {b:#010x}")
        })
    };
    // Corners: every pair of specials, and each against its one-ulp neighbours
    // and negation.
    for &a in &sp {
        for &b in &sp {
            one(a, b);
            for d in [1u64, 2] {
                one(a, (b + d) & f.mask());
                one(a, b.wrapping_sub(d) & f.mask());
            }
        }
    }
    let mut rng = common::Rng::new(20);
    let n = cases();
    let mut i = 0;
    while i < n {
        let a = operand(&mut rng, f, &sp);
        let b = match rng.below(6) {
            0 => operand(&mut rng, f, &sp),
            1 => a ^ f.sign_bit(), // exact cancellation
            2 => (a ^ f.sign_bit()).wrapping_add(rng.below(5) - 2) & f.mask(), // near cancellation
            3 => operand_near(&mut rng, f, a, 30), // alignment beyond the sticky
            _ => operand_near(&mut rng, f, a, 3),
        };
        // Garbage above the format's width is ignored by both paths.
        let junk = if rng.below(16) == 0 {
            rng.next() << 32
        } else {
            0
        };
        one(a | junk, b);
        i += 1;
    }
    eq.finish();
}

/// A bundle of raw operands: random patterns, specials, structured values.
fn raw_bundle(rng: &mut common::Rng, f: FloatFormat, sp: &[u64]) -> BundleIn {
    let mut v = || operand(rng, f, sp);
    BundleIn {
        p_min: [v(), v(), v()],
        p_max: [v(), v(), v()],
        o_lo: [v(), v(), v()],
        o_hi: [v(), v(), v()],
        d_lo: [v(), v(), v()],
        d_hi: [v(), v(), v()],
        t_min: v(),
        t_max: v(),
    }
}

/// `n` silhouette vectors per configuration class of `fmts`: adversarial
/// bundles and rays of `silhouette_gen` (grazing, along a face, origin on
/// the box, specials, ...), realistic binary32 scene rays, and raw operands.
fn silhouette_class(what: &str, fmts: &[FloatFormat], seed: u64) {
    let n = cases();
    let mut eq = Equal::new(format!("silhouette {what}"));
    let mut rng = Rng(seed);
    let mut raw_rng = common::Rng::new(seed);
    let mut k = 0u64;
    while eq.checked < n {
        let f = fmts[(k % fmts.len() as u64) as usize];
        let origin = if k / fmts.len() as u64 % 2 == 0 {
            OriginMode::Shared
        } else {
            OriginMode::Bounded
        };
        let rounding = if k / (2 * fmts.len() as u64) % 4 == 3 {
            Rounding::Nearest
        } else {
            Rounding::Conservative
        };
        k += 1;
        let cfg = Config::new(f, origin, rounding).unwrap();
        let bounded = origin == OriginMode::Bounded;
        let x = match rng.below(16) {
            0 => raw_bundle(&mut raw_rng, f, &specials(f)),
            1 | 2 if f == FloatFormat::BINARY32 => {
                let (bx, r) = realistic_scene_case(&mut rng);
                BundleIn::ray(bx.p_min, bx.p_max, r.o, r.d, r.t_min, r.t_max)
            }
            _ => {
                let kind = KINDS[rng.below(KINDS.len() as u64) as usize];
                let mixed = rng.chance(1, 4);
                gen_bundle(f, &mut rng, kind, bounded, mixed).1
            }
        };
        eq.check(eval(&cfg, &x), eval_generic(&cfg, &x), || {
            format!("{cfg:?}\n{x:x?}")
        });
    }
    eq.finish();
}

#[test]
fn silhouette_binary32() {
    silhouette_class("binary32", &[FloatFormat::BINARY32], 1);
}

#[test]
fn silhouette_small_formats() {
    let fmts = [
        FloatFormat::BINARY16,
        FloatFormat::BFLOAT16,
        FloatFormat::new(4, 3).unwrap(),
        FloatFormat::new(6, 9).unwrap(),
        FloatFormat::new(8, 22).unwrap(),
        FloatFormat::new(2, 1).unwrap(),
    ];
    silhouette_class("E <= 8, F <= 23 (not binary32)", &fmts, 2);
}
