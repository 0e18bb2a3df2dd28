//! A small cycle-based evaluator of the IR, for fast unit tests of the
//! generator. The simulator of record is Verilator; the reference for
//! correctness is the golden model.

use crate::ir::*;

/// The low `w` bits of `v`.
pub fn mask(v: u128, w: u32) -> u128 {
    if w >= 128 {
        v
    } else {
        v & ((1u128 << w) - 1)
    }
}

/// `v` (of width `w`) read as two's complement.
fn to_signed(v: u128, w: u32) -> i128 {
    if w >= 128 {
        v as i128
    } else if (v >> (w - 1)) & 1 == 1 {
        (v | !((1u128 << w) - 1)) as i128
    } else {
        v as i128
    }
}

/// `v` of type `ty` extended to 128 bits by its signedness.
fn extend(v: u128, ty: Ty) -> i128 {
    if ty.is_signed() {
        to_signed(v, ty.width())
    } else {
        v as i128
    }
}

/// Evaluates one operation on operand values (with their types); `ty` is the
/// result type. Sources (inputs, registers, instances) are not handled here.
pub fn eval_op(op: &Op, ty: Ty, args: &[(u128, Ty)]) -> u128 {
    let w = ty.width();
    let a = || args[0];
    let b = || args[1];
    let r: u128 = match op {
        Op::Input(_) | Op::Reg(_) | Op::InstOut { .. } => {
            unreachable!("sources are read by the simulator")
        }
        Op::Const(v) => *v,
        Op::Add(..) => extend(a().0, a().1).wrapping_add(extend(b().0, b().1)) as u128,
        Op::Sub(..) => extend(a().0, a().1).wrapping_sub(extend(b().0, b().1)) as u128,
        Op::Mul(..) => extend(a().0, a().1).wrapping_mul(extend(b().0, b().1)) as u128,
        Op::Not(_) => !a().0,
        Op::Bit(BitOp::And, ..) => a().0 & b().0,
        Op::Bit(BitOp::Or, ..) => a().0 | b().0,
        Op::Bit(BitOp::Xor, ..) => a().0 ^ b().0,
        Op::Cmp(c, ..) => {
            let (x, y) = (extend(a().0, a().1), extend(b().0, b().1));
            let holds = match c {
                CmpOp::Eq => x == y,
                // unsigned operands are < 2^128 only when width is 128; compare as u128 then
                CmpOp::Lt if !a().1.is_signed() => a().0 < b().0,
                CmpOp::Le if !a().1.is_signed() => a().0 <= b().0,
                CmpOp::Lt => x < y,
                CmpOp::Le => x <= y,
            };
            holds as u128
        }
        Op::Shl(..) => {
            let n = b().0;
            if n >= w as u128 {
                0
            } else {
                a().0 << n
            }
        }
        Op::Shr(..) => {
            let n = b().0.min(127) as u32;
            if a().1.is_signed() {
                (to_signed(a().0, w) >> n) as u128
            } else if n >= w {
                0
            } else {
                a().0 >> n
            }
        }
        Op::Mux(..) => {
            if args[0].0 & 1 == 1 {
                args[1].0
            } else {
                args[2].0
            }
        }
        Op::Concat(_) => args.iter().fold(0u128, |acc, (v, t)| {
            let tw = t.width();
            if tw >= 128 {
                *v
            } else {
                (acc << tw) | mask(*v, tw)
            }
        }),
        Op::Slice(_, _, lo) => a().0 >> lo,
        Op::Reduce(ReduceOp::And, _) => {
            (mask(a().0, a().1.width()) == mask(u128::MAX, a().1.width())) as u128
        }
        Op::Reduce(ReduceOp::Or, _) => (a().0 != 0) as u128,
        Op::Reduce(ReduceOp::Xor, _) => (a().0.count_ones() & 1) as u128,
        Op::Cast(_) => a().0,
    };
    mask(r, w)
}

/// Cycle-based simulation state of one module instance (and its submodules).
#[derive(Debug, Clone)]
pub struct Evaluator<'m> {
    module: &'m Module,
    /// operands of every node, resolved once
    operands: Vec<Vec<NodeId>>,
    values: Vec<u128>,
    regs: Vec<u128>,
    subs: Vec<Evaluator<'m>>,
    /// outputs of each instance in the current cycle
    sub_outputs: Vec<Vec<u128>>,
    evaluated: Vec<bool>,
    scratch: Vec<(u128, Ty)>,
    rst: bool,
}

impl<'m> Evaluator<'m> {
    /// Registers start at zero, as after `--x-initial fast` in Verilator.
    pub fn new(module: &'m Module) -> Self {
        let n = module.instances.len();
        Evaluator {
            module,
            operands: module.nodes.iter().map(|node| node.op.operands()).collect(),
            values: vec![0; module.nodes.len()],
            regs: vec![0; module.registers.len()],
            subs: module
                .instances
                .iter()
                .map(|i| Evaluator::new(&i.module))
                .collect(),
            sub_outputs: vec![Vec::new(); n],
            evaluated: vec![false; n],
            scratch: Vec::new(),
            rst: false,
        }
    }

    /// Drives the reset input (synchronous: takes effect at the next clock).
    pub fn set_reset(&mut self, rst: bool) {
        self.rst = rst;
        for s in &mut self.subs {
            s.set_reset(rst);
        }
    }

    /// Evaluates instance `inst` once for this cycle, from its input nodes.
    fn eval_instance(&mut self, inst: usize) {
        let inputs: Vec<u128> = self.module.instances[inst]
            .inputs
            .iter()
            .map(|id| self.values[id.0 as usize])
            .collect();
        self.sub_outputs[inst] = self.subs[inst].eval(&inputs);
        self.evaluated[inst] = true;
    }

    /// Computes every node from the inputs (in port order, valid first if the
    /// module has a handshake) and the registers; returns the outputs in port
    /// order. Each instance is evaluated once (its inputs precede its outputs
    /// in the arena).
    pub fn eval(&mut self, inputs: &[u128]) -> Vec<u128> {
        let m = self.module;
        self.evaluated.fill(false);
        for (i, node) in m.nodes.iter().enumerate() {
            let v = match &node.op {
                Op::Input(p) => mask(inputs[*p], node.ty.width()),
                Op::Reg(r) => self.regs[*r],
                Op::InstOut { inst, port } => {
                    if !self.evaluated[*inst] {
                        self.eval_instance(*inst);
                    }
                    self.sub_outputs[*inst][*port]
                }
                op => {
                    self.scratch.clear();
                    for id in &self.operands[i] {
                        self.scratch
                            .push((self.values[id.0 as usize], m.node(*id).ty));
                    }
                    eval_op(op, node.ty, &self.scratch)
                }
            };
            self.values[i] = v;
        }
        // instances whose outputs nothing reads still hold state
        for inst in 0..m.instances.len() {
            if !self.evaluated[inst] {
                self.eval_instance(inst);
            }
        }
        m.outputs
            .iter()
            .map(|(_, id)| self.values[id.0 as usize])
            .collect()
    }

    /// A rising clock edge: registers load the values of the last `eval`.
    pub fn clock(&mut self) {
        for sub in &mut self.subs {
            sub.clock();
        }
        let m = self.module;
        for (r, cur) in m.registers.iter().zip(self.regs.iter_mut()) {
            *cur = match (self.rst, r.reset) {
                (true, Some(v)) => v,
                _ if r.enable.is_some_and(|e| self.values[e.0 as usize] == 0) => *cur,
                _ => self.values[r.next.0 as usize],
            };
        }
    }

    /// One full cycle: evaluate with `inputs`, sample outputs, clock.
    pub fn step(&mut self, inputs: &[u128]) -> Vec<u128> {
        let out = self.eval(inputs);
        self.clock();
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn signed_arithmetic_wraps_to_width() {
        let s8 = Ty::SInt(8);
        let minus_one = mask(-1i128 as u128, 8);
        let r = eval_op(
            &Op::Add(NodeId(0), NodeId(0)),
            Ty::SInt(9),
            &[(minus_one, s8), (minus_one, s8)],
        );
        assert_eq!(to_signed(r, 9), -2);
        let r = eval_op(
            &Op::Mul(NodeId(0), NodeId(0)),
            Ty::SInt(16),
            &[(minus_one, s8), (0x80, s8)],
        );
        assert_eq!(to_signed(r, 16), 128);
        let lt = eval_op(
            &Op::Cmp(CmpOp::Lt, NodeId(0), NodeId(0)),
            Ty::Bool,
            &[(minus_one, s8), (0, s8)],
        );
        assert_eq!(lt, 1);
        let ult = eval_op(
            &Op::Cmp(CmpOp::Lt, NodeId(0), NodeId(0)),
            Ty::Bool,
            &[(0xff, Ty::UInt(8)), (0, Ty::UInt(8))],
        );
        assert_eq!(ult, 0);
        let sra = eval_op(
            &Op::Shr(NodeId(0), NodeId(0)),
            s8,
            &[(0x80, s8), (3, Ty::UInt(3))],
        );
        assert_eq!(sra, 0xf0);
    }
}
