//! The ports of the operator modules as records ([`crate::ports::Record`]):
//! an operator's generator declares its ports with them and every instance
//! connects and reads them through the same records ([`call`]), so a port is
//! named in one place.

use super::float::{RoundSel, RM_PORT};
use crate::builder::{ModuleBuilder, Sig};
use crate::ir::{Module, Ty};
use crate::ports::{self, Record, Visit, Walk};
use std::sync::Arc;

/// A record of an operator's inputs whose port types are those of its
/// values, so an instance needs no configuration beside the values.
pub trait Operands: Record<Sig> {
    /// The ports the values fill.
    fn ports(&self) -> Self::Config;
}

/// Instantiates the operator `module` as `inst` on `inputs` and returns its
/// outputs as the record `O` (of `out`).
#[track_caller]
pub fn call<I: Operands, O: Record<Sig>>(
    m: &mut ModuleBuilder,
    inst: &str,
    module: &Arc<Module>,
    inputs: &I,
    out: &O::Config,
) -> O {
    ports::instance(m, inst, module, &inputs.ports(), inputs, out)
}

/// Instantiates a rounding operator `module` as `inst` on `inputs` and
/// returns its result `z`, an encoding of `module`'s result format.
#[track_caller]
pub fn rounded<I: Operands>(
    m: &mut ModuleBuilder,
    inst: &str,
    module: &Arc<Module>,
    inputs: &I,
) -> Sig {
    let ty = Rounded::<()>::ty_of(module);
    call::<I, Rounded<Sig>>(m, inst, module, inputs, &ty).z
}

/// The `rm` port of an operator whose rounding mode is an input.
fn rounding_mode<T: Copy, R, V: Visit<T>>(
    w: &mut Walk<'_, T, R, V>,
    present: bool,
    field: impl Fn(&R) -> Option<T>,
) -> Option<T> {
    present.then(|| {
        w.one(RM_PORT, Ty::UInt(2), |r| {
            field(r).expect("the record has its rm")
        })
    })
}

/// Two operands `a`, `b`, then `rm` when the rounding mode is an input.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Pair<T> {
    /// first operand
    pub a: T,
    /// second operand
    pub b: T,
    /// the rounding mode (`dyn` operators)
    pub rm: Option<T>,
}

/// Which ports a [`Pair`] has and their types.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PairPorts {
    /// type of `a`
    pub a: Ty,
    /// type of `b`
    pub b: Ty,
    /// an `rm` port
    pub rm: bool,
}

impl PairPorts {
    /// Two operands of type `ty`, and `rm` if the mode `sel` is an input.
    pub fn rounded(ty: Ty, sel: RoundSel) -> Self {
        PairPorts {
            a: ty,
            b: ty,
            rm: sel.is_port(),
        }
    }

    /// Two operands of type `ty`, no `rm`.
    pub fn same(ty: Ty) -> Self {
        PairPorts {
            a: ty,
            b: ty,
            rm: false,
        }
    }
}

impl Pair<Sig> {
    /// `a`, `b` of an operator with a fixed mode (or none).
    pub fn new(a: Sig, b: Sig) -> Self {
        Pair { a, b, rm: None }
    }
}

impl<T: Copy> Record<T> for Pair<T> {
    type Config = PairPorts;
    fn walk<V: Visit<T>>(c: &PairPorts, w: &mut Walk<'_, T, Self, V>) -> Self {
        Pair {
            a: w.one("a", c.a, |r| r.a),
            b: w.one("b", c.b, |r| r.b),
            rm: rounding_mode(w, c.rm, |r| r.rm),
        }
    }
}

impl Operands for Pair<Sig> {
    fn ports(&self) -> PairPorts {
        PairPorts {
            a: self.a.ty(),
            b: self.b.ty(),
            rm: self.rm.is_some(),
        }
    }
}

/// Three operands `a`, `b`, `c` of one format (`a · b + c`), then `rm`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Triple<T> {
    /// first factor
    pub a: T,
    /// second factor
    pub b: T,
    /// addend
    pub c: T,
    /// the rounding mode (`dyn` operators)
    pub rm: Option<T>,
}

impl Triple<Sig> {
    /// `a`, `b`, `c` of an operator with a fixed mode.
    pub fn new(a: Sig, b: Sig, c: Sig) -> Self {
        Triple { a, b, c, rm: None }
    }
}

impl<T: Copy> Record<T> for Triple<T> {
    /// the operands' type, an `rm` port
    type Config = (Ty, bool);
    fn walk<V: Visit<T>>(&(ty, rm): &(Ty, bool), w: &mut Walk<'_, T, Self, V>) -> Self {
        Triple {
            a: w.one("a", ty, |r| r.a),
            b: w.one("b", ty, |r| r.b),
            c: w.one("c", ty, |r| r.c),
            rm: rounding_mode(w, rm, |r| r.rm),
        }
    }
}

impl Operands for Triple<Sig> {
    fn ports(&self) -> (Ty, bool) {
        (self.a.ty(), self.rm.is_some())
    }
}

/// The factors of a three-term dot product, `a0 b0 a1 b1 a2 b2`, then `rm`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DotTerms<T> {
    /// the `a` factor of each term
    pub a: [T; 3],
    /// the `b` factor of each term
    pub b: [T; 3],
    /// the rounding mode (`dyn` operators)
    pub rm: Option<T>,
}

impl DotTerms<Sig> {
    /// The terms `a[i] · b[i]` of an operator with a fixed mode.
    pub fn new(a: [Sig; 3], b: [Sig; 3]) -> Self {
        DotTerms { a, b, rm: None }
    }
}

impl<T: Copy> Record<T> for DotTerms<T> {
    /// the `a` factors' type, the `b` factors' type, an `rm` port
    type Config = (Ty, Ty, bool);
    fn walk<V: Visit<T>>(&(ta, tb, rm): &(Ty, Ty, bool), w: &mut Walk<'_, T, Self, V>) -> Self {
        let mut a = Vec::with_capacity(3);
        let mut b = Vec::with_capacity(3);
        for i in 0..3 {
            a.push(w.one(format_args!("a{i}"), ta, |r| r.a[i]));
            b.push(w.one(format_args!("b{i}"), tb, |r| r.b[i]));
        }
        DotTerms {
            a: [a[0], a[1], a[2]],
            b: [b[0], b[1], b[2]],
            rm: rounding_mode(w, rm, |r| r.rm),
        }
    }
}

impl Operands for DotTerms<Sig> {
    fn ports(&self) -> (Ty, Ty, bool) {
        (self.a[0].ty(), self.b[0].ty(), self.rm.is_some())
    }
}

/// One operand `a` (a conversion's source), then `rm`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Source<T> {
    /// the value converted
    pub a: T,
    /// the rounding mode (`dyn` operators)
    pub rm: Option<T>,
}

impl Source<Sig> {
    /// `a` of a conversion with a fixed mode.
    pub fn new(a: Sig) -> Self {
        Source { a, rm: None }
    }
}

impl<T: Copy> Record<T> for Source<T> {
    /// the source's type, an `rm` port
    type Config = (Ty, bool);
    fn walk<V: Visit<T>>(&(ty, rm): &(Ty, bool), w: &mut Walk<'_, T, Self, V>) -> Self {
        Source {
            a: w.one("a", ty, |r| r.a),
            rm: rounding_mode(w, rm, |r| r.rm),
        }
    }
}

impl Operands for Source<Sig> {
    fn ports(&self) -> (Ty, bool) {
        (self.a.ty(), self.rm.is_some())
    }
}

/// The one operand `x` of a reciprocal or an unpacker.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Operand<T> {
    /// the operand
    pub x: T,
}

impl<T: Copy> Record<T> for Operand<T> {
    /// its type
    type Config = Ty;
    fn walk<V: Visit<T>>(&ty: &Ty, w: &mut Walk<'_, T, Self, V>) -> Self {
        Operand {
            x: w.one("x", ty, |r| r.x),
        }
    }
}

impl Operands for Operand<Sig> {
    fn ports(&self) -> Ty {
        self.x.ty()
    }
}

/// A raw value for the shared rounder: sign, class, exponent, significand,
/// sticky, then `rm` when the mode is an input.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RawValue<T> {
    /// the sign
    pub sign: T,
    /// the class (0 zero, 1 finite, 2 inf, 3 NaN)
    pub cls: T,
    /// the exponent of the significand's lsb
    pub exp: T,
    /// the significand
    pub sig: T,
    /// bits below the significand are not all zero
    pub sticky: T,
    /// the rounding mode (`dyn` rounders)
    pub rm: Option<T>,
}

impl<T: Copy> Record<T> for RawValue<T> {
    /// the exponent's type, the significand's type, an `rm` port
    type Config = (Ty, Ty, bool);
    fn walk<V: Visit<T>>(&(te, ts, rm): &(Ty, Ty, bool), w: &mut Walk<'_, T, Self, V>) -> Self {
        RawValue {
            sign: w.one("sign", Ty::Bool, |r| r.sign),
            cls: w.one("cls", Ty::UInt(2), |r| r.cls),
            exp: w.one("exp", te, |r| r.exp),
            sig: w.one("sig", ts, |r| r.sig),
            sticky: w.one("sticky", Ty::Bool, |r| r.sticky),
            rm: rounding_mode(w, rm, |r| r.rm),
        }
    }
}

impl Operands for RawValue<Sig> {
    fn ports(&self) -> (Ty, Ty, bool) {
        (self.exp.ty(), self.sig.ty(), self.rm.is_some())
    }
}

/// A raw value for the down/up rounder: a sign per direction (they differ
/// only for an exact zero whose sign depends on the mode), then as
/// [`RawValue`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RawDownUp<T> {
    /// the sign rounded toward −∞
    pub sign_down: T,
    /// the sign rounded toward +∞
    pub sign_up: T,
    /// the class (0 zero, 1 finite, 2 inf, 3 NaN)
    pub cls: T,
    /// the exponent of the significand's lsb
    pub exp: T,
    /// the significand
    pub sig: T,
    /// bits below the significand are not all zero
    pub sticky: T,
}

impl<T: Copy> Record<T> for RawDownUp<T> {
    /// the exponent's type, the significand's type
    type Config = (Ty, Ty);
    fn walk<V: Visit<T>>(&(te, ts): &(Ty, Ty), w: &mut Walk<'_, T, Self, V>) -> Self {
        RawDownUp {
            sign_down: w.one("sign_down", Ty::Bool, |r| r.sign_down),
            sign_up: w.one("sign_up", Ty::Bool, |r| r.sign_up),
            cls: w.one("cls", Ty::UInt(2), |r| r.cls),
            exp: w.one("exp", te, |r| r.exp),
            sig: w.one("sig", ts, |r| r.sig),
            sticky: w.one("sticky", Ty::Bool, |r| r.sticky),
        }
    }
}

impl Operands for RawDownUp<Sig> {
    fn ports(&self) -> (Ty, Ty) {
        (self.exp.ty(), self.sig.ty())
    }
}

/// The result `z` of a rounding operator.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Rounded<T> {
    /// the rounded result
    pub z: T,
}

impl Rounded<()> {
    /// The type of `module`'s result `z` (its first output).
    fn ty_of(module: &Module) -> Ty {
        module
            .outputs
            .first()
            .map(|(p, _)| p.ty)
            .expect("a rounding operator has its result")
    }
}

impl<T: Copy> Record<T> for Rounded<T> {
    /// the result's type
    type Config = Ty;
    fn walk<V: Visit<T>>(&ty: &Ty, w: &mut Walk<'_, T, Self, V>) -> Self {
        Rounded {
            z: w.one("z", ty, |r| r.z),
        }
    }
}

/// One value rounded toward −∞ (`down`) and toward +∞ (`up`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DownUp<T> {
    /// rounded toward −∞
    pub down: T,
    /// rounded toward +∞
    pub up: T,
}

impl<T: Copy> Record<T> for DownUp<T> {
    /// the results' type
    type Config = Ty;
    fn walk<V: Visit<T>>(&ty: &Ty, w: &mut Walk<'_, T, Self, V>) -> Self {
        DownUp {
            down: w.one("down", ty, |r| r.down),
            up: w.one("up", ty, |r| r.up),
        }
    }
}

/// The IEEE comparisons of two values.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Comparison<T> {
    /// `a < b`
    pub lt: T,
    /// `a <= b`
    pub le: T,
    /// `a == b`
    pub eq: T,
}

impl<T: Copy> Record<T> for Comparison<T> {
    type Config = ();
    fn walk<V: Visit<T>>(_: &(), w: &mut Walk<'_, T, Self, V>) -> Self {
        Comparison {
            lt: w.one("lt", Ty::Bool, |r| r.lt),
            le: w.one("le", Ty::Bool, |r| r.le),
            eq: w.one("eq", Ty::Bool, |r| r.eq),
        }
    }
}

/// The minimum and maximum of two values.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MinMax<T> {
    /// the minimum
    pub min: T,
    /// the maximum
    pub max: T,
}

impl<T: Copy> Record<T> for MinMax<T> {
    /// the values' type
    type Config = Ty;
    fn walk<V: Visit<T>>(&ty: &Ty, w: &mut Walk<'_, T, Self, V>) -> Self {
        MinMax {
            min: w.one("min", ty, |r| r.min),
            max: w.one("max", ty, |r| r.max),
        }
    }
}

/// A value unpacked: sign, class, exponent of the lsb, significand.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Fields<T> {
    /// the sign
    pub sign: T,
    /// the class (0 zero, 1 finite, 2 inf, 3 NaN)
    pub cls: T,
    /// the exponent of the significand's lsb
    pub exp: T,
    /// the significand
    pub sig: T,
}

impl<T: Copy> Record<T> for Fields<T> {
    /// the exponent's type, the significand's type
    type Config = (Ty, Ty);
    fn walk<V: Visit<T>>(&(te, ts): &(Ty, Ty), w: &mut Walk<'_, T, Self, V>) -> Self {
        Fields {
            sign: w.one("sign", Ty::Bool, |r| r.sign),
            cls: w.one("cls", Ty::UInt(2), |r| r.cls),
            exp: w.one("exp", te, |r| r.exp),
            sig: w.one("sig", ts, |r| r.sig),
        }
    }
}

/// The full product `p` of an integer multiplier.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Product<T> {
    /// `a · b`
    pub p: T,
}

impl<T: Copy> Record<T> for Product<T> {
    /// the product's type
    type Config = Ty;
    fn walk<V: Visit<T>>(&ty: &Ty, w: &mut Walk<'_, T, Self, V>) -> Self {
        Product {
            p: w.one("p", ty, |r| r.p),
        }
    }
}

/// Instantiates the integer multiplier `module` (`a · b`, full width) as
/// `inst` and returns its product.
#[track_caller]
pub fn product(m: &mut ModuleBuilder, inst: &str, module: &Arc<Module>, a: Sig, b: Sig) -> Sig {
    let ty = Ty::UInt(a.width() + b.width());
    call::<Pair<Sig>, Product<Sig>>(m, inst, module, &Pair::new(a, b), &ty).p
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::arith::float::compare::compare_module;
    use crate::arith::float::Format;

    fn two_inputs(fmt: Format) -> (ModuleBuilder, Sig, Sig) {
        let mut m = ModuleBuilder::new("calls");
        let a = m.input("a", fmt.ty());
        let b = m.input("b", fmt.ty());
        (m, a, b)
    }

    /// The comparator read through its record: its three outputs, in the
    /// module's port order.
    #[test]
    fn an_instance_reads_the_modules_own_record() {
        let fmt = Format::new(5, 4).unwrap();
        let cmp = compare_module(fmt, 0);
        let (mut m, a, b) = two_inputs(fmt);
        let c: Comparison<Sig> = call(&mut m, "u_cmp", &cmp, &Pair::new(a, b), &());
        m.output("lt", c.lt);
        m.output("eq", c.eq);
        m.finish().expect("well formed");
    }

    /// A record that is not the module's (the comparator read as a rounding
    /// operator) is a generator bug, caught at the instance.
    #[test]
    #[should_panic(expected = "the record says z")]
    fn another_modules_record_panics() {
        let fmt = Format::new(5, 4).unwrap();
        let cmp = compare_module(fmt, 0);
        let (mut m, a, b) = two_inputs(fmt);
        let _: Rounded<Sig> = call(&mut m, "u_cmp", &cmp, &Pair::new(a, b), &Ty::Bool);
    }
}
