//! FOON text: parsing never panics, errors are located inside the input, writing back and
//! re-parsing keeps the FU and object counts (and is a fixpoint), and every planner, on an
//! empty kitchen and on a one-item kitchen, returns Ok or Err without panicking; a solved
//! sound plan is a valid tree listed in execution order.

#![no_main]

use foon_core::search::{Compat, Context, Count, Method, Query};
use foon_core::{ParseOptions, parse_foon, write};
use libfuzzer_sys::fuzz_target;

#[path = "common.rs"]
mod common;

fuzz_target!(|data: &[u8]| {
    let strict = parse_foon(data, None, ParseOptions { strict: true });
    let foon = match parse_foon(data, None, ParseOptions::default()) {
        Ok(f) => f,
        Err(e) => {
            common::check_error(data, &e);
            assert!(
                strict.is_err(),
                "strict mode accepted what lenient mode rejected"
            );
            return;
        }
    };
    match &strict {
        Ok(_) => assert!(foon.warnings().is_empty()),
        Err(e) => common::check_error(data, e),
    }

    // Round trip: the written form parses without a load warning to the same graph (not
    // strictly: an empty ingredient, `{}`, is written as it was read, with its lint warning).
    let text = write::foon_text(&foon);
    let again = parse_foon(text.as_bytes(), None, ParseOptions::default())
        .unwrap_or_else(|e| panic!("the written form does not parse: {e}\n{text}"));
    assert!(
        again.warnings().is_empty(),
        "the written form has warnings\n{text}"
    );
    assert!(
        again.notes().iter().all(|w| !matches!(
            w.kind,
            foon_core::WarningKind::TwoContainers | foon_core::WarningKind::TwoIngredientLists
        )),
        "the written form has a conflicting annotation\n{text}"
    );
    assert_eq!(
        foon.fu_count(),
        again.fu_count(),
        "FU count changed\n{text}"
    );
    assert_eq!(
        foon.object_count(),
        again.object_count(),
        "object count changed\n{text}"
    );
    assert_eq!(text, write::foon_text(&again), "writing is not a fixpoint");

    // Planners never panic.
    let n = foon.object_count() as u32;
    if n == 0 {
        return;
    }
    let first = foon_core::ObjectSpec::of_object(&foon, 0);
    let utensils: Vec<String> = (0..n.min(3))
        .map(|o| foon.label_text(o).to_owned())
        .collect();
    let kitchens: [(&[foon_core::ObjectSpec], &[String], Option<f64>); 3] = [
        (&[], &[], None),
        (&[], &[], Some(0.5)),
        (std::slice::from_ref(&first), &utensils, Some(0.9)),
    ];
    let goals: Vec<u32> = (0..n.min(4)).chain(std::iter::once(n - 1)).collect();
    for (kitchen, utensils, default_rate) in kitchens {
        let ctx = Context::new(&foon, kitchen, utensils, None, default_rate).unwrap();
        for &goal in &goals {
            for method in Method::ALL {
                for compat in [Compat::Sound, Compat::Course] {
                    let query = Query {
                        method,
                        compat,
                        count: if goal % 2 == 0 {
                            Count::Nodes
                        } else {
                            Count::Ingredients
                        },
                    };
                    let Ok(plan) = ctx.plan(goal, query) else {
                        continue;
                    };
                    if compat == Compat::Sound && method != Method::Bfs && plan.solved {
                        common::check_solved_tree(&ctx, &plan, &text);
                    }
                }
            }
        }
    }
});
