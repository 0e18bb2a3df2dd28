//! `rtl-gen prove --property sound` (issue 39): a conservative box tester
//! never reports a miss for a ray that truly meets the box, proved for every
//! input of a small float format. The reference is an exact ray/box test
//! written in Verilog ([`exact_reference`]): every float decoded to an
//! integer of one fixed-point scale, the segment's parameter bounds compared
//! as fractions by cross-multiplication, no division and no rounding. It is
//! checked against the Rust exact reference (`golden_model::exact::ray_box`)
//! by simulation in Icarus Verilog before any proof uses it
//! ([`check_reference`]), so that a wrong reference cannot prove a wrong unit.
//!
//! The unit is proved at `stages=0`; `--property equiv` carries the result
//! to every pipeline of it. Units: `silhouette` (`mode=ray`, the ray's
//! direction `d` is its input) and `slab` (`rounding=conservative`: its input
//! is `inv_d`, constrained to `RTZ(1/d)` of a free direction `d` by
//! cross-multiplication, the unit's input contract).

use golden_model::cull::exact::{region_hit, RegionIn};
use golden_model::exact::ray_box::{ray_hits_box, BoxIn, RayIn};
use golden_model::float::FloatFormat;
use rtl_flow::Generated;
use std::fmt::Write as _;
use std::path::Path;
use std::process::Command;

mod bundle_split;
mod node_split;
mod split;
mod triangle;

/// The reference's inputs, in port order (the box, the ray, the segment).
const RAY_BOX_PORTS: [&str; 14] = [
    "p_min_x", "p_min_y", "p_min_z", "p_max_x", "p_max_y", "p_max_z", "o_x", "o_y", "o_z", "d_x",
    "d_y", "d_z", "t_min", "t_max",
];

/// The axes' suffixes, in port order.
const AXES: [&str; 3] = ["x", "y", "z"];

/// Bits of the magnitude integer of a finite value: `value = ±M·2^(1 − bias − F)`,
/// `M < 2^(F + 1 + emax_biased − 1)`.
fn magnitude_bits(fmt: FloatFormat) -> u32 {
    fmt.frac_bits() + 1 + ((1u32 << fmt.exp_bits()) - 3)
}

/// The Verilog functions `<mag>(x)`, the magnitude of a finite value `x` of
/// `fmt` as an unsigned integer `M` of [`magnitude_bits`] (`|x| = M·2^(1 −
/// bias − F)`), and `<value>(x)`, the signed value `±M`, `nw` bits wide.
fn decode_functions(fmt: FloatFormat, mag: &str, value: &str, nw: u32) -> String {
    let (w, f) = (fmt.width(), fmt.frac_bits());
    format!(
        "    function [{}:0] {mag};\n        input [{}:0] x;\n        \
         begin\n            if (x[{}:{f}] == 0) {mag} = x[{}:0];\n            \
         else {mag} = {{1'b1, x[{}:0]}} << (x[{}:{f}] - 1);\n        end\n    endfunction\n\
         \x20   // a finite value as a signed integer in units of 2^{}\n    \
         function signed [{}:0] {value};\n        input [{}:0] x;\n        \
         {value} = x[{}] ? -$signed({{1'b0, {mag}(x)}}) : $signed({{1'b0, {mag}(x)}});\n    endfunction\n",
        magnitude_bits(fmt) - 1,
        w - 1,
        w - 2,
        f - 1,
        f - 1,
        w - 2,
        1 - fmt.bias() - f as i32,
        nw - 1,
        w - 1,
        w - 1,
    )
}

/// `(x is NaN or ±∞)`: the exponent field all ones.
fn exp_ones(fmt: FloatFormat, x: &str) -> String {
    format!(
        "({x}[{}:{}] == {{{}{{1'b1}}}})",
        fmt.width() - 2,
        fmt.frac_bits(),
        fmt.exp_bits()
    )
}

/// `(x is NaN)`.
fn is_nan(fmt: FloatFormat, x: &str) -> String {
    format!(
        "({} && {x}[{}:0] != 0)",
        exp_ones(fmt, x),
        fmt.frac_bits() - 1
    )
}

/// `(x is ±∞)` with the sign `neg`.
fn is_inf(fmt: FloatFormat, x: &str, neg: bool) -> String {
    format!("({x} == {}'h{:x})", fmt.width(), fmt.inf(neg))
}

/// A bound `num / den` (`den > 0`) on the segment parameter, in force while
/// `active`: the names of three Verilog expressions.
#[derive(Clone)]
struct Bound {
    active: String,
    num: String,
    den: String,
}

impl Bound {
    fn new(active: impl Into<String>, num: impl Into<String>, den: impl Into<String>) -> Bound {
        Bound {
            active: active.into(),
            num: num.into(),
            den: den.into(),
        }
    }
}

/// The ray/box part of every exact reference, emitted into `v` (inputs
/// `p_min_*`, `p_max_*`, `o_*`, `d_*`, `t_min`, `t_max` of `fmt` decoded by
/// `value`, `dw`-bit signed wires): the lower and upper bounds on `t` (the
/// segment's ends, per axis the entry and exit `(plane − o)/|d|`) and the
/// conditions a hit needs besides their order (finite ends, a parallel
/// axis's origin inside its slab, ordered corners). `t = N / t_den` with
/// `N` in units of the smallest subnormal.
///
/// `decoded`: the box comes as signed `dw`-bit integers `pmin_*`, `pmax_*` in
/// those units (declared by the caller), not as floats `p_min_*`, `p_max_*`.
fn box_bounds(
    v: &mut String,
    fmt: FloatFormat,
    dw: u32,
    decoded: bool,
) -> (Vec<Bound>, Vec<Bound>, Vec<String>) {
    let t_shift = fmt.bias() + fmt.frac_bits() as i32 - 1;
    let _ = writeln!(
        v,
        "    wire t_min_pos_inf = {};\n    wire t_min_neg_inf = {};\n    \
         wire t_max_pos_inf = {};\n    wire t_max_neg_inf = {};",
        is_inf(fmt, "t_min", false),
        is_inf(fmt, "t_min", true),
        is_inf(fmt, "t_max", false),
        is_inf(fmt, "t_max", true)
    );
    let mut lower = vec![Bound::new("!t_min_neg_inf", "tmin_n", "t_den")];
    let mut upper = vec![Bound::new("!t_max_pos_inf", "tmax_n", "t_den")];
    let _ = writeln!(
        v,
        "    wire signed [{dw1}:0] t_den = {dw}'sd{};\n    \
         wire signed [{dw1}:0] tmin_n = value(t_min);\n    wire signed [{dw1}:0] tmax_n = value(t_max);",
        1u64 << t_shift,
        dw1 = dw - 1,
    );
    let mut conds = vec!["!t_min_pos_inf".to_string(), "!t_max_neg_inf".to_string()];
    for a in AXES {
        if !decoded {
            let _ = writeln!(
                v,
                "    wire signed [{dw1}:0] pmin_{a} = value(p_min_{a});\n    \
                 wire signed [{dw1}:0] pmax_{a} = value(p_max_{a});",
                dw1 = dw - 1
            );
        }
        let _ = writeln!(
            v,
            "    wire signed [{dw1}:0] o_{a}_v = value(o_{a});\n    \
             wire signed [{dw1}:0] d_{a}_v = value(d_{a});\n    \
             wire d_{a}_pos = d_{a}_v > 0;\n    wire d_{a}_zero = d_{a}_v == 0;\n    \
             wire signed [{dw1}:0] enter_{a}_n = d_{a}_pos ? pmin_{a} - o_{a}_v : o_{a}_v - pmax_{a};\n    \
             wire signed [{dw1}:0] exit_{a}_n = d_{a}_pos ? pmax_{a} - o_{a}_v : o_{a}_v - pmin_{a};\n    \
             wire signed [{dw1}:0] den_{a} = d_{a}_pos ? d_{a}_v : -d_{a}_v;\n    \
             // a parallel slab keeps the segment iff the origin is inside it\n    \
             wire inside_{a} = !d_{a}_zero || (pmin_{a} <= o_{a}_v && o_{a}_v <= pmax_{a});",
            dw1 = dw - 1
        );
        lower.push(Bound::new(
            format!("!d_{a}_zero"),
            format!("enter_{a}_n"),
            format!("den_{a}"),
        ));
        upper.push(Bound::new(
            format!("!d_{a}_zero"),
            format!("exit_{a}_n"),
            format!("den_{a}"),
        ));
        conds.push(format!("inside_{a}"));
        conds.push(format!("(pmin_{a} <= pmax_{a})"));
    }
    (lower, upper, conds)
}

/// Every lower bound at most every upper bound (`na/da ≤ nb/db` as `na·db ≤
/// nb·da`, `pw`-bit products; pairs `(i, j)` with `skip(i, j)` left out),
/// emitted into `v` as `ordered<tag>_<i>_<j>`; their names.
fn ordered_pairs(
    v: &mut String,
    lower: &[Bound],
    upper: &[Bound],
    pw: u32,
    tag: &str,
    skip: impl Fn(usize, usize) -> bool,
) -> Vec<String> {
    let mut names = Vec::new();
    for (i, l) in lower.iter().enumerate() {
        for (j, u) in upper.iter().enumerate() {
            if skip(i, j) {
                continue;
            }
            let _ = writeln!(
                v,
                "    wire signed [{p1}:0] lhs{tag}_{i}_{j} = {} * {};\n    \
                 wire signed [{p1}:0] rhs{tag}_{i}_{j} = {} * {};\n    \
                 wire ordered{tag}_{i}_{j} = !({}) || !({}) || lhs{tag}_{i}_{j} <= rhs{tag}_{i}_{j};",
                l.num,
                u.den,
                u.num,
                l.den,
                l.active,
                u.active,
                p1 = pw - 1
            );
            names.push(format!("ordered{tag}_{i}_{j}"));
        }
    }
    names
}

/// The exact reference `exact_ray_box_e<E>m<F>`: `hit` iff some `t` in
/// `[t_min, t_max]` puts `o + t·d` in the closed box, for inputs without NaN,
/// `o`, `d` and the box finite (`t_min`, `t_max` may be infinite).
pub fn exact_reference(fmt: FloatFormat) -> (String, String) {
    let (e, f) = (fmt.exp_bits(), fmt.frac_bits());
    let w = fmt.width();
    let name = format!("exact_ray_box_e{e}m{f}");
    let nw = magnitude_bits(fmt) + 1; // signed value
    let dw = nw + 2; // differences and denominators
    let mut v = String::new();
    let _ = writeln!(
        v,
        "// Generated by rtl-gen prove: the exact ray/box reference for e{e}m{f} (no rounding).\n\
         `default_nettype none\nmodule {name} (\n    input wire [{}:0] p_min_x, p_min_y, p_min_z, p_max_x, p_max_y, p_max_z,\n    \
         input wire [{}:0] o_x, o_y, o_z, d_x, d_y, d_z, t_min, t_max,\n    output wire hit\n);",
        w - 1,
        w - 1
    );
    v.push_str(&decode_functions(fmt, "mag", "value", nw));
    let (lower, upper, mut conds) = box_bounds(&mut v, fmt, dw, false);
    conds.extend(ordered_pairs(&mut v, &lower, &upper, 2 * dw, "", |_, _| {
        false
    }));
    let _ = writeln!(
        v,
        "    assign hit = {};\nendmodule",
        conds.join("\n        && ")
    );
    (name, v)
}

/// The formats and plane count of a cull reference.
#[derive(Debug, Clone, Copy)]
pub struct CullFormats {
    /// rays, boxes, `t`, `no_lo`, `b_lo` and the reciprocals (the crossing
    /// format is the ray format at these sizes)
    pub ray: FloatFormat,
    /// normals and distances
    pub plane: FloatFormat,
    /// planes
    pub k: usize,
}

impl CullFormats {
    /// Signed width of a decoded ray-format value.
    fn nw(&self) -> u32 {
        magnitude_bits(self.ray) + 1
    }
    /// Signed width of the plane terms `n·(o − r)`, `n·d`, `w` (units of
    /// both formats' smallest subnormals multiplied).
    fn pdw(&self) -> u32 {
        magnitude_bits(self.plane) + magnitude_bits(self.ray) + 6
    }
    /// A ray-format value in units of 2^(1 − bias − F) times this is in the
    /// plane terms' units.
    fn ray_to_term_shift(&self) -> i32 {
        self.plane.bias() + self.plane.frac_bits() as i32 - 1
    }
    /// The ports of the geometry, in order: the ray/box inputs, then the
    /// reference point `r` (ray format), the normals `n<j>_*` and the
    /// distances `w<j>` (plane format); with their formats.
    fn geometry(&self) -> Vec<(String, FloatFormat)> {
        let mut p: Vec<(String, FloatFormat)> = RAY_BOX_PORTS
            .iter()
            .map(|n| (n.to_string(), self.ray))
            .collect();
        p.extend(AXES.iter().map(|a| (format!("r_{a}"), self.ray)));
        for j in 0..self.k {
            p.extend(AXES.iter().map(|a| (format!("n{j}_{a}"), self.plane)));
        }
        p.extend((0..self.k).map(|j| (format!("w{j}"), self.plane)));
        p
    }
}

/// The body of the exact region reference (its ports declared by the
/// caller, [`CullFormats::geometry`]): the segment meets the closed box
/// intersected with every plane's non-empty side `n<j>·(x − r) ≤ w<j>`
/// (`golden_model::cull::exact::region_hit`). Per plane `A = n·(o − r) − w`
/// and `B = n·d`, exact (wires `no_<j>` = `n·(o − r)`, `b_<j>`); the points
/// of the line on the non-empty side are `t ≤ −A/B` (`B > 0`), `t ≥ A/|B|`
/// (`B < 0`), all (`B = 0`, `A ≤ 0`) or none. Assigns `exact_box_hit` and
/// `exact_hit`; returns the box's lower and upper bounds (for the contract
/// on the slab's interval).
fn region_body(v: &mut String, c: CullFormats) -> (Vec<Bound>, Vec<Bound>) {
    let (fmt, pf) = (c.ray, c.plane);
    let nw = c.nw();
    let dw = nw + 2;
    let pdw = c.pdw();
    v.push_str(&decode_functions(fmt, "mag", "value", nw));
    v.push_str(&decode_functions(
        pf,
        "mag_p",
        "value_p",
        magnitude_bits(pf) + 1,
    ));
    let (box_lower, box_upper, mut box_conds) = box_bounds(v, fmt, dw, false);
    box_conds.extend(ordered_pairs(
        v,
        &box_lower,
        &box_upper,
        2 * dw,
        "",
        |_, _| false,
    ));
    let _ = writeln!(
        v,
        "    (* keep *) wire exact_box_hit = {};",
        box_conds.join("\n        && ")
    );
    let (mut lower, mut upper) = (Vec::new(), Vec::new());
    let mut conds = vec!["exact_box_hit".to_string()];
    // w in units of the plane terms: w·2^(bias + F − 1)
    let w_shift = fmt.bias() + fmt.frac_bits() as i32 - 1;
    for j in 0..c.k {
        let dot = |x: &str| {
            AXES.iter()
                .map(|a| format!("value_p(n{j}_{a}) * {x}_{a}"))
                .collect::<Vec<_>>()
                .join(" + ")
        };
        let _ = writeln!(
            v,
            "    // plane {j}: n·(o − r), n·d and A = n·(o − r) − w, exact\n    \
             wire signed [{p1}:0] u{j}_x = o_x_v - value(r_x);\n    \
             wire signed [{p1}:0] u{j}_y = o_y_v - value(r_y);\n    \
             wire signed [{p1}:0] u{j}_z = o_z_v - value(r_z);\n    \
             wire signed [{p1}:0] dw{j}_x = d_x_v;\n    \
             wire signed [{p1}:0] dw{j}_y = d_y_v;\n    \
             wire signed [{p1}:0] dw{j}_z = d_z_v;\n    \
             (* keep *) wire signed [{p1}:0] no_{j} = {};\n    \
             (* keep *) wire signed [{p1}:0] b_{j} = {};\n    \
             wire signed [{p1}:0] w{j}_v = value_p(w{j});\n    \
             wire signed [{p1}:0] a_{j} = no_{j} - (w{j}_v <<< {w_shift});\n    \
             wire signed [{p1}:0] minus_a_{j} = -a_{j};\n    \
             wire b_{j}_pos = b_{j} > 0;\n    wire b_{j}_zero = b_{j} == 0;\n    \
             wire signed [{p1}:0] den_p{j} = b_{j}_pos ? b_{j} : -b_{j};\n    \
             // parallel: the line is on the non-empty side iff the origin is\n    \
             wire side_{j} = !b_{j}_zero || a_{j} <= 0;",
            dot(&format!("u{j}")),
            dot(&format!("dw{j}")),
            p1 = pdw - 1
        );
        // B < 0: t ≥ A/|B|; B > 0: t ≤ −A/B
        lower.push(Bound::new(
            format!("!b_{j}_pos && !b_{j}_zero"),
            format!("a_{j}"),
            format!("den_p{j}"),
        ));
        upper.push(Bound::new(
            format!("b_{j}_pos"),
            format!("minus_a_{j}"),
            format!("den_p{j}"),
        ));
        conds.push(format!("side_{j}"));
    }
    // the planes' bounds against each other and against the box's (the box's
    // among themselves are in exact_box_hit)
    let (nb_lo, nb_hi) = (box_lower.len(), box_upper.len());
    let mut all_lower = box_lower.clone();
    all_lower.extend(lower);
    let mut all_upper = box_upper.clone();
    all_upper.extend(upper);
    conds.extend(ordered_pairs(
        v,
        &all_lower,
        &all_upper,
        2 * pdw,
        "_region",
        |i, j| i < nb_lo && j < nb_hi,
    ));
    let _ = writeln!(
        v,
        "    (* keep *) wire exact_hit = {};",
        conds.join("\n        && ")
    );
    (box_lower, box_upper)
}

/// The exact region reference `exact_region_e<E>m<F>_pe<Ep>m<Fp>_k<K>`
/// ([`region_body`]) as a module, outputs `box_hit` and `hit`: what
/// [`check_region_reference`] simulates.
pub fn exact_region_reference(c: CullFormats) -> (String, String) {
    let name = format!(
        "exact_region_e{}m{}_pe{}m{}_k{}",
        c.ray.exp_bits(),
        c.ray.frac_bits(),
        c.plane.exp_bits(),
        c.plane.frac_bits(),
        c.k
    );
    let mut v = String::new();
    let ports: Vec<String> = c
        .geometry()
        .iter()
        .map(|(n, f)| format!("input wire [{}:0] {n}", f.width() - 1))
        .collect();
    let _ = writeln!(
        v,
        "// Generated by rtl-gen prove: the exact ray/box/planes reference (no rounding).\n\
         `default_nettype none\nmodule {name} (\n    {},\n    output wire box_hit,\n    output wire hit\n);",
        ports.join(",\n    ")
    );
    region_body(&mut v, c);
    v.push_str("    assign box_hit = exact_box_hit;\n    assign hit = exact_hit;\nendmodule\n");
    (name, v)
}

/// The widths of the node's outputs the entry bound reads.
#[derive(Debug, Clone, Copy)]
pub struct NodeEntry {
    /// bits of `out<j>_entry`
    pub entry_bits: u32,
    /// bits of the signed `grid_exp`
    pub grid_bits: u32,
}

/// The exact reference of one child of a node, `exact_node_child_e<E>m<F>_q<q>`:
/// `hit` iff some `t` in `[max(t_min, t_start), t_max]` puts `o + t·d` in
/// the closed box `frame_origin + [lo, hi]·2^frame_exp` (the child box as
/// the node record encodes it, decoded exactly), for inputs without NaN,
/// `o`, `d` and the frame finite, `frame_exp` in `emin ..= emax`; and
/// `entry_ok` iff the unit's entry for the child (`t_base`, `grid_exp`,
/// `entry`) is a lower bound of where the segment enters the box: `entry = 0`,
/// or `t_base + entry·2^grid_exp` at most the entry parameter of an axis the
/// ray is not parallel to (the entry is the largest of those and the start,
/// and `t_base` is the start).
pub fn exact_node_child_reference(fmt: FloatFormat, q: u32, out: NodeEntry) -> (String, String) {
    let (e, f) = (fmt.exp_bits(), fmt.frac_bits());
    let w = fmt.width();
    let name = format!(
        "exact_node_child_e{e}m{f}_q{q}_k{}_g{}",
        out.entry_bits, out.grid_bits
    );
    let nw = magnitude_bits(fmt) + 1;
    let dw = node_child_width(fmt, q);
    // a step 2^frame_exp in units of 2^(1 − bias − F): a left shift by frame_exp + bias + F − 1
    let step_shift = fmt.bias() + f as i32 - 1;
    let mut v = String::new();
    let _ = writeln!(
        v,
        "// Generated by rtl-gen prove: the exact ray/child-box reference of the node, e{e}m{f}, q = {q} (no rounding).\n\
         `default_nettype none\nmodule {name} (\n    input wire [{w1}:0] frame_origin_x, frame_origin_y, frame_origin_z,\n    \
         input wire signed [{e1}:0] frame_exp_x, frame_exp_y, frame_exp_z,\n    \
         input wire [{q1}:0] lo_x, lo_y, lo_z, hi_x, hi_y, hi_z,\n    \
         input wire [{w1}:0] o_x, o_y, o_z, d_x, d_y, d_z, t_min, t_start, t_max,\n    \
         input wire [{w1}:0] t_base,\n    input wire signed [{g1}:0] grid_exp,\n    \
         input wire [{k1}:0] entry,\n    output wire hit,\n    output wire entry_ok\n);",
        w1 = w - 1,
        e1 = e - 1,
        q1 = q - 1,
        g1 = out.grid_bits - 1,
        k1 = out.entry_bits - 1,
    );
    v.push_str(&decode_functions(fmt, "mag", "value", nw));
    for a in AXES {
        let _ = writeln!(
            v,
            "    wire signed [7:0] step_shift_{a} = frame_exp_{a} + 8'sd{step_shift};\n    \
             wire signed [{dw1}:0] origin_{a} = value(frame_origin_{a});\n    \
             wire signed [{dw1}:0] pmin_{a} = origin_{a} + ({{{pad}'d0, lo_{a}}} << step_shift_{a});\n    \
             wire signed [{dw1}:0] pmax_{a} = origin_{a} + ({{{pad}'d0, hi_{a}}} << step_shift_{a});",
            dw1 = dw - 1,
            pad = dw - q,
        );
    }
    let (mut lower, upper, mut conds) = box_bounds(&mut v, fmt, dw, true);
    let _ = writeln!(
        v,
        "    wire t_start_pos_inf = {};\n    wire t_start_neg_inf = {};\n    \
         wire signed [{}:0] tstart_n = value(t_start);",
        is_inf(fmt, "t_start", false),
        is_inf(fmt, "t_start", true),
        dw - 1
    );
    lower.push(Bound::new("!t_start_neg_inf", "tstart_n", "t_den"));
    conds.push("!t_start_pos_inf".into());
    conds.extend(ordered_pairs(&mut v, &lower, &upper, 2 * dw, "", |_, _| {
        false
    }));
    // the entry bound, in units of 2^−lg: 2^(grid_exp + lg) is an integer for every grid_exp
    let t_shift = fmt.bias() + f as i32 - 1;
    let lg = (1i32 << (out.grid_bits - 1)).max(t_shift);
    let g_top = (1u32 << (out.grid_bits - 1)) - 1 + lg as u32;
    let xw = (nw + (lg - t_shift) as u32).max(out.entry_bits + g_top) + 2;
    let pw = xw + dw;
    let _ = writeln!(
        v,
        "    // (t_base + entry·2^grid_exp)·2^{lg}\n    \
         wire signed [{x1}:0] base_x = $signed(value(t_base)) <<< {};\n    \
         wire signed [7:0] entry_shift = grid_exp + 8'sd{lg};\n    \
         wire [{x1}:0] entry_x = {{{}'d0, entry}} << entry_shift;\n    \
         wire signed [{x1}:0] bound_x = base_x + $signed(entry_x);",
        lg - t_shift,
        xw - out.entry_bits,
        x1 = xw - 1,
    );
    let mut above = Vec::new();
    for a in AXES {
        let _ = writeln!(
            v,
            "    wire signed [{p1}:0] enter_{a}_x = enter_{a}_n;\n    \
             wire signed [{p1}:0] bound_{a}_x = bound_x * den_{a};\n    \
             wire above_{a} = !d_{a}_zero && (enter_{a}_x <<< {lg}) >= bound_{a}_x;",
            p1 = pw - 1
        );
        above.push(format!("above_{a}"));
    }
    let _ = writeln!(
        v,
        "    assign hit = {};\n    assign entry_ok = entry == 0 || {};\nendmodule",
        conds.join("\n        && "),
        above.join(" || ")
    );
    (name, v)
}

/// Signed width of the node reference's box bounds and differences: the
/// frame origin plus `(2^q − 1)·2^emax`, in units of `2^(1 − bias − F)`,
/// with a sign and two bits of headroom.
fn node_child_width(fmt: FloatFormat, q: u32) -> u32 {
    let step_top = (2 * fmt.bias() + fmt.frac_bits() as i32 - 1) as u32;
    magnitude_bits(fmt).max(q + step_top) + 3
}

/// A value of `fmt` (not NaN) as binary64, exactly at the formats here.
fn as_f64(fmt: FloatFormat, bits: u64) -> f64 {
    use golden_model::exact::ray_box::{decode, Exact};
    match decode(fmt, bits) {
        Exact::Fin { m, e } => m as f64 * 2f64.powi(e),
        Exact::PosInf => f64::INFINITY,
        Exact::NegInf => f64::NEG_INFINITY,
        Exact::NaN => f64::NAN,
    }
}

/// `v` as a `bits`-bit two's-complement field.
fn to_field(v: i64, bits: u32) -> u64 {
    (v as u64) & ((1 << bits) - 1)
}

/// A `bits`-bit two's-complement field's value.
fn from_field(field: u64, bits: u32) -> i32 {
    let sign = 1u64 << (bits - 1);
    ((field ^ sign) as i64 - sign as i64) as i32
}

/// The seeded generator of the reference checks (xorshift64).
struct Cases(u64);

impl Cases {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }
    /// A finite value of `fmt`, zero one time in 8, either sign.
    fn finite(&mut self, fmt: FloatFormat) -> u64 {
        let r = self.next();
        let mag = match r % 8 {
            0 => 0,
            _ => (r >> 8) % fmt.inf(false), // magnitudes below +inf are finite
        };
        fmt.with_sign(r >> 3 & 1 == 1, mag)
    }
    /// Ray/box inputs in [`RAY_BOX_PORTS`] order: finite box, origin and
    /// direction (zero components), corners mostly ordered, origins on the
    /// box's planes, infinite and zero segment ends.
    fn ray_box(&mut self, fmt: FloatFormat) -> [u64; 14] {
        let mut c = [0u64; 14];
        for x in c.iter_mut().take(12) {
            *x = self.finite(fmt);
        }
        // ordered corners mostly (as values: the sign-magnitude bits do not order)
        let val = |b: u64| as_f64(fmt, b);
        for a in 0..3 {
            if !self.next().is_multiple_of(8) && val(c[a]) > val(c[a + 3]) {
                c.swap(a, a + 3);
            }
        }
        // origins on the box's planes (a segment from 0 then starts in the box)
        if self.next().is_multiple_of(2) {
            for a in 0..3 {
                if self.next().is_multiple_of(2) {
                    c[6 + a] = c[a + 3 * (self.next() % 2) as usize];
                }
            }
        }
        for t in 12..14 {
            c[t] = match self.next() % 6 {
                0 => fmt.inf(t == 12),
                1 => fmt.inf(t == 13),
                2 => {
                    if t == 12 {
                        fmt.zero(false)
                    } else {
                        fmt.inf(false)
                    }
                }
                _ => self.finite(fmt),
            };
        }
        c
    }
}

/// Simulates the module `name` (Verilog `text`) in Icarus Verilog in `dir`
/// on `cases` (one value per input of `inputs`, `(name, width)` in order);
/// per case the values of the one-bit `outputs`.
fn simulate(
    dir: &Path,
    (name, text): (&str, &str),
    inputs: &[(String, u32)],
    outputs: &[&str],
    cases: &[Vec<u64>],
) -> Result<Vec<Vec<bool>>, String> {
    std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    std::fs::write(dir.join(format!("{name}.v")), text).map_err(|e| e.to_string())?;
    let digits: Vec<u32> = inputs.iter().map(|(_, w)| w.div_ceil(4)).collect();
    let hex: String = cases
        .iter()
        .map(|c| {
            c.iter()
                .zip(&digits)
                .map(|(x, d)| format!("{x:0width$x}", width = *d as usize))
                .collect::<String>()
                + "\n"
        })
        .collect();
    std::fs::write(dir.join("cases.hex"), hex).map_err(|e| e.to_string())?;
    let vw: u32 = digits.iter().map(|d| 4 * d).sum();
    // field k's low bits, fields from the most significant end
    let mut lo = vw;
    let conns: Vec<String> = inputs
        .iter()
        .zip(&digits)
        .map(|((p, w), d)| {
            lo -= 4 * d;
            format!(".{p}(v[{}:{lo}])", lo + w - 1)
        })
        .chain(outputs.iter().map(|o| format!(".{o}({o})")))
        .collect();
    let count = cases.len();
    let tb = format!(
        "module tb;\n    reg [{}:0] mem [0:{}];\n    reg [{}:0] v;\n    wire {};\n    integer i, out;\n    \
         {name} u_ref ({});\n    initial begin\n        $readmemh(\"cases.hex\", mem);\n        \
         out = $fopen(\"results.txt\", \"w\");\n        for (i = 0; i < {count}; i = i + 1) begin\n            \
         v = mem[i];\n            #1 $fwrite(out, \"{}\\n\", {});\n        end\n        $fclose(out);\n        $finish;\n    end\nendmodule\n",
        vw - 1,
        count - 1,
        vw - 1,
        outputs.join(", "),
        conns.join(", "),
        vec!["%0d"; outputs.len()].join(" "),
        outputs.join(", "),
    );
    std::fs::write(dir.join("tb.v"), tb).map_err(|e| e.to_string())?;
    let run = |cmd: &mut Command| -> Result<(), String> {
        let o = cmd
            .current_dir(dir)
            .output()
            .map_err(|e| format!("{cmd:?}: {e} (Icarus Verilog: scripts/setup.sh installs it)"))?;
        if o.status.success() {
            Ok(())
        } else {
            Err(format!(
                "{cmd:?} failed in {}: {}",
                dir.display(),
                String::from_utf8_lossy(&o.stderr)
            ))
        }
    };
    run(Command::new("iverilog").args(["-g2005", "-o", "tb.vvp", "tb.v", &format!("{name}.v")]))?;
    run(Command::new("vvp").args(["-n", "tb.vvp"]))?;
    let results = std::fs::read_to_string(dir.join("results.txt")).map_err(|e| e.to_string())?;
    let got: Vec<Vec<bool>> = results
        .lines()
        .map(|l| l.split_whitespace().map(|b| b == "1").collect())
        .collect();
    if got.len() != count || got.iter().any(|r| r.len() != outputs.len()) {
        return Err(format!(
            "{}: {} results for {count} cases",
            dir.display(),
            got.len()
        ));
    }
    Ok(got)
}

/// Simulates the reference in Icarus Verilog on `count` seeded random
/// inputs ([`Cases::ray_box`]) and compares each `hit` with
/// `golden_model::exact::ray_box::ray_hits_box`; the number of hits.
pub fn check_reference(fmt: FloatFormat, dir: &Path, count: usize) -> Result<usize, String> {
    let (name, text) = exact_reference(fmt);
    let mut gen = Cases(0x9e37_79b9_7f4a_7c15);
    let cases: Vec<Vec<u64>> = (0..count).map(|_| gen.ray_box(fmt).to_vec()).collect();
    let inputs: Vec<(String, u32)> = RAY_BOX_PORTS
        .iter()
        .map(|p| (p.to_string(), fmt.width()))
        .collect();
    let got = simulate(dir, (&name, &text), &inputs, &["hit"], &cases)?;
    let mut reached = 0;
    for (k, c) in cases.iter().enumerate() {
        let want = ray_hits_box(
            fmt,
            &BoxIn {
                p_min: [c[0], c[1], c[2]],
                p_max: [c[3], c[4], c[5]],
            },
            &RayIn {
                o: [c[6], c[7], c[8]],
                d: [c[9], c[10], c[11]],
                t_min: c[12],
                t_max: c[13],
            },
        );
        if got[k][0] != want.hit {
            return Err(format!(
                "the Verilog exact reference disagrees with the Rust one on case {k} ({c:x?}): Verilog {}, Rust {}",
                got[k][0], want.hit
            ));
        }
        reached += usize::from(want.hit);
    }
    Ok(reached)
}

/// Simulates the region reference in Icarus Verilog on `count` seeded
/// random inputs (the ray/box cases with a finite `t_min`; the reference
/// point the box's lower corner or any point, random normals with zero
/// components, random distances) and compares `box_hit` and `hit` with
/// `golden_model::cull::exact::region_hit`; the region hits and the box hits
/// whose region is missed (what a cull may remove).
pub fn check_region_reference(
    c: CullFormats,
    dir: &Path,
    count: usize,
) -> Result<(usize, usize), String> {
    let (name, text) = exact_region_reference(c);
    let mut gen = Cases(0x2545_f491_4f6c_dd1d);
    let cases: Vec<Vec<u64>> = (0..count)
        .map(|_| {
            let mut x = gen.ray_box(c.ray).to_vec();
            if x[12] & !c.ray.sign_bit() == c.ray.inf(false) {
                x[12] = gen.finite(c.ray); // region_hit takes a finite t_min
            }
            if gen.next().is_multiple_of(2) {
                // from a corner of the box (mostly ordered): the planes decide
                for a in 0..3 {
                    x[6 + a] = x[a + 3 * (gen.next() % 2) as usize];
                }
                x[12] = c.ray.zero(false);
            }
            let corner = gen.next().is_multiple_of(2);
            for a in 0..3 {
                let r = if corner { x[a] } else { gen.finite(c.ray) };
                x.push(r);
            }
            for _ in 0..3 * c.k {
                let n = gen.finite(c.plane);
                x.push(n);
            }
            for _ in 0..c.k {
                let w = gen.finite(c.plane);
                x.push(w);
            }
            x
        })
        .collect();
    let inputs: Vec<(String, u32)> = c
        .geometry()
        .into_iter()
        .map(|(n, f)| (n, f.width()))
        .collect();
    let got = simulate(dir, (&name, &text), &inputs, &["box_hit", "hit"], &cases)?;
    let (mut hits, mut culls) = (0, 0);
    for (i, x) in cases.iter().enumerate() {
        let at = |k: usize| [x[k], x[k + 1], x[k + 2]];
        let want = region_hit(
            c.ray,
            c.plane,
            &RegionIn {
                p_min: at(0),
                p_max: at(3),
                o: at(6),
                d: at(9),
                t_min: x[12],
                t_max: x[13],
                r: at(14),
                normals: (0..c.k).map(|j| at(17 + 3 * j)).collect(),
                w: x[17 + 3 * c.k..].to_vec(),
            },
        );
        if got[i] != [want.box_hit, want.region_hit] {
            return Err(format!(
                "the Verilog exact region reference disagrees with the Rust one on case {i} ({x:x?}): \
                 Verilog box_hit {} hit {}, Rust {} {}",
                got[i][0], got[i][1], want.box_hit, want.region_hit
            ));
        }
        hits += usize::from(want.region_hit);
        culls += usize::from(want.box_hit && !want.region_hit);
    }
    Ok((hits, culls))
}

/// The node reference's ports, in order (the frame, a child's box integers,
/// the ray, the segment, the unit's entry for the child).
const NODE_CHILD_PORTS: [&str; 24] = [
    "frame_origin_x",
    "frame_origin_y",
    "frame_origin_z",
    "frame_exp_x",
    "frame_exp_y",
    "frame_exp_z",
    "lo_x",
    "lo_y",
    "lo_z",
    "hi_x",
    "hi_y",
    "hi_z",
    "o_x",
    "o_y",
    "o_z",
    "d_x",
    "d_y",
    "d_z",
    "t_min",
    "t_start",
    "t_max",
    "t_base",
    "grid_exp",
    "entry",
];

/// Simulates the node child reference in Icarus Verilog on `count` seeded
/// random inputs (frames of every exponent, boxes mostly ordered, origins on
/// the frame's corner, the ray/box cases' directions and segment ends, a
/// start of either kind) and compares `hit` with
/// `golden_model::exact::ray_box::ray_hits_box` on the same geometry in
/// binary64 (the decoded child box and the segment from `max(t_min,
/// t_start)`, all exact there), and `entry_ok` with the entry parameters
/// compared in binary64 (exact there too) for random small entries; the
/// number of hits, and of nonzero entries found below and not below the
/// segment's entry into the box.
pub fn check_node_reference(
    fmt: FloatFormat,
    q: u32,
    out: NodeEntry,
    dir: &Path,
    count: usize,
) -> Result<(usize, usize, usize), String> {
    let (name, text) = exact_node_child_reference(fmt, q, out);
    let mut gen = Cases(0x6a09_e667_f3bc_c908);
    let cases: Vec<Vec<u64>> = (0..count)
        .map(|_| {
            let rb = gen.ray_box(fmt);
            let mut c = Vec::with_capacity(NODE_CHILD_PORTS.len());
            let origin: Vec<u64> = (0..3).map(|_| gen.finite(fmt)).collect();
            c.extend(&origin);
            let span = (fmt.emax() - fmt.emin() + 1) as u64;
            for _ in 0..3 {
                let e = i64::from(fmt.emin()) + (gen.next() % span) as i64;
                c.push(to_field(e, fmt.exp_bits()));
            }
            let mut lo: Vec<u64> = (0..3).map(|_| gen.next() % (1 << q)).collect();
            let mut hi: Vec<u64> = (0..3).map(|_| gen.next() % (1 << q)).collect();
            for a in 0..3 {
                if !gen.next().is_multiple_of(8) && lo[a] > hi[a] {
                    std::mem::swap(&mut lo[a], &mut hi[a]);
                }
            }
            // the origin at the frame's corner on most axes, on the box's lower plane there
            // (in the box at t = 0 when it is on every axis)
            let mut o = rb[6..9].to_vec();
            if gen.next().is_multiple_of(2) {
                for (a, x) in o.iter_mut().enumerate() {
                    if !gen.next().is_multiple_of(4) {
                        *x = origin[a];
                        lo[a] = 0;
                    }
                }
            }
            c.extend(&lo);
            c.extend(&hi);
            c.extend(&o);
            c.extend(&rb[9..13]); // d, t_min
            c.push(match gen.next() % 12 {
                0..=2 => fmt.inf(true),
                3..=5 => fmt.zero(false),
                6 => fmt.inf(false),
                _ => gen.finite(fmt),
            });
            c.push(rb[13]);
            // an entry: t_base + entry·2^grid_exp near the box (small counts and cells)
            c.push(gen.finite(fmt));
            let g_min = -(1i64 << (out.grid_bits - 1));
            let g = (-6 + (gen.next() % 9) as i64).max(g_min);
            c.push(to_field(g, out.grid_bits));
            c.push(match gen.next() % 4 {
                0 => 0,
                _ => gen.next() % 64,
            });
            c
        })
        .collect();
    let inputs: Vec<(String, u32)> = NODE_CHILD_PORTS
        .iter()
        .map(|p| {
            let width = match *p {
                "grid_exp" => out.grid_bits,
                "entry" => out.entry_bits,
                _ if p.starts_with("frame_exp") => fmt.exp_bits(),
                _ if p.starts_with("lo_") || p.starts_with("hi_") => q,
                _ => fmt.width(),
            };
            (p.to_string(), width)
        })
        .collect();
    let got = simulate(dir, (&name, &text), &inputs, &["hit", "entry_ok"], &cases)?;
    let b64 = FloatFormat::new(11, 52).map_err(|e| e.to_string())?;
    let (mut hits, mut below, mut not_below) = (0, 0, 0);
    let val = |b: u64| as_f64(fmt, b);
    for (k, c) in cases.iter().enumerate() {
        // the decoded child box, exact in binary64
        let corner = |ints: usize| -> [f64; 3] {
            std::array::from_fn(|a| {
                let step = 2f64.powi(from_field(c[3 + a], fmt.exp_bits()));
                val(c[a]) + c[ints + a] as f64 * step
            })
        };
        let (p_min, p_max) = (corner(6), corner(9));
        let bits = |i: usize| val(c[i]).to_bits();
        let want = ray_hits_box(
            b64,
            &BoxIn {
                p_min: p_min.map(f64::to_bits),
                p_max: p_max.map(f64::to_bits),
            },
            &RayIn {
                o: [bits(12), bits(13), bits(14)],
                d: [bits(15), bits(16), bits(17)],
                t_min: val(c[18]).max(val(c[19])).to_bits(),
                t_max: bits(20),
            },
        );
        // the entry bound: some axis's entry parameter at least x (d > 0: pmin − o ≥ x·d;
        // d < 0: pmax − o ≤ x·d), every term exact in binary64 at these widths
        let entry = c[23];
        let x = val(c[21]) + entry as f64 * 2f64.powi(from_field(c[22], out.grid_bits));
        let entry_ok = entry == 0
            || (0..3).any(|a| {
                let (o, d) = (val(c[12 + a]), val(c[15 + a]));
                (d > 0.0 && p_min[a] - o >= x * d) || (d < 0.0 && p_max[a] - o <= x * d)
            });
        if got[k] != [want.hit, entry_ok] {
            return Err(format!(
                "the Verilog node child reference disagrees with the Rust exact test on case {k} \
                 ({c:x?}): Verilog hit {} entry_ok {}, Rust {} {}",
                got[k][0], got[k][1], want.hit, entry_ok
            ));
        }
        hits += usize::from(want.hit);
        if entry != 0 {
            below += usize::from(entry_ok);
            not_below += usize::from(!entry_ok);
        }
    }
    Ok((hits, below, not_below))
}

/// The unit tests bundles (silhouette `mode=bundle`, shared origin: it has `all_hit`).
fn is_bundle(unit: &Generated) -> bool {
    unit.ports.outputs.iter().any(|x| x.name == "all_hit")
}

/// The input contract `inv_d = RTZ(1/d)` of a unit that takes `inv_d_*`
/// beside `d_*`, emitted into `v` (with the decode functions `mag`, `value`):
/// `±∞` iff `d = ±0`; else the same sign, `|c|·|d| ≤ 1 < next(|c|)·|d|` by
/// cross-multiplication, in units of `2^(2(1 − bias − F))` (one is
/// `2^(2(bias + F − 1))`). The names of the assumptions.
fn rtz_contract(v: &mut String, fmt: FloatFormat) -> Vec<String> {
    let w = fmt.width();
    let exp_ones = |x: &str| exp_ones(fmt, x);
    let mut assumes = Vec::new();
    let mw = magnitude_bits(fmt);
    let one_shift = 2 * (fmt.bias() + fmt.frac_bits() as i32 - 1);
    let pw = 2 * (mw + 1);
    v.push_str(&decode_functions(
        fmt,
        "mag",
        "value",
        magnitude_bits(fmt) + 1,
    ));
    let max_mag = fmt.max_finite(false);
    for a in AXES {
        let _ = writeln!(
            v,
            "    wire [{p1}:0] c_times_d_{a} = mag(inv_d_{a}) * mag(d_{a});\n    \
             wire [{w1}:0] inv_d_{a}_next = {{1'b0, inv_d_{a}[{w2}:0]}} + 1'b1;\n    \
             wire [{p1}:0] next_times_d_{a} = mag(inv_d_{a}_next) * mag(d_{a});\n    \
             wire d_{a}_zero = d_{a}[{w2}:0] == 0;\n    \
             wire rtz_{a} = d_{a}_zero ? (inv_d_{a}[{w2}:0] == {w1}'h{inf:x} && inv_d_{a}[{w1}] == d_{a}[{w1}])\n        \
             : (!{inv_special} && inv_d_{a}[{w1}] == d_{a}[{w1}] && c_times_d_{a} <= ({p}'d1 << {one_shift})\n           \
             && (inv_d_{a}[{w2}:0] == {w1}'h{max_mag:x} || next_times_d_{a} > ({p}'d1 << {one_shift})));",
            p1 = pw - 1,
            p = pw,
            w1 = w - 1,
            w2 = w - 2,
            inf = fmt.inf(false),
            inv_special = exp_ones(&format!("inv_d_{a}")),
        );
        assumes.push(format!("rtz_{a}"));
    }
    assumes
}

/// The unit's instance `u_unit` at stages=0: the clock, reset low, `in_valid`
/// high, each data input to `input(name)`, `out_valid` open and each output
/// to `output(name)` (open when `None`).
fn unit_instance(
    unit: &Generated,
    input: impl Fn(&str) -> String,
    output: impl Fn(&str) -> Option<String>,
) -> String {
    let p = &unit.ports;
    let mut conns = vec![
        format!(".{}(clk)", p.clock),
        format!(".{}(1'b0)", p.reset),
        format!(".{}(1'b1)", p.in_valid),
    ];
    conns.extend(
        p.inputs
            .iter()
            .map(|x| format!(".{}({})", x.name, input(&x.name))),
    );
    conns.push(format!(".{}()", p.out_valid));
    conns.extend(
        p.outputs
            .iter()
            .map(|x| format!(".{}({})", x.name, output(&x.name).unwrap_or_default())),
    );
    format!("{} u_unit ({});", p.top, conns.join(", "))
}

/// The head of a wrapper `prove_sound` whose inputs are the clock and the
/// unit's own inputs (the node and triangle wrappers), its comment naming the
/// unit and `reference`.
fn wrapper_head(unit: &Generated, reference: &str) -> String {
    let p = &unit.ports;
    let ports: Vec<String> = std::iter::once("input wire clk".to_string())
        .chain(
            p.inputs
                .iter()
                .map(|x| format!("input wire [{}:0] {}", x.width - 1, x.name)),
        )
        .collect();
    format!(
        "// Generated by rtl-gen prove --property sound: {} {} against the exact {reference} reference.\n\
         `default_nettype none\nmodule prove_sound (\n    {}\n);\n",
        p.top,
        unit.param_args(),
        ports.join(",\n    ")
    )
}

/// The wrapper `prove_sound`: the unit (stages=0) beside the reference, the
/// input contract assumed, `exact hit → unit hit` asserted; with `split`,
/// also the slab's lemmas ([`split`]).
pub fn wrapper(unit: &Generated, fmt: FloatFormat, split: bool) -> Result<String, String> {
    let (reference, _) = exact_reference(fmt);
    let p = &unit.ports;
    let takes_inv_d = p.inputs.iter().any(|x| x.name == "inv_d_x");
    // a bundle: the free ray `d` is any ray of the bundle `d_lo ≤ d ≤ d_hi`
    let bundle = is_bundle(unit);
    let w = fmt.width();
    let mut v = String::new();
    let mut ports = vec!["input wire clk".to_string()];
    for n in RAY_BOX_PORTS {
        ports.push(format!("input wire [{}:0] {n}", w - 1));
    }
    if takes_inv_d {
        for a in AXES {
            ports.push(format!("input wire [{}:0] inv_d_{a}", w - 1));
        }
    }
    if bundle {
        for end in ["lo", "hi"] {
            for a in AXES {
                ports.push(format!("input wire [{}:0] d_{end}_{a}", w - 1));
            }
        }
    }
    let _ = writeln!(
        v,
        "// Generated by rtl-gen prove --property sound: {} {} against the exact reference.\n\
         `default_nettype none\nmodule prove_sound (\n    {}\n);",
        p.top,
        unit.param_args(),
        ports.join(",\n    ")
    );
    let _ = writeln!(
        v,
        "    (* keep *) wire exact_hit;\n    {reference} u_exact (.p_min_x(p_min_x), .p_min_y(p_min_y), .p_min_z(p_min_z), \
         .p_max_x(p_max_x), .p_max_y(p_max_y), .p_max_z(p_max_z), .o_x(o_x), .o_y(o_y), .o_z(o_z), \
         .d_x(d_x), .d_y(d_y), .d_z(d_z), .t_min(t_min), .t_max(t_max), .hit(exact_hit));"
    );
    let _ = writeln!(
        v,
        "    (* keep *) wire unit_hit;\n    (* keep *) wire unit_all_hit;"
    );
    if !bundle {
        let _ = writeln!(v, "    assign unit_all_hit = 1'b0;");
    }
    let instance = unit_instance(
        unit,
        // the bundle's shared origin is the free ray's
        |name| match name.strip_prefix("o_lo_") {
            Some(a) => format!("o_{a}"),
            None => name.to_string(),
        },
        |name| match name {
            "hit" | "any_hit" => Some("unit_hit".into()),
            "all_hit" => Some("unit_all_hit".into()),
            _ => None,
        },
    );
    let _ = writeln!(v, "    {instance}");
    // the contract: no NaN; box, origin, direction finite
    let exp_ones = |x: &str| exp_ones(fmt, x);
    let mut assumes = Vec::new();
    // the box, the origin and the direction: finite
    for n in &RAY_BOX_PORTS[..12] {
        assumes.push(format!("!{}", exp_ones(n)));
    }
    for n in ["t_min", "t_max"] {
        assumes.push(format!("!{}", is_nan(fmt, n)));
    }
    if takes_inv_d {
        assumes.extend(rtz_contract(&mut v, fmt));
    }
    if bundle {
        // the bundle's bounds: finite, and the free ray within them (as reals)
        let mw = magnitude_bits(fmt);
        if !takes_inv_d {
            v.push_str(&decode_functions(
                fmt,
                "mag",
                "value",
                magnitude_bits(fmt) + 1,
            ));
        }
        for a in AXES {
            for n in [format!("d_lo_{a}"), format!("d_{a}"), format!("d_hi_{a}")] {
                let _ = writeln!(
                    v,
                    "    wire signed [{mw}:0] real_{n} = {n}[{w1}] ? -$signed({{1'b0, mag({n})}}) : $signed({{1'b0, mag({n})}});",
                    w1 = w - 1
                );
            }
            assumes.push(format!("!{}", exp_ones(&format!("d_lo_{a}"))));
            assumes.push(format!("!{}", exp_ones(&format!("d_hi_{a}"))));
            assumes.push(format!(
                "real_d_lo_{a} <= real_d_{a} && real_d_{a} <= real_d_hi_{a}"
            ));
        }
    }
    if split && bundle {
        v.push_str(&bundle_split::bundle_wrapper_part(fmt));
    } else if split {
        v.push_str(&split::wrapper_part(fmt, split::axis_unit(&unit.unit)));
    }
    let _ = writeln!(
        v,
        "    always @(*) begin\n        assume ({});\n        \
         // never a miss for a ray that meets the box; AllHit only for a ray that meets it\n        \
         assert (!exact_hit || unit_hit);\n        assert (!unit_all_hit || exact_hit);\n    end\nendmodule",
        assumes.join("\n            && ")
    );
    Ok(v)
}

/// The wrapper `prove_sound` of the cull tester: the unit (stages=0) beside
/// the exact region reference ([`region_body`], inline: the contract reads
/// its exact terms), the unit's input contract assumed in terms of the exact
/// geometry, `exact hit → keep` asserted. The contract (docs/cull.md §3.4)
/// over a free ray, box, segment, reference point `r`, normals and distances:
/// * no NaN; box, origin, direction, `r`, `t_min`, normals, distances finite;
/// * the slab's `[t_lo, t_hi]` contains the exact segment ∩ box (when the
///   segment meets the box): `t_lo ≤` its entry, `t_hi ≥` its exit;
/// * per plane `no_lo ≤ n·(o − r)` (or −∞) and a free `b_lo ≤ n·d` (the
///   crossing format, or −∞), `dir` its sign (0 zero, 1 positive, 2
///   negative), `0 ≤ rcp_lo ≤ 1/|b_lo| ≤ rcp_hi` (`rcp_hi` may be +∞) by
///   cross-multiplication; `+∞` both for `b_lo = 0` and `+0` both for
///   `b_lo = −∞`, as `cull_ray` gives them.
fn cull_wrapper(unit: &Generated, c: CullFormats, split: bool) -> String {
    let p = &unit.ports;
    let fmt = c.ray;
    let w = fmt.width();
    let mut ports = vec!["input wire clk".to_string()];
    for (n, f) in c.geometry() {
        ports.push(format!("input wire [{}:0] {n}", f.width() - 1));
    }
    for j in 0..c.k {
        ports.push(format!("input wire [{}:0] b_lo{j}", w - 1));
    }
    let geometry: Vec<String> = c.geometry().into_iter().map(|(n, _)| n).collect();
    for x in &p.inputs {
        if !geometry.contains(&x.name) {
            ports.push(format!("input wire [{}:0] {}", x.width - 1, x.name));
        }
    }
    let mut v = String::new();
    let _ = writeln!(
        v,
        "// Generated by rtl-gen prove --property sound: {} {} against the exact region reference.\n\
         `default_nettype none\nmodule prove_sound (\n    {}\n);",
        p.top,
        unit.param_args(),
        ports.join(",\n    ")
    );
    let (box_lower, box_upper) = region_body(&mut v, c);
    let mut assumes = Vec::new();
    for (n, f) in c.geometry() {
        if n != "t_max" {
            assumes.push(format!("!{}", exp_ones(f, &n)));
        }
    }
    for n in ["t_max", "t_lo", "t_hi"] {
        assumes.push(format!("!{}", is_nan(fmt, n)));
    }
    // the slab's interval around the exact segment ∩ box: t_lo at most some
    // active lower bound (so at most their maximum), t_hi at least some upper
    let pw = 2 * (c.nw() + 2) + 2;
    let _ = writeln!(
        v,
        "    // the contract: [t_lo, t_hi] contains the exact segment ∩ box\n    \
         wire signed [{p1}:0] t_lo_v = value(t_lo);\n    wire signed [{p1}:0] t_hi_v = value(t_hi);",
        p1 = pw - 1
    );
    let mut below = Vec::new();
    for (i, b) in box_lower.iter().enumerate() {
        let _ = writeln!(
            v,
            "    wire t_lo_below_{i} = ({}) && t_lo_v * {} <= {} * t_den;",
            b.active, b.den, b.num
        );
        below.push(format!("t_lo_below_{i}"));
    }
    let mut above = Vec::new();
    for (i, b) in box_upper.iter().enumerate() {
        let _ = writeln!(
            v,
            "    wire t_hi_above_{i} = ({}) && {} * t_den <= t_hi_v * {};",
            b.active, b.num, b.den
        );
        above.push(format!("t_hi_above_{i}"));
    }
    let _ = writeln!(
        v,
        "    wire interval_ok = !exact_box_hit\n        || (({} || (!{} && ({}))) && ({} || (!{} && ({}))));",
        is_inf(fmt, "t_lo", true),
        exp_ones(fmt, "t_lo"),
        below.join(" || "),
        is_inf(fmt, "t_hi", false),
        exp_ones(fmt, "t_hi"),
        above.join(" || ")
    );
    assumes.push("interval_ok".into());
    // the ray terms: lower bounds of the exact n·(o − r) and n·d, in their units
    let (pd1, s) = (c.pdw() - 1, c.ray_to_term_shift());
    let mw = magnitude_bits(fmt);
    let one_shift = 2 * (fmt.bias() + fmt.frac_bits() as i32 - 1);
    let (w1, w2) = (w - 1, w - 2);
    for j in 0..c.k {
        let _ = writeln!(
            v,
            "    // plane {j}: no_lo{j} ≤ n·(o − r), b_lo{j} ≤ n·d, dir{j} its sign, rcp_lo{j} ≤ 1/|b_lo{j}| ≤ rcp_hi{j}\n    \
             wire signed [{pd1}:0] no_lo{j}_v = value(no_lo{j});\n    \
             wire no_lo{j}_ok = !{no_nan} && ({no_neg_inf} || (!{no_special} && (no_lo{j}_v <<< {s}) <= no_{j}));\n    \
             wire signed [{pd1}:0] b_lo{j}_v = value(b_lo{j});\n    \
             wire b_lo{j}_neg_inf = {b_neg_inf};\n    \
             wire b_lo{j}_zero = b_lo{j}[{w2}:0] == 0;\n    \
             wire b_lo{j}_ok = b_lo{j}_neg_inf || (!{b_special} && (b_lo{j}_v <<< {s}) <= b_{j});\n    \
             wire dir{j}_ok = dir{j} == (b_lo{j}_zero ? 2'd0 : b_lo{j}[{w1}] ? 2'd2 : 2'd1);\n    \
             wire [{m1}:0] rcp_lo{j}_times_b = mag(rcp_lo{j}) * mag(b_lo{j});\n    \
             wire [{m1}:0] rcp_hi{j}_times_b = mag(rcp_hi{j}) * mag(b_lo{j});\n    \
             wire rcp{j}_ok = b_lo{j}_zero ? (rcp_lo{j} == {w}'h{inf:x} && rcp_hi{j} == {w}'h{inf:x})\n        \
             : b_lo{j}_neg_inf ? (rcp_lo{j} == 0 && rcp_hi{j} == 0)\n        \
             : (!rcp_lo{j}[{w1}] && !{lo_special} && rcp_lo{j}_times_b <= ({m}'d1 << {one_shift})\n           \
             && !rcp_hi{j}[{w1}] && !{hi_nan} && (rcp_hi{j} == {w}'h{inf:x} || rcp_hi{j}_times_b >= ({m}'d1 << {one_shift})));",
            no_nan = is_nan(fmt, &format!("no_lo{j}")),
            no_neg_inf = is_inf(fmt, &format!("no_lo{j}"), true),
            no_special = exp_ones(fmt, &format!("no_lo{j}")),
            b_neg_inf = is_inf(fmt, &format!("b_lo{j}"), true),
            b_special = exp_ones(fmt, &format!("b_lo{j}")),
            lo_special = exp_ones(fmt, &format!("rcp_lo{j}")),
            hi_nan = is_nan(fmt, &format!("rcp_hi{j}")),
            inf = fmt.inf(false),
            m = 2 * mw + 2,
            m1 = 2 * mw + 1,
        );
        for x in ["no_lo", "b_lo", "dir", "rcp"] {
            assumes.push(format!("{x}{j}_ok"));
        }
    }
    let instance = unit_instance(unit, str::to_string, |name| {
        (name == "keep").then(|| "unit_keep".to_string())
    });
    let _ = writeln!(v, "    (* keep *) wire unit_keep;\n    {instance}");
    if split {
        v.push_str(&split::cull_wrapper_part(c));
    }
    let _ = writeln!(
        v,
        "    always @(*) begin\n        \
         assume ({});\n        // never a wrongful cull\n        assert (!exact_hit || unit_keep);\n    end\nendmodule",
        assumes.join("\n            && ")
    );
    v
}

/// The wrapper `prove_sound` of the node tester: the unit (stages=0) beside
/// one exact child reference per slot ([`exact_node_child_reference`]), the
/// contract assumed (no NaN; origin, direction and frame finite; `inv_d =
/// RTZ(1/d)` by cross-multiplication), and per slot `valid ∧ the segment
/// from max(t_min, t_start) meets the child's box → the slot is reported
/// hit` asserted, whichever sorted position it comes out in.
fn node_wrapper(
    unit: &Generated,
    fmt: FloatFormat,
    q: u32,
    children: usize,
    out: NodeEntry,
    split: Option<node_split::NodeShape>,
) -> String {
    let p = &unit.ports;
    let (reference, _) = exact_node_child_reference(fmt, q, out);
    // the outputs the assertions read: the sorted slots, the base and the cell
    let read = |name: &str| name.starts_with("out") || name == "t_base" || name == "grid_exp";
    let mut v = wrapper_head(unit, "child");
    let ray: String = ["o", "d"]
        .iter()
        .flat_map(|n| AXES.iter().map(move |a| format!(".{n}_{a}({n}_{a}), ")))
        .chain(["t_min", "t_start", "t_max"].map(|n| format!(".{n}({n}), ")))
        .collect();
    let frame: String = ["frame_origin", "frame_exp"]
        .iter()
        .flat_map(|n| AXES.iter().map(move |a| format!(".{n}_{a}({n}_{a}), ")))
        .collect();
    for x in p.outputs.iter().filter(|x| read(&x.name)) {
        let _ = writeln!(v, "    wire [{}:0] unit_{};", x.width - 1, x.name);
    }
    for i in 0..children {
        let slot: String = ["lo", "hi"]
            .iter()
            .flat_map(|n| {
                AXES.iter()
                    .map(move |a| format!(".{n}_{a}(slot{i}_{n}_{a}), "))
            })
            .collect();
        // the entry of the sorted position that names the child
        let entry = (0..children)
            .rev()
            .fold(format!("{}'d0", out.entry_bits), |rest, j| {
                format!("unit_out{j}_child == {i} ? unit_out{j}_entry : {rest}")
            });
        let _ = writeln!(
            v,
            "    wire [{k1}:0] unit_entry_{i} = {entry};\n    wire exact_hit_{i}, entry_ok_{i};\n    \
             {reference} u_exact_{i} ({frame}{slot}{ray}.t_base(unit_t_base), .grid_exp(unit_grid_exp), \
             .entry(unit_entry_{i}), .hit(exact_hit_{i}), .entry_ok(entry_ok_{i}));\n    \
             (* keep *) wire child{i}_valid = valid[{i}];\n    \
             (* keep *) wire child{i}_exact_hit = valid[{i}] && exact_hit_{i};",
            k1 = out.entry_bits - 1,
        );
    }
    let instance = unit_instance(unit, str::to_string, |name| {
        read(name).then(|| format!("unit_{name}"))
    });
    let _ = writeln!(v, "    {instance}");
    // a slot is reported hit when some sorted position names it with its hit bit set
    for i in 0..children {
        let named: Vec<String> = (0..children)
            .map(|j| format!("(unit_out{j}_hit && unit_out{j}_child == {i})"))
            .collect();
        let _ = writeln!(
            v,
            "    (* keep *) wire unit_hit_{i} = {};",
            named.join(" || ")
        );
    }
    let mut assumes: Vec<String> = Vec::new();
    for n in ["o", "d", "frame_origin"] {
        for a in AXES {
            assumes.push(format!("!{}", exp_ones(fmt, &format!("{n}_{a}"))));
        }
    }
    for n in ["t_min", "t_max", "t_start"] {
        assumes.push(format!("!{}", is_nan(fmt, n)));
    }
    assumes.extend(rtz_contract(&mut v, fmt));
    if let Some(shape) = split {
        v.push_str(&node_split::node_wrapper_part(shape));
    }
    let asserts: String = (0..children)
        .map(|i| {
            format!(
                "        assert (!child{i}_exact_hit || unit_hit_{i});\n        \
                 assert (!child{i}_exact_hit || entry_ok_{i});\n"
            )
        })
        .collect();
    let _ = writeln!(
        v,
        "    always @(*) begin\n        assume ({});\n        \
         // never a miss for a valid child the segment meets, and its entry a lower bound\n\
         {asserts}    end\nendmodule",
        assumes.join("\n            && ")
    );
    v
}

/// What `--property sound` proves of a unit, and against which reference.
enum Kind {
    /// silhouette (ray or bundle) and the conservative slab: the exact ray/box test
    RayBox,
    /// the cull tester: the exact region (box ∩ every plane's non-empty side)
    Cull(CullFormats),
    /// the node tester: per slot the exact ray/child-box test, box bits `q`
    Node {
        q: u32,
        children: usize,
        out: NodeEntry,
        /// slope bits m
        m: u32,
    },
    /// the triangle unit: the exact axis-ray test ([`triangle`])
    Triangle,
}

/// Proves `unit` (generated at stages=0; its Verilog from `verilog` when
/// given, for the replay) sound against the exact reference in the job
/// directory `work` (emptied first); the reference is checked in Icarus on
/// `reference_cases` inputs before. `split`: prove the lemmas of the slab or the cull tester
/// ([`split`]) instead of the whole property in one SAT call.
pub fn sound(
    unit: &Generated,
    verilog: Option<&Path>,
    work: &Path,
    reference_cases: usize,
    solver: crate::prove::Solver,
    split: bool,
    only: &[String],
) -> Result<crate::prove::Outcome, String> {
    use crate::prove::Outcome;
    let v = unit.params.values();
    let word = |k: &str| v.get(k).map(String::as_str).unwrap_or("");
    let supported = match unit.unit.as_str() {
        // rounding=nearest is allowed: it is known to miss hits (a bug to find)
        "silhouette" => word("mode") == "ray" || word("origin") == "shared",
        "slab" => word("rounding") == "conservative",
        "cull" | "node" | "triangle" => true,
        _ => false,
    } && unit.ports.ready.is_none();
    if solver == crate::prove::Solver::Structural {
        return Err(
            "--solver structural proves pipelines (--property equiv); a soundness proof \
                    has no pipeline to take apart: --solver sat or boolector"
                .into(),
        );
    }
    if !supported {
        return Err(format!(
            "--property sound is built for silhouette (mode=ray, or mode=bundle with origin=shared), slab \
             -p rounding=conservative, cull, node and triangle, with handshake=valid (the testers whose inputs \
             the exact references take); not for {} {}",
            unit.unit,
            unit.param_args()
        ));
    }
    if split
        && (!["slab", "cull", "silhouette", "node", "triangle"].contains(&unit.unit.as_str())
            || !matches!(solver, crate::prove::Solver::Sat))
    {
        return Err(format!(
            "--split is built for slab -p rounding=conservative, silhouette (mode=ray, or mode=bundle \
             with origin=shared), cull, node and triangle with --solver sat (its lemmas are their \
             per-axis, per-plane, per-node and per-edge bounds); not for {} {}",
            unit.unit,
            unit.param_args()
        ));
    }
    let num = |k: &str| {
        word(k)
            .parse::<u32>()
            .map_err(|_| format!("{}: no {k}", unit.unit))
    };
    let fmt = FloatFormat::new(num("exp_bits")?, num("frac_bits")?).map_err(|e| e.to_string())?;
    let kind = if unit.unit == "cull" {
        let plane = FloatFormat::new(num("plane_exp_bits")?, num("plane_frac_bits")?)
            .map_err(|e| e.to_string())?;
        if fmt.frac_bits() > plane.frac_bits() + 8 {
            return Err(format!(
                "cull: the crossing format (e{}m{}) is narrower than the ray format; --property sound \
                 takes b_lo and the reciprocals in the ray format (frac_bits ≤ plane_frac_bits + 8)",
                fmt.exp_bits(),
                plane.frac_bits() + 8
            ));
        }
        Kind::Cull(CullFormats {
            ray: fmt,
            plane,
            k: num("k")? as usize,
        })
    } else if unit.unit == "node" {
        let width = |name: &str| {
            unit.ports
                .outputs
                .iter()
                .find(|x| x.name == name)
                .map(|x| x.width)
                .ok_or_else(|| format!("node: no output {name}"))
        };
        Kind::Node {
            q: num("box_bits")?,
            children: num("children")? as usize,
            out: NodeEntry {
                entry_bits: width("out0_entry")?,
                grid_bits: width("grid_exp")?,
            },
            m: num("slope_bits")?,
        }
    } else if unit.unit == "triangle" {
        Kind::Triangle
    } else {
        Kind::RayBox
    };
    // where a split proof cuts the unit
    let mut cut = match kind {
        _ if !split => None,
        Kind::Triangle => Some(triangle::cut()),
        Kind::Cull(c) => Some(split::cull_cut(c.k)),
        Kind::Node { q, children, m, .. } => Some(node_split::node_cut(node_split::NodeShape {
            fmt,
            q,
            m,
            children,
        })),
        _ if is_bundle(unit) => Some(bundle_split::bundle_cut(fmt)),
        _ => Some(split::axis_unit(&unit.unit).cut()),
    };
    if !only.is_empty() {
        let Some(c) = cut.as_mut().filter(|c| !c.stages.is_empty()) else {
            return Err(
                "--lemma picks lemmas of node and silhouette mode=bundle --property sound --split"
                    .into(),
            );
        };
        if let Some(unknown) = only.iter().find(|l| !c.lemmas.contains(l)) {
            return Err(format!(
                "--lemma {unknown}: no such lemma; the lemmas are {}",
                c.lemmas.join(", ")
            ));
        }
        split::keep_only(c, only);
    }
    if work.exists() {
        std::fs::remove_dir_all(work).map_err(|e| format!("{}: {e}", work.display()))?;
    }
    let started = std::time::Instant::now();
    let reference_dir = work.join("reference");
    let checked = match kind {
        Kind::RayBox => format!(
            "{} hits",
            check_reference(fmt, &reference_dir, reference_cases)?
        ),
        Kind::Cull(c) => {
            let (hits, culls) = check_region_reference(c, &reference_dir, reference_cases)?;
            format!("{hits} region hits, {culls} box hits outside the region")
        }
        Kind::Node { q, out, .. } => {
            let (hits, below, not_below) =
                check_node_reference(fmt, q, out, &reference_dir, reference_cases)?;
            format!("{hits} hits; entries {below} below the box's entry, {not_below} not")
        }
        Kind::Triangle => format!(
            "{} crossed",
            triangle::check_axis_reference(fmt, &reference_dir, reference_cases)?
        ),
    };
    let mut files = Vec::new();
    let put = |name: &str, text: &str| -> Result<String, String> {
        std::fs::write(work.join(name), text).map_err(|e| format!("{}: {e}", work.display()))?;
        Ok(name.to_string())
    };
    for f in &unit.files {
        files.push(put(&f.file_name, &f.text)?);
    }
    let covers = match kind {
        Kind::RayBox => {
            let (reference, reference_text) = exact_reference(fmt);
            files.push(put(&format!("{reference}.v"), &reference_text)?);
            if split {
                let (lemmas, lemmas_text) = if is_bundle(unit) {
                    bundle_split::bundle_lemma_module(fmt)
                } else {
                    split::lemma_module(fmt, split::axis_unit(&unit.unit))
                };
                files.push(put(&format!("{lemmas}.v"), &lemmas_text)?);
            }
            files.push(put("prove_sound.v", &wrapper(unit, fmt, split)?)?);
            "# reachable: a ray that meets the box, one the unit rejects, an AllHit (bundles)\n\
             sat -set-assumes -set exact_hit 1\n\
             sat -set-assumes -set exact_hit 0 -set unit_hit 0\n\
             sat -set-assumes -set unit_all_hit 1\n"
                .to_string()
        }
        Kind::Node {
            q,
            children,
            out,
            m,
        } => {
            let (reference, reference_text) = exact_node_child_reference(fmt, q, out);
            files.push(put(&format!("{reference}.v"), &reference_text)?);
            let shape = split.then_some(node_split::NodeShape {
                fmt,
                q,
                m,
                children,
            });
            files.push(put(
                "prove_sound.v",
                &node_wrapper(unit, fmt, q, children, out, shape),
            )?);
            // each on its cone of influence (the whole wrapper is 700,000 variables at e3m2)
            let hit = "-set child0_exact_hit 1";
            let rejected = "-set child0_valid 1 -set unit_hit_0 0";
            format!(
                "# reachable: a valid child the segment meets, a valid child the unit rejects\n\
                 sat -set-assumes {hit} {}\nsat -set-assumes {rejected} {}\n",
                split::cone(hit),
                split::cone(rejected)
            )
        }
        Kind::Triangle => {
            let (reference, reference_text) = triangle::exact_axis_reference(fmt);
            files.push(put(&format!("{reference}.v"), &reference_text)?);
            files.push(put("prove_sound.v", &triangle::wrapper(unit, fmt, split))?);
            triangle::COVERS.to_string()
        }
        Kind::Cull(c) => {
            files.push(put("prove_sound.v", &cull_wrapper(unit, c, split))?);
            "# reachable: a segment that meets the region, and a cull of one that meets the box\n\
             sat -set-assumes -set exact_hit 1\n\
             sat -set-assumes -set exact_box_hit 1 -set unit_keep 0\n"
                .to_string()
        }
    };
    let mut script: String = files
        .iter()
        .map(|f| format!("read_verilog -formal -sv {f}\n"))
        .collect();
    if cut.as_ref().is_some_and(|c| !c.stages.is_empty()) {
        // the cut on the design as read (prep's wreduce and opt would narrow or merge the
        // unit's wires the split watches and drives)
        script += "hierarchy -top prove_sound\nproc\nflatten\ndesign -save raw\n";
    }
    script += "prep -top prove_sound\nflatten\nasync2sync\nopt -fast\nchformal -cover -remove\n\
               design -save proof\nchformal -assert -remove\n";
    script += &covers;
    let cover_script = script.clone();
    if let Some(cut) = &cut {
        script += &split::script(cut);
    } else {
        script += "design -load proof\n\
                   sat -prove-asserts -set-assumes -show-inputs -dump_vcd counterexample.vcd\n";
    }
    put("prove.ys", &script)?;
    // Yosys sat answers the covers and reads counterexamples; Boolector (SBY,
    // word-level) only proves, from the same files
    use crate::prove::{Solver, Verdict};
    let yosys_verdict = |log: &str| {
        if let Some(cut) = &cut {
            return split::verdict(log, cut);
        }
        crate::prove::sat_proof_verdict(log)
    };
    let covered_in = |log: &str| log.matches("SAT solving finished - model found").count();
    let (covered, verdict, log_path) = match solver {
        Solver::Sat | Solver::Structural => {
            let log = crate::prove::run_yosys_script(work, "prove.ys")?;
            (
                covered_in(&log),
                yosys_verdict(&log),
                work.join("prove.log"),
            )
        }
        Solver::Boolector => {
            put("cover.ys", &cover_script)?;
            let covered = covered_in(&crate::prove::run_yosys_script(work, "cover.ys")?);
            let verdict = crate::prove::boolector_verdict(
                work,
                &files,
                crate::prove::SbyCheck::Bounded(1),
                "prove_sound",
                || {
                    let log = crate::prove::run_yosys_script(work, "prove.ys")?;
                    Ok(matches!(yosys_verdict(&log), Verdict::Failed))
                },
            )?;
            let log = match verdict {
                Verdict::Failed => "prove.log",
                _ => "sby.log",
            };
            (covered, verdict, work.join(log))
        }
    };
    let bundle = is_bundle(unit);
    let (claim, contract, wanted, reachable) = match kind {
        Kind::RayBox if bundle => (
            "never reports AllMiss (any_hit = 0) while a ray of the bundle meets the box, nor AllHit \
             while one misses it"
                .to_string(),
            "box, origin, direction finite, no NaN".to_string(),
            if split { 4 } else { 3 },
            if split {
                "a hit, a rejected ray, an AllHit and an AllHit where the axes' facts the lemmas \
                 assume hold"
            } else {
                "a hit, a rejected ray and an AllHit"
            },
        ),
        Kind::RayBox => (
            "never misses a ray that meets the box".to_string(),
            format!(
                "box, origin, direction finite, no NaN{}",
                if unit.unit == "slab" {
                    "; inv_d = RTZ(1/d) by cross-multiplication"
                } else {
                    ""
                }
            ),
            if split { 3 } else { 2 },
            if split {
                "a hit, a rejected ray and a hit where the unit's per-axis results meet"
            } else {
                "a hit and a rejected ray"
            },
        ),
        Kind::Node { q, .. } => (
            format!(
                "never reports a miss for a valid child whose box (frame_origin + [lo, hi]·2^frame_exp, \
                 q = {q}) the segment from max(t_min, t_start) to t_max meets, and reports its entry \
                 t_base + entry·2^grid_exp at most where the segment enters the box"
            ),
            "origin, direction and frame finite, no NaN; inv_d = RTZ(1/d) by cross-multiplication"
                .to_string(),
            if split { 3 } else { 2 },
            if split {
                "a child the segment meets, a child the unit rejects and a hit of slot 0 where the \
                 unit's per-node terms meet"
            } else {
                "a child the segment meets and a child the unit rejects"
            },
        ),
        Kind::Triangle => (
            "never misses without flagging invalid a triangle that the line through the origin along \
             axis kz crosses with a nonzero exact area across it (t unbounded)"
                .to_string(),
            "o = ±0, s_x = s_y = ±0 (ray space exact), s_z and the vertices finite, kz ≠ 3, \
             t_min = −∞, t_max = +∞"
                .to_string(),
            if split { 4 } else { 3 },
            if split {
                "a crossed triangle hit, a crossed triangle flagged, a miss and a crossed triangle \
                 whose edge functions as the unit rounds them agree"
            } else {
                "a crossed triangle hit, a crossed triangle flagged and a miss"
            },
        ),
        Kind::Cull(c) => (
            format!(
                "never culls (keep = 0) a segment that meets the box ∩ the non-empty side of each of its {} plane(s) \
                 (e{}m{} planes)",
                c.k,
                c.plane.exp_bits(),
                c.plane.frac_bits()
            ),
            "geometry finite, no NaN; [t_lo, t_hi] ⊇ the exact segment ∩ box; no_lo ≤ n·(o − r), \
             b_lo ≤ n·d, dir its sign, rcp_lo ≤ 1/|b_lo| ≤ rcp_hi by cross-multiplication"
                .to_string(),
            if split { 3 } else { 2 },
            if split {
                "a segment that meets the region, a cull of one that meets the box and a region hit \
                 where the unit's per-plane results meet"
            } else {
                "a segment that meets the region and a cull of one that meets the box"
            },
        ),
    };
    let what = format!(
        "{} ({} {}) {claim}, for every input of e{}m{} ({contract})",
        unit.ports.top,
        unit.unit,
        unit.param_args(),
        fmt.exp_bits(),
        fmt.frac_bits(),
    );
    if let Verdict::Failed = verdict {
        let steps = crate::prove::vcd_steps(
            &std::fs::read_to_string(work.join("counterexample.vcd")).map_err(|e| e.to_string())?,
        )?;
        let at = steps.last().cloned().unwrap_or_default();
        let names: Vec<&str> = unit.ports.inputs.iter().map(|x| x.name.as_str()).collect();
        let row: Vec<String> = names
            .iter()
            .map(|n| at.get(*n).cloned().unwrap_or_else(|| "0x0".into()))
            .collect();
        let vectors = work.join("counterexample.txt");
        std::fs::write(
            &vectors,
            format!("{}\n{}\n", names.join(" "), row.join(" ")),
        )
        .map_err(|e| e.to_string())?;
        let geometry = match kind {
            Kind::RayBox | Kind::Node { .. } => {
                let d: Vec<String> = AXES
                    .iter()
                    .map(|a| at.get(&format!("d_{a}")).cloned().unwrap_or_default())
                    .collect();
                format!("the ray d = ({})", d.join(", "))
            }
            Kind::Triangle => format!(
                "the triangle {} along axis kz={}",
                triangle::VERTEX_PORTS
                    .iter()
                    .map(|n| format!("{n}={}", at.get(*n).cloned().unwrap_or_default()))
                    .collect::<Vec<_>>()
                    .join(" "),
                at.get("kz").cloned().unwrap_or_default()
            ),
            Kind::Cull(c) => {
                let mut g: Vec<String> = c.geometry().into_iter().map(|(n, _)| n).collect();
                g.extend((0..c.k).map(|j| format!("b_lo{j}")));
                format!(
                    "the geometry {}",
                    g.iter()
                        .map(|n| format!("{n}={}", at.get(n).cloned().unwrap_or_default()))
                        .collect::<Vec<_>>()
                        .join(" ")
                )
            }
        };
        return Ok(Outcome::Counterexample(format!(
            "{what}: refuted: {} with {geometry} ({}; replay: rtl-gen sim {} {}{} --in {} --out {})",
            names
                .iter()
                .zip(&row)
                .map(|(n, v)| format!("{n}={v}"))
                .collect::<Vec<_>>()
                .join(" "),
            work.join("counterexample.vcd").display(),
            unit.unit,
            unit.param_args(),
            verilog
                .map(|d| format!(" --verilog {}", d.display()))
                .unwrap_or_default(),
            vectors.display(),
            work.join("replay.txt").display()
        )));
    }
    // the lemmas' results, when split
    let lemmas = if let Some(cut) = &cut {
        let log = std::fs::read_to_string(&log_path).unwrap_or_default();
        format!(" (split: {})", split::summary(&log, cut))
    } else {
        String::new()
    };
    if !matches!(verdict, Verdict::Proved) {
        return Ok(Outcome::Unknown(format!(
            "{what}: no verdict{lemmas} in {}",
            log_path.display()
        )));
    }
    if !only.is_empty() {
        return Ok(Outcome::Unknown(format!(
            "{what}: only some of the split's lemmas were run{lemmas}, so the property is not proved ({})",
            log_path.display()
        )));
    }
    if covered < wanted {
        return Ok(Outcome::Unknown(format!(
            "{what}: proved, but not all of {reachable} are reachable under the assumptions, so the proof may be vacuous ({})",
            log_path.display()
        )));
    }
    Ok(Outcome::Proved(format!(
        "{what}: the reference agreed with the Rust exact test on {reference_cases} simulated inputs ({checked}); \
         {reachable} are reachable; {}{lemmas}, {:.1} s; {}",
        match solver {
            Solver::Sat | Solver::Structural => "Yosys sat",
            Solver::Boolector => "Boolector",
        },
        started.elapsed().as_secs_f64(),
        log_path.display()
    )))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The Verilog reference against the Rust one, in Icarus (a failure here
    /// would let a wrong reference prove a wrong unit).
    #[test]
    fn the_verilog_reference_is_the_rust_reference() {
        for (e, f) in [(2, 2), (3, 2), (2, 1), (4, 3)] {
            let fmt = FloatFormat::new(e, f).unwrap();
            let dir = std::env::temp_dir()
                .join(format!("rtl-gen-exact-ref-e{e}m{f}-{}", std::process::id()));
            let hits = check_reference(fmt, &dir, 20_000).unwrap();
            // both answers are reached
            assert!(
                hits > 1_000 && hits < 19_000,
                "e{e}m{f}: {hits} hits of 20,000"
            );
            let _ = std::fs::remove_dir_all(&dir);
        }
    }

    /// The Verilog node child reference against the Rust exact test on the
    /// decoded box in binary64, in Icarus, with both answers of `hit` and of
    /// `entry_ok` reached.
    #[test]
    fn the_verilog_node_reference_is_the_rust_reference() {
        for (e, f, q) in [(3, 2, 4), (3, 3, 5), (4, 3, 8)] {
            let fmt = FloatFormat::new(e, f).unwrap();
            let dir = std::env::temp_dir().join(format!(
                "rtl-gen-exact-node-e{e}m{f}-q{q}-{}",
                std::process::id()
            ));
            let out = NodeEntry {
                entry_bits: q + 7,
                grid_bits: e + 2,
            };
            let (hits, below, not_below) = check_node_reference(fmt, q, out, &dir, 20_000).unwrap();
            eprintln!(
                "e{e}m{f} q={q}: {hits} hits of 20,000; entries below the box's {below}, not below {not_below}"
            );
            assert!(
                hits > 1_000 && hits < 19_000 && below > 1_000 && not_below > 1_000,
                "e{e}m{f} q={q}: {hits} hits of 20,000; entries {below} below, {not_below} not"
            );
            let _ = std::fs::remove_dir_all(&dir);
        }
    }

    /// The Verilog region reference against the Rust one (golden
    /// `cull::exact::region_hit`), in Icarus, with both answers and culls
    /// that only the planes make reached.
    #[test]
    fn the_verilog_region_reference_is_the_rust_reference() {
        for (e, f, pe, pf, k) in [
            (2, 2, 2, 2, 1),
            (3, 2, 2, 2, 2),
            (3, 2, 3, 2, 1),
            (4, 3, 3, 2, 2),
        ] {
            let c = CullFormats {
                ray: FloatFormat::new(e, f).unwrap(),
                plane: FloatFormat::new(pe, pf).unwrap(),
                k,
            };
            let dir = std::env::temp_dir().join(format!(
                "rtl-gen-exact-region-e{e}m{f}-pe{pe}m{pf}-k{k}-{}",
                std::process::id()
            ));
            let (hits, culls) = check_region_reference(c, &dir, 10_000).unwrap();
            eprintln!("e{e}m{f} pe{pe}m{pf} k={k}: {hits} region hits, {culls} plane-only misses");
            assert!(
                hits > 500 && culls > 500,
                "e{e}m{f} pe{pe}m{pf} k={k}: {hits} region hits, {culls} box hits outside the region of 10,000"
            );
            let _ = std::fs::remove_dir_all(&dir);
        }
    }
}
