//! The operations of the DSL: arithmetic, logic, comparisons, shifts,
//! selection, bit fields and casts, each checking its operand types.

use super::{ModuleBuilder, Sig};
use crate::ir::*;

impl ModuleBuilder {
    #[track_caller]
    fn expect_arith(&mut self, what: &str, a: Sig, b: Sig) -> bool {
        let ok = matches!(
            (a.ty, b.ty),
            (Ty::UInt(_), Ty::UInt(_)) | (Ty::SInt(_), Ty::SInt(_))
        );
        if !ok {
            let name = format!("{}, {}", self.name_of(a.id), self.name_of(b.id));
            self.error(
                name,
                format!(
                    "{what} needs two UInt or two SInt operands, got {} and {}",
                    a.ty, b.ty
                ),
            );
        }
        ok
    }

    #[track_caller]
    fn expect_same(&mut self, what: &str, a: Sig, b: Sig) -> bool {
        if a.ty != b.ty {
            let name = format!("{}, {}", self.name_of(a.id), self.name_of(b.id));
            self.error(
                name,
                format!(
                    "{what} needs operands of one type, got {} and {}",
                    a.ty, b.ty
                ),
            );
            return false;
        }
        true
    }

    /// a + b, one bit wider than the wider operand (never wraps).
    #[track_caller]
    pub fn add(&mut self, a: Sig, b: Sig) -> Sig {
        let ty = a.ty.with_width(a.width().max(b.width()) + 1);
        if !self.expect_arith("add", a, b) {
            return self.poison(ty);
        }
        self.op(Op::Add(a.id, b.id), ty)
    }

    /// a − b, signed and one bit wider than the wider operand (never wraps).
    #[track_caller]
    pub fn sub(&mut self, a: Sig, b: Sig) -> Sig {
        let ty = Ty::SInt(a.width().max(b.width()) + 1);
        if !self.expect_arith("sub", a, b) {
            return self.poison(ty);
        }
        self.op(Op::Sub(a.id, b.id), ty)
    }

    /// a · b, the full product: as wide as both operands together.
    #[track_caller]
    pub fn mul(&mut self, a: Sig, b: Sig) -> Sig {
        let ty = a.ty.with_width(a.width() + b.width());
        if !self.expect_arith("mul", a, b) {
            return self.poison(ty);
        }
        self.op(Op::Mul(a.id, b.id), ty)
    }

    /// Bitwise complement, same type.
    #[track_caller]
    pub fn not(&mut self, a: Sig) -> Sig {
        self.op(Op::Not(a.id), a.ty)
    }

    #[track_caller]
    fn bit(&mut self, op: BitOp, a: Sig, b: Sig) -> Sig {
        if !self.expect_same("bitwise operation", a, b) {
            return self.poison(a.ty);
        }
        self.op(Op::Bit(op, a.id, b.id), a.ty)
    }

    /// a & b, same type.
    #[track_caller]
    pub fn and(&mut self, a: Sig, b: Sig) -> Sig {
        self.bit(BitOp::And, a, b)
    }

    /// a | b, same type.
    #[track_caller]
    pub fn or(&mut self, a: Sig, b: Sig) -> Sig {
        self.bit(BitOp::Or, a, b)
    }

    /// a ^ b, same type.
    #[track_caller]
    pub fn xor(&mut self, a: Sig, b: Sig) -> Sig {
        self.bit(BitOp::Xor, a, b)
    }

    #[track_caller]
    fn cmp(&mut self, op: CmpOp, a: Sig, b: Sig) -> Sig {
        let ok = match (a.ty, b.ty) {
            (Ty::Bool, Ty::Bool) => op == CmpOp::Eq,
            _ => self.expect_arith("comparison", a, b),
        };
        if !ok {
            if a.ty == Ty::Bool {
                self.error(
                    self.name_of(a.id).to_string(),
                    "only == compares Bool values",
                );
            }
            return self.poison(Ty::Bool);
        }
        // an unsigned value is never below zero: fold `x < 0` and `0 <= x`,
        // which Verilator rejects as constant comparisons (UNSIGNED)
        let is_zero = |s: Sig| matches!(self.nodes[s.id.0 as usize].op, Op::Const(0));
        match op {
            CmpOp::Lt if !b.ty.is_signed() && is_zero(b) => return self.bool(false),
            CmpOp::Le if !a.ty.is_signed() && is_zero(a) => return self.bool(true),
            _ => {}
        }
        self.op(Op::Cmp(op, a.id, b.id), Ty::Bool)
    }

    /// a == b, `Bool`.
    #[track_caller]
    pub fn eq(&mut self, a: Sig, b: Sig) -> Sig {
        self.cmp(CmpOp::Eq, a, b)
    }

    /// a != b, `Bool`.
    #[track_caller]
    pub fn ne(&mut self, a: Sig, b: Sig) -> Sig {
        let e = self.cmp(CmpOp::Eq, a, b);
        self.not(e)
    }

    /// a < b, `Bool` (signed compare for SInt operands).
    #[track_caller]
    pub fn lt(&mut self, a: Sig, b: Sig) -> Sig {
        self.cmp(CmpOp::Lt, a, b)
    }

    /// a <= b, `Bool`.
    #[track_caller]
    pub fn le(&mut self, a: Sig, b: Sig) -> Sig {
        self.cmp(CmpOp::Le, a, b)
    }

    /// a > b, `Bool`.
    #[track_caller]
    pub fn gt(&mut self, a: Sig, b: Sig) -> Sig {
        self.cmp(CmpOp::Lt, b, a)
    }

    /// a >= b, `Bool`.
    #[track_caller]
    pub fn ge(&mut self, a: Sig, b: Sig) -> Sig {
        self.cmp(CmpOp::Le, b, a)
    }

    #[track_caller]
    fn shift(&mut self, left: bool, a: Sig, amount: Sig) -> Sig {
        if !matches!(amount.ty, Ty::UInt(_)) || a.ty == Ty::Bool {
            let name = self.name_of(a.id).to_string();
            self.error(
                name,
                format!(
                    "shift of {} by {}: needs a vector shifted by a UInt",
                    a.ty, amount.ty
                ),
            );
            return self.poison(a.ty);
        }
        let op = if left {
            Op::Shl(a.id, amount.id)
        } else {
            Op::Shr(a.id, amount.id)
        };
        self.op(op, a.ty)
    }

    /// a << amount, width of a (bits shifted out are lost).
    #[track_caller]
    pub fn shl(&mut self, a: Sig, amount: Sig) -> Sig {
        self.shift(true, a, amount)
    }

    /// a >> amount, width of a; arithmetic for SInt, logical for UInt.
    #[track_caller]
    pub fn shr(&mut self, a: Sig, amount: Sig) -> Sig {
        self.shift(false, a, amount)
    }

    /// sel ? t : f, type of t and f.
    #[track_caller]
    pub fn mux(&mut self, sel: Sig, t: Sig, f: Sig) -> Sig {
        if sel.ty != Ty::Bool {
            let name = self.name_of(sel.id).to_string();
            self.error(name, format!("mux select must be Bool, got {}", sel.ty));
            return self.poison(t.ty);
        }
        if !self.expect_same("mux", t, f) {
            return self.poison(t.ty);
        }
        self.op(Op::Mux(sel.id, t.id, f.id), t.ty)
    }

    /// Concatenation, first part most significant; UInt as wide as all parts.
    #[track_caller]
    pub fn cat(&mut self, parts: &[Sig]) -> Sig {
        match parts {
            [] => {
                self.error("{}", "concatenation of nothing");
                self.poison(Ty::Bool)
            }
            [one] => self.as_uint(*one),
            _ => {
                let w = parts.iter().map(|p| p.width()).sum();
                self.op(
                    Op::Concat(parts.iter().map(|p| p.id).collect()),
                    Ty::UInt(w),
                )
            }
        }
    }

    /// Bits hi..=lo of a, unsigned, hi − lo + 1 wide.
    #[track_caller]
    pub fn slice(&mut self, a: Sig, hi: u32, lo: u32) -> Sig {
        if lo > hi || hi >= a.width() {
            let name = self.name_of(a.id).to_string();
            self.error(name, format!("slice [{hi}:{lo}] of {}", a.ty));
            return self.poison(Ty::UInt(hi.saturating_sub(lo) + 1));
        }
        // A slice of a slice, of a cast or of one part of a concatenation
        // built in this stage reads that part directly: the same bits, one
        // wire fewer (earlier stages are left alone: the register would hold
        // the wider source instead of the slice).
        let (mut src, mut hi, mut lo) = (a.id, hi, lo);
        while self.stage_of[src.0 as usize] == Some(self.current_stage) {
            match &self.nodes[src.0 as usize].op {
                Op::Cast(x) => src = *x,
                Op::Slice(x, _, l) => (src, hi, lo) = (*x, hi + l, lo + l),
                Op::Concat(parts) => {
                    // parts are listed most significant first
                    let mut top = self.nodes[src.0 as usize].ty.width();
                    let mut inside = None;
                    for p in parts {
                        let w = self.nodes[p.0 as usize].ty.width();
                        if lo >= top - w && hi < top {
                            inside = Some((*p, hi - (top - w), lo - (top - w)));
                            break;
                        }
                        top -= w;
                    }
                    match inside {
                        Some(part) => (src, hi, lo) = part,
                        None => break,
                    }
                }
                _ => break,
            }
        }
        let src = Sig {
            id: src,
            ty: self.nodes[src.0 as usize].ty,
        };
        if lo == 0 && hi + 1 == src.width() {
            return self.as_uint(src);
        }
        self.op(Op::Slice(src.id, hi, lo), Ty::UInt(hi - lo + 1))
    }

    /// Bit i of a, as `Bool`.
    #[track_caller]
    pub fn bit_at(&mut self, a: Sig, i: u32) -> Sig {
        let s = self.slice(a, i, i);
        self.as_bool(s)
    }

    /// The most significant bit (the sign of an SInt), as `Bool`.
    #[track_caller]
    pub fn msb(&mut self, a: Sig) -> Sig {
        self.bit_at(a, a.width() - 1)
    }

    #[track_caller]
    fn reduce(&mut self, op: ReduceOp, a: Sig) -> Sig {
        if a.width() == 1 {
            return self.as_bool(a);
        }
        self.op(Op::Reduce(op, a.id), Ty::Bool)
    }

    /// True if every bit of a is set.
    #[track_caller]
    pub fn all_ones(&mut self, a: Sig) -> Sig {
        self.reduce(ReduceOp::And, a)
    }

    /// True if any bit of a is set.
    #[track_caller]
    pub fn any_set(&mut self, a: Sig) -> Sig {
        self.reduce(ReduceOp::Or, a)
    }

    /// True if an odd number of bits of a is set.
    #[track_caller]
    pub fn parity(&mut self, a: Sig) -> Sig {
        self.reduce(ReduceOp::Xor, a)
    }

    /// The same bits as type `ty` (same width required).
    #[track_caller]
    pub fn cast(&mut self, a: Sig, ty: Ty) -> Sig {
        if a.ty == ty {
            return a;
        }
        if a.width() != ty.width() {
            let name = self.name_of(a.id).to_string();
            self.error(name, format!("cast of {} to {}: widths differ", a.ty, ty));
            return self.poison(ty);
        }
        // a cast of a cast in this stage is a cast of the source: one node,
        // and equal values stay equal for the emitter's hash-consing
        if let Op::Cast(src) = self.nodes[a.id.0 as usize].op {
            if self.stage_of[a.id.0 as usize] == Some(self.current_stage) {
                let src = Sig {
                    id: src,
                    ty: self.nodes[src.0 as usize].ty,
                };
                return self.cast(src, ty);
            }
        }
        self.op(Op::Cast(a.id), ty)
    }

    /// The same bits as UInt.
    #[track_caller]
    pub fn as_uint(&mut self, a: Sig) -> Sig {
        self.cast(a, Ty::UInt(a.width()))
    }

    /// The same bits as SInt.
    #[track_caller]
    pub fn as_sint(&mut self, a: Sig) -> Sig {
        self.cast(a, Ty::SInt(a.width()))
    }

    /// A one-bit value as Bool.
    #[track_caller]
    pub fn as_bool(&mut self, a: Sig) -> Sig {
        self.cast(a, Ty::Bool)
    }
}
