//! Times opening a `.foonidx` file: `cargo run --release --example open_time -- FILE [N]`.
use std::time::Instant;

fn main() {
    let mut args = std::env::args().skip(1);
    let path = args.next().expect("usage: open_time FILE [N]");
    let n: usize = args.next().and_then(|s| s.parse().ok()).unwrap_or(20);
    let mut best = f64::INFINITY;
    for _ in 0..n {
        let t = Instant::now();
        let f = foon_core::Foon::open_index(std::path::Path::new(&path)).expect("valid index");
        best = best.min(t.elapsed().as_secs_f64());
        std::hint::black_box(f);
    }
    eprintln!("best of {n}: {:.3} ms", best * 1000.0);
}
