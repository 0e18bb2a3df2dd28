//! Verilog emission: IR → typed Verilog tree ([`vast`]) → text ([`print`]).
//! Runs in-process; no external tool is on the emission path.

pub mod lower;
mod names;
pub mod print;
pub mod vast;
mod wires;

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

/// How [`emit_with`] writes the Verilog.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct EmitOptions {
    /// a `// src: file:line` comment above each assignment: the generator
    /// line that built the value
    pub source_lines: bool,
}

/// Emits `top` and every module below it, one file per module (Verilator's
/// `DECLFILENAME` rule), submodules first. Same module, same bytes.
///
/// Every module is checked with [`Module::check_well_formed`] first: the
/// builder already guarantees it, so a failure is a generator bug, reported
/// with the module's name rather than emitted as broken Verilog.
pub fn emit(top: &Module, generator: &str) -> Vec<VerilogFile> {
    emit_with(top, generator, EmitOptions::default())
}

/// [`emit`] with options.
pub fn emit_with(top: &Module, generator: &str, options: EmitOptions) -> Vec<VerilogFile> {
    top.hierarchy()
        .into_iter()
        .map(|m| {
            if let Err(e) = m.check_well_formed() {
                panic!("internal error: module {} is not well formed: {e}", m.name);
            }
            let is_top = std::ptr::eq(m, top);
            VerilogFile {
                file_name: format!("{}.v", m.name),
                module: m.name.clone(),
                text: print::module(&lower::lower(m, generator, is_top, options)),
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::builder::ModuleBuilder;
    use crate::ir::Ty;

    /// A module with a zero-width node is refused with its name, not emitted.
    #[test]
    #[should_panic(expected = "module broken_width is not well formed")]
    fn a_malformed_module_is_refused() {
        let mut m = ModuleBuilder::new("broken_width".to_string());
        let a = m.input("a", Ty::UInt(4));
        let b = m.not(a);
        m.output("z", b);
        let mut module = m.finish().expect("well formed as built");
        let last = module.nodes.len() - 1;
        module.nodes[last].ty = Ty::UInt(0);
        emit(&module, "test");
    }
}
