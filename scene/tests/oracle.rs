//! The culling oracle (`scene::oracle`, issue 37) is a lower bound of the wide traversal: per
//! ray type, every oracle counter is at most the traversal's own (node tests of each tree,
//! transforms, triangle tests; the oracle's root box tests are 0), every hit costs it at least
//! one triangle test, and it is not zero.

use golden_model::float::FloatFormat;
use golden_model::wide::WideFormat;
use scene::bvh::Accel;
use scene::render::render_with;
use scene::scene::Scene;
use scene::stats::RayKind;
use scene::tester::Golden;
use scene::trace::{TraceOpts, Tracer};
use scene::wide::{Boxes, WideAccel, TLAS_BOX_BITS};
use std::path::Path;

#[test]
fn the_oracle_is_a_lower_bound_of_the_wide_traversal() {
    for name in ["cornell", "bunny", "unseen/swarm"] {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("../scenes/{name}.toml"));
        let mut s = Scene::load(&path).unwrap();
        s.render.ao_rays = 2;
        let acc = Accel::build(&s, false);
        let format = WideFormat::new(FloatFormat::BINARY32, 4, 8).unwrap();
        let wide = WideAccel::build(&acc, format, TLAS_BOX_BITS).unwrap();
        let golden = Golden::default();
        let tracer =
            Tracer::new(&s, &acc, &golden, TraceOpts::single_rays()).with_wide(&wide, Boxes::Node);
        let f = render_with(&s, &acc, &tracer, 24, 16, false);
        for kind in RayKind::ALL {
            let k = &f.stats.kinds[kind as usize];
            if k.rays == 0 {
                continue;
            }
            let what = format!("{name} {}", kind.name());
            let pairs = [
                (
                    "BLAS node tests",
                    k.oracle_blas_node_tests,
                    k.node_visits - k.tlas_node_visits,
                ),
                (
                    "TLAS node tests",
                    k.oracle_tlas_node_tests,
                    k.tlas_node_visits,
                ),
                ("transforms", k.oracle_transforms, k.transforms),
                ("triangle tests", k.oracle_tri_tests, k.tri_tests),
            ];
            for (counter, oracle, actual) in pairs {
                println!("{what}: {counter}: oracle {oracle}, traversal {actual}");
                assert!(
                    oracle <= actual,
                    "{what}: oracle {counter} {oracle} > traversal's {actual}"
                );
            }
            assert!(k.hits > 0, "{what}: nothing hit");
            assert!(
                k.oracle_tri_tests >= k.hits,
                "{what}: {} oracle triangle tests for {} hits",
                k.oracle_tri_tests,
                k.hits
            );
            assert!(
                k.oracle_blas_node_tests > 0 && k.oracle_tlas_node_tests > 0,
                "{what}: the oracle makes no node test"
            );
            assert_eq!(k.oracle_transforms, k.hits, "{what}: one transform a hit");
        }
    }
}
