//! Rendering DOT to SVG, PNG or PDF through Graphviz's `dot` (run as a child process; the
//! `FOON_DOT` environment variable names another `dot` binary).

use std::io::{Read, Write};
use std::process::{Command, Stdio};

use crate::error::{Error, Result};

/// Pictures refuse graphs of more nodes (objects + motions) than this by default.
pub const MAX_NODES: usize = 2_000;

/// How to install Graphviz, said when `dot` is missing.
pub const INSTALL_HINT: &str = "install Graphviz (Debian/Ubuntu: apt-get install graphviz; \
     macOS: brew install graphviz; conda: conda install graphviz), or write --format dot";

fn dot_program() -> String {
    std::env::var("FOON_DOT")
        .ok()
        .filter(|s| !s.is_empty())
        .unwrap_or_else(|| "dot".to_owned())
}

/// Runs `dot -T<kind>` (`kind`: `svg`, `png`, `pdf`, `canon`, ...) on `dot_text` and returns
/// what it writes.
pub fn render(dot_text: &str, kind: &str) -> Result<Vec<u8>> {
    let program = dot_program();
    let mut child = Command::new(&program)
        .arg(format!("-T{kind}"))
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|e| {
            if e.kind() == std::io::ErrorKind::NotFound {
                Error::Output(format!(
                    "Graphviz's `{program}` program was not found: {INSTALL_HINT}"
                ))
            } else {
                Error::Output(format!("could not run Graphviz's `{program}`: {e}"))
            }
        })?;
    // Feed stdin from a thread so that a large output cannot block the child on a full pipe.
    let mut stdin = child.stdin.take().expect("piped stdin");
    let input = dot_text.as_bytes().to_vec();
    let feeder = std::thread::spawn(move || {
        let r = stdin.write_all(&input);
        drop(stdin);
        r
    });
    let mut out = Vec::new();
    let mut err = Vec::new();
    if let Some(mut s) = child.stdout.take() {
        s.read_to_end(&mut out)
            .map_err(|e| Error::Output(format!("reading from `{program}`: {e}")))?;
    }
    if let Some(mut s) = child.stderr.take() {
        let _ = s.read_to_end(&mut err);
    }
    let status = child
        .wait()
        .map_err(|e| Error::Output(format!("waiting for `{program}`: {e}")))?;
    let fed = feeder.join().unwrap_or(Ok(()));
    if !status.success() {
        let msg = String::from_utf8_lossy(&err);
        let first = msg.lines().find(|l| !l.trim().is_empty()).unwrap_or("");
        return Err(Error::Output(format!(
            "Graphviz's `{program}` failed ({status}){}{first}",
            if first.is_empty() { "" } else { ": " }
        )));
    }
    fed.map_err(|e| Error::Output(format!("writing to `{program}`: {e}")))?;
    Ok(out)
}
