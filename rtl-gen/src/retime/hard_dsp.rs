//! Hard DSP registers on ECP5 (`dsp=ecp5`): a registered product of at most
//! 18x18 bits becomes an ECP5 MULT18X18D whose own output register holds it.
//!
//! Why: Yosys maps a product to a MULT18X18D without its registers (it packs
//! none on ECP5), so the register after the product is a fabric flip-flop and
//! one clock period holds the route into the DSP row, the multiplier and the
//! route back (binary32 bundle tester, 28 stages: 5.6 + 3.9 + 4.5 ns, 68.8
//! MHz). In the block's output register the route back is a path of its own
//! (105.6 MHz, docs/cost.md). The block's input registers too were measured
//! and not kept: they move the route in onto the logic that computes the
//! operand (53 MHz placed).
//!
//! The product becomes an instance of a small module whose nodes are its
//! behaviour (a product and a register, for the evaluator and Verilator) and
//! whose [`VendorBody`] is the MULT18X18D Yosys instantiates; latency and
//! function are unchanged, so the unit's golden model checks it as before.

use crate::ir::*;
use std::collections::{BTreeMap, HashMap};
use std::sync::Arc;

/// Operand width of a MULT18X18D.
const DSP_BITS: u32 = 18;

/// What [`ecp5_hard_registers`] did.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Hardened {
    /// products now in a MULT18X18D with its output register
    pub products: usize,
}

/// Moves every registered product that fits one MULT18X18D into one, with
/// the block's own output register, here and in every submodule (renamed with
/// `_ecp5dsp` where something changed). Same ports, latency and function.
pub fn ecp5_hard_registers(m: &Module) -> (Module, Hardened) {
    let mut done = HashMap::new();
    harden(m, &mut done)
}

fn harden(m: &Module, done: &mut HashMap<String, (Arc<Module>, Hardened)>) -> (Module, Hardened) {
    let mut m = m.clone();
    let mut total = Hardened::default();
    for inst in &mut m.instances {
        let name = inst.module.name.clone();
        if !done.contains_key(&name) {
            let (sub, h) = harden(&inst.module, done);
            done.insert(name.clone(), (Arc::new(sub), h));
        }
        let (sub, h) = &done[&name];
        if h.products > 0 {
            inst.module = Arc::clone(sub);
            total.products += h.products;
        }
    }
    let own = harden_here(&mut m);
    total.products += own.products;
    if total.products > 0 && !m.name.ends_with("_ecp5dsp") {
        m.name = format!("{}_ecp5dsp", m.name);
    }
    (m, total)
}

/// A pipeline register: no reset, no enable.
fn plain(r: &Register) -> bool {
    r.reset.is_none() && r.enable.is_none()
}

fn harden_here(m: &mut Module) -> Hardened {
    let mut users = vec![0usize; m.nodes.len()];
    for node in &m.nodes {
        node.op
            .operands()
            .iter()
            .for_each(|o| users[o.0 as usize] += 1);
    }
    for r in &m.registers {
        users[r.next.0 as usize] += 1;
        r.enable.iter().for_each(|e| users[e.0 as usize] += 1);
    }
    m.outputs.iter().for_each(|(_, o)| users[o.0 as usize] += 1);
    for inst in &m.instances {
        inst.inputs.iter().for_each(|i| users[i.0 as usize] += 1);
    }
    let mut done = Hardened::default();
    for ri in 0..m.registers.len() {
        let reg = m.registers[ri].clone();
        let Op::Mul(a, b) = m.node(reg.next).op else {
            continue;
        };
        let (ta, tb) = (m.node(a).ty, m.node(b).ty);
        let (wa, wb) = (ta.width(), tb.width());
        // a product only this register reads, on one block, that Yosys
        // would put on a DSP anyway (crate::retime::on_dsp)
        if !plain(&reg)
            || users[reg.next.0 as usize] != 1
            || wa.max(wb) > DSP_BITS
            || !super::on_dsp(wa, wb)
        {
            continue;
        }
        // a pipeline register comes after the value it loads, so the block's
        // output (at the register's place) comes after its operands: the
        // evaluator's order holds without moving a node
        let Some(q) = m.nodes.iter().position(|n| n.op == Op::Reg(ri)) else {
            continue;
        };
        if (reg.next.0 as usize) >= q {
            continue;
        }
        let block = Arc::new(mult18(ta, tb, m.node(reg.next).ty));
        m.instances.push(Instance {
            name: format!("{}_block", reg.name),
            module: block,
            inputs: vec![a, b],
        });
        m.nodes[q].op = Op::InstOut {
            inst: m.instances.len() - 1,
            port: 0,
        };
        done.products += 1;
    }
    done
}

/// One MULT18X18D: `p = a · b` one clock after its operands; `a` and `b`
/// share signedness.
fn mult18(ta: Ty, tb: Ty, tp: Ty) -> Module {
    let signed = ta.is_signed();
    let node = super::cell_node;
    let id = |i: u32| NodeId(i);
    let nodes = vec![
        node(Op::Input(0), ta, "a"),
        node(Op::Input(1), tb, "b"),
        node(Op::Mul(id(0), id(1)), tp, "product"),
        node(Op::Reg(0), tp, "p_q"),
    ];
    let registers = vec![Register {
        name: "p_q".into(),
        ty: tp,
        next: id(2),
        reset: None,
        enable: None,
    }];
    let mut pins = Vec::new();
    for (letter, port, w) in [("A", 0, ta.width()), ("B", 1, tb.width())] {
        for i in 0..DSP_BITS {
            let pin = match (i < w, signed) {
                (true, _) => CellPin::Input { port, bit: i },
                (false, true) => CellPin::Input { port, bit: w - 1 },
                (false, false) => CellPin::Const(false),
            };
            pins.push((format!("{letter}{i}"), vec![pin]));
        }
    }
    for i in 0..DSP_BITS {
        pins.push((format!("C{i}"), vec![CellPin::Const(false)]));
    }
    for p in ["SIGNEDA", "SIGNEDB"] {
        pins.push((p.into(), vec![CellPin::Const(signed)]));
    }
    for p in ["SOURCEA", "SOURCEB"] {
        pins.push((p.into(), vec![CellPin::Const(false)]));
    }
    pins.push(("CLK0".into(), vec![CellPin::Clock]));
    for k in 1..4 {
        pins.push((format!("CLK{k}"), vec![CellPin::Const(false)]));
    }
    for k in 0..4 {
        pins.push((format!("CE{k}"), vec![CellPin::Const(true)]));
        pins.push((format!("RST{k}"), vec![CellPin::Const(false)]));
    }
    for i in 0..tp.width() {
        pins.push((format!("P{i}"), vec![CellPin::Output { port: 0, bit: i }]));
    }
    let sign = if signed { "s" } else { "u" };
    let port = |name: &str, ty: Ty| Port {
        name: name.into(),
        ty,
    };
    Module {
        name: format!("ecp5_mult_{sign}{}x{}_reg", ta.width(), tb.width()),
        description: "One ECP5 MULT18X18D with its output register in synthesis (SYNTHESIS \
                      defined, as by Yosys); the same product and register in fabric logic \
                      otherwise (simulation)."
            .into(),
        params: BTreeMap::new(),
        inputs: vec![port("a", ta), port("b", tb)],
        outputs: vec![(port("p", tp), id(3))],
        nodes,
        registers,
        instances: Vec::new(),
        latency: 1,
        handshake: None,
        vendor: Some(VendorBody {
            library: CellLibrary::Ecp5,
            nets: Vec::new(),
            cells: vec![VendorCell {
                cell: "MULT18X18D".into(),
                name: "hard_block".into(),
                params: vec![
                    ("REG_OUTPUT_CLK".into(), "\"CLK0\"".into()),
                    ("GSR".into(), "\"DISABLED\"".into()),
                    ("RESETMODE".into(), "\"SYNC\"".into()),
                ],
                pins,
            }],
        }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::builder::ModuleBuilder;
    use crate::eval::Evaluator;

    /// A two-stage product pipeline: operands registered, product
    /// registered, then a sum; hardened it keeps its latency and values.
    #[test]
    fn hardened_products_keep_latency_and_function() {
        let mut m = ModuleBuilder::with_handshake("prod");
        let a = m.input("a", Ty::UInt(17));
        let b = m.input("b", Ty::UInt(18));
        let c = m.input("c", Ty::UInt(6));
        let s = m.add(a, c);
        m.stage();
        let p = m.mul(a, b);
        let q = m.mul(s, c);
        m.stage();
        let z = m.add(p, q);
        m.output("z", z);
        let plain = m.finish().unwrap();
        let (hard, h) = ecp5_hard_registers(&plain);
        assert_eq!(h.products, 2, "{h:?}");
        assert!(hard.name.ends_with("_ecp5dsp"));
        hard.check_well_formed().unwrap();
        let (mut e0, mut e1) = (Evaluator::new(&plain), Evaluator::new(&hard));
        let mut x = 0x1234_5678_9abc_def0u128;
        for _ in 0..200 {
            x = x.wrapping_mul(0x9e37_79b9_7f4a_7c15).wrapping_add(1);
            let v = [1, x & 0x1_ffff, (x >> 20) & 0x3_ffff, (x >> 40) & 0x3f];
            assert_eq!(e0.step(&v), e1.step(&v));
        }
        let text = crate::emit::emit(&hard, "test");
        let block = text
            .iter()
            .find(|f| f.module.starts_with("ecp5_mult"))
            .unwrap();
        assert!(block.text.contains("`ifdef SYNTHESIS"));
        assert!(block.text.contains(".REG_OUTPUT_CLK(\"CLK0\")"));
    }
}
