//! The tables in docs/float.md marked `<!-- table:NAME -->` are checked
//! against the code's constants, so the written spec cannot drift.

use golden_model::float::{
    dot3_accumulator_bits, Class, FloatFormat, RoundingMode, RAW_CLASS_BITS, RAW_EXP_BITS,
    RAW_SIGN_BITS, RAW_SIG_BITS, RAW_STICKY_BITS, RAW_STICKY_MIN_EXTRA_BITS,
};

/// The body rows of the table after `<!-- table:{name} -->`, split into cells.
fn table(name: &str) -> Vec<Vec<String>> {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../docs/float.md");
    let doc = std::fs::read_to_string(path).expect("docs/float.md");
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
                .map(|c| c.trim().to_string())
                .collect()
        })
        .collect();
    assert!(!rows.is_empty(), "table {name} is empty");
    rows
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
