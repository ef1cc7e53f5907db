//! Order-preserving maps over independent jobs: on all cores with rayon (feature `parallel`),
//! otherwise one after the other. Scenes call this instead of rayon so that the core model
//! builds without it; the results are the same either way, since the jobs are independent.

/// `items.map(f)` in input order.
#[cfg(feature = "parallel")]
pub(crate) fn map<T: Sync, R: Send>(items: &[T], f: impl Fn(&T) -> R + Sync + Send) -> Vec<R> {
    use rayon::prelude::*;
    items.par_iter().map(f).collect()
}

/// `items.map(f)` in input order.
#[cfg(not(feature = "parallel"))]
pub(crate) fn map<T: Sync, R: Send>(items: &[T], f: impl Fn(&T) -> R + Sync + Send) -> Vec<R> {
    items.iter().map(f).collect()
}
