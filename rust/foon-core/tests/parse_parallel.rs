//! The chunked text parser gives exactly the result of reading the input as one chunk, for
//! every chunk size and number of threads, and from a file read in windows as from bytes in
//! memory: the same index (every column), warnings, notes, duplicates and errors (the first
//! one, or all of them when recovering), on every real data file and on generated texts with
//! malformed lines, CRLF, a byte-order mark, comments and a missing `//`.

use std::path::{Path, PathBuf};

use foon_core::index::Builder;
use foon_core::parse::{ParseControl, load_into, parse_into_with};
use foon_core::progress::Progress;
use foon_core::{Error, ParseOptions};
use proptest::prelude::*;

mod common;
use common::shared;

/// Everything a parse gives, as text: the index (its `Debug` form holds every column), and
/// the errors.
fn outcome(data: &[u8], path: Option<&Path>, strict: bool, recover: bool, chunk: usize) -> String {
    let mut b = Builder::new();
    let mut errors = Vec::new();
    let ctl = ParseControl {
        chunk_bytes: chunk,
        ..ParseControl::default()
    };
    let opts = ParseOptions { strict };
    let r = parse_into_with(
        &mut b,
        data,
        path,
        opts,
        recover.then_some(&mut errors),
        &|| false,
        ctl,
    );
    show(b, r, &errors)
}

fn show(b: Builder, r: foon_core::Result<()>, errors: &[Error]) -> String {
    let errs: Vec<String> = errors.iter().map(ToString::to_string).collect();
    match r {
        Ok(()) => format!("{:?}\n{errs:?}", b.finish()),
        Err(e) => format!("error: {e}\n{errs:?}"),
    }
}

fn loaded(path: &Path, strict: bool, recover: bool, chunk: usize) -> String {
    let mut b = Builder::new();
    let mut errors = Vec::new();
    let ctl = ParseControl {
        chunk_bytes: chunk,
        ..ParseControl::default()
    };
    let r = load_into(
        &mut b,
        path,
        ParseOptions { strict },
        recover.then_some(&mut errors),
        &|| false,
        ctl,
    );
    show(b, r, &errors)
}

/// Checks every mode of `data` for the chunk sizes given against one chunk.
fn check_all(data: &[u8], path: Option<&Path>, chunks: &[usize]) {
    for strict in [false, true] {
        for recover in [false, true] {
            let whole = outcome(data, path, strict, recover, usize::MAX);
            for &c in chunks {
                let got = outcome(data, path, strict, recover, c);
                assert!(
                    got == whole,
                    "chunk {c}, strict {strict}, recovering {recover}, {path:?}: differs"
                );
            }
        }
    }
}

fn files(dir: &Path, out: &mut Vec<PathBuf>) {
    let mut entries: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    entries.sort();
    for p in entries {
        if p.is_dir() {
            files(&p, out);
        } else {
            out.push(p);
        }
    }
}

#[test]
fn every_data_file_parses_the_same_in_any_chunks() {
    let Some(dir) = shared().map(|s| s.join("data/foon")) else {
        return;
    };
    let mut all = Vec::new();
    files(&dir, &mut all);
    assert!(all.len() > 100);
    for p in &all {
        let data = std::fs::read(p).unwrap();
        // Every line a chunk on the small files; chunks ending anywhere on all of them.
        let chunks: &[usize] = if data.len() < 40_000 {
            &[1, 97]
        } else {
            &[4099]
        };
        check_all(&data, Some(p), chunks);
        let whole = outcome(&data, Some(p), false, true, usize::MAX);
        assert_eq!(
            loaded(p, false, true, 4099),
            whole,
            "{p:?} loaded from the file"
        );
    }
}

#[test]
fn the_course_foon_is_the_same_on_one_thread_and_on_several() {
    let Some(dir) = shared().map(|s| s.join("data/foon")) else {
        return;
    };
    let p = dir.join("FOON.txt");
    let data = std::fs::read(&p).unwrap();
    let run = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| outcome(&data, Some(&p), false, false, 1000))
    };
    assert_eq!(run(1), run(3));
    assert_eq!(run(1), outcome(&data, Some(&p), false, false, usize::MAX));
}

#[test]
fn progress_counts_the_bytes_of_the_input() {
    let Some(dir) = shared().map(|s| s.join("data/foon")) else {
        return;
    };
    let p = dir.join("FOON.txt");
    let data = std::fs::read(&p).unwrap();
    for from_file in [false, true] {
        let progress = Progress::new();
        let ctl = ParseControl {
            progress: Some(&progress),
            chunk_bytes: 10_000,
        };
        let mut b = Builder::new();
        let opts = ParseOptions::default();
        if from_file {
            load_into(&mut b, &p, opts, None, &|| false, ctl).unwrap();
        } else {
            parse_into_with(&mut b, &data, None, opts, None, &|| false, ctl).unwrap();
        }
        let s = progress.snapshot();
        assert_eq!(
            (s.phase, s.done, s.total),
            ("parse", data.len() as u64, data.len() as u64)
        );
    }
}

#[test]
fn a_cancelled_parse_stops_in_any_chunks() {
    let text = "O\ta\nS\tx\nM\tm\nO\ta\nS\ty\n//\n".repeat(3000);
    for chunk in [1, 100, 0] {
        let mut b = Builder::new();
        let ctl = ParseControl {
            chunk_bytes: chunk,
            ..ParseControl::default()
        };
        let r = parse_into_with(
            &mut b,
            text.as_bytes(),
            None,
            ParseOptions::default(),
            None,
            &|| true,
            ctl,
        );
        assert!(matches!(r, Err(Error::Cancelled)), "chunk {chunk}");
    }
}

/// Lines that real and broken FOON files hold.
fn line() -> impl Strategy<Value = String> {
    prop_oneof![
        4 => prop::sample::select(vec!["egg", "Bowl", "salt ", "pan", "ÉGG", "water"])
            .prop_map(|l| format!("O\t{l}")),
        1 => prop::sample::select(vec!["O1\tegg\t1", "O2\tpan\t0", "O\tegg\t\t", "O", "O\t"])
            .prop_map(str::to_owned),
        4 => prop::sample::select(vec!["whole", "Cracked", "hot", "", " in"])
            .prop_map(|s| format!("S\t{s}")),
        2 => prop::sample::select(vec![
            "S\tcontains\t{egg,salt}", "S\tcontains\t{egg,egg}", "S\tcontains\t{a,,b}",
            "S\tcontains\t{ a}", "S\tin\t[bowl]", "S\tin\t[ ]", "S\tin\t[pan", "S\tx\t{y",
            "S\tx\tzz", "S\t\t[bowl]",
        ])
        .prop_map(str::to_owned),
        3 => prop::sample::select(vec!["M\tcrack", "M\tPour\t0:05\t0:10", "M\t", "M1\tmix\t \t"])
            .prop_map(str::to_owned),
        3 => Just("//".to_owned()),
        1 => prop::sample::select(vec!["# a comment", "", "   ", "X\tbad", "Ox\tegg", "//junk"])
            .prop_map(str::to_owned),
        1 => Just("O\tnul\u{0}byte".to_owned()),
    ]
}

/// A FOON text from lines: CRLF or LF, an optional byte-order mark, an optional last line
/// feed, and now and then a byte that is not UTF-8.
fn text() -> impl Strategy<Value = Vec<u8>> {
    (
        prop::collection::vec(line(), 0..60),
        any::<bool>(),
        any::<bool>(),
        any::<bool>(),
        prop::option::weighted(0.1, any::<prop::sample::Index>()),
    )
        .prop_map(|(lines, crlf, bom, last_eol, bad)| {
            let eol = if crlf { "\r\n" } else { "\n" };
            let mut t = Vec::new();
            if bom {
                t.extend_from_slice(b"\xEF\xBB\xBF");
            }
            for (i, l) in lines.iter().enumerate() {
                t.extend_from_slice(l.as_bytes());
                if i + 1 < lines.len() || last_eol {
                    t.extend_from_slice(eol.as_bytes());
                }
            }
            if let (Some(i), false) = (bad, t.is_empty()) {
                let at = i.index(t.len());
                t.insert(at, 0xFF);
            }
            t
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    #[test]
    fn generated_texts_parse_the_same_in_any_chunks(data in text(), chunk in 1usize..80) {
        check_all(&data, Some(Path::new("gen.txt")), &[chunk, 1]);
    }

    #[test]
    fn generated_texts_load_from_a_file_as_from_memory(data in text(), chunk in 1usize..80) {
        let dir = std::env::temp_dir().join(format!("foon-parse-parallel-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join(format!("t{chunk}-{}.txt", data.len()));
        std::fs::write(&p, &data).unwrap();
        for recover in [false, true] {
            let whole = outcome(&data, Some(&p), false, recover, usize::MAX);
            prop_assert_eq!(loaded(&p, false, recover, chunk), whole);
        }
        std::fs::remove_file(&p).unwrap();
    }
}
