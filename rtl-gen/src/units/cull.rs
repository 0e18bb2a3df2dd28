//! `cull`: the cull-plane tester (seed 001, issue #6). For a BVH node's box
//! and up to K planes, and a ray segment, reports whether the segment may
//! meet the box (`box_hit`) and the part of it on the non-empty side of every
//! plane (`keep`); `box_hit & !keep` culls the node.
//!
//! The specification is `docs/cull.md`, the golden model
//! `golden_model::cull::tester`; this generator follows its steps:
//! per axis the mirrored entry/exit numerators (one exact difference rounded
//! down and up, [`add_down_up_module`]), the centroid offsets `M = (near −
//! ô) + (far − ô)` rounded down and up; per plane `P ≥ −2A` (three exact
//! products and `2w` summed in the product format, rounded up, converted up)
//! and `B_lo ≤ n·d` (rounded down); then ratios compared by exact
//! cross-multiplication ([`mul_exact_module`], one comparison in the product
//! format): the box interval's largest entry and smallest exit, folded with
//! every plane's crossing.

use super::Unit;
use crate::arith::float::add::add_module;
use crate::arith::float::add_down_up::add_down_up_module;
use crate::arith::float::compare::compare;
use crate::arith::float::convert::convert_module;
use crate::arith::float::mul_exact::{exact_product_format, mul_exact_module};
use crate::arith::float::{spread, Format, Rounding};
use crate::builder::{ModuleBuilder, Sig};
use crate::ir::{Module, Ty};
use crate::params::{ParamError, ParamKind, ParamSpec, Params};
use std::sync::Arc;

/// The `cull` unit.
pub struct Cull;

const PARAMS: &[ParamSpec] = &[
    ParamSpec {
        name: "exp_bits",
        doc: "ray/box format exponent bits E",
        kind: ParamKind::Int { min: 2, max: 9 },
        default: "8",
    },
    ParamSpec {
        name: "frac_bits",
        doc: "ray/box format fraction bits F",
        kind: ParamKind::Int { min: 1, max: 25 },
        default: "23",
    },
    ParamSpec {
        name: "plane_exp_bits",
        doc: "plane format exponent bits (<= E)",
        kind: ParamKind::Int { min: 2, max: 9 },
        default: "5",
    },
    ParamSpec {
        name: "plane_frac_bits",
        doc: "plane format fraction bits (<= F)",
        kind: ParamKind::Int { min: 1, max: 25 },
        default: "10",
    },
    ParamSpec {
        name: "k",
        doc: "planes per node",
        kind: ParamKind::Int { min: 1, max: 8 },
        default: "4",
    },
    ParamSpec {
        name: "stages",
        doc: "pipeline stages (latency in cycles), spread over the datapath's 8 steps",
        kind: ParamKind::Int { min: 0, max: 16 },
        default: "0",
    },
];

/// Logical steps registers are spread over: numerators; centroid offsets and
/// direction products; offset products and first sums; last sums;
/// conversions; box ratio comparisons; plane folding; final comparison.
const STEPS: u32 = 8;

/// A ratio `num / (den · (den2 ? 2 : 1))`, `den > 0`.
#[derive(Clone, Copy)]
struct Frac {
    num: Sig,
    den: Sig,
    den2: Sig,
}

struct Ctx {
    wide: Format,
    mulx: Arc<Module>,
    n_inst: usize,
}

impl Ctx {
    fn inst(&mut self, what: &str) -> String {
        self.n_inst += 1;
        format!("u_{what}_{}", self.n_inst)
    }
    /// The exact product `a · b` in the wide format.
    fn mul(&mut self, m: &mut ModuleBuilder, a: Sig, b: Sig) -> Sig {
        let name = self.inst("mulx");
        let mulx = self.mulx.clone();
        m.instance(&name, &mulx, &[("a", a), ("b", b)])
            .get("z")
            .expect("z")
    }
    fn sign_bit(&self, m: &mut ModuleBuilder, f: Format) -> Sig {
        m.uint(f.width(), 1u128 << (f.width() - 1))
    }
    fn is_zero(&self, m: &mut ModuleBuilder, f: Format, v: Sig) -> Sig {
        let mag = m.slice(v, f.width() - 2, 0);
        let any = m.any_set(mag);
        m.not(any)
    }
    /// `v < 0` (IEEE: false for NaN and both zeros), without a constant
    /// comparison.
    fn is_neg(&self, m: &mut ModuleBuilder, f: Format, v: Sig) -> Sig {
        let mag = m.slice(v, f.width() - 2, 0);
        let inf = m.uint(f.width() - 1, f.inf_bits());
        let not_nan = m.le(mag, inf);
        let nonzero = m.any_set(mag);
        let s = m.msb(v);
        let s = m.and(s, nonzero);
        m.and(s, not_nan)
    }
    /// `2·v` in the wide format for the values that occur (zero, or normal
    /// far from the top), `v` unchanged if zero, infinite or NaN.
    fn dbl(&self, m: &mut ModuleBuilder, v: Sig, on: Sig) -> Sig {
        let w = self.wide;
        let exp = m.slice(v, w.width() - 2, w.frac_bits);
        let special = m.all_ones(exp);
        let zero = self.is_zero(m, w, v);
        let keep = m.or(special, zero);
        let off = m.not(on);
        let keep = m.or(keep, off);
        let one = m.uint(w.width(), 1u128 << w.frac_bits);
        let s = m.add(v, one);
        let s = m.slice(s, w.width() - 1, 0);
        m.mux(keep, v, s)
    }
    /// `a ≤ b` for ratios, by exact cross-multiplication.
    fn le(&mut self, m: &mut ModuleBuilder, a: Frac, b: Frac) -> Sig {
        let l = self.mul(m, a.num, b.den);
        let l = self.dbl(m, l, b.den2);
        let r = self.mul(m, b.num, a.den);
        let r = self.dbl(m, r, a.den2);
        let (_, le, _) = compare(m, self.wide, l, r);
        le
    }
    fn pick(&self, m: &mut ModuleBuilder, sel: Sig, a: Frac, b: Frac) -> Frac {
        Frac {
            num: m.mux(sel, a.num, b.num),
            den: m.mux(sel, a.den, b.den),
            den2: m.mux(sel, a.den2, b.den2),
        }
    }
    fn max(&mut self, m: &mut ModuleBuilder, a: Frac, b: Frac) -> Frac {
        let le = self.le(m, a, b);
        self.pick(m, le, b, a)
    }
    fn min(&mut self, m: &mut ModuleBuilder, a: Frac, b: Frac) -> Frac {
        let le = self.le(m, a, b);
        self.pick(m, le, a, b)
    }
}

/// Module name: formats, K and stages.
pub fn cull_name(fmt: Format, plane: Format, k: u32, stages: u32) -> String {
    format!("cull_{}_p{}_k{k}_s{stages}", fmt.tag(), plane.tag())
}

/// Builds the tester for ray format `fmt`, plane format `plane`, `k` planes.
pub fn build(fmt: Format, plane: Format, k: u32, stages: u32) -> Module {
    let wide = exact_product_format(fmt).expect("checked by the caller");
    let mut m = ModuleBuilder::with_handshake(cull_name(fmt, plane, k, stages));
    m.describe(
        "Cull-plane tester: box_hit = the ray segment may meet the box; keep = it may meet the box part \
         on the non-empty side of every plane (box_hit & !keep culls the node); invalid = NaN or \
         forbidden infinity (then box_hit = keep = 1). Division-free, every rounding directed so \
         that culling only becomes less likely (docs/cull.md).",
    );
    m.param("exp_bits", fmt.exp_bits)
        .param("frac_bits", fmt.frac_bits)
        .param("plane_exp_bits", plane.exp_bits)
        .param("plane_frac_bits", plane.frac_bits)
        .param("k", k)
        .param("stages", stages);
    let rw = Ty::UInt(fmt.width());
    let pw = Ty::UInt(plane.width());
    let ax = ["x", "y", "z"];
    let p_min: Vec<Sig> = ax
        .iter()
        .map(|a| m.input(&format!("p_min_{a}"), rw))
        .collect();
    let p_max: Vec<Sig> = ax
        .iter()
        .map(|a| m.input(&format!("p_max_{a}"), rw))
        .collect();
    let o: Vec<Sig> = ax.iter().map(|a| m.input(&format!("o_{a}"), rw)).collect();
    let d: Vec<Sig> = ax.iter().map(|a| m.input(&format!("d_{a}"), rw)).collect();
    let t_min = m.input("t_min", rw);
    let t_max = m.input("t_max", rw);
    let mut pn: Vec<[Sig; 3]> = Vec::new();
    let mut pwv: Vec<Sig> = Vec::new();
    for j in 0..k {
        let n = [0, 1, 2].map(|i| m.input(&format!("plane{j}_n{}", ax[i]), pw));
        pn.push(n);
        pwv.push(m.input(&format!("plane{j}_w"), pw));
    }
    let cuts = spread(stages, STEPS);
    let cut = |m: &mut ModuleBuilder, step: usize| {
        for _ in 0..cuts[step] {
            m.stage();
        }
    };
    let mut cx = Ctx {
        wide,
        mulx: mul_exact_module(fmt, 0),
        n_inst: 0,
    };
    let sb = cx.sign_bit(&mut m, fmt);
    let f = fmt;

    // Step 1: classify; mirror; numerators.
    let special = |m: &mut ModuleBuilder, ff: Format, v: Sig| {
        let e = m.slice(v, ff.width() - 2, ff.frac_bits);
        m.all_ones(e)
    };
    let mut invalid = m.bool(false);
    for v in p_min
        .iter()
        .chain(&p_max)
        .chain(&o)
        .chain(&d)
        .chain([&t_min])
    {
        let s = special(&mut m, f, *v);
        invalid = m.or(invalid, s);
    }
    {
        let inf = m.uint(f.width() - 1, f.inf_bits());
        let mag = m.slice(t_max, f.width() - 2, 0);
        let nan = m.gt(mag, inf);
        invalid = m.or(invalid, nan);
    }
    for j in 0..k as usize {
        for v in pn[j].iter().chain([&pwv[j]]) {
            let s = special(&mut m, plane, *v);
            invalid = m.or(invalid, s);
        }
    }
    let invalid = m.name(invalid, "invalid");
    let tmin_neg = cx.is_neg(&mut m, f, t_min);
    let planes_on = m.not(tmin_neg);
    let planes_on = m.name(planes_on, "planes_on");
    let adu = add_down_up_module(f, 0);
    let mut neg = Vec::new();
    let mut dz = Vec::new();
    let mut ad = Vec::new();
    let mut e_dn = Vec::new();
    let mut e_up = Vec::new();
    let mut x_dn = Vec::new();
    let mut x_up = Vec::new();
    let mut slab_ok = m.bool(true);
    let abs_mask = m.uint(f.width(), (1u128 << (f.width() - 1)) - 1);
    for i in 0..3 {
        let s = m.msb(d[i]);
        let s = m.name(s, &format!("neg_{}", ax[i]));
        let z = cx.is_zero(&mut m, f, d[i]);
        let z = m.name(z, &format!("dzero_{}", ax[i]));
        let pmax_n = m.xor(p_max[i], sb);
        let pmin_n = m.xor(p_min[i], sb);
        let near = m.mux(s, pmax_n, p_min[i]);
        let far = m.mux(s, pmin_n, p_max[i]);
        let o_n = m.xor(o[i], sb);
        let oo = m.mux(s, o_n, o[i]);
        let moo = m.xor(oo, sb);
        let e = m.instance(
            &format!("u_entry_{}", ax[i]),
            &adu,
            &[("a", near), ("b", moo)],
        );
        let x = m.instance(
            &format!("u_exit_{}", ax[i]),
            &adu,
            &[("a", far), ("b", moo)],
        );
        e_dn.push(e.get("down").unwrap());
        e_up.push(e.get("up").unwrap());
        x_dn.push(x.get("down").unwrap());
        x_up.push(x.get("up").unwrap());
        let (_, le0, _) = compare(&mut m, f, p_min[i], o[i]);
        let (_, le1, _) = compare(&mut m, f, o[i], p_max[i]);
        let inside = m.and(le0, le1);
        let nz = m.not(z);
        let ok = m.or(nz, inside);
        slab_ok = m.and(slab_ok, ok);
        neg.push(s);
        dz.push(z);
        ad.push(m.and(d[i], abs_mask));
    }
    // plane inputs widened (exact)
    let widen_n = (plane != f).then(|| convert_module(plane, f, Rounding::Rne, 0));
    let widen_w = convert_module(plane, wide, Rounding::Rne, 0);
    let mut nh: Vec<[Sig; 3]> = Vec::new();
    let mut w2: Vec<Sig> = Vec::new();
    for j in 0..k as usize {
        let mut row = [sb; 3];
        for i in 0..3 {
            let v = match &widen_n {
                Some(cv) => m
                    .instance(&format!("u_widen_p{j}_n{}", ax[i]), cv, &[("a", pn[j][i])])
                    .get("z")
                    .unwrap(),
                None => pn[j][i],
            };
            let flipped = m.xor(v, sb);
            row[i] = m.mux(neg[i], flipped, v);
        }
        nh.push(row);
        let ww = m
            .instance(&format!("u_widen_p{j}_w"), &widen_w, &[("a", pwv[j])])
            .get("z")
            .unwrap();
        let on = m.bool(true);
        w2.push(cx.dbl(&mut m, ww, on));
    }
    cut(&mut m, 0);

    // Step 2: centroid offsets; direction products.
    let add_dn = add_module(f, Rounding::Rdn, false, 0);
    let add_up = add_module(f, Rounding::Rup, false, 0);
    let mut m_lo = Vec::new();
    let mut m_hi = Vec::new();
    for i in 0..3 {
        m_lo.push(
            m.instance(
                &format!("u_mlo_{}", ax[i]),
                &add_dn,
                &[("a", e_dn[i]), ("b", x_dn[i])],
            )
            .get("z")
            .unwrap(),
        );
        m_hi.push(
            m.instance(
                &format!("u_mhi_{}", ax[i]),
                &add_up,
                &[("a", e_up[i]), ("b", x_up[i])],
            )
            .get("z")
            .unwrap(),
        );
    }
    let mut bprod: Vec<[Sig; 3]> = Vec::new();
    for j in 0..k as usize {
        let mut row = [sb; 3];
        for i in 0..3 {
            row[i] = cx.mul(&mut m, nh[j][i], ad[i]);
        }
        bprod.push(row);
    }
    cut(&mut m, 1);

    // Step 3: offset products (zero normal component → zero), first sums.
    let wadd_dn = add_module(wide, Rounding::Rdn, false, 0);
    let wadd_up = add_module(wide, Rounding::Rup, false, 0);
    let wsb = cx.sign_bit(&mut m, wide);
    let wzero = m.uint(wide.width(), 0);
    let mut q: Vec<[Sig; 3]> = Vec::new();
    let mut b01 = Vec::new();
    for j in 0..k as usize {
        let mut row = [sb; 3];
        for i in 0..3 {
            let sn = m.msb(nh[j][i]);
            let msel = m.mux(sn, m_lo[i], m_hi[i]);
            let p = cx.mul(&mut m, nh[j][i], msel);
            let nzero = cx.is_zero(&mut m, f, nh[j][i]);
            let sm = m.msb(msel);
            let sx = m.xor(sn, sm);
            let signed_zero = m.mux(sx, wsb, wzero);
            row[i] = m.mux(nzero, signed_zero, p);
        }
        q.push(row);
        b01.push(
            m.instance(
                &format!("u_b01_p{j}"),
                &wadd_dn,
                &[("a", bprod[j][0]), ("b", bprod[j][1])],
            )
            .get("z")
            .unwrap(),
        );
    }
    let mut q01 = Vec::new();
    for j in 0..k as usize {
        q01.push(
            m.instance(
                &format!("u_q01_p{j}"),
                &wadd_up,
                &[("a", q[j][0]), ("b", q[j][1])],
            )
            .get("z")
            .unwrap(),
        );
    }
    cut(&mut m, 2);

    // Step 4: last sums.
    let mut psum = Vec::new();
    let mut bsum = Vec::new();
    for j in 0..k as usize {
        let q012 = m
            .instance(
                &format!("u_q012_p{j}"),
                &wadd_up,
                &[("a", q01[j]), ("b", q[j][2])],
            )
            .get("z")
            .unwrap();
        psum.push(
            m.instance(
                &format!("u_psum_p{j}"),
                &wadd_up,
                &[("a", q012), ("b", w2[j])],
            )
            .get("z")
            .unwrap(),
        );
        bsum.push(
            m.instance(
                &format!("u_bsum_p{j}"),
                &wadd_dn,
                &[("a", b01[j]), ("b", bprod[j][2])],
            )
            .get("z")
            .unwrap(),
        );
    }
    cut(&mut m, 3);

    // Step 5: back to the ray format, rounded the safe way.
    let cv_up = convert_module(wide, f, Rounding::Rup, 0);
    let cv_dn = convert_module(wide, f, Rounding::Rdn, 0);
    let mut p_hi = Vec::new();
    let mut b_lo = Vec::new();
    for j in 0..k as usize {
        let p = m
            .instance(&format!("u_phi_p{j}"), &cv_up, &[("a", psum[j])])
            .get("z")
            .unwrap();
        p_hi.push(m.name(p, &format!("p_hi_{j}")));
        let b = m
            .instance(&format!("u_blo_p{j}"), &cv_dn, &[("a", bsum[j])])
            .get("z")
            .unwrap();
        b_lo.push(m.name(b, &format!("b_lo_{j}")));
    }
    cut(&mut m, 4);

    // Step 6: the box interval.
    let one = m.uint(f.width(), (f.bias() as u128) << f.frac_bits);
    let no = m.bool(false);
    let yes = m.bool(true);
    let unit = Frac {
        num: t_min,
        den: one,
        den2: no,
    };
    let tmax = Frac {
        num: t_max,
        den: one,
        den2: no,
    };
    let mut lo_c = vec![unit];
    let mut hi_c = vec![tmax];
    for i in 0..3 {
        let en = Frac {
            num: e_dn[i],
            den: ad[i],
            den2: no,
        };
        let ex = Frac {
            num: x_up[i],
            den: ad[i],
            den2: no,
        };
        lo_c.push(cx.pick(&mut m, dz[i], unit, en));
        hi_c.push(cx.pick(&mut m, dz[i], tmax, ex));
    }
    let a = cx.max(&mut m, lo_c[0], lo_c[1]);
    let b = cx.max(&mut m, lo_c[2], lo_c[3]);
    let lo_box = cx.max(&mut m, a, b);
    let a = cx.min(&mut m, hi_c[0], hi_c[1]);
    let b = cx.min(&mut m, hi_c[2], hi_c[3]);
    let hi_box = cx.min(&mut m, a, b);
    let box_le = cx.le(&mut m, lo_box, hi_box);
    let box_hit = m.and(slab_ok, box_le);
    let box_hit = m.name(box_hit, "box_hit_raw");
    // plane candidates
    let pinf = m.uint(f.width(), f.inf_bits());
    let ninf = m.uint(f.width(), f.inf_bits() | (1u128 << (f.width() - 1)));
    let mut par_cull = m.bool(false);
    let mut lo_p = Vec::new();
    let mut hi_p = Vec::new();
    for j in 0..k as usize {
        let p_inf = m.eq(p_hi[j], pinf);
        let b_ninf = m.eq(b_lo[j], ninf);
        let bad = m.or(p_inf, b_ninf);
        let good = m.not(bad);
        let usable = m.and(planes_on, good);
        let bz = cx.is_zero(&mut m, f, b_lo[j]);
        let p_neg = cx.is_neg(&mut m, f, p_hi[j]);
        let pc = m.and(usable, bz);
        let pc = m.and(pc, p_neg);
        par_cull = m.or(par_cull, pc);
        let bs = m.msb(b_lo[j]);
        let nbz = m.not(bz);
        let ub = m.and(usable, nbz);
        let bneg = m.and(ub, bs);
        let nbs = m.not(bs);
        let bpos = m.and(ub, nbs);
        let pneg = m.xor(p_hi[j], sb);
        let babs = m.and(b_lo[j], abs_mask);
        let lo_f = Frac {
            num: pneg,
            den: babs,
            den2: yes,
        };
        let hi_f = Frac {
            num: p_hi[j],
            den: b_lo[j],
            den2: yes,
        };
        lo_p.push(cx.pick(&mut m, bneg, lo_f, unit));
        hi_p.push(cx.pick(&mut m, bpos, hi_f, tmax));
    }
    cut(&mut m, 5);

    // Step 7: fold the planes in.
    let mut lo = lo_box;
    let mut hi = hi_box;
    for j in 0..k as usize {
        lo = cx.max(&mut m, lo, lo_p[j]);
        hi = cx.min(&mut m, hi, hi_p[j]);
    }
    cut(&mut m, 6);

    // Step 8: the verdict.
    let le = cx.le(&mut m, lo, hi);
    let npc = m.not(par_cull);
    let keep = m.and(box_hit, npc);
    let keep = m.and(keep, le);
    let box_hit = m.or(box_hit, invalid);
    let keep = m.or(keep, invalid);
    cut(&mut m, 7);
    m.output("box_hit", box_hit);
    m.output("keep", keep);
    m.output("invalid", invalid);
    m.finish()
        .expect("cull generator is type-correct for every accepted configuration")
}

/// Checks and resolves the unit's parameters.
pub fn formats(p: &Params) -> Result<(Format, Format), ParamError> {
    let f = Format::new(p.u32("exp_bits"), p.u32("frac_bits")).map_err(ParamError::Combination)?;
    let pf = Format::new(p.u32("plane_exp_bits"), p.u32("plane_frac_bits"))
        .map_err(ParamError::Combination)?;
    exact_product_format(f).map_err(ParamError::Combination)?;
    if pf.exp_bits > f.exp_bits || pf.frac_bits > f.frac_bits {
        return Err(ParamError::Combination(format!(
            "plane format {} must fit in the ray format {}",
            pf.tag(),
            f.tag()
        )));
    }
    Ok((f, pf))
}

impl Unit for Cull {
    fn name(&self) -> &'static str {
        "cull"
    }
    fn summary(&self) -> &'static str {
        "cull-plane tester: box interval folded with K planes, division-free, conservative (box_hit, keep, invalid)"
    }
    fn params(&self) -> &'static [ParamSpec] {
        PARAMS
    }
    fn build(&self, p: &Params) -> Result<Module, ParamError> {
        let (f, pf) = formats(p)?;
        Ok(build(f, pf, p.u32("k"), p.u32("stages")))
    }
}
