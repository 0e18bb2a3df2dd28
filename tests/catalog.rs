//! Every registered unit (`rtl_flow::catalog()`), so that registering a unit
//! is enough to bring it under test: with its default parameters and with
//! `pipeline=balanced`, every emitted module lints clean with
//! `verilator --lint-only -Wall` as its own top, and the IR evaluator agrees
//! with the golden model on corner and random vectors. (The Verilator
//! cross-checks of chosen configurations are the units' own test files.)

mod common;

use rtl_flow::{catalog, Generated, Skipped};
use std::path::Path;

/// Lints the design with each of its modules as the top.
fn lint_every_module(g: &Generated, dir: &Path) {
    for file in &g.files {
        let mut ports = g.ports.clone();
        ports.top = file.module.clone();
        sim::lint(&ports, dir).unwrap_or_else(|e| panic!("{} as top: {e}", file.module));
    }
}

#[test]
fn every_registered_unit_lints_and_matches_its_golden_model() {
    let mut checked = Vec::new();
    for entry in catalog() {
        let unit = entry.unit.name();
        for given in [&[][..], &["pipeline=balanced"][..]] {
            let (g, dir) = common::generate("catalog", unit, given);
            lint_every_module(&g, &dir);
            let tb = g.testbench();
            for first in [0, 1_000_000] {
                let r = g.evaluate(
                    &Skipped {
                        of: tb.as_ref(),
                        first,
                    },
                    1_000,
                    3,
                );
                assert_eq!(
                    (r.vectors, r.mismatches),
                    (1_000, 0),
                    "{unit} {given:?} from vector {first}: {r}"
                );
            }
            checked.push(format!("{} ({} modules)", g.module.name, g.files.len()));
        }
    }
    eprintln!("checked: {}", checked.join(", "));
    // the 21 units of today (a shorter catalog means a unit was dropped)
    assert!(checked.len() >= 2 * 21, "{} configurations", checked.len());
}

/// With `handshake=ready` (docs/handshake.md) every registered unit, in its
/// reduced configuration, emits a top that lints clean with
/// `verilator --lint-only -Wall` (with the hierarchy below it), and the IR
/// evaluator drives it back to back and agrees with the golden model. The
/// stall tests in Verilator are tests/handshake_rtl.rs.
#[test]
fn every_registered_unit_lints_with_the_ready_handshake() {
    let mut checked = Vec::new();
    for entry in catalog() {
        let unit = entry.unit.name();
        let mut given = reduced(&entry);
        given.push("handshake=ready".into());
        let given: Vec<&str> = given.iter().map(String::as_str).collect();
        let (g, dir) = common::generate("catalog_ready", unit, &given);
        assert!(g.ports.ready.is_some(), "{unit}: no in_ready/out_ready");
        sim::lint(&g.ports, &dir).unwrap_or_else(|e| panic!("{unit} {given:?}: {e}"));
        common::evaluated(&g, 300, 3);
        checked.push(g.module.name.clone());
    }
    eprintln!("lint clean with handshake=ready: {}", checked.join(", "));
    assert!(checked.len() >= 20, "{} units", checked.len());
}

/// The reduced configuration of a unit: a narrower format (or narrower
/// operands) than its defaults, from the parameters it has.
fn reduced(entry: &rtl_flow::Entry) -> Vec<String> {
    const NARROWER: [(&str, &str); 9] = [
        ("exp_bits", "5"),
        ("frac_bits", "10"),
        ("to_exp_bits", "4"),
        ("to_frac_bits", "3"),
        ("a_width", "8"),
        ("b_width", "8"),
        ("box_bits", "4"),
        ("prim_bits", "8"),
        ("samples", "8"),
    ];
    let specs = rtl_flow::param_specs(entry);
    NARROWER
        .iter()
        .filter(|(name, _)| specs.iter().any(|s| s.name == *name))
        .map(|(name, value)| format!("{name}={value}"))
        .collect()
}

/// What the naming rules count in one Verilog module's text.
#[derive(Default)]
struct NameAudit {
    /// wire and reg names
    names: usize,
    /// names ending in `_<digits>` that are not a bit range `_<hi>_<lo>`
    numbered: Vec<String>,
    /// names that are only an operation word (`cat`, `or_w`, `mux_3`)
    bare: Vec<String>,
    /// lines over [`LINE_MAX`] characters (their lengths)
    long_lines: Vec<usize>,
    /// right-hand sides assigned twice
    repeated: Vec<String>,
}

/// Longest Verilog line the rules allow.
const LINE_MAX: usize = 200;

/// Words an operation alone would give a wire (the builder's verbs and the
/// roles a helper could leave unqualified).
const OPERATION_WORDS: &[&str] = &[
    "add", "sub", "mul", "not", "and", "or", "xor", "eq", "lt", "le", "shl", "shr", "mux", "cat",
    "bits", "all", "any", "par", "sign",
];

fn is_numbered(name: &str) -> bool {
    let parts: Vec<&str> = name.split('_').collect();
    let digits = |s: &str| !s.is_empty() && s.bytes().all(|b| b.is_ascii_digit());
    let n = parts.len();
    // `x_7_4` is bits 7..4 of `x`; `x_7_4_2` is still numbered
    let bit_range = n >= 3 && digits(parts[n - 1]) && digits(parts[n - 2]) && !digits(parts[n - 3]);
    n >= 2 && digits(parts[n - 1]) && !bit_range
}

fn is_bare_operation(name: &str) -> bool {
    let parts: Vec<&str> = name.split('_').collect();
    let letter = |p: &str| p.len() == 1 && p.bytes().all(|b| b.is_ascii_alphabetic());
    let number = |p: &str| !p.is_empty() && p.bytes().all(|b| b.is_ascii_digit());
    OPERATION_WORDS.contains(&parts[0])
        && match parts[1..] {
            [] => true,
            [p] => letter(p) || number(p),
            [l, n] => letter(l) && number(n),
            _ => false,
        }
}

fn audit(text: &str) -> NameAudit {
    let mut a = NameAudit::default();
    let mut rhs = std::collections::HashSet::new();
    // an assignment may continue over several lines, up to its `;`
    let mut statement = String::new();
    for line in text.lines() {
        if line.len() > LINE_MAX {
            a.long_lines.push(line.len());
        }
        let line = line.trim();
        let declared = ["wire ", "reg "]
            .iter()
            .find_map(|kw| line.strip_prefix(kw));
        if let Some(decl) = declared {
            let name = decl.trim_end_matches(';').rsplit(' ').next().unwrap_or("");
            a.names += 1;
            if is_numbered(name) {
                a.numbered.push(name.to_string());
            }
            if is_bare_operation(name) {
                a.bare.push(name.to_string());
            }
        }
        if line.starts_with("assign ") || !statement.is_empty() {
            statement = format!("{statement} {line}").trim().to_string();
        }
        if statement.ends_with(';') {
            if let Some((_, expr)) = statement.split_once(" = ") {
                if !rhs.insert(expr.to_string()) {
                    a.repeated.push(expr.to_string());
                }
            }
            statement.clear();
        }
    }
    a
}

#[test]
fn audit_counts_what_the_rules_name() {
    let text = "wire [3:0] cat_2;\nwire x_7_4;\nwire x_7_4_2;\nwire lhs_s3;\nwire xor_s_x;\nreg [1:0] or_w;\n\
                wire a_b7;\nassign a = b & c;\nassign d = b\n    & c;\nwire sign_lhs;\n";
    let a = audit(text);
    assert_eq!(a.names, 8);
    assert_eq!(a.numbered, ["cat_2", "x_7_4_2"]);
    assert_eq!(a.bare, ["cat_2", "or_w"]);
    assert_eq!(a.repeated, ["b & c;"]);
    assert!(audit(&format!("// {}", "x".repeat(LINE_MAX))).long_lines == [LINE_MAX + 3]);
}

/// Every unit at its defaults and at a reduced format: at most 5 % of wire
/// and reg names numbered (at most 2 in a module of under 40 names), none
/// that is only an operation word, no line over [`LINE_MAX`] characters, no
/// expression assigned twice in a module. Prints the figures per unit.
#[test]
fn every_registered_unit_names_its_wires_by_role() {
    let mut broken = Vec::new();
    for entry in catalog() {
        let unit = entry.unit.name();
        let small = reduced(&entry);
        assert!(!small.is_empty(), "{unit}: no reduced configuration");
        for given in [vec![], small] {
            let g = rtl_flow::generate(unit, &given)
                .unwrap_or_else(|e| panic!("generate {unit} {given:?}: {e}"));
            let (mut names, mut numbered) = (0, 0);
            for file in &g.files {
                let a = audit(&file.text);
                names += a.names;
                numbered += a.numbered.len();
                let allowed = if a.names < 40 { 2 } else { a.names / 20 };
                let at = format!("{unit} {given:?} {}", file.module);
                if a.numbered.len() > allowed {
                    let n = a.numbered.len();
                    broken.push(format!(
                        "{at}: {n} of {} numbered: {:?}",
                        a.names, a.numbered
                    ));
                }
                if !a.bare.is_empty() {
                    broken.push(format!("{at}: operation words as names: {:?}", a.bare));
                }
                if !a.long_lines.is_empty() {
                    broken.push(format!("{at}: lines of {:?} characters", a.long_lines));
                }
                if !a.repeated.is_empty() {
                    broken.push(format!("{at}: assigned twice: {:?}", a.repeated));
                }
            }
            println!(
                "names {unit} {}: {names} names, {numbered} numbered ({:.1} %)",
                if given.is_empty() {
                    "defaults".to_string()
                } else {
                    given.join(" ")
                },
                100.0 * numbered as f64 / names.max(1) as f64
            );
        }
    }
    assert!(broken.is_empty(), "{}", broken.join("\n"));
}

/// Every integer parameter of every registered unit at each end of its
/// range (the others at their defaults, where the unit accepts the
/// combination): the stimulus and the golden model run without a panic and
/// answer 200 vectors. The ends are where a stimulus's assumptions break
/// (e3m2 with q = 8 once put the frame's exponent range upside down).
#[test]
fn every_parameter_end_has_a_stimulus_and_golden_answers() {
    let mut configurations = 0;
    for entry in catalog() {
        let unit = entry.unit.name();
        for spec in rtl_flow::param_specs(&entry) {
            let rtl_gen::params::ParamKind::Int { min, max } = spec.kind else {
                continue;
            };
            for end in [min, max] {
                let given = vec![format!("{}={end}", spec.name)];
                let Ok(g) = rtl_flow::generate(unit, &given) else {
                    continue; // a combination the unit refuses, with an error
                };
                let answered = common::golden_vectors(&g, 7, 200).count();
                assert_eq!(answered, 200, "{unit} {given:?}");
                configurations += 1;
            }
        }
    }
    // every unit has integer parameters; most ends are accepted
    assert!(configurations > 80, "{configurations} configurations");
}
