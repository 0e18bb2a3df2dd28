//! Measures end-to-end cross-check throughput on the `mulcmp16` fixture (a
//! 3-stage 16x16 multiply-compare: 4 inputs of 16 bits, 2 one-bit outputs).
//!
//! `cargo run --release -p sim --example throughput -- [VECTORS] [SEED]`

use std::path::Path;

use sim::{cross_check, default_cache_root, CheckOptions, Harness, RandomStimulus};

fn main() {
    let mut args = std::env::args().skip(1);
    let vectors: u64 = args
        .next()
        .map_or(50_000_000, |s| s.parse().expect("VECTORS"));
    let seed: u64 = args.next().map_or(1, |s| s.parse().expect("SEED"));
    let port_file =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/mulcmp16.ports.json");
    let h = Harness::from_port_file(&port_file, &default_cache_root()).unwrap_or_else(|e| {
        eprintln!("error: {e}");
        std::process::exit(1)
    });
    eprintln!(
        "harness {} ({}, {:.1} s)",
        h.binary().display(),
        if h.was_cached() { "cached" } else { "built" },
        h.build_time().as_secs_f64()
    );
    let golden = |i: &[u64], o: &mut [u64]| {
        let (ab, cd) = (i[0] * i[1], i[2] * i[3]);
        o[0] = (ab < cd) as u64;
        o[1] = (ab == cd) as u64;
    };
    let stim = RandomStimulus::new(&h.ports().inputs);
    let opts = CheckOptions {
        vectors,
        seed,
        progress: true,
        ..CheckOptions::default()
    };
    match cross_check(&h, &golden, &stim, &opts) {
        Ok(r) => {
            print!("{r}");
            if !r.passed() {
                std::process::exit(1);
            }
        }
        Err(e) => {
            eprintln!("error: {e}");
            std::process::exit(1);
        }
    }
}
