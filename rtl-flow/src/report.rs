//! Machine-readable reports of `check`, `sim` and TestFloat runs: a JSON
//! document (serde) and JUnit XML, and the merge of shard reports into one
//! verdict (`rtl-gen merge-reports`).
//!
//! Values of ports are hex strings (`"0x1f"`) so that 64-bit values survive
//! JSON readers that hold numbers as doubles.

use super::Generated;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::fmt;
use std::path::Path;

/// Version of the report layout; bumped on incompatible changes.
pub const SCHEMA: u32 = 1;

/// One slice of a sharded regression: shard `index` (1-based) of `count`.
/// Shard K of N runs the vectors whose index `i` has `i mod N = K - 1`, so
/// corner vectors are split by index like the random ones and N shards
/// together run exactly the unsharded set.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Shard {
    /// 1-based shard number, `1..=count`
    pub index: u64,
    /// number of shards
    pub count: u64,
}

impl Shard {
    /// The whole vector set.
    pub const ALL: Shard = Shard { index: 1, count: 1 };

    /// Parses `K/N` with `1 <= K <= N`.
    pub fn parse(s: &str) -> Result<Shard, String> {
        let bad = || format!("--shard {s}: expected K/N with 1 <= K <= N, e.g. 3/8");
        let (k, n) = s.split_once('/').ok_or_else(bad)?;
        let (index, count): (u64, u64) = (
            k.trim().parse().map_err(|_| bad())?,
            n.trim().parse().map_err(|_| bad())?,
        );
        if index == 0 || index > count {
            return Err(bad());
        }
        Ok(Shard { index, count })
    }

    /// Global index of this shard's first vector.
    pub fn first(self) -> u64 {
        self.index - 1
    }

    /// How many of the vectors `0..total` belong to this shard.
    pub fn len(self, total: u64) -> u64 {
        total.saturating_sub(self.first()).div_ceil(self.count)
    }

    /// True when the shard has no vectors of `0..total`.
    pub fn is_empty(self, total: u64) -> bool {
        self.len(total) == 0
    }
}

impl fmt::Display for Shard {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

/// Values of some ports, by name, in hex.
pub type Values = BTreeMap<String, String>;

/// The first failing vector of a run.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FailingVector {
    /// global vector index (record number of a vector file, 0-based)
    pub index: u64,
    /// where it came from, e.g. `in.txt line 7`, if from a file
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub location: Option<String>,
    /// input values
    pub inputs: Values,
    /// what the reference (golden model, or a TestFloat file) says
    pub expected: Values,
    /// what the RTL gave
    pub got: Values,
    /// the command that reruns this vector with a trace
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub replay: Option<String>,
}

impl FailingVector {
    /// From a cross-check mismatch.
    pub fn from_mismatch(m: &sim::Mismatch) -> FailingVector {
        FailingVector {
            index: m.index,
            location: None,
            inputs: hex_values(&m.inputs),
            expected: hex_values(&m.expected),
            got: hex_values(&m.got),
            replay: m.replay.lines().next().map(str::to_owned),
        }
    }
}

/// `(name, value)` pairs as a hex map.
pub fn hex_values(pairs: &[(String, u64)]) -> Values {
    pairs
        .iter()
        .map(|(n, v)| (n.clone(), format!("{v:#x}")))
        .collect()
}

/// One harness process of a run.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct WorkerStats {
    /// global index of its first vector
    pub first: u64,
    /// distance between its vector indices
    pub stride: u64,
    /// vectors it ran
    pub vectors: u64,
    /// mismatching vectors among them
    pub mismatches: u64,
    /// its throughput
    pub vectors_per_sec: f64,
}

/// The IR evaluator's part of a check (the third opinion).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct EvaluatorStats {
    /// vectors run through the evaluator
    pub vectors: u64,
    /// of which disagreed with the golden model
    pub mismatches: u64,
    /// global index of the first disagreement
    pub first_index: Option<u64>,
}

/// Everything one `check`, `sim`, `golden` or TestFloat run did, for CI.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RunReport {
    /// layout version, [`SCHEMA`]
    pub schema: u32,
    /// `check`, `sim`, `golden`, `testfloat`, `board` or `merged`
    pub kind: String,
    /// unit name
    pub unit: String,
    /// top module
    pub module: String,
    /// every parameter, defaults included
    pub params: BTreeMap<String, String>,
    /// generator name and version
    pub generator: String,
    /// FNV-1a 128 of the emitted Verilog (file names and contents, in order)
    pub verilog_hash: String,
    /// stimulus seed (checks only)
    pub seed: Option<u64>,
    /// vectors the whole (unsharded) run covers
    pub total_vectors: u64,
    /// which slice of them this run covered
    pub shard: Shard,
    /// vectors run
    pub vectors: u64,
    /// vectors with at least one differing output
    pub mismatches: u64,
    /// the failing vector with the lowest index
    pub first_mismatch: Option<FailingVector>,
    /// mismatch counts by class (TestFloat runs)
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub mismatch_classes: BTreeMap<String, u64>,
    /// end-to-end throughput
    pub vectors_per_sec: f64,
    /// wall time of the run, seconds
    pub wall_time_s: f64,
    /// harness processes
    #[serde(default)]
    pub workers: Vec<WorkerStats>,
    /// the IR evaluator's comparison, when it ran
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub evaluator: Option<EvaluatorStats>,
    /// input vector file (`sim`, `golden`, TestFloat)
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub input: Option<String>,
    /// results file written (`sim`, `golden`)
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub output: Option<String>,
    /// what the comparison ignored or how it was done (e.g. TestFloat flags)
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub notes: Vec<String>,
    /// set when the run stopped with an error instead of a verdict
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub error: Option<String>,
    /// no error, no mismatch (evaluator included)
    pub passed: bool,
}

/// FNV-1a 128 over the Verilog files of `g`, as 32 hex digits.
pub fn verilog_hash(g: &Generated) -> String {
    let mut h = sim::hash::Fnv128::new();
    for f in &g.files {
        h.item(f.file_name.as_bytes()).item(f.text.as_bytes());
    }
    h.hex()
}

impl RunReport {
    /// A report for `g` with no results yet.
    pub fn new(kind: &str, g: &Generated) -> RunReport {
        RunReport {
            schema: SCHEMA,
            kind: kind.to_string(),
            unit: g.unit.clone(),
            module: g.module.name.clone(),
            params: g.params.values().clone(),
            generator: rtl_gen::GENERATOR.to_string(),
            verilog_hash: verilog_hash(g),
            seed: None,
            total_vectors: 0,
            shard: Shard::ALL,
            vectors: 0,
            mismatches: 0,
            first_mismatch: None,
            mismatch_classes: BTreeMap::new(),
            vectors_per_sec: 0.0,
            wall_time_s: 0.0,
            workers: Vec::new(),
            evaluator: None,
            input: None,
            output: None,
            notes: Vec::new(),
            error: None,
            passed: false,
        }
    }

    /// Fills in a cross-check's results (vectors, mismatches, workers,
    /// throughput) and sets `passed` from them and the evaluator.
    pub fn set_check(&mut self, r: &sim::CheckReport) {
        self.vectors = r.vectors;
        self.mismatches = r.mismatches;
        self.first_mismatch = r.first_mismatch.as_ref().map(FailingVector::from_mismatch);
        self.vectors_per_sec = r.vectors_per_sec();
        self.wall_time_s = r.elapsed.as_secs_f64();
        self.workers = r
            .workers
            .iter()
            .map(|w| WorkerStats {
                first: w.first,
                stride: w.stride,
                vectors: w.vectors,
                mismatches: w.mismatches,
                vectors_per_sec: w.vectors_per_sec(),
            })
            .collect();
        self.update_verdict();
    }

    /// `passed` from the error, the mismatches and the evaluator.
    pub fn update_verdict(&mut self) {
        self.passed = self.error.is_none()
            && self.mismatches == 0
            && self.evaluator.as_ref().is_none_or(|e| e.mismatches == 0);
    }

    /// Pretty JSON with a final newline.
    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).expect("a report serialises") + "\n"
    }

    /// Reads a report written by [`RunReport::to_json`].
    pub fn load(path: &Path) -> Result<RunReport, String> {
        let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
        let r: RunReport = serde_json::from_str(&text).map_err(|e| {
            format!(
                "{}: line {}, column {}: not an rtl-gen report: {e}",
                path.display(),
                e.line(),
                e.column()
            )
        })?;
        if r.schema != SCHEMA {
            return Err(format!(
                "{}: report schema {} (this rtl-gen reads {SCHEMA})",
                path.display(),
                r.schema
            ));
        }
        Ok(r)
    }

    /// Writes the JSON all or nothing.
    pub fn save(&self, path: &Path) -> Result<(), sim::SimError> {
        write_text(path, &self.to_json())
    }

    /// Name of the JUnit test case: module, seed and shard.
    pub fn case_name(&self) -> String {
        let mut name = format!("{} {}", self.kind, self.module);
        if let Some(seed) = self.seed {
            name += &format!(" seed={seed}");
        }
        if self.shard.count > 1 {
            name += &format!(" shard={}", self.shard);
        }
        if let Some(input) = &self.input {
            name += &format!(" input={input}");
        }
        name
    }

    /// JUnit XML: one test suite with one test case, a `<failure>` for
    /// mismatches or an `<error>` for a run that stopped, and the
    /// parameters, seed, shard and hash as properties.
    pub fn to_junit(&self) -> String {
        let (failures, errors) = match (&self.error, self.passed) {
            (Some(_), _) => (0, 1),
            (None, false) => (1, 0),
            (None, true) => (0, 0),
        };
        let time = format!("{:.3}", self.wall_time_s);
        let suite = format!("rtl-gen {} {}", self.kind, self.unit);
        let mut x = String::from("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
        x += &format!(
            "<testsuites name=\"rtl-gen\" tests=\"1\" failures=\"{failures}\" errors=\"{errors}\" time=\"{time}\">\n"
        );
        x += &format!(
            "  <testsuite name=\"{}\" tests=\"1\" failures=\"{failures}\" errors=\"{errors}\" skipped=\"0\" time=\"{time}\">\n",
            xml(&suite)
        );
        x += "    <properties>\n";
        let mut props: Vec<(String, String)> = vec![
            ("generator".into(), self.generator.clone()),
            ("module".into(), self.module.clone()),
            ("verilog_hash".into(), self.verilog_hash.clone()),
            ("shard".into(), self.shard.to_string()),
            ("vectors".into(), self.vectors.to_string()),
            ("mismatches".into(), self.mismatches.to_string()),
            (
                "vectors_per_sec".into(),
                format!("{:.0}", self.vectors_per_sec),
            ),
        ];
        if let Some(seed) = self.seed {
            props.push(("seed".into(), seed.to_string()));
        }
        props.extend(
            self.params
                .iter()
                .map(|(k, v)| (format!("param.{k}"), v.clone())),
        );
        for (k, v) in props {
            x += &format!(
                "      <property name=\"{}\" value=\"{}\"/>\n",
                xml(&k),
                xml(&v)
            );
        }
        x += "    </properties>\n";
        x += &format!(
            "    <testcase classname=\"rtl-gen.{}\" name=\"{}\" time=\"{time}\">\n",
            xml(&self.unit),
            xml(&self.case_name())
        );
        if let Some(e) = &self.error {
            x += &format!(
                "      <error type=\"error\" message=\"{}\">{}</error>\n",
                xml(e.lines().next().unwrap_or("")),
                xml(e)
            );
        } else if !self.passed {
            x += &format!(
                "      <failure type=\"mismatch\" message=\"{}\">{}</failure>\n",
                xml(&self.headline()),
                xml(&self.failure_text())
            );
        }
        x += &format!("      <system-out>{}</system-out>\n", xml(&self.headline()));
        x += "    </testcase>\n  </testsuite>\n</testsuites>\n";
        x
    }

    /// Writes the JUnit XML all or nothing.
    pub fn save_junit(&self, path: &Path) -> Result<(), sim::SimError> {
        write_text(path, &self.to_junit())
    }

    /// One line: verdict, counts, throughput.
    pub fn headline(&self) -> String {
        let verdict = match (&self.error, self.passed) {
            (Some(_), _) => "ERROR",
            (None, true) => "PASS",
            (None, false) => "FAIL",
        };
        let mut s = format!(
            "{verdict}: {} `{}`, {} vectors, {} mismatches",
            self.kind, self.module, self.vectors, self.mismatches
        );
        if let Some(e) = &self.evaluator {
            if e.mismatches > 0 {
                s += &format!(", IR evaluator {} mismatches", e.mismatches);
            }
        }
        // a serial port runs a few hundred a second: no "0.00 M" there
        if self.vectors_per_sec >= 1e5 {
            s + &format!(", {:.2} M vectors/s", self.vectors_per_sec / 1e6)
        } else {
            s + &format!(", {:.0} vectors/s", self.vectors_per_sec)
        }
    }

    /// The first failing vector and the classes, as text.
    pub fn failure_text(&self) -> String {
        let mut s = self.headline() + "\n";
        for (class, n) in &self.mismatch_classes {
            s += &format!("  {class}: {n}\n");
        }
        if let Some(f) = &self.first_mismatch {
            s += &format!("first failing vector: index {}", f.index);
            if let Some(l) = &f.location {
                s += &format!(" ({l})");
            }
            s += "\n";
            let line = |m: &Values| {
                m.iter()
                    .map(|(k, v)| format!("{k}={v}"))
                    .collect::<Vec<_>>()
                    .join(" ")
            };
            s += &format!("  inputs:   {}\n", line(&f.inputs));
            s += &format!("  expected: {}\n", line(&f.expected));
            s += &format!("  got:      {}\n", line(&f.got));
            if let Some(r) = &f.replay {
                s += &format!("  replay:   {r}\n");
            }
        }
        if let Some(e) = &self.evaluator {
            if let Some(i) = e.first_index {
                s += &format!("IR evaluator disagrees with the golden model first at index {i}\n");
            }
        }
        s
    }
}

fn write_text(path: &Path, text: &str) -> Result<(), sim::SimError> {
    sim::write_atomically(path, |mut f, name| {
        std::io::Write::write_all(&mut f, text.as_bytes())
            .map_err(|e| sim::SimError::io(format!("writing {name}"), e))
    })
}

/// Escapes text for XML attributes and content.
fn xml(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            '\n' | '\t' | '\r' => out.push(c),
            c if (c as u32) < 0x20 => out.push_str(&format!("&#x{:x};", c as u32)),
            c => out.push(c),
        }
    }
    out
}

/// Combines the reports of the shards of one regression into one verdict.
///
/// The shards must be of the same run (kind, unit, parameters, generator,
/// Verilog hash, seed, total vectors and shard count) and each shard must
/// appear exactly once; all shards are required, since a missing one would
/// leave vectors unchecked. The merged report sums vectors and mismatches,
/// keeps the lowest-index failing vector, takes the longest wall time and
/// the sum of the shards' throughputs (they ran side by side).
pub fn merge(reports: &[(String, RunReport)]) -> Result<RunReport, String> {
    let Some((first_name, first)) = reports.first() else {
        return Err("merge-reports: no reports given".into());
    };
    let n = first.shard.count;
    let mut seen: BTreeMap<u64, &str> = BTreeMap::new();
    for (name, r) in reports {
        let differs = |what: &str, a: String, b: String| {
            Err(format!(
                "{name}: {what} is {b}, but {first_name} has {a}: not shards of one run"
            ))
        };
        macro_rules! same {
            ($field:ident) => {
                if r.$field != first.$field {
                    return differs(
                        stringify!($field),
                        format!("{:?}", first.$field),
                        format!("{:?}", r.$field),
                    );
                }
            };
        }
        same!(kind);
        same!(unit);
        same!(params);
        same!(generator);
        same!(verilog_hash);
        same!(seed);
        same!(total_vectors);
        // the verdict is derived from the counts: a report whose verdict
        // disagrees with them was edited, and merging would hide it
        let mut derived = r.clone();
        derived.update_verdict();
        if derived.passed != r.passed {
            return Err(format!(
                "{name}: says passed = {} but its mismatches and error say {}: not a report \
                 as rtl-gen writes it",
                r.passed, derived.passed
            ));
        }
        if r.shard.count != n {
            return differs("the shard count", n.to_string(), r.shard.count.to_string());
        }
        if let Some(other) = seen.insert(r.shard.index, name) {
            return Err(format!(
                "shard {} appears twice: {other} and {name}",
                r.shard
            ));
        }
    }
    let missing: Vec<String> = (1..=n)
        .filter(|k| !seen.contains_key(k))
        .map(|k| format!("{k}/{n}"))
        .collect();
    if !missing.is_empty() {
        return Err(format!(
            "incomplete: shard(s) {} missing; {} of {n} given",
            missing.join(", "),
            seen.len()
        ));
    }
    let mut m = first.clone();
    m.kind = first.kind.clone();
    m.shard = Shard::ALL;
    m.vectors = reports.iter().map(|(_, r)| r.vectors).sum();
    m.mismatches = reports.iter().map(|(_, r)| r.mismatches).sum();
    m.first_mismatch = reports
        .iter()
        .filter_map(|(_, r)| r.first_mismatch.clone())
        .min_by_key(|f| f.index);
    m.mismatch_classes = BTreeMap::new();
    for (_, r) in reports {
        for (c, k) in &r.mismatch_classes {
            *m.mismatch_classes.entry(c.clone()).or_default() += k;
        }
    }
    m.wall_time_s = reports
        .iter()
        .map(|(_, r)| r.wall_time_s)
        .fold(0.0, f64::max);
    m.vectors_per_sec = reports.iter().map(|(_, r)| r.vectors_per_sec).sum();
    m.workers = reports
        .iter()
        .flat_map(|(_, r)| r.workers.iter().cloned())
        .collect();
    m.workers.sort_by_key(|w| w.first);
    m.evaluator = if reports.iter().all(|(_, r)| r.evaluator.is_none()) {
        None
    } else {
        let evs: Vec<&EvaluatorStats> = reports
            .iter()
            .filter_map(|(_, r)| r.evaluator.as_ref())
            .collect();
        Some(EvaluatorStats {
            vectors: evs.iter().map(|e| e.vectors).sum(),
            mismatches: evs.iter().map(|e| e.mismatches).sum(),
            first_index: evs.iter().filter_map(|e| e.first_index).min(),
        })
    };
    m.error = {
        let errs: Vec<String> = reports
            .iter()
            .filter_map(|(name, r)| r.error.as_ref().map(|e| format!("{name}: {e}")))
            .collect();
        (!errs.is_empty()).then(|| errs.join("\n"))
    };
    if m.error.is_none() && m.vectors != m.total_vectors {
        return Err(format!(
            "the shards ran {} vectors together, but the run has {}",
            m.vectors, m.total_vectors
        ));
    }
    m.notes.push(format!("merged from {n} shard reports"));
    m.update_verdict();
    Ok(m)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shards_partition_the_index_space() {
        assert_eq!(Shard::parse("3/8").unwrap(), Shard { index: 3, count: 8 });
        for bad in ["0/4", "5/4", "x", "1/0", "2"] {
            assert!(Shard::parse(bad).is_err(), "{bad}");
        }
        for total in [0u64, 1, 7, 100, 1001] {
            for n in 1..6 {
                let sum: u64 = (1..=n)
                    .map(|k| Shard { index: k, count: n }.len(total))
                    .sum();
                assert_eq!(sum, total, "{total} over {n}");
            }
        }
    }

    #[test]
    fn xml_escaping() {
        assert_eq!(xml("a<b & \"c\"\u{1}"), "a&lt;b &amp; &quot;c&quot;&#x1;");
    }
}
