//! The last sample each thread took of a steady meshed field.
//!
//! A particle's step samples its start state where the contact event's step cap sampled it a
//! moment before (the same x and t): the repeat is answered from here. A pure function's memo:
//! the answer is bit for bit the one a new evaluation gives, so results do not depend on it.

use crate::error::FlowError;
use crate::flow::FlowSample;
use crate::tensor::Vec3;
use std::cell::Cell;
use std::sync::atomic::{AtomicU64, Ordering};

/// Source of field identities.
static NEXT_ID: AtomicU64 = AtomicU64::new(0);

thread_local! {
    /// The last sample this thread took: (field identity, x and t as bits, sample).
    static LAST_SAMPLE: Cell<Option<(u64, [u64; 4], FlowSample)>> = const { Cell::new(None) };
}

/// A new field identity: no thread's memo holds a sample of it.
pub(super) fn new_id() -> u64 {
    NEXT_ID.fetch_add(1, Ordering::Relaxed)
}

/// The sample of field `id` at (x, t): the memo's if this thread's last sample was that one,
/// else `sample()`, remembered when it succeeds.
pub(super) fn remembered(
    id: u64,
    x: &Vec3,
    t: f64,
    sample: impl FnOnce() -> Result<FlowSample, FlowError>,
) -> Result<FlowSample, FlowError> {
    let key = [x[0].to_bits(), x[1].to_bits(), x[2].to_bits(), t.to_bits()];
    if let Some((at_id, at, s)) = LAST_SAMPLE.get()
        && at_id == id
        && at == key
    {
        return Ok(s);
    }
    let s = sample()?;
    LAST_SAMPLE.set(Some((id, key, s)));
    Ok(s)
}
