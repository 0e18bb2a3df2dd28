//! Several harness processes per check (`CheckOptions::jobs`), index slices
//! (`first`, `stride`: how shards are run), the progress callback and the
//! file helpers that never leave half-written results.

use std::fs;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, OnceLock};

use sim::{
    cross_check, default_cache_root, CheckOptions, Harness, PortList, ProgressFn, RandomStimulus,
    Stimulus,
};

fn fixtures() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures")
}

fn addpipe() -> &'static Harness {
    static H: OnceLock<Harness> = OnceLock::new();
    H.get_or_init(|| {
        let ports = PortList::load(fixtures().join("addpipe.ports.json")).unwrap();
        Harness::build(&ports, &fixtures(), &default_cache_root()).unwrap()
    })
}

fn scratch(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("sim-parallel-{name}-{}", std::process::id()));
    let _ = fs::remove_dir_all(&d);
    fs::create_dir_all(&d).unwrap();
    d
}

fn golden(i: &[u64], o: &mut [u64]) {
    o[0] = i[0] + i[1];
    o[1] = (i[0] == i[1]) as u64;
}

/// Wrong in bit 2 of `sum` whenever a's low byte is 0x5a (about 1 in 256).
fn wrong(i: &[u64], o: &mut [u64]) {
    golden(i, o);
    if i[0] & 0xff == 0x5a {
        o[0] ^= 1 << 2;
    }
}

fn failing_indices(stim: &RandomStimulus, seed: u64, n: u64) -> Vec<u64> {
    let mut v = [0u64; 2];
    (0..n)
        .filter(|&i| {
            stim.vector(seed, i, &mut v);
            v[0] & 0xff == 0x5a
        })
        .collect()
}

#[test]
fn several_workers_check_every_vector_once_and_agree_on_the_first_mismatch() {
    let h = addpipe();
    let stim = RandomStimulus::new(&h.ports().inputs);
    let failing = failing_indices(&stim, 9, 100_003);
    let dir = scratch("jobs");
    for jobs in [1, 3, 4] {
        let opts = CheckOptions {
            vectors: 100_003,
            seed: 9,
            jobs,
            mismatch_dir: Some(dir.clone()),
            ..CheckOptions::default()
        };
        let r = cross_check(h, &wrong, &stim, &opts).unwrap();
        assert_eq!(r.vectors, 100_003);
        assert_eq!(r.workers.len(), jobs);
        assert_eq!(r.workers.iter().map(|w| w.vectors).sum::<u64>(), 100_003);
        assert_eq!(r.mismatches, failing.len() as u64, "jobs {jobs}");
        assert_eq!(r.first_mismatch.as_ref().unwrap().index, failing[0]);
        let more: Vec<u64> = r.more_mismatches.iter().map(|m| m.index).collect();
        assert_eq!(more, failing[1..10], "jobs {jobs}");
        // Per-worker reports partition the index space by stride.
        for (w, wr) in r.workers.iter().enumerate() {
            assert_eq!((wr.first, wr.stride), (w as u64, jobs as u64));
        }
        if jobs > 1 {
            assert!(r.to_string().contains(&format!("{jobs} workers")), "{r}");
        }
    }
    fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn shards_by_first_and_stride_together_run_the_unsharded_vectors() {
    let h = addpipe();
    let stim = RandomStimulus::new(&h.ports().inputs);
    let total = 50_001u64;
    let failing = failing_indices(&stim, 4, total);
    let dir = scratch("shards");
    let mut seen = Vec::new();
    let (mut count, mut mismatches) = (0, 0);
    for k in 0..4u64 {
        let opts = CheckOptions {
            vectors: (total - k).div_ceil(4),
            seed: 4,
            first: k,
            stride: 4,
            jobs: 2,
            keep_mismatches: usize::MAX,
            mismatch_dir: Some(dir.clone()),
            ..CheckOptions::default()
        };
        let r = cross_check(h, &wrong, &stim, &opts).unwrap();
        count += r.vectors;
        mismatches += r.mismatches;
        seen.extend(r.first_mismatch.iter().chain(&r.more_mismatches).map(|m| {
            assert_eq!(m.index % 4, k, "a shard reports global indices");
            m.index
        }));
        assert!(
            r.to_string().contains(&format!("vector indices {k} + 4")),
            "{r}"
        );
    }
    seen.sort_unstable();
    assert_eq!(count, total);
    assert_eq!(mismatches, failing.len() as u64);
    assert_eq!(seen, failing);
    fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn the_progress_callback_counts_up_to_the_total() {
    let h = addpipe();
    let stim = RandomStimulus::new(&h.ports().inputs);
    let calls = Arc::new(AtomicU64::new(0));
    let highest = Arc::new(AtomicU64::new(0));
    let (c, hi) = (calls.clone(), highest.clone());
    let opts = CheckOptions {
        vectors: 40_000,
        seed: 1,
        jobs: 2,
        on_progress: Some(ProgressFn::new(move |p| {
            assert_eq!(p.total, 40_000);
            assert_eq!(p.mismatches, 0);
            c.fetch_add(1, Ordering::Relaxed);
            hi.fetch_max(p.done, Ordering::Relaxed);
        })),
        ..CheckOptions::default()
    };
    let r = cross_check(h, &golden, &stim, &opts).unwrap();
    assert!(r.passed());
    assert_eq!(highest.load(Ordering::Relaxed), 40_000);
    assert!(calls.load(Ordering::Relaxed) >= 10, "one call per batch");
}

#[test]
fn a_failing_worker_stops_the_others_and_its_error_is_returned() {
    let h = addpipe();
    let stim = RandomStimulus::new(&h.ports().inputs);
    // A golden value wider than its port is an error, not a mismatch.
    let broken = |i: &[u64], o: &mut [u64]| {
        golden(i, o);
        if i[0] == 0xffff {
            o[1] = 2;
        }
    };
    let opts = CheckOptions {
        vectors: 2_000_000,
        seed: 1,
        jobs: 3,
        ..CheckOptions::default()
    };
    let e = cross_check(h, &broken, &stim, &opts)
        .unwrap_err()
        .to_string();
    assert!(e.contains("value wider than port"), "{e}");
}
