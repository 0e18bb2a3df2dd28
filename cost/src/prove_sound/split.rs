//! `--split`: soundness proved as lemmas, each a SAT problem small enough
//! for e3m2, where the whole property is not (docs/proofs.md, "Splitting
//! the proof"). The same scheme for the conservative slab and the
//! silhouette ray tester (per-axis bounds, [`AxisUnit`]; the silhouette's
//! combination cut once more per test, [`silhouette_terms`]) and the cull
//! tester (per-plane bounds, [`cull_wrapper_part`]): the unit's own
//! per-axis or per-plane results are watched by one lemma each, then cut
//! (driven by free values) for the combination ([`Cut`], [`script`]).
//!
//! The slab's lemmas, proved on the flattened wrapper (the unit as instantiated,
//! so the top's wiring of each axis is the one proved), under the same
//! input contract as the whole property:
//!
//! * **bounded_a** (a = x, y, z): the unit's per-axis results `t_near`,
//!   `t_far` of instance `u_slab_a` bound the exact axis interval: when the
//!   axis can be met (`d ≠ 0` and ordered corners, or `d = 0` and the origin
//!   inside the slab), neither is NaN and `t_near ≤ enter/|d|`, `t_far ≥
//!   exit/|d|` (cross-multiplied against the reference's own per-axis terms,
//!   [`box_bounds`]), or `t_near = −∞`, `t_far = +∞` for `d = 0`;
//! * **combine**: with the three instances' results cut (free values), if
//!   the intervals meet as extended reals (no NaN, no lower end `+∞`, no
//!   upper end `−∞`, every lower end `t_min`, `t_near_a` at most every upper
//!   end `t_max`, `t_far_a`), the unit reports a hit.
//!
//! Why they imply the property: an exact hit means the reference's
//! conditions hold (finite ends not pointing away, each axis metable) and
//! every lower bound is at most every upper bound, so some real `t` lies in
//! `[t_min, t_max]` and in every non-parallel axis's `[enter, exit]/|d|`.
//! By bounded_a, `t_near_a ≤ t ≤ t_far_a` on every axis (`−∞`, `+∞` on a
//! parallel one), so the unit's intervals meet and, by combine, it hits.
//! The covers of the whole wrapper (an exact hit, a rejected ray) are
//! still answered, and one more: an exact hit where the unit's own
//! intervals meet, so combine's hypothesis is reachable.

use super::*;

/// Where a split proof cuts the unit: each of the unit's wires the lemmas
/// read (flattened name) beside the wrapper's wire that watches it (the
/// bounds) or drives it once cut (the combination); the lemmas' signals in
/// the order the script proves them, the last `combination` of them on the
/// cut design (`lemma_combine` last), where the wrapper also watches the
/// unit's wires `watched_after_cut`.
pub(super) struct Cut {
    pub(super) wires: Vec<(String, String)>,
    pub(super) lemmas: Vec<String>,
    pub(super) combination: usize,
    pub(super) watched_after_cut: Vec<(String, String)>,
    /// the unit's wires the staged lemmas read, never cut (the node's flags)
    pub(super) watched: Vec<(String, String)>,
    /// the `-set` arguments of the cover that shows the combination's hypothesis reachable
    pub(super) cover: String,
    /// the stages of a cut on the design as read (saved as `raw` after `flatten`; the
    /// node's: there the unit's wires keep their widths and drivers, where prep's wreduce and
    /// opt narrow and merge them), `wires` and `watched` then every monitor, `lemmas` the
    /// stages' lemmas in order; empty: one cut of the optimised design (the other units)
    pub(super) stages: Vec<Stage>,
}

/// One stage of a cut on the raw design: the unit's wires in `cut` driven by
/// their monitors (free values), every other monitor driven by the unit's
/// wire; each lemma then proved on its own cone of influence (with the
/// assumptions'), the cover (a `-set` list) answered first.
pub(super) struct Stage {
    pub(super) cut: Vec<String>,
    pub(super) lemmas: Vec<String>,
    pub(super) cover: Option<String>,
    /// per lemma (by name) its cases, each the `-set` arguments of one `sat`
    /// call; together a partition of the inputs (a lemma not named: one call)
    pub(super) cases: Vec<(String, Vec<String>)>,
}

/// Keeps only the lemmas `only` of a staged cut (`--lemma`); a stage left
/// without lemmas is not run.
pub(super) fn keep_only(cut: &mut Cut, only: &[String]) {
    for stage in &mut cut.stages {
        stage.lemmas.retain(|l| only.contains(l));
    }
    cut.stages.retain(|s| !s.lemmas.is_empty());
    cut.lemmas = cut.stages.iter().flat_map(|s| s.lemmas.clone()).collect();
}

/// The Yosys selection of the cone of influence of the signals a `sat`
/// command's `-set` arguments name, and of the assumptions': the same
/// problem, without the design's unrelated logic.
pub(super) fn cone(sets: &str) -> String {
    let words: Vec<&str> = sets.split_whitespace().collect();
    let wires: Vec<String> = words
        .windows(2)
        .filter(|w| w[0] == "-set")
        .map(|w| format!("w:{}", w[1]))
        .collect();
    format!(
        "{} t:$assume{} %ci*",
        wires.join(" "),
        " %u".repeat(wires.len())
    )
}

/// The script of a staged cut ([`Cut::stages`]).
fn staged_script(cut: &Cut) -> String {
    let mut s = String::from("# the lemmas (prove_sound/split.rs), each stage on the raw design\n");
    for (k, stage) in cut.stages.iter().enumerate() {
        let _ = writeln!(
            s,
            "# stage {k}: cut {}\ndesign -load raw",
            stage.cut.join(" ")
        );
        for (monitor, unit) in cut.wires.iter().chain(&cut.watched) {
            if stage.cut.contains(monitor) {
                let _ = writeln!(s, "connect -nomap -set {unit} {monitor}");
            } else {
                let _ = writeln!(s, "connect -nomap -set {monitor} {unit}");
            }
        }
        s += "prep -top prove_sound\nasync2sync\nopt -fast\nchformal -cover -remove\n";
        if let Some(cover) = &stage.cover {
            let _ = writeln!(s, "sat -set-assumes {cover} {}", cone(cover));
        }
        for lemma in &stage.lemmas {
            let cases = stage
                .cases
                .iter()
                .find(|(l, _)| l == lemma)
                .map(|(_, c)| c.clone())
                .unwrap_or_else(|| vec![String::new()]);
            // a marker the log keeps: the lemma and how many calls prove it
            let _ = writeln!(s, "log @lemma {lemma} {}", cases.len());
            for case in cases {
                let _ = writeln!(
                    s,
                    "sat -set-assumes {case} -prove {lemma} 1 -show-inputs {}",
                    cone(&format!("{case} -set {lemma} 1"))
                );
            }
        }
    }
    s
}

/// A ray/box unit whose soundness splits per axis: its per-axis instances
/// (`<instance><a>` in the flattened wrapper) and their results, named
/// `<result>_<a>` in the lemma module and the wrapper.
pub(super) struct AxisUnit {
    name: &'static str,
    instance: &'static str,
    results: &'static [&'static str],
    /// the instance comparing them, and its tests (`<test>_ok`), each
    /// proved from its own part of `meet` before the combination
    tests_instance: &'static str,
    tests: &'static [&'static str],
}

/// The conservative slab: `t_near`, `t_far` of `u_slab_<a>`.
const SLAB: AxisUnit = AxisUnit {
    name: "slab",
    instance: "u_unit.u_slab_",
    results: &["t_near", "t_far"],
    tests_instance: "",
    tests: &[],
};

/// The silhouette ray tester: the entry and exit numerators `n`, `x` and
/// `a = |d|` of `u_axis_<a>`.
const SILHOUETTE: AxisUnit = AxisUnit {
    name: "silhouette",
    instance: "u_unit.u_axis_",
    results: &["n", "x", "a"],
    tests_instance: "u_unit.u_tests",
    tests: SILHOUETTE_TESTS,
};

/// The silhouette tester's twelve tests (its `u_tests` instance, per AnyHit and
/// AllHit in bundle mode): six silhouette edges, three distances, three directions.
pub(super) const SILHOUETTE_TESTS: &[&str] = &[
    "edge_xy", "edge_xz", "edge_yx", "edge_yz", "edge_zx", "edge_zy", "dist_x", "dist_y", "dist_z",
    "dir_x", "dir_y", "dir_z",
];

/// The per-axis split of `unit` (`slab` or `silhouette`).
pub(super) fn axis_unit(unit: &str) -> &'static AxisUnit {
    if unit == SILHOUETTE.name {
        &SILHOUETTE
    } else {
        &SLAB
    }
}

impl AxisUnit {
    /// `<result>_<a>` for every result and axis.
    fn ports(&self) -> Vec<String> {
        self.results
            .iter()
            .flat_map(|r| AXES.iter().map(move |a| format!("{r}_{a}")))
            .collect()
    }

    /// Its cut: every per-axis result; a bound per axis, then the combination.
    pub(super) fn cut(&self) -> Cut {
        Cut {
            wires: self
                .results
                .iter()
                .flat_map(|r| {
                    AXES.iter()
                        .map(move |a| (format!("{r}_{a}"), format!("{}{a}.{r}", self.instance)))
                })
                .collect(),
            lemmas: AXES
                .iter()
                .map(|a| format!("lemma_bounded_{a}"))
                .chain(self.tests.iter().map(|t| format!("lemma_test_{t}")))
                .chain(["lemma_combine".to_string()])
                .collect(),
            combination: self.tests.len() + 1,
            watched_after_cut: self
                .tests
                .iter()
                .map(|t| {
                    (
                        format!("test_{t}_ok"),
                        format!("{}.{t}_ok", self.tests_instance),
                    )
                })
                .collect(),
            watched: Vec::new(),
            cover: "-set exact_hit 1 -set lemma_meet 1".into(),
            stages: Vec::new(),
        }
    }
}

/// The cull tester's cut: per plane its instance's crossing `q` and
/// `dist_neg` (`D < 0`).
pub(super) fn cull_cut(k: usize) -> Cut {
    Cut {
        wires: (0..k)
            .flat_map(|j| {
                [
                    (format!("unit_q{j}"), format!("u_unit.u_plane{j}.q")),
                    (
                        format!("unit_dist_neg{j}"),
                        format!("u_unit.u_plane{j}.dist_neg"),
                    ),
                ]
            })
            .collect(),
        lemmas: (0..k)
            .map(|j| format!("lemma_plane{j}"))
            .chain(["lemma_combine".to_string()])
            .collect(),
        combination: 1,
        watched_after_cut: Vec::new(),
        watched: Vec::new(),
        cover: "-set exact_hit 1 -set lemma_meet 1".into(),
        stages: Vec::new(),
    }
}

/// The cull wrapper's part for the lemmas (inside `prove_sound`, after the
/// exact region's wires `a_<j>` = `A`, `b_<j>` = `B` and the unit's
/// instance; docs/cull.md §2-3.4):
///
/// * **plane_j**: the unit's plane keeps every `t ≥ 0` with `A + t·B ≤ 0`:
///   an exit (`dir = 1`) every such `t ≤ q`, an entry (`dir = 2`) every
///   such `t ≥ −q`, a parallel plane (else) with `dist_neg` none at all; a
///   NaN `q` leaves the plane out. By linearity of `f(t) = A + t·B`: `S =
///   {t ≥ 0 : f(t) ≤ 0}` is empty iff `A > 0 ∧ B ≥ 0`; `S ⊆ [0, q]` for `q ≥
///   0` iff `B > 0 ∧ f(q) ≥ 0` or `B = 0 ∧ A > 0`; `S ⊆ [p, ∞)` for `p = −q >
///   0` iff `A > 0 ∧ f(p) ≥ 0`; `f` at a float compared as `A·2^s ± q_v·B`.
/// * **combine**: with `q`, `dist_neg` cut, if the unit's constraints meet
///   as extended reals (`[t_lo, t_hi]`, and when `t_lo ≥ 0` every usable
///   exit's `t ≤ q`, entry's `t ≥ −q`, no parallel plane with `dist_neg`),
///   the unit keeps.
///
/// An exact region hit gives a real `t` in the segment ∩ box, hence in
/// `[t_lo, t_hi]` (the contract), and on every plane's non-empty side; when
/// `t_lo ≥ 0`, `t ≥ 0`, so by plane_j `t` satisfies the unit's planes: the
/// constraints meet and, by combine, the unit keeps.
pub(super) fn cull_wrapper_part(c: CullFormats) -> String {
    let fmt = c.ray;
    let w = fmt.width();
    let fw = 2 * c.pdw() + 4;
    let t_shift = fmt.bias() + fmt.frac_bits() as i32 - 1;
    let mut v = String::from(
        "    // --split: the unit's per-plane results, driven by the proof script (prove.ys)\n",
    );
    v.push_str(&extended_real(fmt, "t_lo"));
    v.push_str(&extended_real(fmt, "t_hi"));
    let _ = writeln!(
        v,
        "    // the planes apply (t_lo ≥ 0, −0 counts as 0): the witness t ≥ 0\n    \
         wire t_lo_nonneg = !t_lo[{w1}] || t_lo[{w2}:0] == 0;",
        w1 = w - 1,
        w2 = w - 2
    );
    // the lower and upper ends of the unit's constraints: (in force, key, infinite the wrong way)
    let mut lower = vec![(
        "1'b1".to_string(),
        "t_lo_key".to_string(),
        "t_lo_up".to_string(),
    )];
    let mut upper = vec![(
        "1'b1".to_string(),
        "t_hi_key".to_string(),
        "t_hi_down".to_string(),
    )];
    let mut meet = vec!["!t_lo_nan".to_string(), "!t_hi_nan".to_string()];
    for j in 0..c.k {
        let q = format!("unit_q{j}");
        let _ = writeln!(
            v,
            "    (* keep *) wire [{w1}:0] {q};\n    (* keep *) wire unit_dist_neg{j};",
            w1 = w - 1
        );
        v.push_str(&extended_real(fmt, &q));
        let _ = writeln!(
            v,
            "    // plane {j}: the unit keeps every t ≥ 0 with A + t·B ≤ 0\n    \
             wire {q}_neg = {q}[{w1}] && {q}[{w2}:0] != 0 && !{q}_nan;\n    \
             wire signed [{f1}:0] {q}_v = value({q});\n    \
             wire signed [{f1}:0] a{j}_scaled = a_{j} <<< {t_shift};\n    \
             wire signed [{f1}:0] f_at_q{j} = a{j}_scaled + {q}_v * b_{j};\n    \
             wire signed [{f1}:0] f_at_minus_q{j} = a{j}_scaled - {q}_v * b_{j};\n    \
             wire none_ahead{j} = a_{j} > 0 && b_{j} >= 0;\n    \
             wire exit{j} = dir{j} == 2'd1;\n    wire entry{j} = dir{j} == 2'd2;\n    \
             (* keep *) wire lemma_plane{j} = exit{j}\n        \
             ? ({q}_nan || {q}_up || ({q}_neg ? none_ahead{j} : ((b_{j} > 0 && f_at_q{j} >= 0) || (b_{j} == 0 && a_{j} > 0))))\n        \
             : entry{j} ? ({q}_nan || !{q}_neg || ({q}_down ? none_ahead{j} : (a_{j} > 0 && f_at_minus_q{j} >= 0)))\n        \
             : (!unit_dist_neg{j} || none_ahead{j});",
            w1 = w - 1,
            w2 = w - 2,
            f1 = fw - 1,
        );
        let usable = format!("t_lo_nonneg && !{q}_nan");
        lower.push((
            format!("{usable} && entry{j}"),
            format!("-{q}_key"),
            format!("{q}_down"),
        ));
        upper.push((
            format!("{usable} && exit{j}"),
            format!("{q}_key"),
            format!("{q}_down"),
        ));
        meet.push(format!(
            "!(t_lo_nonneg && !exit{j} && !entry{j} && unit_dist_neg{j})"
        ));
    }
    for (on, _, wrong) in lower.iter().chain(&upper) {
        meet.push(format!("(!({on}) || !{wrong})"));
    }
    for (lo_on, lo, _) in &lower {
        for (up_on, up, _) in &upper {
            meet.push(format!("(!({lo_on}) || !({up_on}) || ({lo}) <= {up})"));
        }
    }
    let _ = writeln!(
        v,
        "    // the unit's constraints meet as extended reals\n    \
         (* keep *) wire lemma_meet = {};\n    \
         (* keep *) wire lemma_combine = !lemma_meet || unit_keep;",
        meet.join("\n        && ")
    );
    v
}

/// Wires `<x>_nan`, `<x>_up` (`+∞`), `<x>_down` (`−∞`) and `<x>_key`, the
/// value of the float `x` of `fmt` as an extended real (decoded by the
/// wrapper's `value`, [`decode_functions`]; `±∞` beyond every finite value,
/// symmetric so that `−key` is the key of `−x`), compared signed.
pub(super) fn extended_real(fmt: FloatFormat, x: &str) -> String {
    let kw = magnitude_bits(fmt) + 2;
    format!(
        "    wire {x}_nan = {};\n    wire {x}_up = {};\n    wire {x}_down = {};\n    \
         wire signed [{k1}:0] {x}_key = {x}_up ? {kw}'sd{max} : {x}_down ? -{kw}'sd{max} : value({x});\n",
        is_nan(fmt, x),
        is_inf(fmt, x, false),
        is_inf(fmt, x, true),
        k1 = kw - 1,
        max = (1u64 << (kw - 1)) - 1,
    )
}

/// The module `<unit>_lemmas_e<E>m<F>`: from the ray/box inputs and the
/// unit's per-axis results, `bounded_<a>` per axis and `meet` (module doc;
/// the silhouette's, [`silhouette_terms`]).
pub(super) fn lemma_module(fmt: FloatFormat, u: &AxisUnit) -> (String, String) {
    let (e, f) = (fmt.exp_bits(), fmt.frac_bits());
    let w = fmt.width();
    let name = format!("{}_lemmas_e{e}m{f}", u.name);
    let nw = magnitude_bits(fmt) + 1;
    let dw = nw + 2;
    let pw = 2 * dw;
    let results = u.ports();
    let mut v = String::new();
    let _ = writeln!(
        v,
        "// Generated by rtl-gen prove --split: the {}'s soundness lemmas for e{e}m{f}.\n\
         `default_nettype none\nmodule {name} (\n    input wire [{w1}:0] {},\n    \
         input wire [{w1}:0] {},\n    output wire bounded_x, bounded_y, bounded_z, meet{}\n);",
        u.name,
        RAY_BOX_PORTS.join(", "),
        results.join(", "),
        u.tests
            .iter()
            .map(|t| format!(", holds_{t}"))
            .chain((!u.tests.is_empty()).then(|| ", basic".to_string()))
            .collect::<String>(),
        w1 = w - 1
    );
    v.push_str(&decode_functions(fmt, "mag", "value", nw));
    // the reference's own per-axis terms (enter_a_n, exit_a_n, den_a, ...)
    let _ = box_bounds(&mut v, fmt, dw, false);
    for x in results.iter().map(String::as_str).chain(["t_min", "t_max"]) {
        v.push_str(&extended_real(fmt, x));
    }
    if u.name == SILHOUETTE.name {
        silhouette_terms(&mut v, fmt, pw);
        return (name, v);
    }
    for a in AXES {
        let _ = writeln!(
            v,
            "    // t_near ≤ enter_n/den, t_far ≥ exit_n/den, cross-multiplied (t = N/t_den)\n    \
             wire signed [{p1}:0] near_by_den_{a} = t_near_{a}_key * den_{a};\n    \
             wire signed [{p1}:0] far_by_den_{a} = t_far_{a}_key * den_{a};\n    \
             wire signed [{p1}:0] enter_by_t_den_{a} = enter_{a}_n * t_den;\n    \
             wire signed [{p1}:0] exit_by_t_den_{a} = exit_{a}_n * t_den;\n    \
             wire metable_{a} = inside_{a} && pmin_{a} <= pmax_{a};\n    \
             assign bounded_{a} = !metable_{a} || (!t_near_{a}_nan && !t_far_{a}_nan && (d_{a}_zero\n        \
             ? (t_near_{a}_down && t_far_{a}_up)\n        \
             : ((t_near_{a}_down || (!t_near_{a}_up && near_by_den_{a} <= enter_by_t_den_{a}))\n           \
             && (t_far_{a}_up || (!t_far_{a}_down && far_by_den_{a} >= exit_by_t_den_{a})))));",
            p1 = pw - 1
        );
    }
    let lower: Vec<String> = std::iter::once("t_min".to_string())
        .chain(AXES.iter().map(|a| format!("t_near_{a}")))
        .collect();
    let upper: Vec<String> = std::iter::once("t_max".to_string())
        .chain(AXES.iter().map(|a| format!("t_far_{a}")))
        .collect();
    let mut meet: Vec<String> = lower
        .iter()
        .chain(&upper)
        .map(|x| format!("!{x}_nan"))
        .collect();
    meet.extend(lower.iter().map(|x| format!("!{x}_up")));
    meet.extend(upper.iter().map(|x| format!("!{x}_down")));
    for l in &lower {
        for u in &upper {
            meet.push(format!("{l}_key <= {u}_key"));
        }
    }
    let _ = writeln!(
        v,
        "    // the unit's intervals meet as extended reals\n    assign meet = {};\nendmodule",
        meet.join("\n        && ")
    );
    (name, v)
}

/// The silhouette ray tester's lemmas (the unit's axis gives `n ≤` the
/// entry numerator, `x ≥` the exit numerator, in the units of the decoded
/// values, and `a = |d|`; its tests compare them, docs/silhouette.md):
///
/// * **bounded_a**: with ordered corners, `n`, `x` not NaN, `a = |d|`, and
///   `n ≤ enter_n`, `x ≥ exit_n` (`d ≠ 0`; the reference's numerators), or
///   `n ≤ 0 ≤ x` when `d = 0` and the origin is inside the slab;
/// * **meet**: what a real `t` in `[t_min, t_max]` with `n_i ≤ t·a_i ≤ x_i`
///   on every axis implies, in products of finite values only: no NaN,
///   `a = |d|`, ordered corners, `t_min ≤ t_max` (neither infinite the wrong way), no
///   `n_i = +∞` nor `x_i = −∞`, `n_i ≤ 0 ≤ x_i` where `a_i = 0`, `n_i·a_j ≤
///   x_j·a_i` (i ≠ j), `n_i ≤ t_max·a_i`, `t_min·a_i ≤ x_i` (each where its
///   factors are finite).
///
/// An exact hit gives such a `t` (by bounded_a, `n_i ≤ enter_i ≤ t·|d_i| ≤
/// exit_i ≤ x_i`), and every conjunct of meet follows from it by
/// multiplying with the non-negative `a`.
fn silhouette_terms(v: &mut String, fmt: FloatFormat, pw: u32) {
    let w = fmt.width();
    for a in AXES {
        let _ = writeln!(
            v,
            "    assign bounded_{a} = !(pmin_{a} <= pmax_{a}) || (!n_{a}_nan && !x_{a}_nan\n        \
             && a_{a} == {{1'b0, d_{a}[{w2}:0]}} && (d_{a}_zero\n        \
             ? (!inside_{a} || (n_{a}_key <= 0 && x_{a}_key >= 0))\n        \
             : (n_{a}_key <= enter_{a}_n && x_{a}_key >= exit_{a}_n)));",
            w2 = w - 2
        );
    }
    // the conjuncts without products (`basic`), then one per test of the unit
    let mut basic = vec![
        "!t_min_nan && !t_max_nan && !t_min_up && !t_max_down && t_min_key <= t_max_key"
            .to_string(),
    ];
    let mut holds = Vec::new();
    let p1 = pw - 1;
    for i in AXES {
        basic.push(format!(
            "pmin_{i} <= pmax_{i} && a_{i} == {{1'b0, d_{i}[{w2}:0]}} && !n_{i}_nan && !x_{i}_nan && !n_{i}_up && !x_{i}_down",
            w2 = w - 2
        ));
        basic.push(format!(
            "(a_{i}[{w2}:0] != 0 || (n_{i}_key <= 0 && x_{i}_key >= 0))",
            w2 = w - 2
        ));
        let _ = writeln!(
            v,
            "    wire signed [{p1}:0] n_{i}_by_t_den = n_{i}_key * t_den;\n    \
             wire signed [{p1}:0] x_{i}_by_t_den = x_{i}_key * t_den;\n    \
             wire signed [{p1}:0] t_max_by_a_{i} = t_max_key * a_{i}_key;\n    \
             wire signed [{p1}:0] t_min_by_a_{i} = t_min_key * a_{i}_key;"
        );
        holds.push((
            format!("dist_{i}"),
            format!("n_{i}_down || t_max_up || n_{i}_by_t_den <= t_max_by_a_{i}"),
        ));
        holds.push((
            format!("dir_{i}"),
            format!("x_{i}_up || t_min_down || t_min_by_a_{i} <= x_{i}_by_t_den"),
        ));
        for j in AXES.iter().filter(|j| **j != i) {
            let _ = writeln!(
                v,
                "    wire signed [{p1}:0] n_{i}_by_a_{j} = n_{i}_key * a_{j}_key;\n    \
                 wire signed [{p1}:0] x_{j}_by_a_{i} = x_{j}_key * a_{i}_key;"
            );
            holds.push((
                format!("edge_{i}{j}"),
                format!("n_{i}_down || x_{j}_up || n_{i}_by_a_{j} <= x_{j}_by_a_{i}"),
            ));
        }
    }
    let _ = writeln!(
        v,
        "    // what a real t with n_i ≤ t·a_i ≤ x_i in [t_min, t_max] implies\n    \
         assign basic = {};",
        basic.join("\n        && ")
    );
    for (test, h) in &holds {
        let _ = writeln!(v, "    assign holds_{test} = {h};");
    }
    let all: Vec<String> = holds.iter().map(|(t, _)| format!("holds_{t}")).collect();
    let _ = writeln!(
        v,
        "    assign meet = basic && {};\nendmodule",
        all.join(" && ")
    );
}

/// The wrapper's part for the lemmas: the per-axis results as wires the
/// script drives (from the unit, or free where it cuts the unit), the lemma
/// module, and each lemma as one signal ([`AxisUnit::cut`]).
pub(super) fn wrapper_part(fmt: FloatFormat, u: &AxisUnit) -> String {
    let (name, _) = lemma_module(fmt, u);
    let w = fmt.width();
    let mut conns: Vec<String> = RAY_BOX_PORTS.iter().map(|p| format!(".{p}({p})")).collect();
    let mut v = String::from(
        "    // --split: the unit's per-axis results, driven by the proof script (prove.ys)\n",
    );
    for r in u.ports() {
        let _ = writeln!(v, "    (* keep *) wire [{}:0] {r};", w - 1);
        conns.push(format!(".{r}({r})"));
    }
    // per test of the unit: its `ok` (watched on the cut design) follows from
    // its own part of `meet`; the combination then from every `ok`
    let mut oks = vec!["lemma_meet".to_string()];
    if !u.tests.is_empty() {
        let _ = writeln!(v, "    (* keep *) wire lemma_basic;");
        conns.push(".basic(lemma_basic)".into());
    }
    for t in u.tests {
        let _ = writeln!(
            v,
            "    (* keep *) wire test_{t}_ok, lemma_holds_{t};\n    \
             (* keep *) wire lemma_test_{t} = !(lemma_basic && lemma_holds_{t}) || test_{t}_ok;"
        );
        conns.push(format!(".holds_{t}(lemma_holds_{t})"));
        oks.push(format!("test_{t}_ok"));
    }
    let _ = writeln!(
        v,
        "    (* keep *) wire lemma_bounded_x, lemma_bounded_y, lemma_bounded_z, lemma_meet;\n    \
         {name} u_lemmas ({}, .bounded_x(lemma_bounded_x), .bounded_y(lemma_bounded_y), \
         .bounded_z(lemma_bounded_z), .meet(lemma_meet));\n    \
         (* keep *) wire lemma_combine = !({}) || unit_hit;",
        conns.join(", "),
        oks.join(" && ")
    );
    v
}

/// The Yosys commands after the covers (the flattened wrapper saved as
/// `proof`): the bounds with the watching wires connected from the unit's
/// (and the cover of an exact hit where the lemmas' `lemma_meet` holds),
/// then the combination with the unit's wires driven by them instead
/// (free: nothing else drives them), each lemma its own `sat` call.
pub(super) fn script(cut: &Cut) -> String {
    if !cut.stages.is_empty() {
        return staged_script(cut);
    }
    let mut s = String::from(
        "# the lemmas (prove_sound/split.rs): bounds on the unit's own results\ndesign -load proof\n",
    );
    for (monitor, unit) in &cut.wires {
        let _ = writeln!(s, "connect -set {monitor} {unit}");
    }
    // reachable: an exact hit where the unit's own results meet (the
    // combination's hypothesis, not vacuous)
    let _ = writeln!(s, "sat -set-assumes {}", cut.cover);
    let (bounds, combination) = cut.lemmas.split_at(cut.lemmas.len() - cut.combination);
    for lemma in bounds {
        let _ = writeln!(s, "sat -set-assumes -prove {lemma} 1 -show-inputs");
    }
    s += "# the combination over free (cut) results\ndesign -load proof\n";
    for (monitor, unit) in &cut.wires {
        let _ = writeln!(s, "connect -set {unit} {monitor}");
    }
    for (monitor, unit) in &cut.watched_after_cut {
        let _ = writeln!(s, "connect -set {monitor} {unit}");
    }
    s += "opt_clean\n";
    for lemma in combination {
        let _ = writeln!(s, "sat -set-assumes -prove {lemma} 1 -show-inputs");
    }
    s
}

/// Each lemma's result in the log of [`script`] (Yosys sat's lines, in
/// the cut's order): `Some(true)` proved, `Some(false)` refuted, `None`
/// not reached.
fn results(log: &str, cut: &Cut) -> Vec<Option<bool>> {
    if !cut.stages.is_empty() {
        return staged_results(log, cut);
    }
    let mut found = log.lines().filter_map(|l| {
        if l.contains("SAT proof finished - no model found: SUCCESS!") {
            Some(true)
        } else if l.contains("SAT proof finished - model found: FAIL!") {
            Some(false)
        } else {
            None
        }
    });
    cut.lemmas.iter().map(|_| found.next()).collect()
}

/// [`results`] of a staged cut: each lemma's calls follow its marker
/// (`@lemma NAME CALLS`); proved when all its calls are, refuted when one is.
fn staged_results(log: &str, cut: &Cut) -> Vec<Option<bool>> {
    let mut by_lemma: Vec<(String, usize, usize, bool)> = Vec::new();
    for l in log.lines() {
        if let Some(rest) = l.strip_prefix("@lemma ") {
            let mut w = rest.split_whitespace();
            let (Some(name), Some(calls)) = (w.next(), w.next().and_then(|c| c.parse().ok()))
            else {
                continue;
            };
            by_lemma.push((name.to_string(), calls, 0, false));
        } else if let Some(last) = by_lemma.last_mut() {
            if l.contains("SAT proof finished - no model found: SUCCESS!") {
                last.2 += 1;
            } else if l.contains("SAT proof finished - model found: FAIL!") {
                last.3 = true;
            }
        }
    }
    cut.lemmas
        .iter()
        .map(|name| {
            let (_, calls, proved, failed) = by_lemma.iter().find(|(n, ..)| n == name)?;
            if *failed {
                Some(false)
            } else if proved == calls {
                Some(true)
            } else {
                None
            }
        })
        .collect()
}

/// Proved when every lemma is; a refuted lemma is no counterexample of the
/// property (a lemma is stronger than what the property needs), so it
/// leaves the verdict open, explained by [`summary`].
pub(super) fn verdict(log: &str, cut: &Cut) -> crate::prove::Verdict {
    if results(log, cut).iter().all(|r| *r == Some(true)) {
        crate::prove::Verdict::Proved
    } else {
        crate::prove::Verdict::Open
    }
}

/// One line per lemma: `lemma_bounded_x proved, ...`.
pub(super) fn summary(log: &str, cut: &Cut) -> String {
    cut.lemmas
        .iter()
        .zip(results(log, cut))
        .map(|(l, r)| {
            let r = match r {
                Some(true) => "proved",
                Some(false) => "refuted (its inputs in the log; run without --split for the property's own verdict)",
                None => "not reached",
            };
            format!("{l} {r}")
        })
        .collect::<Vec<_>>()
        .join(", ")
}
