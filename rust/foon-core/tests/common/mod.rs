//! What the integration tests share: the real data set beside the repository, and every
//! plan of a context for comparisons. Each test file uses part of it.
#![allow(dead_code)]

pub(crate) mod generate;

use std::path::{Path, PathBuf};

use foon_core::search::{Compat, Context, Count, Method, Plan, Query};

/// `../shared` beside the repository, when the real FOON data is there; else `None` after a
/// message (and a failure when `FOON_REQUIRE_DATA` is set, as in CI).
pub(crate) fn shared() -> Option<PathBuf> {
    let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared");
    if p.join("data/foon/FOON.txt").is_file() {
        return Some(p);
    }
    assert!(
        std::env::var_os("FOON_REQUIRE_DATA").is_none(),
        "FOON_REQUIRE_DATA is set but ../shared/data/foon is missing"
    );
    eprintln!("skipped: ../shared/data/foon (the real FOON data) is not beside the repository");
    None
}

/// Every method and form (compat, count) for every goal, as (query, goal, plan): time zeroed,
/// an error as its message.
pub(crate) fn all_plans(
    ctx: &Context<'_>,
    goals: &[u32],
) -> Vec<(Query, u32, Result<Plan, String>)> {
    let mut out = Vec::new();
    for method in Method::ALL {
        for compat in [Compat::Sound, Compat::Course] {
            for count in [Count::Nodes, Count::Ingredients] {
                let q = Query {
                    method,
                    compat,
                    count,
                };
                for &g in goals {
                    let plan = ctx.plan(g, q).map(|mut p| {
                        p.seconds = 0.0;
                        p
                    });
                    out.push((q, g, plan.map_err(|e| e.to_string())));
                }
            }
        }
    }
    out
}
