//! Planners on small random graphs (structure-aware: the bytes choose FUs over 18 objects,
//! with containers, ingredients and cycles, a kitchen, a goal; the utensil `l0` triggers the
//! container rule; the motion `m2` has rate 0). Checks: no panic; `ids` and the optimal
//! methods solve exactly the derivable goals; `ids` returns a tree of height rank(goal); every
//! solved sound plan is a valid tree listed in execution order; searches that keep their state
//! in hash maps (as on large FOONs) give exactly the same results as with arrays.

#![no_main]

#[path = "common.rs"]
mod common;

use std::fmt::Write as _;

use foon_core::MotionRates;
use foon_core::search::{Compat, Context, Count, Method, Plan, Query};
use foon_core::{ObjectSpec, ParseOptions, parse_foon};
use libfuzzer_sys::fuzz_target;

fn object(out: &mut String, b: u8) {
    let _ = write!(out, "O\tl{}\nS\ts{}\n", b % 6, (b / 6) % 3);
    if b & 0x80 != 0 {
        out.push_str("S\tin\t[l0]\n");
    }
    if b & 0x40 != 0 {
        let _ = writeln!(out, "S\tcontains\t{{l{}}}", (b >> 3) % 6);
    }
}

fuzz_target!(|data: &[u8]| {
    if data.len() < 3 {
        return;
    }
    let (head, body) = data.split_at(3);
    let mut text = String::new();
    let mut i = 0;
    while i < body.len() {
        let h = body[i];
        let (n_in, n_out) = ((h & 3) as usize, 1 + ((h >> 2) & 1) as usize);
        if i + 1 + n_in + n_out > body.len() {
            break;
        }
        for &b in &body[i + 1..i + 1 + n_in] {
            object(&mut text, b);
        }
        let _ = writeln!(text, "M\tm{}", (h >> 3) % 4);
        for &b in &body[i + 1 + n_in..i + 1 + n_in + n_out] {
            object(&mut text, b);
        }
        text.push_str("//\n");
        i += 1 + n_in + n_out;
    }
    let foon = parse_foon(text.as_bytes(), None, ParseOptions { strict: true })
        .unwrap_or_else(|e| panic!("generated text does not parse: {e}\n{text}"));
    let kitchen: Vec<ObjectSpec> = (0..16u8)
        .filter(|k| u16::from_le_bytes([head[0], head[1]]) & (1 << k) != 0)
        .map(|k| ObjectSpec {
            label: format!("l{}", k % 6),
            states: vec![format!("s{}", (k / 6) % 3)],
            ..ObjectSpec::default()
        })
        .collect();
    let goal_spec = ObjectSpec {
        label: format!("l{}", head[2] % 6),
        states: vec![format!("s{}", (head[2] / 6) % 3)],
        ..ObjectSpec::default()
    };
    let Some(goal) = goal_spec.find_in(&foon) else {
        return;
    };
    let rates = MotionRates::from_pairs(
        [("m0", 0.9), ("m1", 0.5), ("m2", 0.0), ("m3", 1.0)].map(|(m, r)| (m.to_owned(), r)),
    )
    .unwrap();
    let utensils = vec!["l0".to_owned()];
    let ctx = Context::new(&foon, &kitchen, &utensils, Some(&rates), None).unwrap();
    let sparse = Context::new(&foon, &kitchen, &utensils, Some(&rates), None)
        .unwrap()
        .with_scratch_limit(0);
    let rank = ctx.ranks().rank(goal);
    for method in Method::ALL {
        for compat in [Compat::Sound, Compat::Course] {
            for count in [Count::Nodes, Count::Ingredients] {
                let query = Query {
                    method,
                    compat,
                    count,
                };
                let result = ctx.plan(goal, query);
                match (&result, &sparse.plan(goal, query)) {
                    (Ok(a), Ok(b)) => assert_eq!(
                        Plan {
                            seconds: 0.0,
                            ..a.clone()
                        },
                        Plan {
                            seconds: 0.0,
                            ..b.clone()
                        },
                        "{query:?}: array and hash-map search state disagree\n{text}"
                    ),
                    (Err(a), Err(b)) => assert_eq!(a.to_string(), b.to_string()),
                    _ => panic!("{query:?}: array and hash-map search state disagree\n{text}"),
                }
                let Ok(plan) = result else {
                    continue;
                };
                if compat == Compat::Course || method == Method::Bfs {
                    continue;
                }
                if matches!(
                    method,
                    Method::Ids | Method::OptimalUnits | Method::OptimalInputs
                ) {
                    assert_eq!(
                        plan.solved,
                        rank.is_some(),
                        "{method:?}: solved {} but rank {rank:?}\n{text}",
                        plan.solved
                    );
                }
                if plan.solved {
                    common::check_solved_tree(&ctx, &plan, &text);
                    if method == Method::Ids {
                        assert_eq!(plan.height, rank, "ids height\n{text}");
                    }
                }
            }
        }
    }
});
