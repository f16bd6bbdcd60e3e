//! Progress bars: the core counts (`foon_core::progress::Progress`), the bindings draw. A bar
//! is drawn on stderr (by indicatif) only when the Python side asks for one: a terminal, not
//! in CI, not `-q`, not `TERM=dumb` (`foon._progress.wanted`). The waiting thread of
//! [`enter_watching`] updates it every 20 ms from the counters; the work never touches it.

use foon_core::progress::Progress;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use pyo3::prelude::*;

use crate::errors::{Cancel, enter_watching};

/// A bar over a [`Progress`], drawn while it is shown.
struct Bar {
    bar: ProgressBar,
    bytes: bool,
}

impl Bar {
    fn new(bytes: bool) -> Self {
        let bar = ProgressBar::with_draw_target(None, ProgressDrawTarget::stderr_with_hz(10));
        Self { bar, bytes }
    }

    fn update(&self, p: &Progress) {
        let s = p.snapshot();
        if s.phase.is_empty() {
            return;
        }
        let (pos, len) = if self.bytes {
            ("{binary_bytes}/{binary_total_bytes}", "{binary_bytes}")
        } else {
            ("{human_pos}/{human_len}", "{human_pos}")
        };
        let template = if s.total > 0 {
            format!("{{msg:>8}} [{{bar:30}}] {pos} ({{eta}} left)")
        } else {
            format!("{{msg:>8}} {{spinner}} {len}")
        };
        if let Ok(style) = ProgressStyle::with_template(&template) {
            self.bar.set_style(style.progress_chars("=> "));
        }
        if s.total > 0 {
            self.bar.set_length(s.total);
        }
        self.bar.set_message(s.phase);
        self.bar.set_position(s.done.min(s.total.max(s.done)));
    }
}

/// Runs `work` as [`crate::errors::enter`] does, handing it a [`Progress`] to update, and
/// draws a bar from it on stderr while it runs when `show` is true (the bar is cleared at
/// the end). `bytes`: the counters are bytes (else units).
pub(crate) fn enter_progress<T: Send>(
    py: Python<'_>,
    show: bool,
    bytes: bool,
    work: impl FnOnce(Cancel<'_>, &Progress) -> foon_core::Result<T> + Send,
) -> PyResult<T> {
    let progress = Progress::new();
    if !show {
        return crate::errors::enter(py, |cancel| work(cancel, &progress));
    }
    let bar = Bar::new(bytes);
    let watch = || {
        bar.update(&progress);
        false
    };
    let r = enter_watching(py, &watch, |cancel| work(cancel, &progress));
    bar.bar.finish_and_clear();
    r
}
