//! The timing shell: a generated unit between a serial scan chain and a
//! parity tree, so place and route sees a design with three pins (`clk`,
//! `sin`, `sout`) whatever the unit's port count, and every path of the unit
//! is register to register.
//!
//! Written in the DSL like everything else: every data input of the unit
//! (and `in_valid`) is a register of a shift chain fed by `sin`; every output
//! of the unit is captured in a register; the XOR of all captured bits is
//! registered and drives `sout`. XOR keeps every output bit observable, so
//! synthesis cannot remove any of the unit's logic; the chain costs one
//! flip-flop per input bit and the tree about one LUT per three output bits
//! (both reported separately by [`crate::synth`], which subtracts nothing:
//! the shell's cells are counted in the place-and-route utilisation only).

use rtl_gen::builder::{BuildErrors, ModuleBuilder};
use rtl_gen::ir::{Module, Ty};
use std::sync::Arc;

/// Builds the shell around `unit` (a module with the `in_valid`/`out_valid`
/// handshake). The shell's name is `shell_<unit>`.
pub fn timing_shell(unit: &Module) -> Result<Module, BuildErrors> {
    let unit = Arc::new(unit.clone());
    let mut m = ModuleBuilder::new(format!("shell_{}", unit.name));
    m.describe(format!(
        "Timing shell of {}: inputs from a scan chain (sin), outputs captured and XOR-reduced (sout).",
        unit.name
    ));
    let sin = m.input("sin", Ty::Bool);
    let mut prev = sin;
    let mut conns: Vec<(String, rtl_gen::builder::Sig)> = Vec::new();
    for port in &unit.inputs {
        let w = port.ty.width();
        let r = m.reg(&format!("scan_{}", port.name), Ty::UInt(w), None);
        let next = if w == 1 {
            m.as_uint(prev)
        } else {
            let low = m.slice(r.q, w - 2, 0);
            let p = m.as_uint(prev);
            m.cat(&[low, p])
        };
        m.set_next(r, next, None);
        prev = m.msb(r.q);
        let v = m.cast(r.q, port.ty);
        conns.push((port.name.clone(), v));
    }
    let outs = m.instance("u_dut", &unit, &conns);
    for _ in 0..unit.latency {
        m.stage();
    }
    let mut acc: Option<rtl_gen::builder::Sig> = None;
    for (name, sig) in outs.named() {
        let w = sig.width();
        let cap = m.reg(&format!("cap_{name}"), Ty::UInt(w), None);
        let v = m.as_uint(sig);
        m.set_next(cap, v, None);
        let p = if w == 1 {
            m.as_bool(cap.q)
        } else {
            m.parity(cap.q)
        };
        acc = Some(match acc {
            None => p,
            Some(a) => m.xor(a, p),
        });
    }
    let acc = acc.unwrap_or(prev);
    let out = m.reg("sout_q", Ty::Bool, None);
    m.set_next(out, acc, None);
    m.output("sout", out.q);
    m.finish()
}
