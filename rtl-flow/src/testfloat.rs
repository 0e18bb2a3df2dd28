//! TestFloat interop: check a float operator unit against cases in the
//! format of Berkeley TestFloat's `testfloat_gen` (one case a line: the
//! operands, the expected result, the exception flags, all in hex without a
//! prefix, e.g. `3F800000 BF800000 00000000 00`).
//!
//! Every case runs through the Verilated RTL and through the golden model,
//! and both are compared with the expected result. Comparison rules:
//!
//! * **NaN**: an expected NaN is matched by any NaN (any sign, any payload)
//!   unless `nan_exact`, in which case the bits must be equal. Our operators
//!   always return the canonical NaN (`docs/float.md` §1), while TestFloat's
//!   default NaN depends on its build's specialisation.
//! * **Subnormals** are never flushed, neither on input nor on output
//!   (IEEE 754 gradual underflow): a case file made for a flush-to-zero
//!   implementation shows up as mismatches in the classes `subnormal input`
//!   and `subnormal result`.
//! * **Flags** are read (when present) and ignored: our operators produce no
//!   exception flags (`docs/float.md`, version 1); the report says so.
//!
//! Mismatches are grouped by class, decided in this order from the operands
//! and the expected result: `NaN` (an operand or the expected result is a
//! NaN), `infinity` (an operand is infinite), `overflow` (finite operands,
//! expected ±∞ or ±largest finite), `subnormal input`, `subnormal result`,
//! `other`.

use super::report::{FailingVector, RunReport};
use super::{FlowError, Generated, Testbench};
use sim::{Location, Port, SimError};
use std::collections::BTreeMap;
use std::fmt;
use std::io::BufRead;
use std::time::Instant;

/// One case of a TestFloat file.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Case {
    /// 1-based line in the source
    pub line: u64,
    /// operands, in input-port order
    pub operands: Vec<u64>,
    /// expected result
    pub expected: u64,
    /// exception flags, if the line has them (ignored)
    pub flags: Option<u64>,
}

/// Reads TestFloat cases: per line, one hex operand per input port, the
/// expected result, then optionally the flags. Blank lines and `#`
/// comments are skipped. Errors name the stream, line and field.
pub fn read_cases<R: BufRead>(
    input: R,
    stream: &str,
    inputs: &[Port],
    result: &Port,
) -> Result<Vec<Case>, SimError> {
    let mut cases = Vec::new();
    for (i, line) in input.lines().enumerate() {
        let line_no = i as u64 + 1;
        let line = line.map_err(|e| SimError::io(format!("reading {stream}"), e))?;
        let content = line.split('#').next().unwrap_or("");
        let fields: Vec<&str> = content.split_ascii_whitespace().collect();
        if fields.is_empty() {
            continue;
        }
        let at = || Location::Line(line_no);
        let n = inputs.len();
        if fields.len() != n + 1 && fields.len() != n + 2 {
            let names: Vec<&str> = inputs.iter().map(|p| p.name.as_str()).collect();
            return Err(SimError::format(
                stream,
                at(),
                None,
                format!(
                    "wrong field count: {} fields, expected {} operand(s) ({}), the result and \
                     optionally the flags",
                    fields.len(),
                    n,
                    names.join(", ")
                ),
            ));
        }
        // TestFloat writes every field with exactly its width's hex digits (4 for
        // binary16, 8 for binary32, 1 for a boolean, 2 for the flags): a field of
        // another length is a cut line or a file for another format
        let parse = |tok: &str, field: &str, width: u32| -> Result<u64, SimError> {
            let digits = width.div_ceil(4) as usize;
            if tok.len() != digits || !tok.bytes().all(|b| b.is_ascii_hexdigit()) {
                return Err(SimError::format(
                    stream,
                    at(),
                    Some(field),
                    format!(
                        "`{tok}` is not {digits} hex digit(s): a {width}-bit field has exactly {digits} \
                         (a line cut short, or a file for another format)"
                    ),
                ));
            }
            let v = u64::from_str_radix(tok, 16).expect("checked hex digits");
            if width < 64 && v >> width != 0 {
                return Err(SimError::format(
                    stream,
                    at(),
                    Some(field),
                    format!("value wider than port: {v:#x} does not fit {width} bits"),
                ));
            }
            Ok(v)
        };
        let mut operands = Vec::with_capacity(n);
        for (tok, p) in fields.iter().zip(inputs) {
            operands.push(parse(tok, &p.name, p.width)?);
        }
        let expected = parse(fields[n], &format!("result {}", result.name), result.width)?;
        let flags = match fields.get(n + 1) {
            Some(tok) => Some(parse(tok, "flags", 8)?),
            None => None,
        };
        cases.push(Case {
            line: line_no,
            operands,
            expected,
            flags,
        });
    }
    if cases.is_empty() {
        return Err(SimError::format(
            stream,
            Location::Whole,
            None,
            "no TestFloat cases (expected lines of hex operands, result and flags)",
        ));
    }
    Ok(cases)
}

/// A float encoding's fields.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Fmt {
    /// exponent bits
    pub exp_bits: u32,
    /// fraction bits
    pub frac_bits: u32,
}

impl Fmt {
    fn width(self) -> u32 {
        1 + self.exp_bits + self.frac_bits
    }
    fn exp(self, x: u64) -> u64 {
        (x >> self.frac_bits) & ((1 << self.exp_bits) - 1)
    }
    fn frac(self, x: u64) -> u64 {
        x & ((1 << self.frac_bits) - 1)
    }
    fn exp_max(self) -> u64 {
        (1 << self.exp_bits) - 1
    }
    /// True for NaN encodings.
    pub fn is_nan(self, x: u64) -> bool {
        self.exp(x) == self.exp_max() && self.frac(x) != 0
    }
    fn is_inf(self, x: u64) -> bool {
        self.exp(x) == self.exp_max() && self.frac(x) == 0
    }
    fn is_subnormal(self, x: u64) -> bool {
        self.exp(x) == 0 && self.frac(x) != 0
    }
    fn is_max_finite(self, x: u64) -> bool {
        self.exp(x) == self.exp_max() - 1 && self.frac(x) == (1 << self.frac_bits) - 1
    }
}

/// Mismatch classes, in the order they are decided and printed.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Class {
    /// an operand or the expected result is a NaN
    Nan,
    /// an operand is infinite
    Infinity,
    /// finite operands, expected ±∞ or ±largest finite
    Overflow,
    /// an operand is subnormal
    SubnormalInput,
    /// the expected result is subnormal
    SubnormalResult,
    /// everything else
    Other,
}

impl Class {
    /// Every class, in order.
    pub const ALL: [Class; 6] = [
        Class::Nan,
        Class::Infinity,
        Class::Overflow,
        Class::SubnormalInput,
        Class::SubnormalResult,
        Class::Other,
    ];
}

impl fmt::Display for Class {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Class::Nan => "NaN",
            Class::Infinity => "infinity",
            Class::Overflow => "overflow",
            Class::SubnormalInput => "subnormal input",
            Class::SubnormalResult => "subnormal result",
            Class::Other => "other",
        })
    }
}

/// How a unit's ports map to a TestFloat case.
#[derive(Clone, Debug)]
pub struct Mapping {
    /// index of the output compared with the expected result
    pub result: usize,
    /// format of the operands
    pub operand_fmt: Fmt,
    /// format of the result; `None` for a boolean (comparison) result
    pub result_fmt: Option<Fmt>,
}

impl Mapping {
    /// The mapping for a generated float unit: operands are its inputs in
    /// order, in the format `exp_bits`/`frac_bits`; the result is the output
    /// `result` (default: the only output, else `z`), in the format
    /// `to_exp_bits`/`to_frac_bits` when the unit has them, else the
    /// operands' format or the exact-product format, or a boolean.
    pub fn for_unit(g: &Generated, result: Option<&str>) -> Result<Mapping, String> {
        let outs = &g.ports.outputs;
        let names: Vec<&str> = outs.iter().map(|p| p.name.as_str()).collect();
        let idx = match result {
            Some(r) => outs.iter().position(|p| p.name == r).ok_or_else(|| {
                format!(
                    "--result {r}: `{}` has no output `{r}` (outputs: {})",
                    g.unit,
                    names.join(", ")
                )
            })?,
            None if outs.len() == 1 => 0,
            None => outs.iter().position(|p| p.name == "z").ok_or_else(|| {
                format!(
                    "`{}` has several outputs ({}): choose the one TestFloat's result is \
                     compared with, e.g. --result {}",
                    g.unit,
                    names.join(", "),
                    names[0]
                )
            })?,
        };
        let get = |k: &str| g.params.values().get(k).and_then(|v| v.parse::<u32>().ok());
        let (Some(e), Some(f)) = (get("exp_bits"), get("frac_bits")) else {
            return Err(format!(
                "`{}` is not a float operator (no exp_bits/frac_bits parameters)",
                g.unit
            ));
        };
        let operand_fmt = Fmt {
            exp_bits: e,
            frac_bits: f,
        };
        let width = outs[idx].width;
        let result_fmt = if width == 1 {
            None
        } else if let (Some(te), Some(tf)) = (get("to_exp_bits"), get("to_frac_bits")) {
            Some(Fmt {
                exp_bits: te,
                frac_bits: tf,
            })
        } else if width == operand_fmt.width() {
            Some(operand_fmt)
        } else {
            let wide = Fmt {
                exp_bits: e + 2,
                frac_bits: 2 * f + 1,
            };
            (width == wide.width()).then_some(wide)
        };
        if let Some(i) = g
            .ports
            .inputs
            .iter()
            .find(|p| p.width != operand_fmt.width())
        {
            return Err(format!(
                "input `{}` of `{}` is {} bits, not a {}-bit operand",
                i.name,
                g.unit,
                i.width,
                operand_fmt.width()
            ));
        }
        Ok(Mapping {
            result: idx,
            operand_fmt,
            result_fmt,
        })
    }

    /// The class of a case.
    pub fn classify(&self, operands: &[u64], expected: u64) -> Class {
        let o = self.operand_fmt;
        let r = self.result_fmt;
        if operands.iter().any(|&x| o.is_nan(x)) || r.is_some_and(|r| r.is_nan(expected)) {
            Class::Nan
        } else if operands.iter().any(|&x| o.is_inf(x)) {
            Class::Infinity
        } else if r.is_some_and(|r| r.is_inf(expected) || r.is_max_finite(expected)) {
            Class::Overflow
        } else if operands.iter().any(|&x| o.is_subnormal(x)) {
            Class::SubnormalInput
        } else if r.is_some_and(|r| r.is_subnormal(expected)) {
            Class::SubnormalResult
        } else {
            Class::Other
        }
    }

    /// `got` matches `expected` under the NaN rule.
    pub fn matches(&self, got: u64, expected: u64, nan_exact: bool) -> bool {
        got == expected
            || (!nan_exact
                && self
                    .result_fmt
                    .is_some_and(|r| r.is_nan(got) && r.is_nan(expected)))
    }
}

/// One case where the RTL or the golden model differs from the file.
#[derive(Clone, Debug)]
pub struct CaseMismatch {
    /// the case
    pub case: Case,
    /// its class
    pub class: Class,
    /// the RTL's result
    pub rtl: u64,
    /// the golden model's result
    pub golden: u64,
}

/// Counts of one class.
#[derive(Clone, Debug, Default)]
pub struct ClassCount {
    /// cases where the RTL differs from the expected result
    pub rtl: u64,
    /// cases where the golden model differs from the expected result
    pub golden: u64,
    /// first few mismatching cases
    pub examples: Vec<CaseMismatch>,
}

/// Mismatching cases shown per class.
pub const EXAMPLES_PER_CLASS: usize = 5;

/// What a TestFloat run found.
pub struct Outcome {
    /// cases checked
    pub cases: u64,
    /// cases where the RTL or the golden model differs from the file
    pub mismatches: u64,
    /// cases where RTL and golden model differ from each other
    pub rtl_vs_golden: u64,
    /// per class
    pub classes: BTreeMap<Class, ClassCount>,
    /// lines with flags
    pub with_flags: u64,
    /// the run as a report
    pub report: RunReport,
}

impl fmt::Display for Outcome {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let rtl: u64 = self.classes.values().map(|c| c.rtl).sum();
        let golden: u64 = self.classes.values().map(|c| c.golden).sum();
        writeln!(
            f,
            "{} TestFloat cases: RTL differs from the file in {rtl}, golden model in {golden}, \
             RTL from golden model in {}",
            self.cases, self.rtl_vs_golden
        )?;
        for (class, c) in &self.classes {
            writeln!(f, "  {class}: RTL {} golden {}", c.rtl, c.golden)?;
            for m in &c.examples {
                let ops: Vec<String> = m.case.operands.iter().map(|v| format!("{v:X}")).collect();
                writeln!(
                    f,
                    "    line {}: {} -> expected {:X}, rtl {:X}, golden {:X}",
                    m.case.line,
                    ops.join(" "),
                    m.case.expected,
                    m.rtl,
                    m.golden
                )?;
            }
        }
        for n in &self.report.notes {
            writeln!(f, "  note: {n}")?;
        }
        Ok(())
    }
}

/// Runs `cases` through the harness and the golden model of `g` and
/// compares both with the expected results.
pub fn run(
    g: &Generated,
    harness: &sim::Harness,
    tb: &dyn Testbench,
    map: &Mapping,
    cases: &[Case],
    source: &str,
    nan_exact: bool,
) -> Result<Outcome, FlowError> {
    let started = Instant::now();
    let ports = &g.ports;
    let tmp = std::env::temp_dir().join(format!(
        "rtl-gen-testfloat-{}-{}-{:?}",
        g.module.name,
        std::process::id(),
        std::thread::current().id()
    ));
    let (_, outputs) = harness.run_records(
        cases.iter().map(|c| c.operands.as_slice()),
        &tmp,
        &sim::RunOptions::default(),
    )?;
    let n_out = ports.outputs.len();
    let mut gold = vec![0u64; ports.outputs.len()];
    let mut classes: BTreeMap<Class, ClassCount> = BTreeMap::new();
    let (mut mismatches, mut rtl_vs_golden) = (0u64, 0u64);
    let mut first: Option<FailingVector> = None;
    for (c, got) in cases.iter().zip(outputs.chunks(n_out)) {
        tb.eval(&c.operands, &mut gold);
        let (r, gv) = (got[map.result], gold[map.result]);
        let rtl_ok = map.matches(r, c.expected, nan_exact);
        let golden_ok = map.matches(gv, c.expected, nan_exact);
        rtl_vs_golden += (got != gold) as u64;
        if rtl_ok && golden_ok {
            continue;
        }
        mismatches += 1;
        let class = map.classify(&c.operands, c.expected);
        let e = classes.entry(class).or_default();
        e.rtl += !rtl_ok as u64;
        e.golden += !golden_ok as u64;
        let m = CaseMismatch {
            case: c.clone(),
            class,
            rtl: r,
            golden: gv,
        };
        if e.examples.len() < EXAMPLES_PER_CLASS {
            e.examples.push(m);
        }
        if first.is_none() {
            let name = &ports.outputs[map.result].name;
            first = Some(FailingVector {
                index: c.line - 1,
                location: Some(format!("{source} line {}", c.line)),
                inputs: super::report::hex_values(
                    &ports
                        .inputs
                        .iter()
                        .map(|p| p.name.clone())
                        .zip(c.operands.iter().copied())
                        .collect::<Vec<_>>(),
                ),
                expected: [(name.clone(), format!("{:#x}", c.expected))].into(),
                got: [
                    (name.clone(), format!("{r:#x}")),
                    (format!("{name} (golden model)"), format!("{gv:#x}")),
                ]
                .into(),
                replay: None,
            });
        }
    }
    let elapsed = started.elapsed().as_secs_f64();
    let with_flags = cases.iter().filter(|c| c.flags.is_some()).count() as u64;
    let mut report = RunReport::new("testfloat", g);
    report.total_vectors = cases.len() as u64;
    report.vectors = cases.len() as u64;
    report.mismatches = mismatches;
    report.first_mismatch = first;
    report.mismatch_classes = classes
        .iter()
        .flat_map(|(k, c)| {
            [
                (format!("{k} (rtl)"), c.rtl),
                (format!("{k} (golden)"), c.golden),
            ]
        })
        .filter(|(_, n)| *n > 0)
        .collect();
    report.vectors_per_sec = cases.len() as f64 / elapsed.max(1e-9);
    report.wall_time_s = elapsed;
    report.input = Some(source.to_string());
    report.notes.push(format!(
        "exception flags ignored ({with_flags} of {} cases have them): the operators \
             produce no flags",
        cases.len()
    ));
    report.notes.push(if nan_exact {
        "NaN results compared bit for bit (--nan-exact)".into()
    } else {
        "any NaN result matches any expected NaN (our NaN is canonical)".into()
    });
    report
        .notes
        .push("subnormals are not flushed (inputs or results); compared bit for bit".into());
    if rtl_vs_golden > 0 {
        report.notes.push(format!(
            "RTL and golden model differ on {rtl_vs_golden} cases (some outputs)"
        ));
    }
    report.update_verdict();
    Ok(Outcome {
        cases: cases.len() as u64,
        mismatches,
        rtl_vs_golden,
        classes,
        with_flags,
        report,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cases_parse_with_and_without_flags_and_errors_name_line_and_field() {
        let ins = [Port::new("a", 32), Port::new("b", 32)];
        let z = Port::new("z", 32);
        let text =
            "# made by a script\n3F800000 BF800000 00000000 00\n\n7F800000 00000001 7FC00000\n";
        let c = read_cases(text.as_bytes(), "t", &ins, &z).unwrap();
        assert_eq!(c.len(), 2);
        assert_eq!(c[0].operands, [0x3f80_0000, 0xbf80_0000]);
        assert_eq!((c[0].line, c[0].flags), (2, Some(0)));
        assert_eq!(
            (c[1].line, c[1].flags, c[1].expected),
            (4, None, 0x7fc0_0000)
        );
        let err = |t: &str| {
            read_cases(t.as_bytes(), "t", &ins, &z)
                .unwrap_err()
                .to_string()
        };
        assert!(err("1 2\n").contains("t: line 1: wrong field count: 2 fields"));
        let ok = "3F800000 BF800000 00000000 00\n";
        assert_eq!(
            err(&format!("{ok}3F800000 0000000G 00000000 00\n")),
            "t: line 2, field `b`: `0000000G` is not 8 hex digit(s): a 32-bit field has exactly 8 \
             (a line cut short, or a file for another format)"
        );
        // a line cut inside the result (the cut value would have read as a small number)
        assert!(err(&format!("{ok}3F800000 3F800000 3F8\n"))
            .contains("line 2, field `result z`: `3F8` is not 8 hex digit(s)"));
        // a binary16 file fed to a binary32 unit (zero-extended, it could have matched)
        assert!(
            err("3C00 3C00 3C00 00\n").contains("line 1, field `a`: `3C00` is not 8 hex digit(s)")
        );
        // flags are two hex digits (8 bits)
        assert!(err("3F800000 3F800000 3F800000 100\n")
            .contains("line 1, field `flags`: `100` is not 2 hex digit(s)"));
        assert!(err("3F800000 3F800000 3F800000 0\n").contains("field `flags`"));
    }

    #[test]
    fn classes_and_the_nan_rule() {
        let f32 = Fmt {
            exp_bits: 8,
            frac_bits: 23,
        };
        let m = Mapping {
            result: 0,
            operand_fmt: f32,
            result_fmt: Some(f32),
        };
        assert_eq!(m.classify(&[0x7fc0_0001, 0], 0x7fc0_0000), Class::Nan);
        assert_eq!(m.classify(&[0xff80_0000, 0], 0xff80_0000), Class::Infinity);
        assert_eq!(
            m.classify(&[0x7f00_0000, 0x7f00_0000], 0x7f7f_ffff),
            Class::Overflow
        );
        assert_eq!(m.classify(&[1, 0], 1), Class::SubnormalInput);
        assert_eq!(
            m.classify(&[0x0080_0000, 0x3f00_0000], 0x0040_0000),
            Class::SubnormalResult
        );
        assert_eq!(
            m.classify(&[0x3f80_0000, 0x3f80_0000], 0x4000_0000),
            Class::Other
        );
        assert!(m.matches(0x7fc0_0000, 0xffc0_0001, false));
        assert!(!m.matches(0x7fc0_0000, 0xffc0_0001, true));
        assert!(!m.matches(0x7f80_0000, 0x7fc0_0000, false));
    }
}
