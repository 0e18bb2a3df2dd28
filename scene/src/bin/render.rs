use scene::bvh::Accel;
use scene::render::render;
use scene::scene::Scene;
use scene::tester::Golden;
use scene::trace::TraceOpts;
fn main() {
    let a: Vec<String> = std::env::args().collect();
    let s = Scene::load(std::path::Path::new(&a[1])).unwrap_or_else(|e| {
        eprintln!("{e}");
        std::process::exit(2)
    });
    let acc = Accel::build(&s, true);
    eprintln!("{}", acc.describe());
    let w: u32 = a[2].parse().unwrap();
    let f = render(
        &s,
        &acc,
        &Golden::default(),
        TraceOpts::default(),
        w,
        w,
        true,
    );
    eprintln!(
        "{:?} {} rays {:.0} rays/s",
        f.time,
        f.rays(),
        f.rays() as f64 / f.time.as_secs_f64()
    );
    println!("{}", scene::stats::table(&f.stats));
    f.save_png(std::path::Path::new(&a[3])).unwrap();
}
