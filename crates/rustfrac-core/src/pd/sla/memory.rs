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
/// threshold at 4 MiB (once per process; glibc only) keeps every large block mmapped and returned
/// to the system when freed, so the memory stays flat.
pub(super) fn keep_large_blocks_mmapped() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    {
        static ONCE: std::sync::Once = std::sync::Once::new();
        extern "C" {
            fn mallopt(param: i32, value: i32) -> i32;
        }
        const M_MMAP_THRESHOLD: i32 = -3;
        // SAFETY: mallopt only changes an allocator tuning parameter; it is thread safe in glibc.
        ONCE.call_once(|| unsafe {
            mallopt(M_MMAP_THRESHOLD, 4 << 20);
        });
    }
}
