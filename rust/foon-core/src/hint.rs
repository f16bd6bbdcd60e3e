//! Hints to the processor: they change how fast the core runs, never what it computes.

/// Asks the processor to bring the cache line of `x` in (a hint: no effect on what the
/// program computes, and none at all where the target has no such instruction).
#[inline]
#[allow(unsafe_code)]
pub(crate) fn prefetch<T>(x: &T) {
    #[cfg(target_arch = "x86_64")]
    // SAFETY: a prefetch reads nothing and writes nothing (it cannot fault, whatever the
    // address); `sse`, which it needs, is part of every x86-64 processor.
    unsafe {
        std::arch::x86_64::_mm_prefetch::<{ std::arch::x86_64::_MM_HINT_T0 }>(
            std::ptr::from_ref(x).cast::<i8>(),
        );
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = x;
}

/// How many units ahead of the one computed a pipeline over units brings in the values a
/// unit reads: [`AHEAD`] times two ([`Ahead::Far`]); three and four times as far, its row and
/// where the row starts (`Flows::each_flow_ahead`).
pub(crate) const AHEAD: usize = 4;

/// Where a unit stands in a pipeline over units (`Flows::each_flow_ahead`).
#[derive(Clone, Copy, PartialEq, Eq)]
pub(crate) enum Ahead {
    /// [`AHEAD`] times two units ahead: its row is in, bring in the values it reads.
    Far,
    /// The unit to compute.
    Now,
}
