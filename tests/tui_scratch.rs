#[test]
fn t() {
    let p = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("models/four-span.toml");
    let text = std::fs::read_to_string(&p).unwrap();
    let t0 = std::time::Instant::now();
    for _ in 0..5 { deckspin::model::load_str(&text, &p, &[]).unwrap(); }
    eprintln!("load_str {:?}", t0.elapsed() / 5);
}
