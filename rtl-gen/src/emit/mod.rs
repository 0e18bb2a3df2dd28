//! Verilog emission: IR → typed Verilog tree ([`vast`]) → text ([`print`]).
//! Runs in-process; no external tool is on the emission path.

pub mod lower;
pub mod print;
pub mod vast;

use crate::ir::Module;

/// One emitted Verilog file.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct VerilogFile {
    /// file name, `<module>.v`
    pub file_name: String,
    /// module name
    pub module: String,
    /// the file's text
    pub text: String,
}

/// Emits `top` and every module below it, one file per module (Verilator's
/// `DECLFILENAME` rule), submodules first. Same module, same bytes.
pub fn emit(top: &Module, generator: &str) -> Vec<VerilogFile> {
    top.hierarchy()
        .into_iter()
        .map(|m| {
            let is_top = std::ptr::eq(m, top);
            VerilogFile {
                file_name: format!("{}.v", m.name),
                module: m.name.clone(),
                text: print::module(&lower::lower(m, generator, is_top)),
            }
        })
        .collect()
}
