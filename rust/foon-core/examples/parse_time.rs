//! Times parsing a FOON file: `cargo run --release --example parse_time -- FILE [N]`.
use std::time::Instant;

fn main() {
    let mut args = std::env::args().skip(1);
    let path = args.next().expect("usage: parse_time FILE [N]");
    let n: usize = args.next().and_then(|s| s.parse().ok()).unwrap_or(20);
    let data = std::fs::read(&path).expect("readable file");
    let mut best = f64::INFINITY;
    for _ in 0..n {
        let t = Instant::now();
        let f = foon_core::parse_foon(&data, None, foon_core::ParseOptions::default())
            .expect("valid FOON");
        best = best.min(t.elapsed().as_secs_f64());
        std::hint::black_box(f);
    }
    eprintln!("best of {n}: {:.3} ms", best * 1000.0);
}
