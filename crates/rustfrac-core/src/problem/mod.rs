//! The problem description: one value that every driver (FEM, XFEM, PD, CCM-PD) reads.
//!
//! A [`Problem`] states the domain, the material, the boundary conditions, the cracks and the
//! method with its options, each once. It is read from a scene tree ([`value::Value`], what the
//! Python package or a TOML file gives) by [`Problem::from_scene`], which applies every rule of
//! [`schema`] (kinds, ranges, defaults) and the cross-parameter checks of [`validate`] before
//! anything is built; an error names the scene key it refuses (`Error::InvalidInput { param:
//! "pd.dx", .. }`).
//!
//! Extension points for the general scenes (holes and notches, boundary conditions on regions,
//! point loads, probes): [`Domain`] gains hole and notch lists (level sets on the structured
//! grid), [`Boundary`] a variant of region supports and loads, both read from new scene tables;
//! the drivers match on them. Today they hold the paper's plate: the rectangle [0, W] x [0, L]
//! loaded through its top and bottom edges (eq. 61).

pub mod fit;
pub mod general;
pub mod grading;
pub mod grid;
pub mod grips;
pub mod key_value;
pub mod kink_rule;
pub mod material;
pub mod number;
pub mod parse;
pub mod pd_model;
pub mod pd_region;
pub mod range;
mod read;
#[cfg(test)]
mod refusals_test;
pub mod regions;
pub mod s0_calibration;
pub mod scene_of;
pub mod schema;
pub mod side;
pub mod validate;
pub mod value;

use std::path::PathBuf;

pub use grid::{FeGrid, MAX_ELEMENTS};
pub use grips::{Grip, PlateLoad};
pub use kink_rule::KinkRule;
pub use material::{Elastic, Plane};
pub use pd_model::{Influence, PdModel};
pub use regions::{Hole, LoadKind, Probe, ProbeKind, Region, RegionLoad, Shape, Support};
pub use s0_calibration::{Calibration, S0Calibration};
pub use side::Side;

/// The material: isotropic linear elasticity and the fracture energy.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Material {
    pub elastic: Elastic,
    /// critical energy release rate G0 (force / length)
    pub g0: f64,
}

/// The body: the rectangle [0, width] x [0, height] less its holes and notches (a fictitious
/// domain on the structured grid: level sets, cut elements integrated over their material part).
#[derive(Debug, Clone, PartialEq)]
pub struct Domain {
    pub width: f64,
    pub height: f64,
    /// holes and notches (`[[hole]]`, `[[notch]]`), in scene order: holes first
    pub holes: Vec<Hole>,
}

impl Domain {
    /// The plain rectangle [0, width] x [0, height].
    pub fn rect(width: f64, height: f64) -> Self {
        Self {
            width,
            height,
            holes: Vec::new(),
        }
    }

    /// The domain's level set: positive in the material, negative in a hole (the smallest of the
    /// holes' signed distances; +inf without holes). The plate's outer edges are not part of it.
    pub fn level_set(&self, p: [f64; 2]) -> f64 {
        self.holes
            .iter()
            .map(|h| h.shape.level_set(p))
            .fold(f64::INFINITY, f64::min)
    }

    /// A point on or inside a hole or notch (level set within 1e-9 x the plate's diagonal): a
    /// crack end there is a mouth, not a tip.
    pub fn on_or_in_hole(&self, p: [f64; 2]) -> bool {
        self.level_set(p) <= 1e-9 * self.width.hypot(self.height)
    }
}

/// Boundary conditions, all proportional to one load factor (growth and the SLA scale it).
#[derive(Debug, Clone, PartialEq)]
pub enum Boundary {
    /// the paper's grips on the top and bottom edges (eq. 61; [`PlateLoad`])
    Grips(PlateLoad),
    /// supports and loads on regions (`[[support]]`, `[[load]]`; [`crate::fe::regions`])
    Regions {
        supports: Vec<Support>,
        loads: Vec<RegionLoad>,
    },
}

impl Boundary {
    /// The plate load of [`Boundary::Grips`] (None for regions); traction grips prescribe no
    /// displacement, so their `u0` is 0 (the histories' `u0` column is then 0).
    pub fn grips(&self) -> Option<PlateLoad> {
        match self {
            Boundary::Grips(l) if l.grip == Grip::Traction => Some(PlateLoad { u0: 0.0, ..*l }),
            Boundary::Grips(l) => Some(*l),
            Boundary::Regions { .. } => None,
        }
    }

    /// The plate load of a problem with grips; for regions, a zero traction load (drivers that
    /// read it are only reached with grips: [`validate::problem`] refuses regions elsewhere).
    pub fn plate_load(&self) -> PlateLoad {
        self.grips().unwrap_or(PlateLoad {
            grip: Grip::Traction,
            u0: 0.0,
            traction: 0.0,
        })
    }

    /// The work-conjugate pair (a, b) of the histories' load columns: the load's work at a state
    /// is 1/2 (a sigma22)(b u0), so the energy released between states follows from the load
    /// path alone (`rustfrac.energy`). Grips u2 = +-u0 on the top and bottom edges: a = W t (the
    /// top edge's force over sigma22), b = 2 (the edges' relative displacement over u0). None
    /// where the history has no conjugate displacement (traction grips: u0 = 0) or the pair is
    /// not exact for every scene (supports and loads on regions).
    pub fn work_conjugate(&self, width: f64, thickness: f64) -> Option<[f64; 2]> {
        match self {
            Boundary::Grips(l) if l.grip != Grip::Traction => Some([width * thickness, 2.0]),
            _ => None,
        }
    }

    /// The stable name of the conditions: the grip ("free", "clamped", "traction") or "regions".
    pub fn name(&self) -> &'static str {
        match self.grips() {
            Some(l) => l.grip.name(),
            None => "regions",
        }
    }

    /// One line saying which conditions ran (results carry it).
    pub fn description(&self) -> &'static str {
        let Some(load) = self.grips() else {
            return "supports and loads on regions ([[support]], [[load]])";
        };
        match load.grip {
            Grip::Free => "u2 = +-u0 on top/bottom, u1 free (u1 = 0 at the anchor node only)",
            Grip::Clamped => "u2 = +-u0 and u1 = 0 on top/bottom (clamped grips)",
            Grip::Traction => {
                "uniform normal traction on top/bottom (u1, u2 = 0 at the anchor node, u1 = 0 at \
                 the top-right corner)"
            }
        }
    }
}

/// How a crack is represented.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CrackKind {
    /// FEM: duplicated nodes along the grid line nearest `y`, from x1 = 0 to `a0`
    Seam,
    /// a crack from an edge (XFEM level set; PD pre-broken bonds)
    Edge,
    /// an interior crack (XFEM)
    Center,
}

impl CrackKind {
    /// The scene's spelling (`crack.kind`).
    pub fn name(&self) -> &'static str {
        match self {
            CrackKind::Seam => "seam",
            CrackKind::Edge => "edge",
            CrackKind::Center => "center",
        }
    }
}

/// One straight crack as the scene states it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CrackSpec {
    pub kind: CrackKind,
    /// length (half-length of a centre crack)
    pub a0: f64,
    /// x2 of the mouth (left/right sides) or of the centre
    pub y: f64,
    /// degrees, counter-clockwise from x1 (centre) or from the side's inward normal (edge)
    pub angle: f64,
    /// x1 of the centre, or of the mouth on the bottom/top sides
    pub x: f64,
    /// the side an edge crack starts from
    pub side: Side,
}

impl CrackSpec {
    /// The crack as two points: (mouth, tip) for edge cracks and seams, (tip, tip) for centre
    /// cracks.
    pub fn polyline(&self, d: &Domain) -> Vec<[f64; 2]> {
        let t = self.angle.to_radians();
        let (c, s) = (t.cos(), t.sin());
        match self.kind {
            CrackKind::Center => vec![
                [self.x - self.a0 * c, self.y - self.a0 * s],
                [self.x + self.a0 * c, self.y + self.a0 * s],
            ],
            CrackKind::Seam => vec![[0.0, self.y], [self.a0, self.y]],
            CrackKind::Edge => {
                let (mouth, n) = match self.side {
                    Side::Left => ([0.0, self.y], [1.0, 0.0]),
                    Side::Right => ([d.width, self.y], [-1.0, 0.0]),
                    Side::Bottom => ([self.x, 0.0], [0.0, 1.0]),
                    Side::Top => ([self.x, d.height], [0.0, -1.0]),
                };
                let dir = [n[0] * c - n[1] * s, n[0] * s + n[1] * c];
                vec![
                    mouth,
                    [mouth[0] + self.a0 * dir[0], mouth[1] + self.a0 * dir[1]],
                ]
            }
        }
    }

    /// The crack's tips: the end of an edge crack or seam; both ends of a centre crack except an
    /// end on or inside a hole or notch, which is a mouth (a crack from a hole's boundary, as
    /// [`crate::xfem::Crack::named_in`] reads it).
    pub fn tips(&self, d: &Domain) -> Vec<[f64; 2]> {
        let line = self.polyline(d);
        match self.kind {
            CrackKind::Center => line.into_iter().filter(|&q| !d.on_or_in_hole(q)).collect(),
            _ => vec![line[line.len() - 1]],
        }
    }
}

/// Discretisation options of the XFEM model (enrichment and integration; the model-level API
/// `XfemModel` takes them too). Defaults and ranges are the scene's ([`schema`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct XfemOptions {
    /// sub-quads per direction in split and branch-enriched elements (eq. 35); paper: 4
    pub nsub: usize,
    /// sub-quads per direction in tip elements (>= nsub); default: nsub
    pub tip_nsub: usize,
    /// fixed-area tip enrichment radius (Laborde et al. 2005); None = tip element nodes only
    pub fixed_area_radius: Option<f64>,
    /// small-area rule threshold, 0 <= t < 0.5 (0 disables the rule except for exactly zero areas)
    pub area_threshold: f64,
}

impl Default for XfemOptions {
    /// The scene's defaults (the paper's: 4 x 4 sub-quads, the small-area threshold 1e-4).
    fn default() -> Self {
        let d = |key: &str| schema::spec("xfem", key).map_or(0.0, |s| s.default.f());
        let nsub = d("nsub") as usize;
        Self {
            nsub,
            tip_nsub: nsub,
            fixed_area_radius: None,
            area_threshold: d("area_threshold"),
        }
    }
}

/// Plain Q4 FEM.
#[derive(Debug, Clone, PartialEq)]
pub struct FemMethod {
    pub grid: FeGrid,
    /// Gauss points per direction
    pub gauss: usize,
    /// compute the condition estimate of the solve (2 extra solves)
    pub condition: bool,
}

/// LEFM growth of the XFEM model.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Growth {
    /// most growth steps (critical states)
    pub max_steps: usize,
    /// extension per step; None = one element length
    pub da: Option<f64>,
    /// stop once a crack length would exceed this
    pub a_stop: f64,
    /// the direction rule of each extension (`xfem.kink_rule`)
    pub kink_rule: KinkRule,
    /// keep the whole plate's state of every this many growth steps and of the last one
    /// (`xfem.state_every`; 0: none; [`crate::xfem::GrowthState`])
    pub state_every: usize,
}

/// XFEM (section 2.1).
#[derive(Debug, Clone, PartialEq)]
pub struct XfemMethod {
    pub grid: FeGrid,
    /// enrichment and integration options
    pub options: XfemOptions,
    /// r_I in tip-element lengths
    pub r_i: f64,
    /// further radii (tip-element lengths) at which the SIFs are reported
    pub extra_radii: Vec<f64>,
    pub growth: Option<Growth>,
    /// tips within this relative tolerance of the smallest critical load factor grow together
    pub tip_tie_tol: f64,
    /// compute the condition estimate of every solve (2 extra solves each)
    pub condition: bool,
}

/// Peridynamics: the grid, horizon, PD region and the sequentially linear analysis.
#[derive(Debug, Clone, PartialEq)]
pub struct PdMethod {
    /// grid spacing
    pub dx: f64,
    /// horizon factor m = delta / dx
    pub m: usize,
    /// CCM-PD: the PD rectangles [x0, y0, x1, y1] (a scene states one, by `pd.center` and
    /// `pd.size`); pure PD: none (the whole plate)
    pub regions: Vec<[f64; 4]>,
    /// CCM-PD with `pd.region = "adaptive"`: `regions` is where the run starts and grows by
    /// this rule ([`pd_region`]); None: the rectangles stay fixed
    pub adaptive: Option<AdaptiveRegion>,
    /// CCM-PD: ratio of neighbouring FEM element sizes away from the PD rectangles (1: one
    /// uniform dx grid, the paper's; > 1: a graded FEM grid, `pd::splice::graded`)
    pub fem_grading: f64,
    /// CCM-PD graded grid: the largest FEM element size, in units of dx
    pub fem_coarse: f64,
    pub sla: SlaParams,
    /// the volume of a node whose cell a hole cuts (`pd.hole_volumes`, [`HoleVolumes`])
    pub hole_volumes: HoleVolumes,
    /// the PD surface correction (`pd.surface_correction`, [`SurfaceCorrection`])
    pub surface_correction: SurfaceCorrection,
    /// the critical stretch's rule (`pd.s0_calibration`, [`crate::pd::calibration`])
    pub s0_calibration: S0Calibration,
    /// the constitutive model (`pd.model`, [`PdModel`]; [`crate::pd::lps`] for the LPS)
    pub model: PdModel,
    /// the LPS influence function (`pd.influence`, [`Influence`])
    pub influence: Influence,
}

/// Options of the adaptive region (scene keys `pd.adapt_margin`, `pd.adapt_size`; in horizons).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AdaptiveRegion {
    /// no bond breaks within this many horizons of a FEM node (the trigger distance)
    pub margin: f64,
    /// half-side of the squares the region starts with and grows by, in horizons
    pub size: f64,
}

/// The PD surface correction (scene key `pd.surface_correction`,
/// [`schema::SURFACE_CORRECTIONS`]; [`crate::pd::surface_correction`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum SurfaceCorrection {
    /// the paper's bonds: one micromodulus c for every bond
    #[default]
    None,
    /// the energy method (Le & Bobaru 2018; Madenci & Oterkus 2014, section 4.2)
    Energy,
}

impl SurfaceCorrection {
    /// From the scene key's value (None: not one of [`schema::SURFACE_CORRECTIONS`]).
    pub fn from_name(s: &str) -> Option<Self> {
        [Self::None, Self::Energy]
            .into_iter()
            .find(|c| c.name() == s)
    }
    /// The scene key's value.
    pub fn name(self) -> &'static str {
        schema::SURFACE_CORRECTIONS[self as usize]
    }
}

/// The volume of a PD node whose cell a hole or notch cuts (scene key `pd.hole_volumes`;
/// `pd::splice::holes`). In both, a node is material iff its cell centre is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum HoleVolumes {
    /// the centre rule: every material node keeps its full cell volume dx^2 t
    #[default]
    Centre,
    /// the material part of its cell (exact for circles and rectangles, sub-sampled otherwise)
    Exact,
}

impl HoleVolumes {
    /// From the scene key's value (None: not one of [`schema::HOLE_VOLUMES`]).
    pub fn from_name(s: &str) -> Option<Self> {
        [Self::Centre, Self::Exact]
            .into_iter()
            .find(|h| h.name() == s)
    }
    /// The scene key's value.
    pub fn name(self) -> &'static str {
        schema::HOLE_VOLUMES[self as usize]
    }
}

/// The SLA solver (scene key `pd.engine`, whose names are [`schema::SLA_ENGINES`] in this
/// order; `pd.fast = false` is another name of `Oracle`, [`schema::sla_engine`];
/// `crate::pd::sla`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SlaEngine {
    /// the cheaper of dense and sparse by the cost model
    Auto,
    /// condensed PD system, dense inverse
    Dense,
    /// condensed PD system, sparse factor
    Sparse,
    /// refactorise every step
    Oracle,
}

impl SlaEngine {
    const ALL: [SlaEngine; 4] = [Self::Auto, Self::Dense, Self::Sparse, Self::Oracle];
    /// From the scene key's value (None: not one of [`schema::SLA_ENGINES`]).
    pub fn from_name(s: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|e| e.name() == s)
    }
    /// The scene key's value.
    pub fn name(self) -> &'static str {
        schema::SLA_ENGINES[self as usize]
    }
}

/// Options of the sequentially linear analysis (paper section 3). Defaults and ranges are the
/// scene's `[pd]` keys ([`schema`]); a hand-built problem meets them in [`validate::problem`].
#[derive(Debug, Clone, PartialEq)]
pub struct SlaParams {
    /// number of SLA steps (bond-break events); 0 = only the reference solution (`pd.sla_steps`)
    pub max_steps: usize,
    /// stop when the crack (pre-crack + broken bonds, along the pre-crack direction) reaches this
    pub stop_crack_length: Option<f64>,
    /// break together every bond with load factor <= lambda (1 + tie_tol); 0 = one bond per step
    pub tie_tol: f64,
    /// fast solver: re-condense after this many low-rank updates (0 = automatic,
    /// [`crate::pd::cost::auto_refactor_every`])
    pub refactor_every: usize,
    /// the solver (`pd.engine`; a scene's `pd.fast = false` is [`SlaEngine::Oracle`])
    pub engine: SlaEngine,
    /// steps after which the damage field is stored (besides the final one)
    pub damage_at_steps: Vec<usize>,
    /// write a checkpoint to `checkpoint_path` after every this many steps (0 = never); a
    /// cancelled run writes one too
    pub checkpoint_every: usize,
    /// checkpoint file (written atomically: a temporary file in the same directory, then renamed)
    pub checkpoint_path: Option<PathBuf>,
    /// resume from this checkpoint: the model is rebuilt, the checkpoint's steps are replayed
    /// exactly (same low-rank updates in the same order) and the run continues; the history is the
    /// same bit for bit as an uninterrupted run's
    pub resume_from: Option<PathBuf>,
}

impl Default for SlaParams {
    /// The scene's defaults (the paper's 500 steps, one bond per step, the fast solver).
    fn default() -> Self {
        let d = |key: &str| schema::spec("pd", key).expect("a pd key").default.clone();
        Self {
            max_steps: d("sla_steps").i() as usize,
            stop_crack_length: None,
            tie_tol: d("tie_tol").f(),
            refactor_every: d("refactor_every").i() as usize,
            engine: SlaEngine::from_name(d("engine").s()).expect("an engine name"),
            damage_at_steps: Vec::new(),
            checkpoint_every: d("checkpoint_every").i() as usize,
            checkpoint_path: None,
            resume_from: None,
        }
    }
}

/// The method and its options.
#[derive(Debug, Clone, PartialEq)]
pub enum Method {
    Fem(FemMethod),
    Xfem(XfemMethod),
    /// bond-based PD on the whole plate (volumetric boundary layers)
    Pd(PdMethod),
    /// splice CCM-PD coupling: PD in the region, Q4 FEM elsewhere
    CcmPd(PdMethod),
}

impl Method {
    /// Stable name: "fem" | "xfem" | "pd" | "ccm_pd".
    pub fn name(&self) -> &'static str {
        match self {
            Method::Fem(_) => "fem",
            Method::Xfem(_) => "xfem",
            Method::Pd(_) => PdVariant::Pd.name(),
            Method::CcmPd(_) => PdVariant::CcmPd.name(),
        }
    }

    /// Which of the two PD methods this is (None: FEM or XFEM).
    pub fn pd_variant(&self) -> Option<PdVariant> {
        match self {
            Method::Pd(_) => Some(PdVariant::Pd),
            Method::CcmPd(_) => Some(PdVariant::CcmPd),
            Method::Fem(_) | Method::Xfem(_) => None,
        }
    }
}

/// The two PD methods without their options (a PD result's method).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PdVariant {
    /// bond-based PD on the whole plate
    Pd,
    /// the splice CCM-PD coupling
    CcmPd,
}

impl PdVariant {
    /// Stable name: "pd" | "ccm_pd" (the method's, [`Method::name`]).
    pub fn name(self) -> &'static str {
        match self {
            PdVariant::Pd => "pd",
            PdVariant::CcmPd => "ccm_pd",
        }
    }
}

/// One complete, validated description of a run.
#[derive(Debug, Clone)]
pub struct Problem {
    /// optional label
    pub name: String,
    pub domain: Domain,
    pub material: Material,
    pub boundary: Boundary,
    /// the cracks (empty: uncracked); the first is the primary crack (CMOD, history `a`)
    pub cracks: Vec<CrackSpec>,
    /// named responses (`[[probe]]`)
    pub probes: Vec<Probe>,
    pub method: Method,
}

impl Problem {
    /// The same problem under other grips (the reference load stays).
    pub fn with_grip(mut self, grip: Grip) -> Self {
        self.load_mut().grip = grip;
        self
    }

    /// The grips' load (grip, reference displacement, reference traction).
    pub fn load_mut(&mut self) -> &mut PlateLoad {
        match &mut self.boundary {
            Boundary::Grips(l) => l,
            Boundary::Regions { .. } => panic!("load_mut on a problem with regions"),
        }
    }

    /// The FEM options (panics for another method: a programming error).
    pub fn fem_mut(&mut self) -> &mut FemMethod {
        match &mut self.method {
            Method::Fem(m) => m,
            m => panic!("fem_mut on a {} problem", m.name()),
        }
    }

    /// The XFEM options (panics for another method: a programming error).
    pub fn xfem_mut(&mut self) -> &mut XfemMethod {
        match &mut self.method {
            Method::Xfem(m) => m,
            m => panic!("xfem_mut on a {} problem", m.name()),
        }
    }

    /// The PD options of "pd" and "ccm_pd" (None for another method).
    pub fn pd(&self) -> Option<&PdMethod> {
        match &self.method {
            Method::Pd(m) | Method::CcmPd(m) => Some(m),
            _ => None,
        }
    }

    /// The PD pre-crack: the polyline of the first crack, empty for none: (mouth, tip) of an
    /// edge crack, (tip, centre, tip) of a centre crack (its middle vertex is where the CMOD is
    /// read, [`Problem::pd_mouth_vertex`]).
    pub fn pd_precrack(&self) -> Vec<[f64; 2]> {
        let Some(c) = self.cracks.first() else {
            return Vec::new();
        };
        let line = c.polyline(&self.domain);
        match c.kind {
            CrackKind::Center => {
                let mid = [c.x, c.y];
                vec![line[0], mid, line[1]]
            }
            _ => line,
        }
    }

    /// The vertex of [`Problem::pd_precrack`] where the crack-mouth opening is read: 0 (the
    /// mouth) for edge cracks, 1 (the centre) for centre cracks.
    pub fn pd_mouth_vertex(&self) -> usize {
        match self.cracks.first() {
            Some(c) if c.kind == CrackKind::Center => 1,
            _ => 0,
        }
    }

    /// The FEM or XFEM grid (None for the PD methods).
    pub fn fe_grid(&self) -> Option<&FeGrid> {
        match &self.method {
            Method::Fem(f) => Some(&f.grid),
            Method::Xfem(x) => Some(&x.grid),
            Method::Pd(_) | Method::CcmPd(_) => None,
        }
    }

    /// The PD options of "pd" and "ccm_pd" (panics for another method: a programming error).
    pub fn pd_mut(&mut self) -> &mut PdMethod {
        match &mut self.method {
            Method::Pd(m) | Method::CcmPd(m) => m,
            m => panic!("pd_mut on a {} problem", m.name()),
        }
    }

    /// Whether FEM and XFEM solves compute their condition estimate (2 extra solves each; a
    /// run option, not part of the scene).
    pub fn set_condition(&mut self, on: bool) {
        match &mut self.method {
            Method::Fem(m) => m.condition = on,
            Method::Xfem(m) => m.condition = on,
            _ => {}
        }
    }

    /// XFEM growth: the number of steps the primary crack needs to reach `a_stop` with the
    /// step's extension (`da`, or one element chord along the crack), at most `max_steps`: the
    /// total that progress reports count to.
    pub fn growth_steps_estimate(&self) -> Option<usize> {
        let Method::Xfem(x) = &self.method else {
            return None;
        };
        let g = x.growth?;
        let c = self.cracks.first()?;
        let line = c.polyline(&self.domain);
        let (d0, d1) = (line[1][0] - line[0][0], line[1][1] - line[0][1]);
        let len = d0.hypot(d1);
        // the spacing of the grid cell holding the tip (graded grids: the fine one)
        let tip = line[line.len() - 1];
        let cell = |lines: &[f64], len: f64, n: usize, v: f64| {
            if lines.len() < 2 {
                return len / n as f64;
            }
            let k = lines.partition_point(|&l| l <= v).clamp(1, lines.len() - 1);
            lines[k] - lines[k - 1]
        };
        let (hx, hy) = (
            cell(&x.grid.xs, self.domain.width, x.grid.nx, tip[0]),
            cell(&x.grid.ys, self.domain.height, x.grid.ny, tip[1]),
        );
        let chord = |h: f64, d: f64| {
            if (d / len).abs() > 1e-12 {
                h / (d / len).abs()
            } else {
                f64::INFINITY
            }
        };
        let da = g.da.unwrap_or_else(|| chord(hx, d0).min(chord(hy, d1)));
        let n = ((g.a_stop - c.a0) / da + 1e-9).floor().max(0.0) as usize + 1;
        Some(n.clamp(1, g.max_steps))
    }

    /// The crack polylines.
    pub fn crack_polylines(&self) -> Vec<Vec<[f64; 2]>> {
        self.cracks
            .iter()
            .map(|c| c.polyline(&self.domain))
            .collect()
    }
}
