//! `.foonidx` index files: the bytes are opened as an index (seed corpus: the index files of
//! the course FOON and of some subgraphs, written by `FOONIDX_SEED_CORPUS=DIR cargo test -p
//! foon-core --test foonidx seed_corpus`). Checks: no panic; a refused file is a one-line
//! `BadIndex` error naming the source; a file that opens answers every look-up, writes its
//! text, writes bytes that open again to the same bytes, and plans every method over its raw objects as the
//! kitchen.

#![no_main]

use std::path::Path;

use foon_core::search::{Compat, Context, Count, Method, Query};
use foon_core::{Error, Foon, ObjectSpec, write};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let f = match Foon::from_index_bytes(data, Path::new("fuzz.foonidx")) {
        Ok(f) => f,
        Err(e) => {
            assert!(matches!(e, Error::BadIndex { .. }), "{e:?}");
            let msg = e.to_string();
            assert!(
                msg.starts_with("fuzz.foonidx: ") && !msg.contains('\n'),
                "{msg}"
            );
            return;
        }
    };
    // What an opened index writes opens again and writes the same bytes.
    let bytes = f.index_bytes();
    let again = Foon::from_index_bytes(&bytes, Path::new("again")).expect("rewritten index");
    assert_eq!(again.index_bytes(), bytes);
    let _ = f.stats();
    let _ = f.verify_checksum();
    let _ = write::foon_text(&f);
    for o in 0..f.object_count() as u32 {
        let _ = ObjectSpec::of_object(&f, o).find_in(&f);
    }
    for u in 0..f.fu_count() as u32 {
        let _ = f.find_fu(f.motion(u), f.inputs(u), f.outputs(u));
        let _ = f.origins(u).count();
        let _ = f.support(u);
    }
    let kitchen: Vec<ObjectSpec> = (0..f.object_count() as u32)
        .filter(|&o| f.producers(o).is_empty())
        .map(|o| ObjectSpec::of_object(&f, o))
        .collect();
    let Ok(ctx) = Context::new(&f, &kitchen, &[], None, Some(0.5)) else {
        return;
    };
    for method in Method::ALL {
        for compat in [Compat::Sound, Compat::Course] {
            let q = Query {
                method,
                compat,
                count: Count::Nodes,
            };
            for g in (0..f.object_count() as u32).step_by(5).take(40) {
                let _ = ctx.plan(g, q);
            }
        }
    }
});
