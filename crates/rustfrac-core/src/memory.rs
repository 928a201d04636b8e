//! The memory budget of a run (issue 17, item 2): what the machine (`MemAvailable`) and the
//! process (its address-space limit, `ulimit -v`) leave for it, and the refusal, before anything
//! large is built, of a run whose estimated need does not fit: an [`Error::OutOfMemory`] naming
//! the size, never an abort in the middle of the run. The estimates are upper bounds from the
//! sizes of the model (unknowns, bonds, the dense condensed system), with constants measured on
//! this code (benches/RESULTS.md: the 1e6-unknown FEM solve peaks at 2.1 GiB).

use crate::error::{Error, Result};

/// Bytes per unknown of a FEM / XFEM solve (matrix, nested-dissection Cholesky factor, vectors,
/// stresses): measured 2.2 kB per unknown at 1e6 unknowns, bounded here by 3 kB.
pub const BYTES_PER_DOF: f64 = 3000.0;

/// Address space a run needs beyond its data: the allocator arenas and stacks of the worker
/// threads (glibc reserves 64 MiB per arena), the solver libraries' workspaces.
pub const RUN_OVERHEAD: f64 = 256.0 * 1024.0 * 1024.0;

/// The bytes this process may still allocate: the smaller of the machine's available memory and
/// what the address-space limit leaves above the current size; None when neither is known.
pub fn available_bytes() -> Option<f64> {
    let free = proc_value("/proc/meminfo", "MemAvailable:").map(|kb| kb * 1024.0);
    let limit = address_space_limit();
    let size = proc_value("/proc/self/status", "VmSize:").map(|kb| kb * 1024.0);
    let left = match (limit, size) {
        (Some(l), Some(s)) => Some((l - s).max(0.0)),
        _ => None,
    };
    match (free, left) {
        (Some(a), Some(b)) => Some(a.min(b)),
        (a, b) => a.or(b),
    }
}

/// Refuses a run of `what` that needs about `bytes` (plus [`RUN_OVERHEAD`]) when less is
/// available.
pub fn check(what: &str, bytes: f64) -> Result<()> {
    let need = bytes + RUN_OVERHEAD;
    match available_bytes() {
        Some(avail) if need > avail => Err(Error::OutOfMemory {
            what: what.to_string(),
            needed: need as u64,
            available: avail as u64,
        }),
        _ => Ok(()),
    }
}

/// A vector of `n` copies of `v`, or [`Error::OutOfMemory`] when the allocation fails (fallible
/// allocation for the large buffers).
pub fn try_filled<T: Clone>(n: usize, v: T, what: &str) -> Result<Vec<T>> {
    let mut out = Vec::new();
    out.try_reserve_exact(n).map_err(|_| Error::OutOfMemory {
        what: what.to_string(),
        needed: (n * std::mem::size_of::<T>()) as u64,
        available: available_bytes().unwrap_or(0.0) as u64,
    })?;
    out.resize(n, v);
    Ok(out)
}

/// The value (first number, kB) of the line starting with `key` in a /proc file.
fn proc_value(file: &str, key: &str) -> Option<f64> {
    let s = std::fs::read_to_string(file).ok()?;
    let line = s.lines().find(|l| l.starts_with(key))?;
    line.split_whitespace().nth(1)?.parse().ok()
}

/// The soft address-space limit of this process in bytes (`Max address space` of
/// /proc/self/limits), None when unlimited or unknown.
fn address_space_limit() -> Option<f64> {
    let s = std::fs::read_to_string("/proc/self/limits").ok()?;
    let line = s.lines().find(|l| l.starts_with("Max address space"))?;
    let soft = line
        .trim_start_matches("Max address space")
        .split_whitespace()
        .next()?;
    soft.parse().ok()
}
