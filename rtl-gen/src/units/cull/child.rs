//! The per-child tester's generator: the plane block (`D`, the pick of the
//! reciprocal bound, `q`) and the top that compares every entry bound with
//! every exit bound.

use super::*;
use crate::arith::ports::{rounded, Source};

/// `x` of `from` widened exactly into `to` (`from`'s exponent and fraction
/// no wider than `to`'s). Equal exponent widths: the fraction padded with
/// zeros. Otherwise the exponent is rebiased and a subnormal of `from`
/// normalised (a leading-zero count over Fp + 1 bits), or, where a
/// subnormal of `from` can stay subnormal in `to`, the converter
/// (`inst`). Infinities and zeros keep their sign; a NaN stays a NaN (its
/// payload padded, not made canonical).
#[track_caller]
pub fn widen(m: &mut ModuleBuilder, from: Format, to: Format, x: Sig, inst: &str) -> Sig {
    assert!(from.exp_bits <= to.exp_bits && from.frac_bits <= to.frac_bits);
    let pad = to.frac_bits - from.frac_bits;
    let pad_frac = |m: &mut ModuleBuilder, v: Sig| -> Sig {
        if pad == 0 {
            v
        } else {
            let z = m.uint(pad, 0);
            m.cat(&[v, z])
        }
    };
    if from.exp_bits == to.exp_bits {
        return pad_frac(m, x);
    }
    if from.emin() - (from.frac_bits as i64) < to.emin() {
        let cv = convert_module(from, to, Rounding::Rne, 0);
        return rounded(m, inst, &cv, &Source::new(x));
    }
    let (e, f) = (to.exp_bits, from.frac_bits);
    let (u, n) = m.scope("narrow", |m| {
        let u = unpack(m, from, x);
        let n = normalize(m, from, &u);
        (u, n)
    });
    let exp = add_const(m, n.exp, to.bias(), e + 2);
    let exp = m.slice(exp, e - 1, 0);
    let frac = m.slice(n.sig, f - 1, 0);
    let frac = pad_frac(m, frac);
    let ones = m.uint(e, to.exp_ones());
    let zero_e = m.uint(e, 0);
    let special = m.or(u.inf, u.nan);
    let exp = m.mux(special, ones, exp);
    let exp = m.mux(u.zero, zero_e, exp);
    let raw_frac = pad_frac(m, u.frac);
    let frac = m.mux(special, raw_frac, frac);
    let sign = m.as_uint(u.sign);
    let v = m.cat(&[sign, exp, frac]);
    m.name(v, "widened")
}

/// `!cond | invalid`: a check that does not apply.
#[track_caller]
fn unless(m: &mut ModuleBuilder, cond: Sig, invalid: Sig) -> Sig {
    let nc = m.not(cond);
    m.or(nc, invalid)
}

/// A non-NaN bound of the interval for comparisons: its order key (an
/// unsigned integer of the encoding's width whose order is the order of
/// the values, except that −0 sits just below +0:
/// `{!sign, sign ? !magnitude : magnitude}`) and whether it is ±0.
#[derive(Debug, Clone, Copy)]
struct Bound {
    key: Sig,
    zero: Sig,
}

impl Bound {
    #[track_caller]
    fn of(m: &mut ModuleBuilder, fmt: Format, v: Sig) -> Bound {
        let w = fmt.width();
        let s = m.msb(v);
        let mag = m.slice(v, w - 2, 0);
        let flipped = m.not(mag);
        let low = m.mux(s, flipped, mag);
        let ns = m.not(s);
        let top = m.as_uint(ns);
        let key = m.cat(&[top, low]);
        let zero = is_zero(m, fmt, v);
        Bound {
            key: m.name(key, "key"),
            zero: m.name(zero, "zero"),
        }
    }

    /// The bound of `−v`: the key complemented.
    #[track_caller]
    fn negated(&self, m: &mut ModuleBuilder) -> Bound {
        let key = m.not(self.key);
        Bound {
            key: m.name(key, "neg_key"),
            zero: self.zero,
        }
    }

    /// IEEE `self <= other` (one unsigned comparison of the keys, the two
    /// zeros equal), or `pass`.
    #[track_caller]
    fn le(&self, m: &mut ModuleBuilder, other: &Bound, pass: Sig, name: &str) -> Sig {
        let le = m.le(self.key, other.key);
        let zeros = m.and(self.zero, other.zero);
        let early = m.or(zeros, pass);
        let r = m.or(le, early);
        m.name(r, name)
    }
}

/// The logical steps of `cull`: the widening of `w`; the adder's exact sum
/// ([`ADD_RAW_STEPS`]) and its rounder ([`ROUND_STEPS`]); the pick of the
/// reciprocal with the multiplier's unpacking, then its significand
/// product ([`MUL_RAW_STEPS`]); the product's rounder, whose last step also
/// holds the comparisons and the verdict. The steps are of about equal
/// logic depth, so [`spread_over`] balances the stages (at 4: the widening and
/// exact sum | the sum's rounding | the product | its rounding and the
/// comparisons). Per phase, in the order of [`StagePlan`]'s fields: the
/// widening, each of the exact sum's steps (its registers are placed per
/// step), the sum's rounder, the pick and the product, the product's rounder
/// but its last step, and that step (the outputs).
pub const PHASES: [u32; 8] = [
    1,
    1,
    1,
    1,
    ROUND_STEPS,
    1 + MUL_RAW_STEPS,
    ROUND_STEPS - 1,
    1,
];

/// How `cull`'s `stages` registers are placed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct StagePlan {
    /// after the widening of `w`
    pub widen: u32,
    /// after each step of the exact sum `w − no_lo`
    pub add_raw: [u32; ADD_RAW_STEPS as usize],
    /// inside the sum's rounder
    pub add_round: u32,
    /// inside the significand multiplier
    pub mul_raw: u32,
    /// inside the product's rounder
    pub mul_round: u32,
    /// after the verdict (the outputs)
    pub out: u32,
}

impl StagePlan {
    /// The plan for `stages` registers ([`spread_over`] the [`PHASES`]).
    pub fn new(stages: u32) -> StagePlan {
        let [widen, add_0, add_1, add_2, add_round, mul_raw, mul_round, out] =
            spread_over(stages, PHASES);
        StagePlan {
            widen,
            add_raw: [add_0, add_1, add_2],
            add_round,
            mul_raw,
            mul_round,
            out,
        }
    }

    /// Registers inside the per-plane block.
    pub fn plane(&self) -> u32 {
        self.widen
            + self.add_raw.iter().sum::<u32>()
            + self.add_round
            + self.mul_raw
            + self.mul_round
    }

    /// The tag of the per-plane block's name, e.g. `w0a001r1m1p0`.
    fn tag(&self) -> String {
        let a: String = self.add_raw.iter().map(|c| c.to_string()).collect();
        format!(
            "w{}a{a}r{}m{}p{}",
            self.widen, self.add_round, self.mul_raw, self.mul_round
        )
    }
}

/// Module name of the per-plane block.
pub fn plane_name(cfg: &Config, plan: &StagePlan) -> String {
    format!(
        "cull_plane_{}_p{}_{}",
        cfg.ray.tag(),
        cfg.plane.tag(),
        plan.tag()
    )
}

/// The inputs of a per-plane block: the plane's distance, and the ray's
/// terms for the plane's normal.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PlaneIn<T> {
    /// the plane's distance, plane format
    pub w: T,
    /// `≤ n·(o − r)`, ray format
    pub no_lo: T,
    /// `≤ 1/|b_lo|`, crossing format
    pub rcp_lo: T,
    /// `≥ 1/|b_lo|`, crossing format
    pub rcp_hi: T,
}

impl<T: Copy> Record<T> for PlaneIn<T> {
    type Config = Config;
    fn walk<V: Visit<T>>(cfg: &Config, w: &mut Walk<'_, T, Self, V>) -> Self {
        let (ray, crossing) = (cfg.ray.ty(), cfg.crossing().ty());
        PlaneIn {
            w: w.one("w", cfg.plane.ty(), |r| r.w),
            no_lo: w.one("no_lo", ray, |r| r.no_lo),
            rcp_lo: w.one("rcp_lo", crossing, |r| r.rcp_lo),
            rcp_hi: w.one("rcp_hi", crossing, |r| r.rcp_hi),
        }
    }
}

/// The outputs of a per-plane block.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PlaneOut<T> {
    /// `RUP(D · rcp)`, ray format
    pub q: T,
    /// `D < 0`
    pub dist_neg: T,
}

impl<T: Copy> Record<T> for PlaneOut<T> {
    type Config = Config;
    fn walk<V: Visit<T>>(cfg: &Config, w: &mut Walk<'_, T, Self, V>) -> Self {
        PlaneOut {
            q: w.one("q", cfg.ray.ty(), |r| r.q),
            dist_neg: w.one("dist_neg", Ty::Bool, |r| r.dist_neg),
        }
    }
}

/// The per-plane block: `D = RUP(w − no_lo)` with `w` widened exactly,
/// `rcp = D > 0 ? rcp_hi : rcp_lo`, `q = RUP(D · rcp)` (the exact product
/// of a ray-format and a crossing-format significand, one rounding).
/// Inputs `w` (plane format), `no_lo` (ray), `rcp_lo`, `rcp_hi`
/// (crossing); outputs `q` and `dist_neg` (`D < 0`), [`StagePlan::plane`]
/// cycles later.
pub fn plane_module(cfg: &Config, plan: &StagePlan) -> Arc<Module> {
    let (f, pf, cf) = (cfg.ray, cfg.plane, cfg.crossing());
    let mut m = ModuleBuilder::new(plane_name(cfg, plan));
    m.describe(
        "One cull plane: D = RUP(w - no_lo) (w widened exactly into the ray format), \
         q = RUP(D * (D > 0 ? rcp_hi : rcp_lo)) from the exact product of a ray-format and a \
         crossing-format significand; dist_neg = D < 0.",
    );
    m.param("exp_bits", f.exp_bits)
        .param("frac_bits", f.frac_bits)
        .param("plane_exp_bits", pf.exp_bits)
        .param("plane_frac_bits", pf.frac_bits)
        .param("stages", plan.plane());
    let PlaneIn {
        w,
        no_lo,
        rcp_lo,
        rcp_hi,
    } = ports::declare_inputs(&mut m, cfg);
    let wf = widen(&mut m, pf, f, w, "u_widen");
    for _ in 0..plan.widen {
        m.stage();
    }
    let sum = m.scope("distance", |m| {
        add_raw(m, f, wf, no_lo, true, &plan.add_raw)
    });
    let raw = sum.for_mode(&mut m, Rounding::Rup);
    let d = round(
        &mut m,
        f,
        Rounding::Rup,
        &raw,
        plan.add_round,
        "u_round_dist",
    );
    for _ in 0..plan.add_round {
        m.stage();
    }
    let d = m.name(d, "dist_up");
    let pos = is_positive(&mut m, f, d);
    let pos = m.name(pos, "dist_pos");
    let neg = is_negative(&mut m, f, d);
    let neg = m.name(neg, "dist_neg");
    let rcp = m.mux(pos, rcp_hi, rcp_lo);
    let rcp = m.name(rcp, "rcp");
    let raw = m.scope("q", |m| {
        mul_mixed_raw(m, f, cf, d, rcp, plan.mul_raw, "u_mul")
    });
    let q = round(&mut m, f, Rounding::Rup, &raw, plan.mul_round, "u_round_q");
    for _ in 0..plan.mul_round {
        m.stage();
    }
    ports::declare_outputs(&mut m, cfg, &PlaneOut { q, dist_neg: neg });
    Arc::new(
        m.finish()
            .expect("cull plane generator is type-correct for every accepted configuration"),
    )
}

/// Module name of `cull`, e.g. `cull_e8m23_pe5m10_k4_s4`.
pub fn cull_name(cfg: &Config) -> String {
    format!("cull_{}", cfg.tag())
}

/// Builds the per-child tester.
pub fn build(cfg: &Config) -> Module {
    let (f, pf, cf) = (cfg.ray, cfg.plane, cfg.crossing());
    let k = cfg.k as usize;
    let plan = StagePlan::new(cfg.stages);
    let mut m = ModuleBuilder::with_handshake(cull_name(cfg));
    m.describe(
        "Cull-plane tester, per child (docs/cull.md): keep = the ray segment [t_lo, t_hi] (the box \
         interval) may meet the part of the child's box on the non-empty side of every plane \
         n.(x - r) <= w (keep = 0 culls the child); invalid = a NaN input, an infinite distance or \
         no_lo = +inf (then keep = 1). Per plane D = RUP(w - no_lo), q = RUP(D * rcp), exits lower \
         the exit, entries raise the entry; every rounding widens the interval.",
    );
    let CullIn {
        t_lo,
        t_hi,
        w,
        terms,
    } = ports::declare_inputs(&mut m, cfg);

    // Step 1: classify.
    let mut bad = vec![is_nan(&mut m, f, t_lo), is_nan(&mut m, f, t_hi)];
    let pinf = m.uint(f.width(), f.inf_bits());
    for j in 0..k {
        bad.push(is_special(&mut m, pf, w[j]));
        let no_lo = terms[j].no_lo;
        bad.push(is_nan(&mut m, f, no_lo));
        bad.push(m.eq(no_lo, pinf));
        bad.push(is_nan(&mut m, cf, terms[j].rcp_lo));
        bad.push(is_nan(&mut m, cf, terms[j].rcp_hi));
    }
    let invalid = any_of(&mut m, &bad, "invalid_in");
    let t_lo_neg = is_negative(&mut m, f, t_lo);
    let planes_on = m.not(t_lo_neg);
    let planes_on = m.name(planes_on, "planes_on");

    // Steps 2 and 3, per plane: D, the pick of the reciprocal, q.
    let block = plane_module(cfg, &plan);
    let mut qs = Vec::new();
    let mut par = Vec::new();
    for j in 0..k {
        let plane = PlaneIn {
            w: w[j],
            no_lo: terms[j].no_lo,
            rcp_lo: terms[j].rcp_lo,
            rcp_hi: terms[j].rcp_hi,
        };
        let out: PlaneOut<Sig> =
            ports::instance(&mut m, &format!("u_plane{j}"), &block, cfg, &plane, cfg);
        qs.push(out.q);
        let dir = terms[j].dir;
        let c_exit = m.uint(DIR_WIDTH, DIR_EXIT);
        let c_entry = m.uint(DIR_WIDTH, DIR_ENTRY);
        let is_exit = m.eq(dir, c_exit);
        let is_exit = m.name(is_exit, &format!("dir{j}_exit"));
        let is_entry = m.eq(dir, c_entry);
        let is_entry = m.name(is_entry, &format!("dir{j}_entry"));
        par.push((out.dist_neg, is_exit, is_entry));
    }
    for _ in 0..plan.plane() {
        m.stage();
    }
    let par: Vec<(Sig, Sig, Sig)> = par
        .into_iter()
        .enumerate()
        .map(|(j, (neg, is_exit, is_entry))| {
            let crossing = m.or(is_exit, is_entry);
            let parallel = m.not(crossing);
            let pc = m.and(parallel, neg);
            (m.name(pc, &format!("par_cull{j}")), is_exit, is_entry)
        })
        .collect();

    // Step 4: every bound of the entry against every bound of the exit.
    // `keep` needs max(entries) <= min(exits), i.e. l <= h for each pair;
    // one entry -q_i against one exit q_j is -q_i <= q_j, which is
    // -q_j <= q_i: one comparison per pair of planes, whichever is the
    // exit. A pair that does not apply, and an invalid input, pass.
    let lo = m.scope("t_lo", |m| Bound::of(m, f, t_lo));
    let hi = m.scope("t_hi", |m| Bound::of(m, f, t_hi));
    let mut ok = vec![lo.le(&mut m, &hi, invalid, "box_ok")];
    let mut planes = Vec::new();
    for j in 0..k {
        let q = m.name(qs[j], &format!("q{j}"));
        let (pc, is_exit, is_entry) = par[j];
        let nan = is_nan(&mut m, f, q);
        let usable = m.not(nan);
        let usable = m.and(usable, planes_on);
        let usable = m.name(usable, &format!("q{j}_usable"));
        let ex = m.and(is_exit, usable);
        let ex = m.name(ex, &format!("exit{j}"));
        let en = m.and(is_entry, usable);
        let en = m.name(en, &format!("entry{j}"));
        let (exit, entry) = m.scope(&format!("q{j}"), |m| {
            let exit = Bound::of(m, f, q);
            (exit, exit.negated(m))
        });
        let skip = unless(&mut m, ex, invalid);
        let skip = m.name(skip, &format!("exit{j}_skip"));
        ok.push(lo.le(&mut m, &exit, skip, &format!("exit{j}_ok")));
        let skip = unless(&mut m, en, invalid);
        let skip = m.name(skip, &format!("entry{j}_skip"));
        ok.push(entry.le(&mut m, &hi, skip, &format!("entry{j}_ok")));
        let pc = m.and(pc, planes_on);
        let npc = m.not(pc);
        let par_ok = m.or(npc, invalid);
        ok.push(m.name(par_ok, &format!("par{j}_ok")));
        planes.push((ex, en, exit, entry));
    }
    for j in 0..k {
        for i in 0..j {
            let (ex_i, en_i, _, entry_i) = planes[i];
            let (ex_j, en_j, exit_j, _) = planes[j];
            let ij = m.and(en_i, ex_j);
            let ji = m.and(en_j, ex_i);
            let pair = m.or(ij, ji);
            let skip = unless(&mut m, pair, invalid);
            let skip = m.name(skip, &format!("pair{i}{j}_skip"));
            ok.push(entry_i.le(&mut m, &exit_j, skip, &format!("pair{i}{j}_ok")));
        }
    }

    // Step 5: the verdict.
    let keep = all_of(&mut m, &ok, "keep_all");
    for _ in 0..plan.out {
        m.stage();
    }
    ports::declare_outputs(&mut m, cfg, &CullOut { keep, invalid });
    m.finish()
        .expect("cull generator is type-correct for every accepted configuration")
}
