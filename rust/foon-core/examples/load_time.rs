//! Times loading FOON files from disk (parse + index), as `foon.load` does:
//! `cargo run --release --example load_time -- [--synth UNITS] FILE [N]`. With `--synth`, a
//! synthetic FOON of UNITS units (seed 1) is written to FILE first when FILE is missing.
use std::path::Path;
use std::time::Instant;

fn main() {
    let mut args: Vec<String> = std::env::args().skip(1).collect();
    let mut synth = None;
    if args.first().map(String::as_str) == Some("--synth") {
        synth = args.get(1).and_then(|s| s.parse::<u64>().ok());
        args.drain(..2);
    }
    let path = args
        .first()
        .expect("usage: load_time [--synth UNITS] FILE [N]");
    let n: usize = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(3);
    let path = Path::new(path);
    if let (Some(units), false) = (synth, path.exists()) {
        let opts = foon_core::synth::SynthOptions {
            units,
            seed: 1,
            threads: None,
        };
        foon_core::synth::synth_to_path(&opts, path, &mut |_, _| true).expect("written");
    }
    let mut best = f64::INFINITY;
    for _ in 0..n {
        let t = Instant::now();
        let f = foon_core::parse::load_foon(path, foon_core::ParseOptions::default())
            .expect("valid FOON");
        best = best.min(t.elapsed().as_secs_f64());
        eprintln!(
            "{:.3} s ({} units)",
            t.elapsed().as_secs_f64(),
            f.fu_count()
        );
        std::hint::black_box(f);
    }
    eprintln!("best of {n}: {best:.3} s");
}
