//! The port records of the silhouette tester and of its blocks: the top's
//! inputs and outputs, the axis block's (one axis of the top's inputs) and
//! the tests block's (the three axis blocks' outputs and the segment).

use super::*;

/// The data inputs (`*` = x, y, z). Ray: `p_min_* p_max_* o_* d_* t_min
/// t_max`, whose upper bounds are its lower ones; bundle: `p_min_* p_max_*
/// o_lo_* [o_hi_* if bounded] d_lo_* d_hi_* t_min t_max` (shared: `o_hi` is
/// `o_lo`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SilhouetteIn<T> {
    /// the box's lower corner
    pub p_min: [T; 3],
    /// the box's upper corner
    pub p_max: [T; 3],
    /// the origins' lower bounds (a ray's origin)
    pub o_lo: [T; 3],
    /// the origins' upper bounds
    pub o_hi: [T; 3],
    /// the directions' lower bounds (a ray's direction)
    pub d_lo: [T; 3],
    /// the directions' upper bounds
    pub d_hi: [T; 3],
    /// the segment's start
    pub t_min: T,
    /// the segment's end
    pub t_max: T,
}

impl<T: Copy> Record<T> for SilhouetteIn<T> {
    type Config = Config;
    fn walk<V: Visit<T>>(cfg: &Config, w: &mut Walk<'_, T, Self, V>) -> Self {
        let ty = Ty::UInt(cfg.fmt.width());
        let b = Bounds::from_ports(cfg, |name, field| w.xyz(name, ty, |r| field(&r.bounds())));
        SilhouetteIn {
            p_min: b.p_min,
            p_max: b.p_max,
            o_lo: b.o_lo,
            o_hi: b.o_hi,
            d_lo: b.d_lo,
            d_hi: b.d_hi,
            t_min: w.one("t_min", ty, |r| r.t_min),
            t_max: w.one("t_max", ty, |r| r.t_max),
        }
    }
}

impl<T: Copy> SilhouetteIn<T> {
    /// The box, origin and direction bounds, a vector each.
    fn bounds(&self) -> Bounds<[T; 3]> {
        Bounds {
            p_min: self.p_min,
            p_max: self.p_max,
            o_lo: self.o_lo,
            o_hi: self.o_hi,
            d_lo: self.d_lo,
            d_hi: self.d_hi,
        }
    }

    /// The box, origin and direction bounds of axis `i`: the axis block's
    /// inputs.
    pub fn axis(&self, i: usize) -> AxisIn<T> {
        let b = self.bounds();
        Bounds {
            p_min: b.p_min[i],
            p_max: b.p_max[i],
            o_lo: b.o_lo[i],
            o_hi: b.o_hi[i],
            d_lo: b.d_lo[i],
            d_hi: b.d_hi[i],
        }
    }
}

/// The box, origin and direction bounds of a test's inputs: a vector each
/// at the top ([`SilhouetteIn`]), one axis in the axis block ([`AxisIn`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Bounds<P> {
    /// the box's lower bound
    pub p_min: P,
    /// the box's upper bound
    pub p_max: P,
    /// the origins' lower bound (a ray's origin)
    pub o_lo: P,
    /// the origins' upper bound
    pub o_hi: P,
    /// the directions' lower bound (a ray's direction)
    pub d_lo: P,
    /// the directions' upper bound
    pub d_hi: P,
}

impl<P: Copy> Bounds<P> {
    /// The ports' rules, once for the top and the axis block: ray `p_min
    /// p_max o d` (its upper bounds are its lower ones); bundle `p_min p_max
    /// o_lo [o_hi if bounded] d_lo d_hi` (a shared origin has no `o_hi`).
    /// `port(name, field)` makes or reads the port of the bound `field`.
    fn from_ports(cfg: &Config, mut port: impl FnMut(&'static str, fn(&Self) -> P) -> P) -> Self {
        let ray = cfg.ray();
        let p_min = port("p_min", |b| b.p_min);
        let p_max = port("p_max", |b| b.p_max);
        let o_lo = port(if ray { "o" } else { "o_lo" }, |b| b.o_lo);
        let o_hi = if cfg.bounded() {
            port("o_hi", |b| b.o_hi)
        } else {
            o_lo
        };
        let d_lo = port(if ray { "d" } else { "d_lo" }, |b| b.d_lo);
        let d_hi = if ray { d_lo } else { port("d_hi", |b| b.d_hi) };
        Bounds {
            p_min,
            p_max,
            o_lo,
            o_hi,
            d_lo,
            d_hi,
        }
    }
}

/// The axis block's inputs: one axis of [`SilhouetteIn`], the same ports
/// without the axis suffix.
pub type AxisIn<T> = Bounds<T>;

impl<T: Copy> Record<T> for Bounds<T> {
    type Config = Config;
    fn walk<V: Visit<T>>(cfg: &Config, w: &mut Walk<'_, T, Self, V>) -> Self {
        let ty = Ty::UInt(cfg.fmt.width());
        Bounds::from_ports(cfg, |name, field| w.one(name, ty, field))
    }
}

/// The axis block's outputs. Ray: `a` (`|d|`), `n` (entry numerator,
/// rounded down), `x` (exit numerator, rounded up), read as both corners'
/// (`b = a`, `n_all = n_any = n`, `x_all = x_any = x`). Bundle: `neg`
/// (`d_lo < 0`: the axis is mirrored), `pos` (`d_hi > 0`), `a`/`b`
/// (smallest / largest `|d|`), `n_any x_any n_all x_all`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct AxisOut<T> {
    /// the axis is mirrored (bundle)
    pub neg: Option<T>,
    /// the largest direction is positive (bundle)
    pub pos: Option<T>,
    /// the smallest `|d|`
    pub a: T,
    /// the largest `|d|`
    pub b: T,
    /// AnyHit entry numerator
    pub n_any: T,
    /// AnyHit exit numerator
    pub x_any: T,
    /// AllHit entry numerator
    pub n_all: T,
    /// AllHit exit numerator
    pub x_all: T,
}

impl<T: Copy> AxisOut<T> {
    /// A ray's axis: `|d|`, its entry and exit numerators, as both corners.
    pub fn ray(a: T, n: T, x: T) -> Self {
        AxisOut {
            neg: None,
            pos: None,
            a,
            b: a,
            n_any: n,
            x_any: x,
            n_all: n,
            x_all: x,
        }
    }
}

impl<T: Copy> Record<T> for AxisOut<T> {
    type Config = Config;
    fn walk<V: Visit<T>>(cfg: &Config, w: &mut Walk<'_, T, Self, V>) -> Self {
        let ty = Ty::UInt(cfg.fmt.width());
        if cfg.ray() {
            let a = w.one("a", ty, |r| r.a);
            let n = w.one("n", ty, |r| r.n_any);
            let x = w.one("x", ty, |r| r.x_any);
            return AxisOut::ray(a, n, x);
        }
        let bundle_only = "a bundle's axis has its signs";
        AxisOut {
            neg: Some(w.one("neg", Ty::Bool, |r| r.neg.expect(bundle_only))),
            pos: Some(w.one("pos", Ty::Bool, |r| r.pos.expect(bundle_only))),
            a: w.one("a", ty, |r| r.a),
            b: w.one("b", ty, |r| r.b),
            n_any: w.one("n_any", ty, |r| r.n_any),
            x_any: w.one("x_any", ty, |r| r.x_any),
            n_all: w.one("n_all", ty, |r| r.n_all),
            x_all: w.one("x_all", ty, |r| r.x_all),
        }
    }
}

/// The tests block's inputs: per axis the numerators and the bounds of
/// `|d|` of every axis block, then the segment. Ray: `n_* x_* d_* t_min
/// t_max` (one corner); bundle: `n_any_* x_any_* n_all_* x_all_* a_* b_*
/// t_min t_max`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TestsIn<T> {
    /// AnyHit entry numerators
    pub n_any: [T; 3],
    /// AnyHit exit numerators
    pub x_any: [T; 3],
    /// AllHit entry numerators
    pub n_all: [T; 3],
    /// AllHit exit numerators
    pub x_all: [T; 3],
    /// smallest `|d|`
    pub a: [T; 3],
    /// largest `|d|`
    pub b: [T; 3],
    /// segment start
    pub t_min: T,
    /// segment end
    pub t_max: T,
}

impl<T: Copy> TestsIn<T> {
    /// The inputs from the three axis blocks' outputs and the segment.
    pub fn from_axes(axes: &[AxisOut<T>; 3], t_min: T, t_max: T) -> Self {
        let per_axis = |f: fn(&AxisOut<T>) -> T| [f(&axes[0]), f(&axes[1]), f(&axes[2])];
        TestsIn {
            n_any: per_axis(|a| a.n_any),
            x_any: per_axis(|a| a.x_any),
            n_all: per_axis(|a| a.n_all),
            x_all: per_axis(|a| a.x_all),
            a: per_axis(|a| a.a),
            b: per_axis(|a| a.b),
            t_min,
            t_max,
        }
    }
}

impl<T: Copy> Record<T> for TestsIn<T> {
    type Config = Config;
    fn walk<V: Visit<T>>(cfg: &Config, w: &mut Walk<'_, T, Self, V>) -> Self {
        let ty = Ty::UInt(cfg.fmt.width());
        let (n_any, x_any, n_all, x_all, a, b) = if cfg.ray() {
            let n = w.xyz("n", ty, |r| r.n_any);
            let x = w.xyz("x", ty, |r| r.x_any);
            let d = w.xyz("d", ty, |r| r.a);
            (n, x, n, x, d, d)
        } else {
            (
                w.xyz("n_any", ty, |r| r.n_any),
                w.xyz("x_any", ty, |r| r.x_any),
                w.xyz("n_all", ty, |r| r.n_all),
                w.xyz("x_all", ty, |r| r.x_all),
                w.xyz("a", ty, |r| r.a),
                w.xyz("b", ty, |r| r.b),
            )
        };
        TestsIn {
            n_any,
            x_any,
            n_all,
            x_all,
            a,
            b,
            t_min: w.one("t_min", ty, |r| r.t_min),
            t_max: w.one("t_max", ty, |r| r.t_max),
        }
    }
}

/// The tests block's outputs: ray `pass` (read as both), bundle `pass_any
/// pass_all`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TestsOut<T> {
    /// every AnyHit test passes
    pub pass_any: T,
    /// every AllHit test passes
    pub pass_all: T,
}

impl<T: Copy> Record<T> for TestsOut<T> {
    type Config = Config;
    fn walk<V: Visit<T>>(cfg: &Config, w: &mut Walk<'_, T, Self, V>) -> Self {
        if cfg.ray() {
            let pass = w.one("pass", Ty::Bool, |r| r.pass_any);
            return TestsOut {
                pass_any: pass,
                pass_all: pass,
            };
        }
        TestsOut {
            pass_any: w.one("pass_any", Ty::Bool, |r| r.pass_any),
            pass_all: w.one("pass_all", Ty::Bool, |r| r.pass_all),
        }
    }
}

/// The data outputs. Ray: `hit nan invalid` (`hit` is `any_hit`); bundle:
/// `all_hit any_hit nan invalid mixed_sign`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SilhouetteOut<T> {
    /// every ray of the bundle hits the box (bundle only)
    pub all_hit: Option<T>,
    /// 0 only if every ray misses the box (a ray's `hit`)
    pub any_hit: T,
    /// a NaN input
    pub nan: T,
    /// an infinite or unordered origin or direction
    pub invalid: T,
    /// the direction bounds straddle 0 on an axis (bundle only)
    pub mixed_sign: Option<T>,
}

impl<T: Copy> Record<T> for SilhouetteOut<T> {
    type Config = Config;
    fn walk<V: Visit<T>>(cfg: &Config, w: &mut Walk<'_, T, Self, V>) -> Self {
        let bundle_only = "a bundle's record has every output";
        if cfg.ray() {
            SilhouetteOut {
                any_hit: w.one("hit", Ty::Bool, |r| r.any_hit),
                all_hit: None,
                nan: w.one("nan", Ty::Bool, |r| r.nan),
                invalid: w.one("invalid", Ty::Bool, |r| r.invalid),
                mixed_sign: None,
            }
        } else {
            SilhouetteOut {
                all_hit: Some(w.one("all_hit", Ty::Bool, |r| r.all_hit.expect(bundle_only))),
                any_hit: w.one("any_hit", Ty::Bool, |r| r.any_hit),
                nan: w.one("nan", Ty::Bool, |r| r.nan),
                invalid: w.one("invalid", Ty::Bool, |r| r.invalid),
                mixed_sign: Some(
                    w.one("mixed_sign", Ty::Bool, |r| r.mixed_sign.expect(bundle_only)),
                ),
            }
        }
    }
}
