//! Checkpoints of the sequentially linear analysis ([`crate::pd::sla`]).
//!
//! The state of an SLA run is the sequence of bonds it broke (everything else follows from the
//! model), so a checkpoint holds the history: per step its recorded numbers (lambda, sigma22,
//! CMOD, u0, crack length), the bonds broken and the nodes grounded. Resuming rebuilds the model
//! and *replays* the steps: the same low-rank updates in the same order, re-condensations at the
//! same points, so the solver's floating-point state and therefore every later step are the same
//! bit for bit as in an uninterrupted run (the recorded numbers themselves are restored from their
//! stored bits, not recomputed).
//!
//! Format (little endian, no external serialiser): magic `RFSLACK\0`, version (u32), model
//! fingerprint (u64), step count (u64), then per step: step, lambda, sigma22, cmod, u0,
//! crack_length, node_i, node_j (u64 / f64 bits), the broken bonds and the detached nodes (each a
//! u64 count and u64 values), the probes (a u64 count and two f64 each; version 2); then the
//! adaptive region's switches (version 3): a u64 count, per switch its first step (u64) and the
//! midpoints of the bonds that grew the region (a u64 count and two f64 each); finally an
//! FNV-1a checksum (u64) of everything before it.
//!
//! Writing: the file goes to a temporary name beside it, created exclusively under a random name
//! (never following a planted symlink), synced, then renamed into place, so a reader never sees a
//! partial file; `checkpoint_path` may name a new file or an existing checkpoint, never another
//! file. Reading: regular files only (a FIFO or device is refused before it is opened), at most
//! the size a checkpoint of the model can have; a checkpoint is refused with a clear error when
//! its version, fingerprint, checksum or contents (finite values, positive load factors, every
//! bond once) do not fit the model.

use super::result::SlaStep;
use crate::error::{Error, Result};
use crate::problem::Grip;
use crate::problem::Problem;
use std::io::{Read, Write};
use std::path::Path;

const MAGIC: &[u8; 8] = b"RFSLACK\0";
/// Format version of the checkpoint files written (version 1, without the probes, is still
/// read for scenes without probes; versions 1 and 2 have no region switches).
pub const VERSION: u32 = 3;

/// A growth of the adaptive region as a checkpoint stores it: the first step solved on the
/// grown region and the midpoints of the bonds that grew it ([`crate::problem::pd_region`]
/// gives the rectangles again).
pub(crate) type Switch = (usize, Vec<[f64; 2]>);
/// Version of the fingerprint's field sequence (unchanged by format versions that only add
/// recorded values, so older checkpoints of the same model keep resuming).
const FINGERPRINT_SCHEME: u64 = 1;

/// FNV-1a, 64 bit: the checksum and the model fingerprint (stable across platforms and runs).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Fnv(u64);

impl Default for Fnv {
    fn default() -> Self {
        Fnv(0xcbf2_9ce4_8422_2325)
    }
}

impl Fnv {
    pub fn bytes(&mut self, b: &[u8]) {
        for &x in b {
            self.0 ^= x as u64;
            self.0 = self.0.wrapping_mul(0x0100_0000_01b3);
        }
    }
    pub fn u64(&mut self, v: u64) {
        self.bytes(&v.to_le_bytes());
    }
    pub fn f64(&mut self, v: f64) {
        self.u64(v.to_bits());
    }
    pub fn str(&mut self, s: &str) {
        self.u64(s.len() as u64);
        self.bytes(s.as_bytes());
    }
    pub fn finish(&self) -> u64 {
        self.0
    }
}

/// Fingerprint of everything that determines an SLA's sequence of floating-point operations: the
/// model (method, plate, grid, horizon, material, G0, PD rectangles, pre-crack polyline, the load
/// that acts; holes and supports and loads on regions, as their full description; a graded FEM
/// grid's pd.fem_grading and pd.fem_coarse) and the solver options (fast, refactor_every, tie_tol), plus the built model's
/// counts. The step limit, stop length, damage snapshots and checkpoint options may change
/// between the runs.
pub fn fingerprint(p: &Problem, precrack: &[[f64; 2]], n_dofs: usize, n_bonds: usize) -> u64 {
    let pd = p.pd().expect("a PD problem");
    let (d, mat, sla) = (&p.domain, &p.material.elastic, &pd.sla);
    let load = p.boundary.plate_load();
    let mut h = Fnv::default();
    h.u64(FINGERPRINT_SCHEME);
    h.str(p.method.name());
    for v in [d.width, d.height, pd.dx, p.material.g0, mat.e, mat.nu] {
        h.f64(v);
    }
    h.f64(mat.thickness);
    h.str(&format!("{:?}", mat.plane));
    h.u64(pd.m as u64);
    h.u64(pd.regions.len() as u64);
    for r in &pd.regions {
        r.iter().for_each(|&v| h.f64(v));
    }
    h.u64(precrack.len() as u64);
    for q in precrack {
        q.iter().for_each(|&v| h.f64(v));
    }
    // only the load that acts: u0 under displacement grips, the traction under the traction
    // grip (the other is hashed as 0, so changing it does not invalidate a checkpoint)
    let traction = if load.grip == Grip::Traction {
        load.traction
    } else {
        0.0
    };
    h.str(load.grip.name());
    h.f64(load.u0);
    h.f64(traction);
    h.u64(sla.fast as u64);
    h.u64(sla.refactor_every as u64);
    // the solver form when forced (nothing is hashed for "auto", so existing fingerprints stay)
    if sla.engine != crate::problem::SlaEngine::Auto {
        h.str(sla.engine.name());
    }
    h.f64(sla.tie_tol);
    h.u64(n_dofs as u64);
    h.u64(n_bonds as u64);
    // general scenes: the holes and the supports and loads on regions (nothing is hashed for
    // the paper's plate, so its fingerprints stay)
    if !d.holes.is_empty() {
        h.str(&format!("{:?}", d.holes));
    }
    // a graded FEM grid (nothing is hashed for the uniform one)
    if pd.fem_grading != 1.0 {
        h.f64(pd.fem_grading);
        h.f64(pd.fem_coarse);
    }
    // the surface correction (nothing is hashed without it)
    if pd.surface_correction != crate::problem::SurfaceCorrection::None {
        h.str(pd.surface_correction.name());
    }
    // the adaptive region's rule (nothing is hashed for a fixed region)
    if let Some(a) = &pd.adaptive {
        h.str("adaptive");
        h.f64(a.margin);
        h.f64(a.size);
    }
    if let crate::problem::Boundary::Regions { supports, loads } = &p.boundary {
        h.str(&format!("{supports:?}{loads:?}"));
    }
    // the critical stretch's rule (nothing is hashed for the default "continuum": the same
    // bonds break under every rule, but the recorded loads differ)
    if pd.s0_calibration != crate::problem::S0Calibration::Continuum {
        h.str(pd.s0_calibration.name());
    }
    h.finish()
}

fn io_err(path: &Path, what: &str, e: std::io::Error) -> Error {
    Error::Io {
        path: path.display().to_string(),
        detail: format!("{what}: {e}"),
    }
}

/// Writes a checkpoint of `steps` atomically (temporary file + rename).
pub(crate) fn write(
    path: &Path,
    fingerprint: u64,
    steps: &[SlaStep],
    switches: &[Switch],
) -> Result<()> {
    let mut buf = Vec::with_capacity(64 + steps.len() * 96);
    buf.extend_from_slice(MAGIC);
    buf.extend_from_slice(&VERSION.to_le_bytes());
    let put = |buf: &mut Vec<u8>, v: u64| buf.extend_from_slice(&v.to_le_bytes());
    put(&mut buf, fingerprint);
    put(&mut buf, steps.len() as u64);
    for s in steps {
        put(&mut buf, s.step as u64);
        for v in [s.lambda, s.sigma22, s.cmod, s.u0, s.crack_length] {
            put(&mut buf, v.to_bits());
        }
        put(&mut buf, s.nodes[0] as u64);
        put(&mut buf, s.nodes[1] as u64);
        for list in [&s.bonds, &s.detached] {
            put(&mut buf, list.len() as u64);
            for &b in list {
                put(&mut buf, b as u64);
            }
        }
        put(&mut buf, s.probes.len() as u64);
        for v in s.probes.iter().flatten() {
            put(&mut buf, v.to_bits());
        }
    }
    put(&mut buf, switches.len() as u64);
    for (step, centres) in switches {
        put(&mut buf, *step as u64);
        put(&mut buf, centres.len() as u64);
        for v in centres.iter().flatten() {
            put(&mut buf, v.to_bits());
        }
    }
    let mut h = Fnv::default();
    h.bytes(&buf);
    put(&mut buf, h.finish());
    refuse_foreign_target(path)?;
    let (tmp, mut file) = exclusive_temporary(path)?;
    let written = file
        .write_all(&buf)
        .and_then(|()| file.sync_all())
        .map_err(|e| io_err(&tmp, "writing the checkpoint", e));
    drop(file);
    let placed = written.and_then(|()| {
        std::fs::rename(&tmp, path)
            .map_err(|e| io_err(path, "renaming the checkpoint into place", e))
    });
    if placed.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    placed?;
    // the rename itself is durable once the directory is synced
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        if let Ok(d) = std::fs::File::open(dir) {
            let _ = d.sync_all();
        }
    }
    Ok(())
}

/// A checkpoint may replace only a checkpoint: an existing `path` that is not a regular file
/// starting with the checkpoint magic is refused (a scene's `pd.checkpoint_path` cannot
/// overwrite other files).
fn refuse_foreign_target(path: &Path) -> Result<()> {
    let Ok(meta) = std::fs::symlink_metadata(path) else {
        return Ok(()); // nothing there yet
    };
    let mut head = [0u8; 8];
    let is_checkpoint = meta.is_file()
        && std::fs::File::open(path)
            .and_then(|mut f| f.read_exact(&mut head))
            .is_ok()
        && &head == MAGIC;
    if is_checkpoint {
        Ok(())
    } else {
        Err(Error::invalid(
            "pd.checkpoint_path",
            "a new file or an existing rustfrac checkpoint (other files are never overwritten)",
            format!(
                "{} (an existing file that is not a checkpoint)",
                path.display()
            ),
        ))
    }
}

/// A new temporary file beside `path`, created exclusively (O_CREAT | O_EXCL: an existing name
/// or a planted symlink is never followed) under an unpredictable name.
fn exclusive_temporary(path: &Path) -> Result<(std::path::PathBuf, std::fs::File)> {
    use std::hash::{BuildHasher, Hasher};
    let name = path
        .file_name()
        .ok_or_else(|| Error::invalid("pd.checkpoint_path", "a file path", path.display()))?;
    let mut last = None;
    for attempt in 0..16u64 {
        // RandomState is seeded from the OS per process and per instance
        let mut h = std::collections::hash_map::RandomState::new().build_hasher();
        h.write_u64(attempt);
        h.write_u32(std::process::id());
        let mut tmp_name = std::ffi::OsString::from(".");
        tmp_name.push(name);
        tmp_name.push(format!(".tmp-{:016x}", h.finish()));
        let tmp = path.with_file_name(tmp_name);
        match std::fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(&tmp)
        {
            Ok(f) => return Ok((tmp, f)),
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => last = Some(e),
            Err(e) => return Err(io_err(&tmp, "creating the checkpoint's temporary file", e)),
        }
    }
    Err(io_err(
        path,
        "creating the checkpoint's temporary file",
        last.expect("16 attempts"),
    ))
}

struct Reader<'a> {
    b: &'a [u8],
    pos: usize,
}

impl Reader<'_> {
    fn u64(&mut self) -> Result<u64> {
        let s = self.b.get(self.pos..self.pos + 8).ok_or_else(|| {
            Error::invalid(
                "pd.resume_from",
                "a complete checkpoint file",
                "a truncated file",
            )
        })?;
        self.pos += 8;
        Ok(u64::from_le_bytes(s.try_into().expect("8 bytes")))
    }
    fn index(&mut self, limit: usize, what: &str) -> Result<usize> {
        let v = self.u64()?;
        if v >= limit as u64 {
            return Err(Error::invalid(
                "pd.resume_from",
                &format!("a checkpoint of this model ({what} < {limit})"),
                format!("{what} {v}"),
            ));
        }
        Ok(v as usize)
    }
}

/// The largest checkpoint of a model with `n_bonds` bonds, `n_nodes` nodes and `n_probes`
/// probes: the header, at most [`crate::problem::schema::MAX_STEPS`] steps of 12 words and two
/// per probe (and two for a region switch), every bond once (and its midpoint once as a
/// switch's) and every node grounded at most twice (one word each).
fn size_limit(n_bonds: usize, n_nodes: usize, n_probes: usize) -> u64 {
    let per_step = 14 + 2 * n_probes as u64;
    let words = per_step * crate::problem::schema::MAX_STEPS as u64
        + 3 * n_bonds as u64
        + 2 * n_nodes as u64;
    36 + 8 * words
}

/// The bytes of the checkpoint at `path`: a regular file (a FIFO, device or directory is refused
/// before it is opened) of at most [`size_limit`] bytes (read with that bound, so a file that
/// grows while it is read cannot exhaust memory).
fn read_bounded(
    path: &Path,
    (n_bonds, n_nodes, n_probes): (usize, usize, usize),
) -> Result<Vec<u8>> {
    let meta = std::fs::metadata(path).map_err(|e| io_err(path, "reading the checkpoint", e))?;
    if !meta.is_file() {
        return Err(Error::invalid(
            "pd.resume_from",
            "a regular checkpoint file",
            format!("{} (not a regular file)", path.display()),
        ));
    }
    let limit = size_limit(n_bonds, n_nodes, n_probes);
    let too_big = |len: u64| {
        Error::invalid(
            "pd.resume_from",
            &format!("a checkpoint of this model: at most {limit} bytes"),
            format!("{} ({len} bytes)", path.display()),
        )
    };
    if meta.len() > limit {
        return Err(too_big(meta.len()));
    }
    let f = std::fs::File::open(path).map_err(|e| io_err(path, "reading the checkpoint", e))?;
    let mut b = Vec::with_capacity(meta.len() as usize);
    f.take(limit + 1)
        .read_to_end(&mut b)
        .map_err(|e| io_err(path, "reading the checkpoint", e))?;
    if b.len() as u64 > limit {
        return Err(too_big(b.len() as u64));
    }
    Ok(b)
}

/// Reads and validates a checkpoint written by [`write()`] for the model with this `fingerprint`
/// (`n_bonds` bonds, `n_nodes` nodes, `n_probes` probes).
pub(crate) fn read(
    path: &Path,
    fingerprint: u64,
    (n_bonds, n_nodes, n_probes): (usize, usize, usize),
) -> Result<(Vec<SlaStep>, Vec<Switch>)> {
    let bad = |what: &str, got: String| Error::invalid("pd.resume_from", what, got);
    let b = read_bounded(path, (n_bonds, n_nodes, n_probes))?;
    if b.len() < 36 || &b[..8] != MAGIC {
        return Err(bad(
            "a rustfrac SLA checkpoint file",
            format!("{} (no checkpoint header)", path.display()),
        ));
    }
    let version = u32::from_le_bytes(b[8..12].try_into().expect("4 bytes"));
    if !(1..=VERSION).contains(&version) {
        return Err(bad(
            &format!("a checkpoint of format version 1..={VERSION}"),
            format!("version {version}"),
        ));
    }
    if version == 1 && n_probes > 0 {
        return Err(bad(
            &format!(
                "a checkpoint recording the scene's {n_probes} probes (format version 2; a \
                 version 1 file resumes only a scene without [[probe]])"
            ),
            "version 1".into(),
        ));
    }
    let (body, tail) = b.split_at(b.len() - 8);
    let mut h = Fnv::default();
    h.bytes(body);
    if h.finish() != u64::from_le_bytes(tail.try_into().expect("8 bytes")) {
        return Err(bad(
            "an intact checkpoint file",
            "a checksum mismatch (corrupt or truncated file)".into(),
        ));
    }
    let mut r = Reader { b: body, pos: 12 };
    let fp = r.u64()?;
    if fp != fingerprint {
        return Err(bad(
            &format!(
                "a checkpoint made for this model and solver (fingerprint {fingerprint:016x}); it \
                 was made for a different plate, grid, horizon, material, load, pre-crack, PD \
                 region or solver option"
            ),
            format!("fingerprint {fp:016x}"),
        ));
    }
    let n = r.u64()? as usize;
    let mut steps = Vec::with_capacity(n.min(body.len() / 96));
    for k in 0..n {
        let step = r.u64()? as usize;
        if step != k + 1 {
            return Err(bad("consecutive steps 1, 2, ...", format!("step {step}")));
        }
        let mut v = [0.0; 5];
        for x in v.iter_mut() {
            *x = f64::from_bits(r.u64()?);
        }
        let nodes = [r.index(n_nodes, "node")?, r.index(n_nodes, "node")?];
        let nb = r.u64()? as usize;
        let bonds = (0..nb)
            .map(|_| r.index(n_bonds, "bond"))
            .collect::<Result<Vec<_>>>()?;
        if bonds.is_empty() {
            return Err(bad("at least one bond per step", format!("step {step}")));
        }
        let mut sorted = bonds.clone();
        sorted.sort_unstable();
        if sorted.windows(2).any(|w| w[0] == w[1]) {
            return Err(bad(
                "every bond of a step once",
                format!("step {step} lists a bond twice"),
            ));
        }
        if !(v.iter().all(|x| x.is_finite()) && v[0] > 0.0) {
            return Err(bad(
                "finite recorded values and a positive load factor",
                format!(
                    "step {step}: lambda {}, sigma22 {}, cmod {}, u0 {}, crack length {}",
                    v[0], v[1], v[2], v[3], v[4]
                ),
            ));
        }
        let nd = r.u64()? as usize;
        let detached = (0..nd)
            .map(|_| r.index(n_nodes, "node"))
            .collect::<Result<Vec<_>>>()?;
        let np = if version == 1 { 0 } else { r.u64()? };
        if np != n_probes as u64 {
            return Err(bad(
                &format!("a checkpoint of a scene with {n_probes} probes"),
                format!("step {step} records {np}"),
            ));
        }
        let mut probes = Vec::with_capacity(n_probes);
        for _ in 0..n_probes {
            let pv = [f64::from_bits(r.u64()?), f64::from_bits(r.u64()?)];
            if !pv.iter().all(|x| x.is_finite()) {
                return Err(bad(
                    "finite recorded probes",
                    format!("step {step}: {pv:?}"),
                ));
            }
            probes.push(pv);
        }
        steps.push(SlaStep {
            step,
            lambda: v[0],
            sigma22: v[1],
            cmod: v[2],
            u0: v[3],
            crack_length: v[4],
            bonds,
            nodes,
            detached,
            probes,
        });
    }
    let mut switches = Vec::new();
    if version >= 3 {
        let ns = r.u64()?;
        let mut last = 0;
        for _ in 0..ns {
            let step = r.u64()? as usize;
            if step <= last || step > n + 1 {
                return Err(bad(
                    &format!("region switches at increasing steps in 1..={}", n + 1),
                    format!("a switch at step {step}"),
                ));
            }
            last = step;
            let nc = r.index(n_bonds + 1, "switch bond count")?;
            let mut centres = Vec::with_capacity(nc);
            for _ in 0..nc {
                let c = [f64::from_bits(r.u64()?), f64::from_bits(r.u64()?)];
                if !c.iter().all(|x| x.is_finite()) {
                    return Err(bad("finite switch midpoints", format!("{c:?}")));
                }
                centres.push(c);
            }
            switches.push((step, centres));
        }
    }
    if r.pos != body.len() {
        return Err(bad(
            "no data after the last step",
            format!("{} extra bytes", body.len() - r.pos),
        ));
    }
    Ok((steps, switches))
}
