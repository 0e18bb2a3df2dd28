//! The port list: the contract between the generator and the simulator.
//!
//! `rtl-gen` writes `<top>.ports.json` beside the Verilog; everything in this
//! crate (vector headers, the harness's `ports.inc`, the cross-check) is
//! derived from it.

use std::collections::{BTreeMap, HashSet};
use std::fmt::Write as _;
use std::fs;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use crate::error::{Location, SimError};

/// Widest port this version supports: values travel as `u64`.
pub const MAX_WIDTH: u32 = 64;

/// Largest accepted latency. Real pipelines are far shorter; the bound keeps a
/// corrupt port list from making the harness allocate a huge history ring.
pub const MAX_LATENCY: u32 = 1 << 16;

/// One data port of the top module.
#[derive(Serialize, Deserialize, Clone, Debug, PartialEq, Eq)]
#[serde(deny_unknown_fields)]
pub struct Port {
    /// Verilog port name.
    pub name: String,
    /// Width in bits, `1..=64`.
    pub width: u32,
}

impl Port {
    /// Builds a port.
    pub fn new(name: impl Into<String>, width: u32) -> Port {
        Port {
            name: name.into(),
            width,
        }
    }

    /// Bytes the port takes in a binary record: `ceil(width / 8)`.
    pub fn bytes(&self) -> usize {
        self.width.div_ceil(8) as usize
    }

    /// Mask of the bits a value of this port may have set.
    pub fn mask(&self) -> u64 {
        width_mask(self.width)
    }
}

/// Mask of the low `width` bits (`width` in `1..=64`).
pub(crate) fn width_mask(width: u32) -> u64 {
    if width >= 64 {
        u64::MAX
    } else {
        (1u64 << width) - 1
    }
}

/// The two ports a valid/ready unit adds (docs/handshake.md).
#[derive(Serialize, Deserialize, Clone, Debug, PartialEq, Eq)]
#[serde(deny_unknown_fields)]
pub struct ReadyPorts {
    /// The unit takes a transaction at an edge where this output and
    /// `in_valid` are high.
    pub in_ready: String,
    /// The consumer takes a result at an edge where this input and
    /// `out_valid` are high.
    pub out_ready: String,
}

/// Description of a generated top module, as written by the generator.
#[derive(Serialize, Deserialize, Clone, Debug, PartialEq, Eq)]
#[serde(deny_unknown_fields)]
pub struct PortList {
    /// Top module name.
    pub top: String,
    /// Verilog files relative to the port list's directory, submodules first.
    pub files: Vec<String>,
    /// Generator name and version, e.g. `rtl-gen 0.1.0`.
    pub generator: String,
    /// Unit kind, e.g. `mulcmp`.
    pub unit: String,
    /// Generator parameters of this instance.
    pub params: BTreeMap<String, String>,
    /// Cycles from `in_valid` to `out_valid`; 0 means combinational.
    pub latency: u32,
    /// Clock port (rising edge).
    pub clock: String,
    /// Synchronous active-high reset port.
    pub reset: String,
    /// Input-valid port.
    pub in_valid: String,
    /// Output-valid port.
    pub out_valid: String,
    /// The backpressure ports of a valid/ready unit (`handshake=ready`);
    /// absent for a valid-only one.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ready: Option<ReadyPorts>,
    /// Data inputs in record order (not clock, reset or `in_valid`).
    pub inputs: Vec<Port>,
    /// Data outputs in record order (not `out_valid`).
    pub outputs: Vec<Port>,
}

impl PortList {
    /// Reads and validates a `.ports.json` file.
    pub fn load(path: impl AsRef<Path>) -> Result<PortList, SimError> {
        let path = path.as_ref();
        let text = fs::read_to_string(path)
            .map_err(|e| SimError::io(format!("reading port list {}", path.display()), e))?;
        PortList::from_json(&text, &path.display().to_string())
    }

    /// Parses and validates port-list JSON; `source` names it in errors.
    pub fn from_json(text: &str, source: &str) -> Result<PortList, SimError> {
        let list: PortList = serde_json::from_str(text).map_err(|e| {
            SimError::format(
                source,
                Location::LineColumn(e.line() as u64, e.column() as u64),
                None,
                e.to_string(),
            )
        })?;
        list.validate_as(source)?;
        Ok(list)
    }

    /// Validates, then writes the port list as pretty JSON.
    pub fn save(&self, path: impl AsRef<Path>) -> Result<(), SimError> {
        let path = path.as_ref();
        self.validate_as(&path.display().to_string())?;
        let mut text = self.to_json();
        text.push('\n');
        fs::write(path, text)
            .map_err(|e| SimError::io(format!("writing port list {}", path.display()), e))
    }

    /// Pretty JSON of the port list (deterministic: fields in declaration
    /// order, `params` sorted).
    pub fn to_json(&self) -> String {
        // Serialising plain strings, integers and maps cannot fail.
        serde_json::to_string_pretty(self).expect("PortList serialises")
    }

    /// Checks the invariants everything downstream relies on.
    pub fn validate(&self) -> Result<(), SimError> {
        self.validate_as(&format!("port list of `{}`", self.top))
    }

    /// [`PortList::validate`], naming the list `source` in errors.
    pub fn validate_as(&self, source: &str) -> Result<(), SimError> {
        let err = |field: &str, msg: String| {
            Err(SimError::format(source, Location::Whole, Some(field), msg))
        };
        if !is_identifier(&self.top) {
            return err("top", format!("`{}` is not a Verilog identifier", self.top));
        }
        if self.files.is_empty() {
            return err("files", "no Verilog files listed".into());
        }
        for (i, f) in self.files.iter().enumerate() {
            if f.is_empty() || Path::new(f).is_absolute() {
                return err(
                    &format!("files[{i}]"),
                    format!("`{f}` must be a non-empty path relative to the port list"),
                );
            }
        }
        if self.latency > MAX_LATENCY {
            return err(
                "latency",
                format!(
                    "{} exceeds the supported maximum {MAX_LATENCY}",
                    self.latency
                ),
            );
        }
        if self.inputs.is_empty() {
            return err("inputs", "a unit needs at least one data input".into());
        }
        if self.outputs.is_empty() {
            return err("outputs", "a unit needs at least one data output".into());
        }
        let mut seen = HashSet::new();
        let mut controls = vec![
            ("clock", &self.clock),
            ("reset", &self.reset),
            ("in_valid", &self.in_valid),
            ("out_valid", &self.out_valid),
        ];
        if let Some(r) = &self.ready {
            controls.extend([
                ("ready.in_ready", &r.in_ready),
                ("ready.out_ready", &r.out_ready),
            ]);
        }
        for (field, name) in controls {
            if !is_identifier(name) {
                return err(field, format!("`{name}` is not a Verilog identifier"));
            }
            if !seen.insert(name.as_str()) {
                return err(field, format!("port name `{name}` is used twice"));
            }
        }
        for (kind, ports) in [("inputs", &self.inputs), ("outputs", &self.outputs)] {
            for (i, p) in ports.iter().enumerate() {
                if !is_identifier(&p.name) {
                    return err(
                        &format!("{kind}[{i}].name"),
                        format!("`{}` is not a Verilog identifier", p.name),
                    );
                }
                if !seen.insert(p.name.as_str()) {
                    return err(
                        &format!("{kind}[{i}].name"),
                        format!("port name `{}` is used twice", p.name),
                    );
                }
                if !(1..=MAX_WIDTH).contains(&p.width) {
                    return err(
                        &format!("{kind}[{i}].width"),
                        format!(
                            "width {} of `{}` is outside 1..={MAX_WIDTH}",
                            p.width, p.name
                        ),
                    );
                }
            }
        }
        Ok(())
    }

    /// Absolute-or-relative paths of the Verilog files, resolved against
    /// `dir` (the directory holding the port list).
    pub fn file_paths(&self, dir: &Path) -> Vec<PathBuf> {
        self.files.iter().map(|f| dir.join(f)).collect()
    }

    /// Bytes of one binary input record.
    pub fn input_record_bytes(&self) -> usize {
        self.inputs.iter().map(Port::bytes).sum()
    }

    /// Bytes of one binary output record.
    pub fn output_record_bytes(&self) -> usize {
        self.outputs.iter().map(Port::bytes).sum()
    }

    /// The X-macro include the generic harness is compiled with
    /// (see `verilator/harness.cpp`). Call on a validated list.
    pub fn ports_inc(&self) -> String {
        let mut s = String::new();
        let _ = writeln!(
            s,
            "// Generated by the sim crate from the port list of `{}`; do not edit.",
            self.top
        );
        let _ = writeln!(s, "#define RTL_TOP_NAME \"{}\"", self.top);
        let _ = writeln!(s, "#define RTL_LATENCY {}", self.latency);
        let _ = writeln!(s, "#define RTL_CLK {}", self.clock);
        let _ = writeln!(s, "#define RTL_RST {}", self.reset);
        let _ = writeln!(s, "#define RTL_IN_VALID {}", self.in_valid);
        let _ = writeln!(s, "#define RTL_OUT_VALID {}", self.out_valid);
        if let Some(r) = &self.ready {
            let _ = writeln!(s, "#define RTL_IN_READY {}", r.in_ready);
            let _ = writeln!(s, "#define RTL_OUT_READY {}", r.out_ready);
        }
        for (mac, ports) in [("RTL_INPUTS", &self.inputs), ("RTL_OUTPUTS", &self.outputs)] {
            let _ = write!(s, "#define {mac}(X)");
            for p in ports {
                let _ = write!(s, " X({}, {})", p.name, p.width);
            }
            s.push('\n');
        }
        s
    }
}

/// True for a plain Verilog identifier; escaped identifiers and `$` are
/// refused because they do not survive the trip into C++ member names.
pub(crate) fn is_identifier(s: &str) -> bool {
    let mut chars = s.chars();
    matches!(chars.next(), Some(c) if c.is_ascii_alphabetic() || c == '_')
        && chars.all(|c| c.is_ascii_alphanumeric() || c == '_')
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample() -> PortList {
        PortList {
            top: "addpipe".into(),
            files: vec!["addpipe.v".into()],
            generator: "hand-written".into(),
            unit: "add".into(),
            params: BTreeMap::from([("width".to_string(), "16".to_string())]),
            latency: 2,
            clock: "clk".into(),
            reset: "rst".into(),
            in_valid: "in_valid".into(),
            out_valid: "out_valid".into(),
            ready: None,
            inputs: vec![Port::new("a", 16), Port::new("b", 16)],
            outputs: vec![Port::new("sum", 17), Port::new("eq", 1)],
        }
    }

    #[test]
    fn json_round_trip() {
        let p = sample();
        let back = PortList::from_json(&p.to_json(), "mem").unwrap();
        assert_eq!(p, back);
    }

    #[test]
    fn save_and_load() {
        let dir = std::env::temp_dir().join(format!("sim-ports-{}", std::process::id()));
        fs::create_dir_all(&dir).unwrap();
        let path = dir.join("addpipe.ports.json");
        sample().save(&path).unwrap();
        assert_eq!(PortList::load(&path).unwrap(), sample());
        fs::remove_dir_all(&dir).unwrap();
    }

    fn invalid(edit: impl FnOnce(&mut PortList)) -> String {
        let mut p = sample();
        edit(&mut p);
        p.validate_as("x.ports.json").unwrap_err().to_string()
    }

    #[test]
    fn validation_names_the_field() {
        assert_eq!(
            invalid(|p| p.inputs[1].width = 0),
            "x.ports.json: field `inputs[1].width`: width 0 of `b` is outside 1..=64"
        );
        assert!(invalid(|p| p.outputs[0].width = 65).contains("`outputs[0].width`"));
        assert!(invalid(|p| p.outputs[1].name = "a".into())
            .contains("`outputs[1].name`: port name `a` is used twice"));
        assert!(invalid(|p| p.inputs[0].name = "clk".into()).contains("used twice"));
        assert!(invalid(|p| p.inputs.clear()).contains("`inputs`"));
        assert!(invalid(|p| p.outputs.clear()).contains("`outputs`"));
        assert!(invalid(|p| p.files.clear()).contains("`files`"));
        assert!(invalid(|p| p.files[0] = "/abs.v".into()).contains("`files[0]`"));
        assert!(invalid(|p| p.inputs[0].name = "a b".into()).contains("identifier"));
        assert!(invalid(|p| p.latency = MAX_LATENCY + 1).contains("`latency`"));
    }

    #[test]
    fn json_errors_have_line_and_column() {
        let text = sample()
            .to_json()
            .replace("\"latency\": 2", "\"latency\": -2");
        let e = PortList::from_json(&text, "bad.json")
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("bad.json: line "), "{e}");
        assert!(e.contains("column"), "{e}");
        let text = sample().to_json().replace("\"unit\"", "\"unti\"");
        let e = PortList::from_json(&text, "bad.json")
            .unwrap_err()
            .to_string();
        assert!(e.contains("unknown field `unti`"), "{e}");
    }

    #[test]
    fn ports_inc_lists_ports_in_order() {
        let inc = sample().ports_inc();
        assert!(inc.contains("#define RTL_LATENCY 2\n"));
        assert!(inc.contains("#define RTL_INPUTS(X) X(a, 16) X(b, 16)\n"));
        assert!(inc.contains("#define RTL_OUTPUTS(X) X(sum, 17) X(eq, 1)\n"));
        assert!(inc.contains("#define RTL_OUT_VALID out_valid\n"));
    }
}
