//! Shared checks: an error on user data must be a parse error whose location lies inside the
//! input (1-based line at most one past the last line, column at most one past the end of
//! that line, counted in characters).

use foon_core::Error;
use foon_core::search::{Context, Plan};

#[allow(dead_code)]
pub fn check_error(data: &[u8], e: &Error) {
    let Error::Parse { at, reason, .. } = e else {
        panic!("an error on bytes that is not a parse error: {e}");
    };
    assert!(!reason.is_empty(), "empty reason");
    assert!(
        at.line >= 1 && at.column >= 1,
        "location {at} is not 1-based"
    );
    let lines: Vec<&[u8]> = data.split(|&b| b == b'\n').collect();
    assert!(
        at.line as usize <= lines.len(),
        "line {} past the end ({} lines)",
        at.line,
        lines.len()
    );
    let line = lines[at.line as usize - 1];
    let chars = String::from_utf8_lossy(line).chars().count();
    assert!(
        at.column as usize <= chars + 1,
        "column {} past the end of line {} ({chars} characters)",
        at.column,
        at.line
    );
}

/// A solved sound plan must be a valid tree listed in execution order.
#[allow(dead_code)]
pub fn check_solved_tree(ctx: &Context<'_>, plan: &Plan, text: &str) {
    let method = plan.query.method;
    assert!(
        ctx.is_valid(&plan.units, plan.goal),
        "{method:?}: invalid tree {:?} for goal {}\n{text}",
        plan.units,
        plan.goal
    );
    assert_eq!(
        ctx.first_unavailable(&plan.units),
        None,
        "{method:?}: units {:?} not in execution order\n{text}",
        plan.units
    );
}
