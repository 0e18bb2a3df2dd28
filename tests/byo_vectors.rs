//! Vector files through the RTL and the golden model (`flow::byo`): a wrong
//! golden model is reported against the file's line, `--rtl-only` keeps the
//! RTL's results, and binary files work like text ones.

mod common;

use common::{generate, scratch};
use rtl_flow::byo::{run_file, Mode};
use rtl_flow::Testbench;

/// The real testbench with `eq` inverted whenever a == 7.
struct Wrong(Box<dyn Testbench>);

impl sim::Golden for Wrong {
    fn eval(&self, inputs: &[u64], outputs: &mut [u64]) {
        self.0.eval(inputs, outputs);
        if inputs[0] == 7 {
            outputs[1] ^= 1;
        }
    }
}

impl sim::Stimulus for Wrong {
    fn vector(&self, seed: u64, index: u64, inputs: &mut [u64]) {
        self.0.vector(seed, index, inputs)
    }
}

impl Testbench for Wrong {}

#[test]
fn a_wrong_golden_model_is_reported_with_the_files_line() {
    let (g, dir) = generate("byo", "mulcmp", &["stages=2"]);
    let h = sim::Harness::build(&g.ports, &dir, &sim::default_cache_root()).unwrap();
    let files = scratch("byo_files");
    let input = files.join("in.txt");
    std::fs::write(
        &input,
        "# two mismatching lines: a == 7\nd c b a\n1 2 3 4\n\n0 0 0 7\n5 6 7 8\n1 1 1 7 # again\n",
    )
    .unwrap();
    let wrong = Wrong(g.testbench());
    let out = files.join("results.rtlvec");
    let o = run_file(
        &g,
        Some(&h),
        &wrong,
        &input,
        &out,
        Mode::Rtl { compare: true },
    )
    .unwrap();
    assert_eq!((o.vectors, o.mismatches), (4, 2));
    assert_eq!(o.shown[0].index, 1);
    assert_eq!(o.shown[0].location, format!("{} line 5", input.display()));
    assert_eq!(o.shown[1].location, format!("{} line 7", input.display()));
    assert!(
        o.shown[0].to_string().contains("<- differs"),
        "{}",
        o.shown[0]
    );
    assert!(!o.report.passed);
    assert_eq!(o.report.first_mismatch.as_ref().unwrap().index, 1);
    assert_eq!(o.report.first_mismatch.as_ref().unwrap().inputs["a"], "0x7");

    // The results hold the RTL's outputs (eq = 1 for 0*0 == 0*7), in binary.
    let mut rd = sim::BinReader::open(&out).unwrap();
    assert_eq!(rd.ports().len(), 4 + 3);
    let mut rec = vec![0u64; 7];
    rd.read_record(&mut rec).unwrap();
    assert_eq!(rec, [4, 3, 2, 1, 0, 0, 12], "a=4 b=3 c=2 d=1: 12 > 2");
    rd.read_record(&mut rec).unwrap();
    assert_eq!(rec[..6], [7, 0, 0, 0, 0, 1]);

    // --rtl-only: no comparison, same results; golden mode: the model's.
    let out2 = files.join("rtl_only.rtlvec");
    let o = run_file(
        &g,
        Some(&h),
        &wrong,
        &input,
        &out2,
        Mode::Rtl { compare: false },
    )
    .unwrap();
    assert_eq!((o.vectors, o.mismatches), (4, 0));
    assert_eq!(std::fs::read(&out).unwrap(), std::fs::read(&out2).unwrap());
    let out3 = files.join("golden.txt");
    let o = run_file(
        &g,
        None,
        &wrong,
        &out2.with_file_name("in.txt"),
        &out3,
        Mode::Golden,
    )
    .unwrap();
    assert_eq!(o.format, sim::VecFormat::Text);
    let text = std::fs::read_to_string(&out3).unwrap();
    assert!(
        text.lines()
            .nth(3)
            .unwrap()
            .contains("0x0007 0x0000 0x0000 0x0000 0x0  0x0  0x00000000"),
        "{text}"
    );
}
