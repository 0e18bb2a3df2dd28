//! Sharded regressions: four shards together run exactly the vectors of one
//! unsharded run, with the same verdict, and a planted mismatch (a golden
//! model wrong on one vector) is found by exactly one shard, with the same
//! replay command as the unsharded run; the shard reports merge into the
//! unsharded verdict.

mod common;

use common::generate;
use rtl_flow::regress::{run_check, CheckRun};
use rtl_flow::report::{merge, Shard};
use rtl_flow::Testbench;

const VECTORS: u64 = 300_000;
const SEED: u64 = 11;

/// The real testbench, except that the golden model flips bit 0 of `ab`
/// on one input vector.
struct Planted {
    tb: Box<dyn Testbench>,
    bad: Vec<u64>,
}

impl sim::Golden for Planted {
    fn eval(&self, inputs: &[u64], outputs: &mut [u64]) {
        self.tb.eval(inputs, outputs);
        if inputs == &self.bad[..] {
            outputs[2] ^= 1;
        }
    }
}

impl sim::Stimulus for Planted {
    fn vector(&self, seed: u64, index: u64, inputs: &mut [u64]) {
        self.tb.vector(seed, index, inputs)
    }
}

impl Testbench for Planted {}

#[test]
fn four_shards_run_the_unsharded_vectors_and_find_a_planted_mismatch_once() {
    let (g, dir) = generate("shards", "mulcmp", &["stages=2"]);
    sim::lint(&g.ports, &dir).unwrap();
    let h = sim::Harness::build(&g.ports, &dir, &sim::default_cache_root()).unwrap();

    // Plant the error on a vector whose inputs occur exactly once.
    let tb = g.testbench();
    let planted_at = 123_457u64;
    let mut bad = vec![0u64; 4];
    tb.vector(SEED, planted_at, &mut bad);
    let mut v = vec![0u64; 4];
    let same = (0..VECTORS)
        .filter(|&i| {
            tb.vector(SEED, i, &mut v);
            v == bad
        })
        .count();
    assert_eq!(same, 1, "the planted inputs must be unique");
    let planted = Planted {
        tb: g.testbench(),
        bad,
    };

    let mismatch_dir = dir.join("mismatches");
    let run = |shard: Shard, jobs: usize| {
        let mut r = CheckRun::new(VECTORS, SEED);
        r.shard = shard;
        r.jobs = jobs;
        r.evaluator_vectors = 2_000;
        r.mismatch_dir = Some(mismatch_dir.clone());
        run_check(&g, &h, &planted, &r).expect("check runs")
    };
    let whole = run(Shard::ALL, 2);
    assert_eq!(whole.report.vectors, VECTORS);
    assert_eq!(whole.report.mismatches, 1);
    assert!(!whole.report.passed);
    let first = whole.report.first_mismatch.clone().unwrap();
    assert_eq!(first.index, planted_at);
    let replay = first.replay.clone().unwrap();
    assert!(
        replay.starts_with(&format!(
            "rtl-gen replay mulcmp {} --seed {SEED} --index {planted_at}",
            g.param_args()
        )),
        "{replay}"
    );

    let mut shards = Vec::new();
    for k in 1..=4 {
        let o = run(Shard { index: k, count: 4 }, 1 + (k as usize % 2));
        assert_eq!(o.report.vectors, Shard { index: k, count: 4 }.len(VECTORS));
        let planted_here = planted_at % 4 == k - 1;
        assert_eq!(o.report.mismatches, planted_here as u64, "shard {k}/4");
        if planted_here {
            let f = o.report.first_mismatch.clone().unwrap();
            assert_eq!(f.index, planted_at);
            assert_eq!(f.replay.as_deref(), Some(replay.as_str()), "same replay");
            assert_eq!(f, first, "same failing vector, values and replay");
        }
        shards.push((format!("shard{k}.json"), o.report));
    }
    let total: u64 = shards.iter().map(|(_, r)| r.vectors).sum();
    assert_eq!(total, VECTORS);
    let evaluated: u64 = shards
        .iter()
        .map(|(_, r)| r.evaluator.as_ref().unwrap().vectors)
        .sum();
    assert_eq!(evaluated, 2_000, "the evaluator's vectors are sharded too");

    let merged = merge(&shards).unwrap();
    assert_eq!(merged.vectors, whole.report.vectors);
    assert_eq!(merged.mismatches, whole.report.mismatches);
    assert_eq!(merged.passed, whole.report.passed);
    assert_eq!(merged.first_mismatch, whole.report.first_mismatch);
    assert_eq!(merged.verilog_hash, whole.report.verilog_hash);

    // An incomplete or mixed set of shards is no verdict.
    let e = merge(&shards[..3]).unwrap_err();
    assert!(e.contains("shard(s) 4/4 missing"), "{e}");
    let mut other_seed = shards.clone();
    other_seed[1].1.seed = Some(SEED + 1);
    let e = merge(&other_seed).unwrap_err();
    assert!(e.contains("shard2.json: seed"), "{e}");
    let mut twice = shards.clone();
    twice[3] = twice[2].clone();
    assert!(merge(&twice).unwrap_err().contains("appears twice"));
}
