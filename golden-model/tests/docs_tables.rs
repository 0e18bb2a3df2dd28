//! The tables in docs/float.md and docs/wide.md marked `<!-- table:NAME -->`
//! are checked against the code's constants, so the written spec cannot
//! drift.

use golden_model::float::{
    dot3_accumulator_bits, Class, FloatFormat, RoundingMode, RAW_CLASS_BITS, RAW_EXP_BITS,
    RAW_SIGN_BITS, RAW_SIG_BITS, RAW_STICKY_BITS, RAW_STICKY_MIN_EXTRA_BITS,
};
use golden_model::wide::WideFormat;

/// The body rows of the table after `<!-- table:{name} -->` in `docs/{doc}`,
/// split into cells (code quotes dropped).
fn table_in(doc: &str, name: &str) -> Vec<Vec<String>> {
    let path = format!("{}/../docs/{doc}", env!("CARGO_MANIFEST_DIR"));
    let doc = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"));
    let start = doc
        .find(&format!("<!-- table:{name} -->"))
        .unwrap_or_else(|| panic!("no table {name}"));
    let body = &doc[start..];
    let end = body.find("<!-- end -->").expect("table end marker");
    let rows: Vec<Vec<String>> = body[..end]
        .lines()
        .filter(|l| l.starts_with('|'))
        .skip(2) // header and separator
        .map(|l| {
            l.trim_matches('|')
                .split('|')
                .map(|c| c.trim().trim_matches('`').to_string())
                .collect()
        })
        .collect();
    assert!(!rows.is_empty(), "table {name} is empty");
    rows
}

/// A table of docs/float.md.
fn table(name: &str) -> Vec<Vec<String>> {
    table_in("float.md", name)
}

#[test]
fn raw_format_table_matches_code() {
    let rows = table("raw");
    let width = |field: &str| -> String {
        rows.iter()
            .find(|r| r[0] == field)
            .unwrap_or_else(|| panic!("no row {field}"))[1]
            .clone()
    };
    assert_eq!(width("sign"), RAW_SIGN_BITS.to_string());
    assert_eq!(width("class"), RAW_CLASS_BITS.to_string());
    assert_eq!(width("exp"), RAW_EXP_BITS.to_string());
    assert_eq!(width("sig"), RAW_SIG_BITS.to_string());
    assert_eq!(width("sticky"), RAW_STICKY_BITS.to_string());
    assert_eq!(
        width("sticky ⇒ sig ≥ 2^(F+1)"),
        format!("F + {RAW_STICKY_MIN_EXTRA_BITS}")
    );
    // The class encoding written in the class row.
    let class_row = &rows.iter().find(|r| r[0] == "class").unwrap()[2];
    for c in [Class::Zero, Class::Finite, Class::Inf, Class::NaN] {
        let entry = format!("{} {:?}", c as u8, c);
        assert!(class_row.contains(&entry), "class row lacks `{entry}`");
        assert!((c as u32) < 1 << RAW_CLASS_BITS);
    }
    // The field types really have these widths.
    assert_eq!(i32::BITS, RAW_EXP_BITS);
    assert_eq!(u128::BITS, RAW_SIG_BITS);
}

#[test]
fn rounding_mode_table_matches_code() {
    let rows = table("modes");
    assert_eq!(rows.len(), RoundingMode::ALL.len());
    for (row, mode) in rows.iter().zip(RoundingMode::ALL) {
        assert_eq!(row[0], (mode as u8).to_string());
        assert_eq!(row[1], format!("{mode:?}"));
    }
}

#[test]
fn format_table_matches_code() {
    let rows = table("formats");
    let named = [
        ("BINARY16", FloatFormat::BINARY16),
        ("BFLOAT16", FloatFormat::BFLOAT16),
        ("BINARY32", FloatFormat::BINARY32),
        ("BINARY64", FloatFormat::BINARY64),
    ];
    assert_eq!(rows.len(), named.len());
    for (row, (name, f)) in rows.iter().zip(named) {
        let want = [
            name.to_string(),
            f.exp_bits().to_string(),
            f.frac_bits().to_string(),
            f.width().to_string(),
            f.bias().to_string(),
            f.emin().to_string(),
            f.emax().to_string(),
            format!("{:#x}", f.canonical_nan()),
            dot3_accumulator_bits(f).to_string(),
        ];
        assert_eq!(row, &want, "format table row for {name}");
    }
}

#[test]
fn wide_record_tables_match_the_record() {
    let w = WideFormat::new(FloatFormat::BINARY32, 4, 8).unwrap();
    let fields = w.fields();
    let rows = table_in("wide.md", "wide-record");
    for r in &rows {
        let f = fields
            .iter()
            .find(|f| f.kind.name() == r[0])
            .unwrap_or_else(|| panic!("no field {}", r[0]));
        assert_eq!(r[1], f.width.to_string(), "width of {}", r[0]);
        assert_eq!(r[2], f.offset.to_string(), "offset of {}", r[0]);
    }
    // the table's last row is the record's last field
    let last = fields.last().unwrap();
    assert_eq!(rows.last().unwrap()[0], last.kind.name());
    // the fields tile the record without gaps
    let mut at = 0;
    for f in &fields {
        assert_eq!(f.offset, at, "{}", f.kind.name());
        at += f.width;
    }
    assert_eq!(at, w.record_bits());
    for r in table_in("wide.md", "wide-bytes") {
        let n: usize = r[0].parse().unwrap();
        let q: u32 = r[1].parse().unwrap();
        let w = WideFormat::new(FloatFormat::BINARY32, n, q).unwrap();
        assert_eq!(r[2], w.record_bits().to_string(), "N={n} q={q} bits");
        assert_eq!(r[3], w.record_bytes().to_string(), "N={n} q={q} bytes");
        assert_eq!(r[4], w.baseline_bytes().to_string(), "N={n} q={q} baseline");
        let ratio = w.record_bytes() as f64 / w.baseline_bytes() as f64;
        assert_eq!(r[5], format!("{ratio:.2}"), "N={n} q={q} ratio");
    }
}
