//! Unit parameters: declared per unit with a range and a default, given on the
//! command line as `--param key=value`, resolved and checked before building.

use std::collections::BTreeMap;
use std::fmt;

/// The values a parameter accepts.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ParamKind {
    /// an integer in `min..=max`
    Int {
        /// smallest accepted value
        min: i64,
        /// largest accepted value
        max: i64,
    },
    /// one of a fixed set of words
    Choice(&'static [&'static str]),
}

/// A declared parameter.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ParamSpec {
    /// key on the command line
    pub name: &'static str,
    /// what it controls
    pub doc: &'static str,
    /// accepted values
    pub kind: ParamKind,
    /// value when not given
    pub default: &'static str,
}

impl fmt::Display for ParamSpec {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let range = match self.kind {
            ParamKind::Int { min, max } => format!("{min}..={max}"),
            ParamKind::Choice(words) => words.join("|"),
        };
        write!(
            f,
            "{}={} ({range}, default {})",
            self.name, self.doc, self.default
        )
    }
}

/// Why parameters were rejected.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum ParamError {
    /// no unit of that name
    UnknownUnit {
        /// what was asked for
        name: String,
        /// what exists
        known: Vec<String>,
    },
    /// the unit has no such parameter
    Unknown {
        /// unit
        unit: String,
        /// key given
        key: String,
        /// keys accepted
        known: Vec<String>,
    },
    /// not of the form key=value
    Syntax(String),
    /// a value outside the accepted set
    Invalid {
        /// unit
        unit: String,
        /// key
        key: String,
        /// value given
        value: String,
        /// what is accepted
        expected: String,
    },
    /// a combination of values the unit cannot build
    Combination(String),
}

impl fmt::Display for ParamError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ParamError::UnknownUnit { name, known } => {
                write!(
                    f,
                    "unknown unit `{name}`; known units: {}",
                    known.join(", ")
                )
            }
            ParamError::Unknown { unit, key, known } => {
                write!(
                    f,
                    "unit `{unit}` has no parameter `{key}`; its parameters: {}",
                    known.join(", ")
                )
            }
            ParamError::Syntax(s) => write!(f, "parameter `{s}` is not of the form key=value"),
            ParamError::Invalid {
                unit,
                key,
                value,
                expected,
            } => {
                write!(
                    f,
                    "unit `{unit}`: parameter {key}={value} is invalid; expected {expected}"
                )
            }
            ParamError::Combination(s) => write!(f, "{s}"),
        }
    }
}

impl std::error::Error for ParamError {}

/// Resolved parameters: every declared key has a checked value.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Params {
    values: BTreeMap<String, String>,
}

impl Params {
    /// Resolves `given` (`key=value` strings) against `specs`: unknown keys,
    /// bad syntax and out-of-range values are errors; missing keys take defaults.
    pub fn resolve(
        unit: &str,
        specs: &[ParamSpec],
        given: &[String],
    ) -> Result<Params, ParamError> {
        let mut values: BTreeMap<String, String> = specs
            .iter()
            .map(|s| (s.name.to_string(), s.default.to_string()))
            .collect();
        for g in given {
            let (k, v) = g
                .split_once('=')
                .ok_or_else(|| ParamError::Syntax(g.clone()))?;
            let (k, v) = (k.trim(), v.trim());
            let spec = specs
                .iter()
                .find(|s| s.name == k)
                .ok_or_else(|| ParamError::Unknown {
                    unit: unit.to_string(),
                    key: k.to_string(),
                    known: specs.iter().map(|s| s.name.to_string()).collect(),
                })?;
            let invalid = |expected: String| ParamError::Invalid {
                unit: unit.to_string(),
                key: k.to_string(),
                value: v.to_string(),
                expected,
            };
            match spec.kind {
                ParamKind::Int { min, max } => {
                    let n: i64 = v
                        .parse()
                        .map_err(|_| invalid(format!("an integer in {min}..={max}")))?;
                    if n < min || n > max {
                        return Err(invalid(format!("an integer in {min}..={max}")));
                    }
                    values.insert(k.to_string(), n.to_string());
                }
                ParamKind::Choice(words) => {
                    if !words.contains(&v) {
                        return Err(invalid(format!("one of {}", words.join(", "))));
                    }
                    values.insert(k.to_string(), v.to_string());
                }
            }
        }
        Ok(Params { values })
    }

    /// The integer value of `key` (declared as `Int`).
    pub fn int(&self, key: &str) -> i64 {
        self.values
            .get(key)
            .and_then(|v| v.parse().ok())
            .unwrap_or_else(|| panic!("parameter `{key}` is not a declared integer"))
    }

    /// The integer value of `key` as `u32` (declared as `Int` with `min >= 0`).
    pub fn u32(&self, key: &str) -> u32 {
        self.int(key) as u32
    }

    /// The word value of `key` (declared as `Choice`).
    pub fn word(&self, key: &str) -> &str {
        self.values
            .get(key)
            .map(String::as_str)
            .unwrap_or_else(|| panic!("parameter `{key}` is not declared"))
    }

    /// All values, sorted by key.
    pub fn values(&self) -> &BTreeMap<String, String> {
        &self.values
    }

    /// `--param k=v` arguments that reproduce these values.
    pub fn to_args(&self) -> String {
        self.values
            .iter()
            .map(|(k, v)| format!("--param {k}={v}"))
            .collect::<Vec<_>>()
            .join(" ")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const SPECS: &[ParamSpec] = &[
        ParamSpec {
            name: "width",
            doc: "bits",
            kind: ParamKind::Int { min: 1, max: 32 },
            default: "16",
        },
        ParamSpec {
            name: "round",
            doc: "mode",
            kind: ParamKind::Choice(&["rne", "rtz"]),
            default: "rne",
        },
    ];

    #[test]
    fn defaults_overrides_and_errors() {
        let p = Params::resolve("u", SPECS, &["width=8".into()]).unwrap();
        assert_eq!((p.int("width"), p.word("round")), (8, "rne"));
        let e = Params::resolve("u", SPECS, &["width=0".into()]).unwrap_err();
        assert!(
            e.to_string()
                .contains("width=0 is invalid; expected an integer in 1..=32"),
            "{e}"
        );
        let e = Params::resolve("u", SPECS, &["depth=3".into()]).unwrap_err();
        assert!(
            e.to_string()
                .contains("no parameter `depth`; its parameters: width, round"),
            "{e}"
        );
        assert!(matches!(
            Params::resolve("u", SPECS, &["width".into()]),
            Err(ParamError::Syntax(_))
        ));
        assert!(Params::resolve("u", SPECS, &["round=up".into()])
            .unwrap_err()
            .to_string()
            .contains("one of rne, rtz"));
    }
}
