//! Memory of a run: the peak resident memory it reports, and the allocator tuning that keeps the
//! memory of a long run flat (the solver's own bound is the re-condensation interval,
//! [`super::auto_refactor_every`]).

/// Peak resident set size of this process (Linux `VmHWM`), if available.
pub fn peak_memory_bytes() -> Option<u64> {
    let s = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = s.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}

/// Large temporaries of the re-condensation (three n_P x n_P matrices) alternate with the small
/// long-lived allocations of the history. glibc's allocator raises its mmap threshold
/// dynamically after the first large free, after which such matrices come from the heap and the
/// history's small blocks split the holes they leave: the resident memory then grew by about one
/// condensation's matrices per re-condensation (85 kB per step in a 1e5-step run). Fixing the
/// threshold at [`MMAP_THRESHOLD`] (once per process; glibc only) keeps every large block mmapped
/// and returned to the system when freed, so the memory stays flat.
///
/// Fixing it also fixes glibc's trim threshold, at its default of 128 kB: every free at the top
/// of the heap above that gave the pages back, and the next step's vectors of the unknowns (about
/// 0.8 MB each on the paper's grid) took them again, page fault by page fault. The trim threshold
/// is set to [`TRIM_THRESHOLD`]: at most that much free heap is kept, so the memory still stays
/// flat (benches/RESULTS.md, "Page faults").
pub(super) fn keep_large_blocks_mmapped() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    {
        static ONCE: std::sync::Once = std::sync::Once::new();
        extern "C" {
            fn mallopt(param: i32, value: i32) -> i32;
        }
        const M_TRIM_THRESHOLD: i32 = -1;
        const M_MMAP_THRESHOLD: i32 = -3;
        // SAFETY: mallopt only changes an allocator tuning parameter; it is thread safe in glibc.
        ONCE.call_once(|| unsafe {
            mallopt(M_MMAP_THRESHOLD, MMAP_THRESHOLD);
            mallopt(M_TRIM_THRESHOLD, TRIM_THRESHOLD);
        });
    }
}

/// Blocks at least this large (bytes) are mmapped ([`keep_large_blocks_mmapped`]).
const MMAP_THRESHOLD: i32 = 4 << 20;
/// Free heap (bytes) kept at the top of a heap before it is given back
/// ([`keep_large_blocks_mmapped`]).
const TRIM_THRESHOLD: i32 = 64 << 20;
