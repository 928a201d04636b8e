//! The memory budget of a run: what the machine (`MemAvailable`) and the
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
    let (free, left) = (free_bytes(), address_space_left());
    match (free, left) {
        (Some(a), Some(b)) => Some(a.min(b)),
        (a, b) => a.or(b),
    }
}

/// The machine's available memory (`MemAvailable`).
fn free_bytes() -> Option<f64> {
    proc_value("/proc/meminfo", "MemAvailable:").map(|kb| kb * 1024.0)
}

/// What the address-space limit leaves above the process's current size (None: no limit).
fn address_space_left() -> Option<f64> {
    let limit = address_space_limit()?;
    let size = proc_value("/proc/self/status", "VmSize:").map(|kb| kb * 1024.0)?;
    Some((limit - size).max(0.0))
}

/// Address space (not memory) the dense kernels reserve: faer's matrix product (private-gemm,
/// used by the supernodal Cholesky and the condensation) keeps a thread-local packing buffer of
/// twice the largest cache per thread that runs it, reserved but mostly untouched. Some virtual
/// machines report caches of hundreds of MiB (480 MiB measured here: 960 MiB a thread), which
/// only an address-space limit (`ulimit -v`) feels; an allocation failing inside the kernel
/// aborts the process, so [`check`] counts it against that limit.
pub fn matmul_reserve() -> f64 {
    let largest = (0..8)
        .filter_map(|k| {
            let s = std::fs::read_to_string(format!(
                "/sys/devices/system/cpu/cpu0/cache/index{k}/size"
            ))
            .ok()?;
            let s = s.trim();
            let (num, unit) = s.split_at(s.find(|c: char| !c.is_ascii_digit()).unwrap_or(s.len()));
            let v: f64 = num.parse().ok()?;
            Some(
                v * match unit {
                    "K" => 1024.0,
                    "M" => 1024.0 * 1024.0,
                    "G" => 1024.0 * 1024.0 * 1024.0,
                    _ => 1.0,
                },
            )
        })
        .fold(0.0, f64::max);
    2.0 * largest * (rayon::current_num_threads() + 1) as f64
}

/// Refuses a run of `what` that needs about `bytes` (plus [`RUN_OVERHEAD`]) when the machine has
/// less available, or when the address-space limit leaves less than that plus the dense kernels'
/// reserve ([`matmul_reserve`]).
pub fn check(what: &str, bytes: f64) -> Result<()> {
    let need = bytes + RUN_OVERHEAD;
    let refuse = |needed: f64, available: f64| {
        Err(Error::OutOfMemory {
            what: what.to_string(),
            needed: needed as u64,
            available: available as u64,
        })
    };
    if let Some(free) = free_bytes() {
        if need > free {
            return refuse(need, free);
        }
    }
    if let Some(left) = address_space_left() {
        let need_as = need + matmul_reserve();
        if need_as > left {
            return refuse(need_as, left);
        }
    }
    Ok(())
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
