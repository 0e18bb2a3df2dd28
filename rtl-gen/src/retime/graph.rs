//! The graph scheduling works on: the flattened module, which nodes are
//! live, who reads each node, and each node's delay.

use super::delay_model::delay;
use super::flatten::{flatten, Flat};
use super::split::DSP_ROUTE;
use crate::ir::Module;

/// The flattened graph with what scheduling needs.
pub(super) struct Graph {
    pub(super) flat: Flat,
    /// read (through other nodes) by an output
    pub(super) live: Vec<bool>,
    /// drives an output
    pub(super) is_output: Vec<bool>,
    /// the live nodes reading each node
    pub(super) users: Vec<Vec<usize>>,
    /// [`delay`] of each node
    pub(super) delay: Vec<f64>,
}

pub(super) fn analyse(m: &Module, products: super::Products) -> Result<Graph, String> {
    if m.instances.iter().any(|i| has_handshake_below(&i.module)) {
        return Err(format!(
            "module {}: a submodule has its own handshake",
            m.name
        ));
    }
    let flat = flatten(m, products)?;
    let n = flat.nodes.len();
    let mut live = vec![false; n];
    let mut is_output = vec![false; n];
    for (_, o) in &flat.outputs {
        live[*o] = true;
        is_output[*o] = true;
    }
    for i in (0..n).rev() {
        if live[i] {
            for o in flat.nodes[i].op.operands() {
                live[o.0 as usize] = true;
            }
        }
    }
    let mut users: Vec<Vec<usize>> = vec![Vec::new(); n];
    for (i, node) in flat.nodes.iter().enumerate().filter(|&(i, _)| live[i]) {
        for o in node.op.operands() {
            users[o.0 as usize].push(i);
        }
    }
    let delay: Vec<f64> = flat
        .nodes
        .iter()
        .map(|node| match node.wire {
            true => DSP_ROUTE,
            false => delay(&node.op, node.ty, |id| flat.nodes[id.0 as usize].ty),
        })
        .collect();
    Ok(Graph {
        flat,
        live,
        is_output,
        users,
        delay,
    })
}

fn has_handshake_below(m: &Module) -> bool {
    m.handshake.is_some() || m.instances.iter().any(|i| has_handshake_below(&i.module))
}
