//! Rendering DOT to SVG, PNG or PDF through Graphviz's `dot` (run as a child process; the
//! `FOON_DOT` environment variable names another `dot` binary).

use std::io::Write;
use std::process::{Command, Stdio};

use crate::error::{Error, Result};

/// Pictures (SVG, PNG, PDF, pages) refuse graphs of more nodes (objects + motions) than this
/// by default. `dot`'s layout time grows faster than the graph: on the course FOON, the 12
/// first course trees in one picture (862 nodes) take about 4 s, all 25 (2,122 nodes) 40 s,
/// and the 3,757 nodes within 3 steps of the Greek salad more than 8 minutes; a dense
/// 462-node neighbourhood already takes 5 s. At 1,000 nodes a picture still renders in
/// seconds, and it is about as much as anyone can read on a page.
pub const MAX_NODES: usize = 1_000;

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
/// what it writes. The program is `dot`, or the one `FOON_DOT` names. Errors
/// ([`Error::Output`]): the program is missing (with how to install Graphviz), cannot be
/// run, or fails (with the first line of what it wrote to stderr).
pub fn render(dot_text: &str, kind: &str) -> Result<Vec<u8>> {
    run(&dot_program(), dot_text, kind)
}

/// [`render`] with `program` as `dot`. Its input is written from another thread while its
/// stdout and stderr are read together, so no amount of output (or of warnings) can leave
/// both sides waiting on a full pipe. There is no time limit: a big graph takes as long
/// as `dot` takes (the size limit, [`MAX_NODES`], is what keeps that short).
fn run(program: &str, dot_text: &str, kind: &str) -> Result<Vec<u8>> {
    let mut child = Command::new(program)
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
    let feeder = child.stdin.take().map(|mut stdin| {
        let input = dot_text.as_bytes().to_vec();
        std::thread::spawn(move || stdin.write_all(&input))
    });
    // Reads stdout and stderr at the same time until both close, then waits for the child.
    let output = child
        .wait_with_output()
        .map_err(|e| Error::Output(format!("running `{program}`: {e}")))?;
    let fed = feeder.map_or(Ok(()), |t| {
        t.join()
            .unwrap_or_else(|_| Err(std::io::Error::other("the writer thread failed")))
    });
    if !output.status.success() {
        // Graphviz says why on stderr; its first line names the problem.
        let msg = String::from_utf8_lossy(&output.stderr);
        let first = msg.lines().map(str::trim).find(|l| !l.is_empty());
        return Err(Error::Output(match first {
            Some(line) => format!("Graphviz's `{program}` failed ({}): {line}", output.status),
            None => format!("Graphviz's `{program}` failed ({})", output.status),
        }));
    }
    // `dot` succeeded without reading all its input: what it drew is not the picture.
    fed.map_err(|e| Error::Output(format!("writing to `{program}`: {e}")))?;
    check_output(program, kind, &output.stdout)?;
    Ok(output.stdout)
}

/// Refuses what a program that exits 0 wrote when it is not a document of `kind`: nothing
/// at all, or for `svg`, `png` and `pdf` something that does not begin (and for SVG end)
/// as one does, so that a broken `FOON_DOT` never passes for a picture.
fn check_output(program: &str, kind: &str, out: &[u8]) -> Result<()> {
    let ok = match kind {
        _ if out.is_empty() => false,
        "svg" => {
            let text = String::from_utf8_lossy(out);
            text.trim_start().starts_with('<') && text.trim_end().ends_with("</svg>")
        }
        "png" => out.starts_with(b"\x89PNG\r\n\x1a\n"),
        "pdf" => out.starts_with(b"%PDF-"),
        _ => true,
    };
    if ok {
        return Ok(());
    }
    let what = if out.is_empty() {
        "nothing".to_owned()
    } else {
        format!("{} bytes that are not {kind}", out.len())
    };
    Err(Error::Output(format!(
        "Graphviz's `{program}` wrote {what} for -T{kind}"
    )))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::os::unix::fs::PermissionsExt;

    /// A shell script standing in for `dot` (in a fresh temporary folder).
    fn script(name: &str, body: &str) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!("foon-render-{}-{name}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("dot");
        std::fs::write(&path, format!("#!/bin/sh\n{body}\n")).unwrap();
        std::fs::set_permissions(&path, std::fs::Permissions::from_mode(0o755)).unwrap();
        path
    }

    #[test]
    fn a_missing_program_says_how_to_install_graphviz() {
        let e = run("/nonexistent/dot", "digraph {}", "svg").unwrap_err();
        assert!(matches!(e, Error::Output(_)));
        let msg = e.to_string();
        assert!(msg.contains("was not found"), "{msg}");
        assert!(msg.contains("apt-get install graphviz"), "{msg}");
    }

    #[test]
    fn a_failing_program_gives_the_first_line_of_its_stderr() {
        let p = script(
            "fail",
            "cat >/dev/null; echo >&2; echo 'Error: syntax error in line 1' >&2; echo second >&2; exit 3",
        );
        let msg = run(p.to_str().unwrap(), "digraph {", "svg")
            .unwrap_err()
            .to_string();
        assert!(msg.ends_with(": Error: syntax error in line 1"), "{msg}");
        assert!(!msg.contains("second"), "{msg}");
        let p = script("silent", "exit 1");
        let msg = run(p.to_str().unwrap(), "digraph {}", "svg")
            .unwrap_err()
            .to_string();
        assert!(msg.contains("failed (exit status: 1)"), "{msg}");
    }

    #[test]
    fn big_input_and_big_output_on_both_pipes_do_not_block() {
        // Writes 4 MB to stderr before reading anything, then copies its input to stdout
        // twice: a reader that drained one pipe after the other would wait forever.
        let p = script(
            "big",
            "head -c 4000000 /dev/zero >&2; t=$(mktemp); cat > \"$t\"; cat \"$t\" \"$t\"; rm -f \"$t\"",
        );
        let input = "x".repeat(3_000_000);
        let out = run(p.to_str().unwrap(), &input, "canon").unwrap();
        assert_eq!(out.len(), 6_000_000);
    }

    #[test]
    fn a_program_that_succeeds_with_no_picture_is_an_error() {
        for (name, body, kind) in [
            ("empty", "cat >/dev/null", "svg"),
            ("empty-canon", "cat >/dev/null", "canon"),
            ("garbage-svg", "cat >/dev/null; echo garbage", "svg"),
            (
                "cut-svg",
                "cat >/dev/null; echo '<?xml version=\"1.0\"?><svg>'",
                "svg",
            ),
            ("garbage-png", "cat >/dev/null; echo garbage", "png"),
            ("garbage-pdf", "cat >/dev/null; echo '<svg></svg>'", "pdf"),
        ] {
            let p = script(name, body);
            let e = run(p.to_str().unwrap(), "digraph {}", kind).unwrap_err();
            assert!(matches!(e, Error::Output(_)), "{name}");
            let msg = e.to_string();
            assert!(msg.contains(&format!("for -T{kind}")), "{name}: {msg}");
        }
        let p = script(
            "ok-svg",
            "cat >/dev/null; printf '<?xml?>\\n<svg>\\n</svg>\\n'",
        );
        assert!(run(p.to_str().unwrap(), "digraph {}", "svg").is_ok());
    }

    #[test]
    fn real_dot_renders_when_installed() {
        if Command::new("dot").arg("-V").output().is_err() {
            // Graphviz is not installed here; CI installs it.
            assert!(
                std::env::var_os("CI").is_none(),
                "CI is set but `dot` is missing"
            );
            return;
        }
        let svg = run("dot", "digraph { a -> b }", "svg").unwrap();
        assert!(String::from_utf8(svg).unwrap().contains("<svg"));
        let msg = run("dot", "digraph { a -> ", "svg")
            .unwrap_err()
            .to_string();
        assert!(msg.contains("syntax error"), "{msg}");
    }
}
