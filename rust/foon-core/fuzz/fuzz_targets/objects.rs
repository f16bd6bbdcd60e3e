//! Kitchen and goal files (JSON or FOON object blocks): never a panic, errors located inside
//! the input, and every object read has a non-empty label.

#![no_main]

use foon_core::InputKind;
use foon_core::parse::parse_objects;
use libfuzzer_sys::fuzz_target;

#[path = "common.rs"]
mod common;

fuzz_target!(|data: &[u8]| {
    for kind in [InputKind::Kitchen, InputKind::Goal] {
        match parse_objects(data, None, kind) {
            Ok(list) => assert!(list.iter().all(|o| !o.label.is_empty())),
            Err(e) => common::check_error(data, &e),
        }
    }
});
