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
//! u64 count and u64 values), the probes (a u64 count and two f64 each); then the adaptive
//! region's switches: a u64 count, per switch its first step (u64) and the midpoints of the
//! bonds that grew the region (a u64 count and two f64 each); finally an FNV-1a checksum (u64)
//! of everything before it. The fingerprint hashes the scene's physics and solver keys
//! ([`fingerprint`]; `docs/design.md`, "Checkpoints").
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
use crate::problem::scene_of::scene_of;
use crate::problem::schema::{self, Role, Val};
use crate::problem::Problem;
use std::io::{Read, Write};
use std::path::Path;

const MAGIC: &[u8; 8] = b"RFSLACK\0";
/// Format version of the checkpoint files written and read. Versions 1 to 3 (without the probes,
/// without the region switches, and all three with the earlier model fingerprint, a hand
/// projection of the problem) and 4 (a fingerprint without `pd.model` and `pd.influence`) are
/// refused with a message saying so.
pub const VERSION: u32 = 5;

/// A growth of the adaptive region as a checkpoint stores it: the first step solved on the
/// grown region and the midpoints of the bonds that grew it ([`crate::problem::pd_region`]
/// gives the rectangles again).
pub(crate) type Switch = (usize, Vec<[f64; 2]>);
/// Version of the fingerprint's byte sequence ([`fingerprint`]): 2, the schema's keys.
const FINGERPRINT_SCHEME: u64 = 2;

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
    /// A key's value: its kind, then its numbers (floats by their bits) or its text; lists with
    /// their length.
    pub fn val(&mut self, v: &Val) {
        self.str(v.kind().name());
        match v {
            Val::Float(x) => self.f64(*x),
            Val::Int(i) => self.u64(*i as u64),
            Val::Str(s) => self.str(s),
            Val::Bool(b) => self.u64(u64::from(*b)),
            Val::Pair(q) => q.iter().for_each(|&x| self.f64(x)),
            Val::IntList(l) => {
                self.u64(l.len() as u64);
                l.iter().for_each(|&x| self.u64(x as u64));
            }
            Val::FloatList(l) => {
                self.u64(l.len() as u64);
                l.iter().for_each(|&x| self.f64(x));
            }
            Val::PairList(l) => {
                self.u64(l.len() as u64);
                l.iter().flatten().for_each(|&x| self.f64(x));
            }
        }
    }
    pub fn finish(&self) -> u64 {
        self.0
    }
}

/// Fingerprint of everything that determines an SLA's sequence of floating-point operations and
/// the values its steps record: every physics and solver key of the problem's scene
/// ([`schema::Role`], read through [`scene_of`], so a new key of the table is included), by its
/// scene name (`crack[1].a0`, `hole[0].radius`) and value (floats by their bits), then the built
/// model: the PD rectangles (an adaptive region's start), the pre-crack polyline and the counts
/// of dofs and bonds. Output keys (the step limit, stop length, damage snapshots, checkpoint
/// options, probe names) may change between the runs. FNV-1a of a fixed byte sequence: stable
/// across runs and platforms.
pub fn fingerprint(p: &Problem, precrack: &[[f64; 2]], n_dofs: usize, n_bonds: usize) -> u64 {
    let mut h = Fnv::default();
    h.u64(FINGERPRINT_SCHEME);
    h.str(p.method.name());
    for e in scene_of(p) {
        for spec in schema::section_keys(e.section) {
            if spec.role == Role::Output {
                continue;
            }
            h.str(&e.name);
            h.str(spec.key);
            h.val(&e.values[spec.key]);
        }
    }
    let regions = p.pd().map_or(&[][..], |pd| &pd.regions);
    h.u64(regions.len() as u64);
    for r in regions {
        r.iter().for_each(|&v| h.f64(v));
    }
    h.u64(precrack.len() as u64);
    for q in precrack {
        q.iter().for_each(|&v| h.f64(v));
    }
    h.u64(n_dofs as u64);
    h.u64(n_bonds as u64);
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
    if (1..VERSION).contains(&version) {
        return Err(bad(
            &format!(
                "a checkpoint of format version {VERSION} (versions 1 to {} were written with an \
                 earlier model fingerprint and cannot be matched to this model: run again from \
                 the start)",
                VERSION - 1
            ),
            format!("version {version}"),
        ));
    }
    if version != VERSION {
        return Err(bad(
            &format!("a checkpoint of format version {VERSION}"),
            format!("version {version}"),
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
                 was made for a different one: other values of the scene's physics or solver \
                 keys (plate, material, load, cracks, pd grid and region, holes, supports, \
                 probes' points, engine, tie_tol, refactor_every)"
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
        let np = r.u64()?;
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
    if r.pos != body.len() {
        return Err(bad(
            "no data after the last step",
            format!("{} extra bytes", body.len() - r.pos),
        ));
    }
    Ok((steps, switches))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::problem::parse;
    use crate::problem::scene_of::tests::scenes;
    use crate::problem::value::{Table, Value};
    use std::collections::BTreeSet;

    /// `t` with `key` of the entry `name` (`pd`, `crack`, `crack[1]`, `hole[2]`, `load[1]`)
    /// set to `v`; None when the scene has no such entry.
    fn with(t: &Table, name: &str, key: &str, v: Value) -> Option<Table> {
        let mut t = t.clone();
        let (head, index) = match name.split_once('[') {
            Some((h, rest)) => (h, Some(rest.trim_end_matches(']').parse::<usize>().ok()?)),
            None => (name, None),
        };
        let table = match (t.get_mut(head)?, index) {
            (Value::Table(s), None) => s,
            (Value::List(l), Some(k)) => match l.get_mut(k)? {
                Value::Table(s) => s,
                _ => return None,
            },
            (Value::List(l), None) if head == "crack" => match l.first_mut()? {
                Value::Table(s) => s,
                _ => return None,
            },
            _ => return None,
        };
        table.insert(key.to_string(), v);
        Some(t)
    }

    /// Every physics and solver key is in the fingerprint, every output key out of it: in
    /// scenes that state every key, each key is changed in turn to other values of its range
    /// (the first the scene accepts that changes the problem), and a checkpoint written for
    /// the scene is refused by the changed problem exactly when the key is not an output key.
    /// Every key of the sections a PD scene reads is changed in some scene.
    #[test]
    fn every_physics_and_solver_key_is_fingerprinted() {
        let dir = std::env::temp_dir().join(format!("rustfrac-fingerprint-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let file = dir.join("base.ckpt");
        let fp = |q: &Problem| fingerprint(q, &q.pd_precrack(), 100, 1000);
        let mut changed = BTreeSet::new();
        for scene in scenes() {
            let p = parse::problem(&scene).unwrap();
            write(&file, fp(&p), &[], &[]).unwrap();
            assert!(read(&file, fp(&p), (1000, 1000, p.probes.len())).is_ok());
            for e in scene_of(&p) {
                for spec in schema::section_keys(e.section) {
                    for v in spec.range.others(&e.values[spec.key]) {
                        let Some(t) = with(&scene, &e.name, spec.key, v.to_value()) else {
                            break;
                        };
                        let Ok(q) = parse::problem(&t) else {
                            continue;
                        };
                        if format!("{q:?}") == format!("{p:?}") {
                            continue; // a key this entry does not read (a circle's corners)
                        }
                        changed.insert(spec.param());
                        let refused = read(&file, fp(&q), (1000, 1000, q.probes.len())).is_err();
                        assert_eq!(
                            refused,
                            spec.role != Role::Output,
                            "{}.{} = {} ({})",
                            e.name,
                            spec.key,
                            v.repr(),
                            spec.role.name()
                        );
                        break;
                    }
                }
            }
        }
        let sections = schema::method_sections("ccm_pd").iter().copied();
        let lists = schema::LIST_SECTIONS.iter().map(|(_, s)| *s);
        for sec in sections.chain(lists) {
            for spec in schema::section_keys(sec) {
                assert!(
                    changed.contains(&spec.param()),
                    "{} never changed",
                    spec.param()
                );
            }
        }
        let _ = std::fs::remove_dir_all(&dir);
    }

    /// The case that a hand projection of the problem missed: a checkpoint written with
    /// `pd.hole_volumes = "centre"` does not resume an `"exact"` run.
    #[test]
    fn hole_volumes_are_fingerprinted() {
        let p = parse::problem(&scenes()[0]).unwrap();
        let mut q = p.clone();
        q.pd_mut().hole_volumes = crate::problem::HoleVolumes::Exact;
        let fp = |q: &Problem| fingerprint(q, &q.pd_precrack(), 100, 1000);
        assert_ne!(fp(&p), fp(&q));
    }
}
