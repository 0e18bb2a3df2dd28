//! The identifiers of a lowered module: every port, register, instance and
//! wire named once, in a fixed order, from the names the generator gave;
//! and the counts the naming rules are checked by.

use super::wires::*;
use crate::ir::*;
use std::collections::{HashMap, HashSet};

/// Gives every port, register, instance and wire a unique identifier, in a
/// fixed order so the same module always gets the same names.
pub(super) struct Names {
    pub(super) taken: HashSet<String>,
    pub(super) node: HashMap<NodeId, String>,
    pub(super) reg: Vec<String>,
    pub(super) instance: Vec<String>,
    /// (instance, output port) → the wire of an output no live node reads
    /// (an instance port still needs something to connect to)
    pub(super) dead_outputs: HashMap<(usize, usize), String>,
    /// identifiers claimed, and how many of them needed a number to be unique
    pub(super) claimed: usize,
    pub(super) numbered: usize,
}

impl Names {
    fn claim(&mut self, want: &str) -> String {
        // a derived name can happen to be a reserved word (e.g. a slice of `in`)
        let want = if crate::ir::is_identifier(want) {
            want.to_string()
        } else {
            format!("{want}_w")
        };
        let want = want.as_str();
        let mut name = want.to_string();
        let mut k = 1;
        while !self.taken.insert(name.clone()) {
            name = format!("{want}_{k}");
            k += 1;
        }
        self.claimed += 1;
        self.numbered += usize::from(k > 1);
        name
    }
}

/// How a module's identifiers came out: a figure the naming tests bound.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct NameCounts {
    /// wires, registers and instances named (ports not included)
    pub names: usize,
    /// of them, names that needed a number to be unique (`lt_3`)
    pub numbered: usize,
    /// length of the longest identifier
    pub longest: usize,
}

/// Names every identifier of `m` as [`lower`] does and counts them.
pub fn name_counts(m: &Module) -> NameCounts {
    let (lv, same) = used_values(m);
    let inline = inlined(m, &lv, &same);
    let names = assign_names(m, &lv, &same, &inline);
    let longest = names.taken.iter().map(|n| n.len()).max().unwrap_or(0);
    NameCounts {
        names: names.claimed,
        numbered: names.numbered,
        longest,
    }
}

/// Liveness and hash-consing, with the read bits of a copy of an
/// expression carried by the one emitted.
pub(super) fn used_values(m: &Module) -> (Liveness, Vec<NodeId>) {
    let mut lv = liveness(m);
    let same = same_expressions(m, &lv.live);
    for (i, s) in same.iter().enumerate() {
        if s.0 as usize != i {
            let bits = lv.used_bits[i];
            lv.used_bits[s.0 as usize] |= bits;
        }
    }
    (lv, same)
}

/// Every identifier: ports as declared, then instances, registers and
/// wires in node order (so the same module always gets the same names).
pub(super) fn assign_names(m: &Module, lv: &Liveness, same: &[NodeId], inline: &[bool]) -> Names {
    let mut names = Names {
        taken: HashSet::new(),
        node: HashMap::new(),
        reg: vec![],
        instance: vec![],
        dead_outputs: HashMap::new(),
        claimed: 0,
        numbered: 0,
    };
    for c in [control::CLOCK, control::RESET] {
        names.taken.insert(c.to_string());
    }
    for p in m.inputs.iter().chain(m.outputs.iter().map(|(p, _)| p)) {
        names.taken.insert(p.name.clone());
    }
    names.instance = m.instances.iter().map(|i| names.claim(&i.name)).collect();
    names.reg = m.registers.iter().map(|r| names.claim(&r.name)).collect();
    let drives = port_values(m, lv, same, inline);
    let source = name_sources(m, same);
    for (i, node) in m.nodes.iter().enumerate() {
        let id = NodeId(i as u32);
        match node.op {
            Op::Input(p) => {
                names.node.insert(id, m.inputs[p].name.clone());
            }
            Op::Reg(r) => {
                names.node.insert(id, names.reg[r].clone());
            }
            Op::Const(_) | Op::Cast(_) => {}
            _ if drives.contains_key(&id) => {
                names.node.insert(id, drives[&id].clone());
            }
            _ if lv.live[i] && same[i].0 as usize == i && !inline[i] => {
                let n = names.claim(&m.node(source[i]).name);
                names.node.insert(id, n);
            }
            _ => {}
        }
    }
    for (ii, inst) in m
        .instances
        .iter()
        .enumerate()
        .filter(|(ii, _)| lv.instances[*ii])
    {
        for (port, (p, _)) in inst.module.outputs.iter().enumerate() {
            let live = m
                .nodes
                .iter()
                .enumerate()
                .any(|(k, n)| n.op == Op::InstOut { inst: ii, port } && lv.live[k]);
            if !live {
                let w = names.claim(&format!("{}_{}", names.instance[ii], p.name));
                names.dead_outputs.insert((ii, port), w);
            }
        }
    }
    names
}

/// The computed values named like an output port they drive: such a value
/// is the port (`assign hit = ...`), not a wire `hit_1` copied into it.
pub(super) fn port_values(
    m: &Module,
    lv: &Liveness,
    same: &[NodeId],
    inline: &[bool],
) -> HashMap<NodeId, String> {
    let mut drives = HashMap::new();
    let source = name_sources(m, same);
    for (p, id) in &m.outputs {
        let c = same[id.0 as usize];
        let node = m.node(c);
        let computed = !matches!(
            node.op,
            Op::Input(_) | Op::Const(_) | Op::Reg(_) | Op::Cast(_) | Op::InstOut { .. }
        );
        let emitted = lv.live[c.0 as usize] && !inline[c.0 as usize];
        let named_as = &m.node(source[c.0 as usize]).name;
        if computed && emitted && *named_as == p.name && !drives.contains_key(&c) {
            drives.insert(c, p.name.clone());
        }
    }
    drives
}
