//! Progress of long operations: a [`Progress`] value that the core updates (units done out of
//! a total, and the name of the current phase) and that a caller reads from another thread to
//! draw a bar. The core never draws anything.

use std::sync::Mutex;
use std::sync::atomic::{AtomicU64, Ordering};

/// Counters of a long operation, shared between the thread doing the work and any thread
/// watching it (`Send + Sync`; updates are relaxed atomic additions, cheap enough to make
/// every few hundred kilobytes or every few thousand units).
///
/// An operation calls [`Progress::begin`] with its phase name and total (for a parse: bytes
/// of the input), [`Progress::add`] as it goes, and [`Progress::finish`] at its end. A total
/// of 0 means unknown (a pipe).
#[derive(Debug, Default)]
pub struct Progress {
    done: AtomicU64,
    total: AtomicU64,
    phase: Mutex<&'static str>,
}

/// What a [`Progress`] holds at one moment.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Snapshot {
    /// The current phase (`""` before any).
    pub phase: &'static str,
    /// Units done in this phase.
    pub done: u64,
    /// Units in this phase (0: unknown).
    pub total: u64,
}

impl Progress {
    /// A progress with no phase yet.
    pub fn new() -> Self {
        Self::default()
    }

    /// Starts a phase of `total` units (0 when unknown): done goes back to 0.
    pub fn begin(&self, phase: &'static str, total: u64) {
        if let Ok(mut p) = self.phase.lock() {
            *p = phase;
        }
        self.done.store(0, Ordering::Relaxed);
        self.total.store(total, Ordering::Relaxed);
    }

    /// Records `n` more units done.
    pub fn add(&self, n: u64) {
        self.done.fetch_add(n, Ordering::Relaxed);
    }

    /// Sets the total (when it becomes known, or grows).
    pub fn set_total(&self, total: u64) {
        self.total.store(total, Ordering::Relaxed);
    }

    /// Ends the phase: done is the total (or stays, when the total is unknown).
    pub fn finish(&self) {
        let total = self.total.load(Ordering::Relaxed);
        if total > 0 {
            self.done.store(total, Ordering::Relaxed);
        }
    }

    /// Units done in the current phase.
    pub fn done(&self) -> u64 {
        self.done.load(Ordering::Relaxed)
    }

    /// Units in the current phase (0: unknown).
    pub fn total(&self) -> u64 {
        self.total.load(Ordering::Relaxed)
    }

    /// The current phase name (`""` before any).
    pub fn phase(&self) -> &'static str {
        self.phase.lock().map_or("", |p| *p)
    }

    /// Phase, done and total together (each read once; done never exceeds the total shown
    /// unless the total is unknown).
    pub fn snapshot(&self) -> Snapshot {
        let phase = self.phase();
        let total = self.total();
        let done = self.done();
        Snapshot {
            phase,
            done: if total > 0 { done.min(total) } else { done },
            total,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::Progress;

    #[test]
    fn phases_and_counts() {
        let p = Progress::new();
        assert_eq!(p.phase(), "");
        p.begin("parse", 100);
        p.add(30);
        p.add(30);
        let s = p.snapshot();
        assert_eq!((s.phase, s.done, s.total), ("parse", 60, 100));
        p.add(70);
        assert_eq!(p.snapshot().done, 100);
        p.finish();
        assert_eq!(p.done(), 100);
        p.begin("index", 0);
        p.add(5);
        p.finish();
        assert_eq!((p.phase(), p.done(), p.total()), ("index", 5, 0));
        std::thread::scope(|s| {
            for _ in 0..4 {
                s.spawn(|| (0..1000).for_each(|_| p.add(1)));
            }
        });
        assert_eq!(p.done(), 4005);
    }
}
