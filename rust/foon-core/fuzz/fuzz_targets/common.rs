//! Shared checks: an error on user data must be a parse error whose location lies inside the
//! input (1-based line at most one past the last line, column at most one past the end of
//! that line, counted in characters).

use foon_core::Error;

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
