fn main() {
    let args: Vec<u32> = std::env::args()
        .skip(1)
        .map(|a| a.parse().unwrap())
        .collect();
    let m = rtl_gen::units::mulcmp::build(args[0], args[1], args[2]);
    let dir = std::path::Path::new("/tmp/dump");
    std::fs::create_dir_all(dir).unwrap();
    for f in rtl_gen::emit::emit(&m, rtl_gen::GENERATOR) {
        std::fs::write(dir.join(&f.file_name), &f.text).unwrap();
        println!("{}", f.file_name);
    }
}
