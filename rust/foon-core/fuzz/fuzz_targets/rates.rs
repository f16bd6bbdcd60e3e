//! Motion-rate tables: never a panic, errors located inside the input, every rate read is
//! between 0 and 1 and every motion name is non-empty.

#![no_main]

use foon_core::parse::parse_rates;
use libfuzzer_sys::fuzz_target;

#[path = "common.rs"]
mod common;

fuzz_target!(|data: &[u8]| {
    match parse_rates(data, None) {
        Ok(r) => {
            for (m, v) in &r.entries {
                assert!(!m.is_empty());
                assert!((0.0..=1.0).contains(v), "rate {v} of {m:?}");
                assert_eq!(r.get(m), Some(*v));
            }
        }
        Err(e) => common::check_error(data, &e),
    }
});
