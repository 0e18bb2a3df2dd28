//! Unit parameters, declared once per unit as a typed table ([`params!`]):
//! the list `rtl-gen list` prints, the range and word checks with their
//! messages, the typed values a generator reads, the Verilog header and the
//! depth that `pipeline=balanced` sets all come from that one table. Choice
//! parameters are enums declared with their words ([`choice!`]).
//!
//! Reading `key=value` words from a command line is the flow's
//! (`rtl_flow::params`); this module takes (key, value) pairs.

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

/// A declared parameter (one row of a [`params!`] table).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ParamSpec {
    /// key on the command line
    pub name: &'static str,
    /// what it controls (the row's doc comment; read it through [`ParamSpec::help`])
    pub doc: &'static str,
    /// accepted values
    pub kind: ParamKind,
    /// value when not given
    pub default: &'static str,
}

impl ParamSpec {
    /// What the parameter controls, as one line.
    pub fn help(&self) -> &'static str {
        self.doc.trim()
    }

    /// The accepted values: `min..=max` or `word|word|...`.
    pub fn range(&self) -> String {
        match self.kind {
            ParamKind::Int { min, max } => format!("{min}..={max}"),
            ParamKind::Choice(words) => words.join("|"),
        }
    }
}

impl fmt::Display for ParamSpec {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{}={} ({}, default {})",
            self.name,
            self.help(),
            self.range(),
            self.default
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

/// Checked parameters: every declared key has a value its row accepts.
/// The typed tables read them ([`ParamSet::from_params`]); nothing else
/// looks a value up by its key.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Params {
    values: BTreeMap<String, String>,
}

impl Params {
    /// Checks `given` (key, value) pairs against `specs`: unknown keys and
    /// values outside a row's range or words are errors; missing keys take
    /// their defaults.
    pub fn check<'a>(
        unit: &str,
        specs: &[ParamSpec],
        given: impl IntoIterator<Item = (&'a str, &'a str)>,
    ) -> Result<Params, ParamError> {
        let mut values: BTreeMap<String, String> = specs
            .iter()
            .map(|s| (s.name.to_string(), s.default.to_string()))
            .collect();
        for (k, v) in given {
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

    /// The defaults of `specs`.
    pub fn defaults(specs: &[ParamSpec]) -> Params {
        Params::check("", specs, []).expect("no values given, none can be wrong")
    }

    /// The typed value of the row `key` of a table; the values were checked
    /// against that table's rows, so a miss is a generator bug.
    #[doc(hidden)]
    pub fn typed<T: ParamValue>(&self, key: &str) -> T {
        self.values
            .get(key)
            .and_then(|v| T::parse_word(v))
            .unwrap_or_else(|| panic!("parameter `{key}` was not checked against its table"))
    }

    /// The same values without `key`: a parameter that does not apply to
    /// this configuration, left out of its headers (a reader of the
    /// values takes the default for a missing key).
    pub fn without(&self, key: &str) -> Params {
        let mut values = self.values.clone();
        values.remove(key);
        Params { values }
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

/// The type of one parameter: how its checked word reads and is written
/// back (header, `to_args`). Integers and [`choice!`] enums.
pub trait ParamValue: Copy {
    /// The value of a word its row accepted.
    fn parse_word(word: &str) -> Option<Self>;
    /// The word of the value.
    fn to_word(self) -> String;
}

impl ParamValue for u32 {
    fn parse_word(word: &str) -> Option<Self> {
        word.parse().ok()
    }
    fn to_word(self) -> String {
        self.to_string()
    }
}

/// A unit's parameters as one typed value, declared by [`params!`].
pub trait ParamSet: Copy + Sized + 'static {
    /// The rows: names, docs, ranges or words, defaults, in table order.
    const SPECS: &'static [ParamSpec];
    /// The typed values of parameters checked against [`ParamSet::SPECS`]
    /// (or a superset of it).
    fn from_params(p: &Params) -> Self;
    /// Every parameter's word, sorted by key: the module header.
    fn header(&self) -> BTreeMap<String, String>;
    /// The pipeline depth, the row called `stages` (`pipeline=balanced`
    /// builds the datapath with it set to 0); `None` for a unit without one.
    fn stages_mut(&mut self) -> Option<&mut u32>;
    /// The defaults.
    fn defaults() -> Self {
        Self::from_params(&Params::defaults(Self::SPECS))
    }
}

/// Declares a unit's parameters once: a struct with a typed field per
/// parameter and its [`ParamSet`] (the rows, the typed read, the header).
///
/// ```
/// rtl_gen::params! {
///     /// Parameters of a demo unit.
///     pub struct DemoParams {
///         /// operand width
///         width: u32 [1..=32] = 16,
///         /// rounding of the result
///         round: rtl_gen::arith::float::Rounding = rtl_gen::arith::float::Rounding::Rne,
///         /// pipeline stages
///         stages: u32 [0..=8] = 2,
///     }
/// }
/// use rtl_gen::params::ParamSet;
/// let p = rtl_gen::params::Params::check("demo", DemoParams::SPECS, [("width", "8")]).unwrap();
/// let d = DemoParams::from_params(&p);
/// assert_eq!((d.width, d.round.word(), d.stages), (8, "rne", 2));
/// ```
///
/// An integer row gives its range (`[min..=max]`) and a literal default; a
/// choice row names a [`choice!`] type (or another type with `WORDS` and a
/// `const fn word`) and a value of it. The doc comment of a row is its help.
#[macro_export]
macro_rules! params {
    (
        $(#[$meta:meta])*
        $vis:vis struct $name:ident {
            $(
                $(#[doc = $doc:literal])*
                $field:ident : $ty:ty $([$min:literal ..= $max:literal])? = $default:expr
            ),* $(,)?
        }
    ) => {
        $(#[$meta])*
        #[derive(Debug, Clone, Copy, PartialEq, Eq)]
        $vis struct $name {
            $( $(#[doc = $doc])* pub $field: $ty, )*
        }

        impl $crate::params::ParamSet for $name {
            const SPECS: &'static [$crate::params::ParamSpec] = &[
                $( $crate::params::ParamSpec {
                    name: stringify!($field),
                    doc: concat!($($doc),*),
                    kind: $crate::__param_kind!($ty $(, $min, $max)?),
                    default: $crate::__param_default!($ty, $default $(, $min)?),
                }, )*
            ];
            fn from_params(p: &$crate::params::Params) -> Self {
                Self { $( $field: p.typed(stringify!($field)), )* }
            }
            fn header(&self) -> ::std::collections::BTreeMap<String, String> {
                [$( (
                    stringify!($field).to_string(),
                    $crate::params::ParamValue::to_word(self.$field),
                ), )*]
                .into_iter()
                .collect()
            }
            fn stages_mut(&mut self) -> Option<&mut u32> {
                let found: Option<&mut u32> = None;
                $( let found = found.or($crate::__param_stages!(self, $field)); )*
                found
            }
        }
    };
}

/// A row's kind: an integer range, or the words of its type.
#[doc(hidden)]
#[macro_export]
macro_rules! __param_kind {
    ($ty:ty, $min:literal, $max:literal) => {
        $crate::params::ParamKind::Int {
            min: $min,
            max: $max,
        }
    };
    ($ty:ty) => {
        $crate::params::ParamKind::Choice(<$ty>::WORDS)
    };
}

/// A row's default word: the literal of an integer row, the word of a choice.
#[doc(hidden)]
#[macro_export]
macro_rules! __param_default {
    ($ty:ty, $default:expr, $min:literal) => {
        stringify!($default)
    };
    ($ty:ty, $default:expr) => {
        <$ty>::word($default)
    };
}

/// The field called `stages` (the pipeline depth), `None` for the others.
#[doc(hidden)]
#[macro_export]
macro_rules! __param_stages {
    ($s:ident, stages) => {
        Some(&mut $s.stages)
    };
    ($s:ident, $other:ident) => {
        None
    };
}

/// Declares a choice parameter's type: an enum whose variants are its words,
/// with `WORDS`, `ALL`, `word`, `parse` and [`ParamValue`].
///
/// ```
/// rtl_gen::choice! {
///     /// What a unit outputs.
///     pub enum Outputs {
///         /// the hit bit only
///         Hit = "hit",
///         /// the hit and its distance
///         Full = "full",
///     }
/// }
/// assert_eq!(Outputs::parse("full"), Some(Outputs::Full));
/// assert_eq!(Outputs::WORDS, &["hit", "full"]);
/// ```
#[macro_export]
macro_rules! choice {
    (
        $(#[$meta:meta])*
        $vis:vis enum $name:ident {
            $( $(#[doc = $doc:literal])* $variant:ident = $word:literal ),* $(,)?
        }
    ) => {
        $(#[$meta])*
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
        $vis enum $name {
            $( $(#[doc = $doc])* $variant, )*
        }

        impl $name {
            /// Every value, in word order.
            pub const ALL: &'static [$name] = &[$($name::$variant),*];
            /// The parameter words, in [`Self::ALL`] order.
            pub const WORDS: &'static [&'static str] = &[$($word),*];
            /// The parameter word.
            pub const fn word(self) -> &'static str {
                match self {
                    $( $name::$variant => $word, )*
                }
            }
            /// The value of `word`.
            pub fn parse(word: &str) -> Option<$name> {
                Self::ALL.iter().copied().find(|v| v.word() == word)
            }
        }

        impl $crate::params::ParamValue for $name {
            fn parse_word(word: &str) -> Option<Self> {
                Self::parse(word)
            }
            fn to_word(self) -> String {
                self.word().to_string()
            }
        }

        impl ::std::fmt::Display for $name {
            fn fmt(&self, f: &mut ::std::fmt::Formatter<'_>) -> ::std::fmt::Result {
                f.write_str(self.word())
            }
        }
    };
}

#[cfg(test)]
mod tests {
    use super::*;

    crate::choice! {
        /// test words
        enum Round {
            /// nearest
            Rne = "rne",
            /// toward zero
            Rtz = "rtz",
        }
    }

    crate::params! {
        /// a test table
        struct Demo {
            /// bits
            width: u32 [1..=32] = 16,
            /// mode
            round: Round = Round::Rne,
            /// registers
            stages: u32 [0..=4] = 2,
        }
    }

    crate::params! {
        /// a table without stages
        struct Flat {
            /// bits
            width: u32 [1..=32] = 16,
        }
    }

    fn demo(given: &[(&'static str, &'static str)]) -> Result<Demo, ParamError> {
        Params::check("u", Demo::SPECS, given.iter().copied()).map(|p| Demo::from_params(&p))
    }

    #[test]
    fn rows_defaults_values_and_errors() {
        let names: Vec<_> = Demo::SPECS.iter().map(|s| (s.name, s.default)).collect();
        assert_eq!(names, [("width", "16"), ("round", "rne"), ("stages", "2")]);
        assert_eq!(Demo::SPECS[1].kind, ParamKind::Choice(&["rne", "rtz"]));
        assert_eq!(Demo::SPECS[0].help(), "bits");
        assert_eq!(
            demo(&[("width", "8"), ("round", "rtz")]).unwrap(),
            Demo {
                width: 8,
                round: Round::Rtz,
                stages: 2
            }
        );
        assert_eq!(Demo::defaults(), demo(&[]).unwrap());
        let e = demo(&[("width", "0")]).unwrap_err();
        assert!(
            e.to_string()
                .contains("width=0 is invalid; expected an integer in 1..=32"),
            "{e}"
        );
        let e = demo(&[("depth", "3")]).unwrap_err();
        assert!(
            e.to_string()
                .contains("no parameter `depth`; its parameters: width, round, stages"),
            "{e}"
        );
        assert!(demo(&[("round", "up")])
            .unwrap_err()
            .to_string()
            .contains("one of rne, rtz"));
    }

    #[test]
    fn header_and_stages_come_from_the_table() {
        let mut d = demo(&[("width", "8")]).unwrap();
        let header: Vec<_> = d.header().into_iter().collect();
        assert_eq!(
            header,
            [
                ("round".to_string(), "rne".to_string()),
                ("stages".to_string(), "2".to_string()),
                ("width".to_string(), "8".to_string())
            ]
        );
        *d.stages_mut().unwrap() = 0;
        assert_eq!(d.stages, 0);
        assert!(Flat::defaults().stages_mut().is_none());
    }
}
