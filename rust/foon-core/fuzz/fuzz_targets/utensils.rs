//! Utensil lists: never a panic, errors located inside the input, names without TAB or
//! surrounding blanks on the right.

#![no_main]

use foon_core::parse::parse_utensils;
use libfuzzer_sys::fuzz_target;

#[path = "common.rs"]
mod common;

fuzz_target!(|data: &[u8]| {
    match parse_utensils(data, None) {
        Ok(names) => {
            for n in &names {
                assert!(
                    !n.is_empty() && !n.contains('\t') && n.trim_end() == n,
                    "{n:?}"
                );
            }
        }
        Err(e) => common::check_error(data, &e),
    }
});
