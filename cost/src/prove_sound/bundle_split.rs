//! `--split` for the silhouette bundle tester (`mode=bundle origin=shared`):
//! both of its guarantees, never AllMiss while a ray of the bundle meets the
//! box and never AllHit while one misses it, as lemmas small enough for e3m2
//! (docs/proofs.md, "Bundles, split"). The free ray of the reference is any
//! ray of the bundle (`d_lo ≤ d ≤ d_hi`, the wrapper's assumption).
//!
//! **Stage 0** (the unit as built), per axis `a`, **bounded_a**: unless the
//! axis is mixed (`neg ∧ pos`) or its corners are unordered, the axis
//! instance's results are not NaN, `a ≤ |d| ≤ b` (its smallest and largest
//! `|d|` bound the free ray's), its mirror agrees with the free ray's sign
//! (`d < 0 → neg`, `d > 0 → ¬neg`), and its rounded numerators bracket the
//! exact ones of its mirror, `n_any ≤ E ≤ n_all`, `x_all ≤ X ≤ x_any` (`E`,
//! `X` the plane minus the origin, `near − o` and `far − o` mirrored; the
//! reference's entry and exit numerators when `d ≠ 0`).
//!
//! **Stage 1** (every axis result cut: free values; the tests instance's
//! `ok`s watched), from those facts over the cut values (`axes_any`,
//! `axes_all`), per test `t` of the unit (six edges, three distances, three
//! directions) with `ref_t` the reference's own conjunct for it (its
//! cross-multiplied pair of bounds; a distance or direction test also gives
//! one half of a parallel axis's `inside`):
//! * **test_any_t**: `basic ∧ axes_any ∧ ref_t → any_t ok` (the best
//!   corner passes when the free ray's pair holds);
//! * **test_all_t**: `basic ∧ axes_all ∧ all_t ok → ref_t` (the worst
//!   corner passing makes the free ray's pair hold);
//! * **box_order**: `basic` gives the reference's pairs of one axis (`E·|d|
//!   ≤ X·|d|`) and of the segment;
//! * **combine_any**: `basic ∧ (mixed ∨ (axes_any ∧ every any ok)) → any_hit`;
//! * **all_basic**: `all_hit → basic ∧ ¬mixed ∧ every all ok`;
//! * **combine_all**: `basic ∧ every ref_t ∧ the pairs of box_order →
//!   exact hit`.
//!
//! Why they give the property: an exact hit is the reference's conditions
//! and every pair (its definition), so `basic` and every `ref_t`; by stage 0
//! the real results satisfy `axes_any` (or an axis is mixed), so by
//! test_any every any test passes and by combine_any the unit reports
//! AnyHit. An AllHit gives by all_basic `basic`, no mixed axis and every all
//! test passed; by stage 0 `axes_all`, so by test_all every `ref_t`, and by
//! box_order and combine_all the exact hit.

use super::split::{extended_real, Cut, Stage, SILHOUETTE_TESTS};
use super::*;

/// The axis instance's results: `(name, width)`; `neg`, `pos` one bit.
fn results(fmt: FloatFormat) -> Vec<(&'static str, u32)> {
    let w = fmt.width();
    vec![
        ("neg", 1),
        ("pos", 1),
        ("a", w),
        ("b", w),
        ("n_any", w),
        ("x_any", w),
        ("n_all", w),
        ("x_all", w),
    ]
}

/// The unit's twelve tests ([`SILHOUETTE_TESTS`]) as `(kind, axes)`:
/// `("edge", "xy")` ... `("dir", "z")`.
fn tests() -> Vec<(&'static str, String)> {
    SILHOUETTE_TESTS
        .iter()
        .map(|t| {
            let (kind, axes) = t.split_once('_').expect("a test is kind_axes");
            (kind, axes.to_string())
        })
        .collect()
}

/// A test's `ok` in the tests instance (`edge_any_xy_ok`), and its name here
/// (`any_edge_xy`).
fn test_names(side: &str, kind: &str, axes: &str) -> (String, String) {
    (
        format!("{kind}_{side}_{axes}_ok"),
        format!("{side}_{kind}_{axes}"),
    )
}

/// Where the split cuts the bundle tester: stage 0 the per-axis bounds on the
/// unit as built, stage 1 the rest with every axis result cut.
pub(super) fn bundle_cut(fmt: FloatFormat) -> Cut {
    let wires: Vec<(String, String)> = results(fmt)
        .iter()
        .flat_map(|(r, _)| {
            AXES.iter()
                .map(move |a| (format!("{r}_{a}"), format!("u_unit.u_axis_{a}.{r}")))
        })
        .collect();
    let mut watched = Vec::new();
    let mut stage1 = Vec::new();
    for side in ["any", "all"] {
        for (kind, axes) in tests() {
            let (unit, here) = test_names(side, kind, &axes);
            watched.push((format!("test_{here}_ok"), format!("u_unit.u_tests.{unit}")));
            stage1.push(format!("lemma_test_{here}"));
        }
    }
    stage1.extend(
        [
            "lemma_box_order",
            "lemma_combine_any",
            "lemma_all_basic",
            "lemma_combine_all",
        ]
        .map(String::from),
    );
    let stage0: Vec<String> = AXES.iter().map(|a| format!("lemma_bounded_{a}")).collect();
    let cover = "-set unit_all_hit 1 -set lemma_axes_all 1".to_string();
    Cut {
        lemmas: stage0.iter().chain(&stage1).cloned().collect(),
        combination: stage1.len(),
        watched_after_cut: Vec::new(),
        cover: cover.clone(),
        stages: vec![
            Stage {
                cut: Vec::new(),
                lemmas: stage0,
                cover: None,
                cases: Vec::new(),
            },
            Stage {
                cut: wires.iter().map(|(monitor, _)| monitor.clone()).collect(),
                lemmas: stage1,
                cover: Some(cover),
                cases: Vec::new(),
            },
        ],
        wires,
        watched,
    }
}

/// The module `silhouette_bundle_lemmas_e<E>m<F>`: from the ray/box inputs
/// (the free ray) and the axis results, the facts the lemmas combine (module
/// doc), with the reference's own per-axis terms and pairs (the same text as
/// the reference's, so that they merge with it).
pub(super) fn bundle_lemma_module(fmt: FloatFormat) -> (String, String) {
    let (e, f) = (fmt.exp_bits(), fmt.frac_bits());
    let w = fmt.width();
    let name = format!("silhouette_bundle_lemmas_e{e}m{f}");
    let nw = magnitude_bits(fmt) + 1;
    let dw = nw + 2;
    let mut inputs: Vec<String> = RAY_BOX_PORTS
        .iter()
        .map(|p| format!("input wire [{}:0] {p}", w - 1))
        .collect();
    for (r, rw) in results(fmt) {
        for a in AXES {
            inputs.push(if rw == 1 {
                format!("input wire {r}_{a}")
            } else {
                format!("input wire [{}:0] {r}_{a}", rw - 1)
            });
        }
    }
    let refs: Vec<String> = tests()
        .iter()
        .map(|(k, ax)| format!("ref_{k}_{ax}"))
        .collect();
    let mut v = String::new();
    let _ = writeln!(
        v,
        "// Generated by rtl-gen prove --split: the silhouette bundle tester's soundness lemmas for e{e}m{f}.\n\
         `default_nettype none\nmodule {name} (\n    {},\n    \
         output wire bounded_x, bounded_y, bounded_z, basic, mixed, axes_any, axes_all, order,\n    \
         output wire {}\n);",
        inputs.join(",\n    "),
        refs.join(", ")
    );
    v.push_str(&decode_functions(fmt, "mag", "value", nw));
    let (lower, upper, _) = box_bounds(&mut v, fmt, dw, false);
    let _ = ordered_pairs(&mut v, &lower, &upper, 2 * dw, "", |_, _| false);
    for (r, rw) in results(fmt) {
        if rw > 1 {
            for a in AXES {
                v.push_str(&extended_real(fmt, &format!("{r}_{a}")));
            }
        }
    }
    for t in ["t_min", "t_max"] {
        v.push_str(&extended_real(fmt, t));
    }
    let d1 = dw - 1;
    let mut basic = vec![
        "!t_min_nan && !t_max_nan && !t_min_up && !t_max_down && t_min_key <= t_max_key"
            .to_string(),
    ];
    let (mut any, mut all, mut mixed) = (Vec::new(), Vec::new(), Vec::new());
    for a in AXES {
        let nans: Vec<String> = ["a", "b", "n_any", "x_any", "n_all", "x_all"]
            .iter()
            .map(|r| format!("!{r}_{a}_nan"))
            .collect();
        let _ = writeln!(
            v,
            "    // axis {a}: the mirror's exact numerators, and what the axis instance guarantees\n    \
             wire mixed_{a} = neg_{a} && pos_{a};\n    \
             wire signed [{d1}:0] e_unit_{a} = neg_{a} ? o_{a}_v - pmax_{a} : pmin_{a} - o_{a}_v;\n    \
             wire signed [{d1}:0] x_unit_{a} = neg_{a} ? o_{a}_v - pmin_{a} : pmax_{a} - o_{a}_v;\n    \
             wire facts_{a} = {} && !a_{a}_up && !b_{a}_up\n        \
             && a_{a}_key >= 0 && a_{a}_key <= den_{a} && den_{a} <= b_{a}_key\n        \
             && (d_{a}_v >= 0 || neg_{a}) && (d_{a}_v <= 0 || !neg_{a})\n        \
             && n_any_{a}_key <= e_unit_{a} && e_unit_{a} <= n_all_{a}_key\n        \
             && x_all_{a}_key <= x_unit_{a} && x_unit_{a} <= x_any_{a}_key;\n    \
             assign bounded_{a} = mixed_{a} || !(pmin_{a} <= pmax_{a}) || facts_{a};",
            nans.join(" && ")
        );
        basic.push(format!("pmin_{a} <= pmax_{a}"));
        any.push(format!("!mixed_{a} && facts_{a} && inside_{a}"));
        all.push(format!("!mixed_{a} && facts_{a}"));
        mixed.push(format!("mixed_{a}"));
    }
    // the reference's pairs: lower 0 = t_min, 1 + i = entry i; upper 0 = t_max, 1 + j = exit j
    let k = |a: &str| 1 + AXES.iter().position(|x| *x == a).expect("an axis");
    for (kind, ax) in tests() {
        let r = match kind {
            "edge" => {
                let (i, j) = (&ax[..1], &ax[1..]);
                format!("ordered_{}_{}", k(i), k(j))
            }
            "dist" => format!("ordered_{}_0 && (!d_{ax}_zero || e_unit_{ax} <= 0)", k(&ax)),
            _ => format!("ordered_0_{} && (!d_{ax}_zero || x_unit_{ax} >= 0)", k(&ax)),
        };
        let _ = writeln!(v, "    assign ref_{kind}_{ax} = {r};");
    }
    let _ = writeln!(
        v,
        "    assign basic = {};\n    assign mixed = {};\n    assign axes_any = {};\n    \
         assign axes_all = {};\n    assign order = ordered_0_0 && ordered_1_1 && ordered_2_2 && ordered_3_3;\nendmodule",
        basic.join("\n        && "),
        mixed.join(" || "),
        any.join("\n        && "),
        all.join("\n        && ")
    );
    (name, v)
}

/// The wrapper's part: the axis results as wires the script drives, the
/// tests' `ok`s it watches, the lemma module and each lemma as one signal.
pub(super) fn bundle_wrapper_part(fmt: FloatFormat) -> String {
    let (name, _) = bundle_lemma_module(fmt);
    let mut conns: Vec<String> = RAY_BOX_PORTS.iter().map(|p| format!(".{p}({p})")).collect();
    let mut v = String::from(
        "    // --split: the bundle tester's axis results, driven by the proof script (prove.ys)\n",
    );
    for (r, rw) in results(fmt) {
        for a in AXES {
            let n = format!("{r}_{a}");
            let _ = if rw == 1 {
                writeln!(v, "    (* keep *) wire {n};")
            } else {
                writeln!(v, "    (* keep *) wire [{}:0] {n};", rw - 1)
            };
            conns.push(format!(".{n}({n})"));
        }
    }
    let facts = [
        "bounded_x",
        "bounded_y",
        "bounded_z",
        "basic",
        "mixed",
        "axes_any",
        "axes_all",
        "order",
    ];
    for f in facts {
        let _ = writeln!(v, "    (* keep *) wire lemma_{f};");
        conns.push(format!(".{f}(lemma_{f})"));
    }
    let mut any_oks = Vec::new();
    let mut all_oks = Vec::new();
    let mut refs = Vec::new();
    for (kind, ax) in tests() {
        let r = format!("lemma_ref_{kind}_{ax}");
        let _ = writeln!(v, "    (* keep *) wire {r};");
        conns.push(format!(".ref_{kind}_{ax}({r})"));
        let (_, any) = test_names("any", kind, &ax);
        let (_, all) = test_names("all", kind, &ax);
        let _ = writeln!(
            v,
            "    (* keep *) wire test_{any}_ok, test_{all}_ok;\n    \
             (* keep *) wire lemma_test_{any} = !(lemma_basic && lemma_axes_any && {r}) || test_{any}_ok;\n    \
             (* keep *) wire lemma_test_{all} = !(lemma_basic && lemma_axes_all && test_{all}_ok) || {r};"
        );
        any_oks.push(format!("test_{any}_ok"));
        all_oks.push(format!("test_{all}_ok"));
        refs.push(r);
    }
    let _ = writeln!(
        v,
        "    {name} u_lemmas ({});\n    \
         (* keep *) wire lemma_box_order = !lemma_basic || lemma_order;\n    \
         (* keep *) wire lemma_combine_any = !(lemma_basic && (lemma_mixed || (lemma_axes_any && {}))) || unit_hit;\n    \
         (* keep *) wire lemma_all_basic = !unit_all_hit || (lemma_basic && !lemma_mixed && {});\n    \
         (* keep *) wire lemma_combine_all = !(lemma_basic && lemma_order && {}) || exact_hit;",
        conns.join(", "),
        any_oks.join(" && "),
        all_oks.join(" && "),
        refs.join(" && ")
    );
    v
}
