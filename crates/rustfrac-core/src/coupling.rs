//! Splice CCM-PD coupling on the paper's plate (section 2.2.2, eq. 58; DESIGN.md sections 3-4).
//!
//! Every node of one uniform `dx` grid is a FEM node or a PD node; PD nodes are those inside the
//! given rectangles (closed, tolerance 1e-9 dx), or all nodes for the pure PD model.
//!
//! * FEM rows: every Q4 element (exact 2 x 2 Gauss stiffness of a dx x dx square) with at least one
//!   FEM node writes the rows of its FEM nodes only (all 8 columns): hybrid elements included.
//! * PD rows: every bond of a PD node (to PD or FEM nodes of its family) writes the rows of its PD
//!   end(s) only. PD rows hold forces (the bond force density times both node volumes), so PD and
//!   FEM rows, reactions and residuals are comparable.
//! * The matrix is not symmetric: it is factorised with the general sparse LU (oracle path) or
//!   condensed onto the PD unknowns ([`crate::sla`]).
//!
//! Pre-crack (a polyline): a bond is broken when its end nodes lie strictly on opposite sides of a
//! crack segment and the crossing point lies on the *closed* segment (the tip counts), decided in
//! grid units with tolerance 1e-9 x bond length; the pre-crack must not pass through a grid node
//! (refused). In the FEM part the crack is a real discontinuity by *removed elements*: every element
//! whose interior the crack cuts is dropped. On the paper's grid the crack x2 = 10.5 lies midway
//! between node rows, so this removes one row of elements (a slit one cell high), which is exactly
//! the set of material the broken PD bonds disconnect: nodes on rows x2 = 10.467 and 10.533 are
//! coupled neither by bonds nor by elements across the crack. (Duplicated nodes would need the
//! crack on a grid line, i.e. a different grid than the paper's.)
//!
//! Loading: the plate's top and bottom edges ([`crate::loading::plate_conditions`]). In the coupled
//! model those are the edge node rows; in the pure PD model the displacement conditions act on
//! volumetric boundary layers of m node rows (thickness m dx = delta) at the top and bottom, the
//! usual choice that gives edge nodes a full family of prescribed neighbours. The u1 anchor of the
//! "free" grip is the bottom-right corner node (reported).

use crate::error::{check_finite, check_positive, Error, Result};
use crate::fem::{element_stiffness, Dirichlet};
use crate::loading::{plate_conditions, tributary_lengths, PlateEdges, PlateLoad};
use crate::material::Elastic;
use crate::pd::{find_bonds, Bond, Grid, PdConstants};
use crate::quadrature::subquad_rule;
use crate::solver::Lu;
use crate::sparse::{CscMatrix, Pattern, Reduction};
use crate::warning::{Warning, WarningKind};

/// Model choice: splice coupling with PD rectangles, or PD everywhere.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Method {
    CcmPd,
    Pd,
}

impl Method {
    /// Parses "ccm_pd" | "pd".
    pub fn parse(s: &str) -> Result<Self> {
        match s {
            "ccm_pd" => Ok(Method::CcmPd),
            "pd" => Ok(Method::Pd),
            _ => Err(Error::invalid("method", "'ccm_pd' or 'pd'", s)),
        }
    }
    pub fn name(&self) -> &'static str {
        match self {
            Method::CcmPd => "ccm_pd",
            Method::Pd => "pd",
        }
    }
}

/// Geometry, material and loading of a coupled (or pure PD) plate model (the paper's values in
/// [`ModelSpec::paper`]).
#[derive(Debug, Clone)]
pub struct ModelSpec {
    /// splice coupling with the PD rectangles, or every node PD (pure PD model with volumetric
    /// boundary layers)
    pub method: Method,
    /// plate width W along x1 (the paper: 11)
    pub width: f64,
    /// plate height L along x2 (the paper: 21)
    pub height: f64,
    /// grid spacing; W / dx and L / dx must be integers (within 1e-6)
    pub dx: f64,
    /// horizon ratio m = delta / dx
    pub m: usize,
    pub material: Elastic,
    /// critical energy release rate G0
    pub g0: f64,
    /// PD rectangles [x0, y0, x1, y1] (ignored by [`Method::Pd`])
    pub pd_regions: Vec<[f64; 4]>,
    /// pre-crack polyline (first point = crack mouth); empty for none
    pub precrack: Vec<[f64; 2]>,
    pub load: PlateLoad,
}

impl ModelSpec {
    /// The paper's benchmark: W = 11, L = 21, dx = 1/15, m = 4, PD rectangle 2.73 x 1.67 centred at
    /// (1.70, 10.5), E = 10000, nu = 0.25, G0 = 0.367, plane strain, h = 1, pre-crack a = 1.1 along
    /// x2 = 10.5, u0 = 0.01, u1 free.
    pub fn paper() -> Self {
        use crate::loading::Grip;
        use crate::material::Plane;
        Self {
            method: Method::CcmPd,
            width: 11.0,
            height: 21.0,
            dx: 1.0 / 15.0,
            m: 4,
            material: Elastic {
                e: 10000.0,
                nu: 0.25,
                plane: Plane::Strain,
                thickness: 1.0,
            },
            g0: 0.367,
            pd_regions: vec![[
                1.70 - 2.73 / 2.0,
                10.5 - 1.67 / 2.0,
                1.70 + 2.73 / 2.0,
                10.5 + 1.67 / 2.0,
            ]],
            precrack: vec![[0.0, 10.5], [1.1, 10.5]],
            load: PlateLoad {
                grip: Grip::Free,
                u0: 0.01,
                traction: 0.0,
            },
        }
    }

    /// Every node PD (the pure PD model)?
    pub fn all_pd(&self) -> bool {
        self.method == Method::Pd
    }
}

/// The assembled description of a coupled model (everything but the matrix values).
pub struct SpliceModel {
    pub spec: ModelSpec,
    pub grid: Grid,
    pub pd: PdConstants,
    pub is_pd: Vec<bool>,
    /// PD node ids, ascending
    pub pd_nodes: Vec<usize>,
    /// FEM elements that contribute (at least one FEM node, not cut by the pre-crack)
    pub elements: Vec<[usize; 4]>,
    /// elements removed because the pre-crack cuts them
    pub n_removed_elements: usize,
    pub bonds: Vec<Bond>,
    /// bonds broken by the pre-crack
    pub precrack_broken: Vec<bool>,
    /// element stiffness (all elements are the same dx x dx square), row-major 8 x 8
    pub ke: Vec<f64>,
    rows_of: Vec<Vec<usize>>,
    cols_of: Vec<Vec<usize>>,
    pattern: Pattern,
    pub edges: PlateEdges,
    pub bc: Dirichlet,
    /// external forces (traction grip)
    pub f: Vec<f64>,
    /// node carrying the u1 = 0 anchor (bottom-right corner)
    pub anchor: usize,
    pub mask: Vec<bool>,
    /// prescribed values (reference load) at constrained dofs, zero elsewhere
    pub prescribed: Vec<f64>,
    /// (node below, node above, unit normal) at the crack mouth, for the CMOD
    pub cmod_nodes: Option<(usize, usize, [f64; 2])>,
    /// bonds of each node (CSR over nodes: `node_bonds[node_bond_ptr[n]..node_bond_ptr[n + 1]]`)
    node_bond_ptr: Vec<usize>,
    node_bonds: Vec<u32>,
    /// accuracy warnings about the discretisation (e.g. m < 2: too few bonds per node)
    pub warnings: Vec<Warning>,
}

/// A grounding spring k p p^T on the free dofs of one PD node, along the unit direction `p`: it
/// removes a direction in which the node's intact bonds give no stiffness (all bonds broken, or
/// all remaining bonds parallel), see [`SpliceModel::null_directions`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Spring {
    pub node: usize,
    pub p: [f64; 2],
}

/// A static solution of the coupled model.
#[derive(Debug, Clone)]
pub struct StaticSolution {
    pub u: Vec<f64>,
    /// K u - f at every dof
    pub reactions: Vec<f64>,
    pub sigma22: f64,
    pub cmod: f64,
    /// sum over all nodes of the external forces (reactions + applied) per component: zero for a
    /// balanced model, small but not zero for the splice coupling
    pub out_of_balance: [f64; 2],
    /// relative residual of the free equations
    pub residual: f64,
}

fn orient(a: [f64; 2], b: [f64; 2], p: [f64; 2]) -> f64 {
    (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0])
}

/// Does the bond p-q cross the segment a-b (grid units)? Strict sides for the nodes, closed segment.
pub fn bond_crosses(p: [f64; 2], q: [f64; 2], a: [f64; 2], b: [f64; 2]) -> bool {
    let lab = ((b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2)).sqrt();
    let lpq = ((q[0] - p[0]).powi(2) + (q[1] - p[1]).powi(2)).sqrt();
    let t1 = 1e-9 * lab;
    let o1 = orient(a, b, p);
    let o2 = orient(a, b, q);
    if !((o1 > t1 && o2 < -t1) || (o1 < -t1 && o2 > t1)) {
        return false;
    }
    let t2 = 1e-9 * lpq;
    let o3 = orient(p, q, a);
    let o4 = orient(p, q, b);
    (o3 <= t2 && o4 >= -t2) || (o3 >= -t2 && o4 <= t2)
}

/// Length of the part of segment a-b inside the open box [x0, x1] x [y0, y1] (Liang-Barsky).
fn clipped_length(a: [f64; 2], b: [f64; 2], bx: [f64; 4]) -> f64 {
    let d = [b[0] - a[0], b[1] - a[1]];
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    let checks = [
        (-d[0], a[0] - bx[0]),
        (d[0], bx[2] - a[0]),
        (-d[1], a[1] - bx[1]),
        (d[1], bx[3] - a[1]),
    ];
    for (p, q) in checks {
        if p == 0.0 {
            if q <= 0.0 {
                return 0.0;
            }
        } else {
            let r = q / p;
            if p < 0.0 {
                t0 = t0.max(r);
            } else {
                t1 = t1.min(r);
            }
        }
    }
    if t1 > t0 {
        (t1 - t0) * (d[0] * d[0] + d[1] * d[1]).sqrt()
    } else {
        0.0
    }
}

pub(crate) fn grid_count(len: f64, dx: f64, name: &str) -> Result<usize> {
    let r = len / dx;
    let n = r.round();
    if !(1.0..=1e7).contains(&n) || (r - n).abs() > 1e-6 * n.max(1.0) {
        return Err(Error::invalid(
            name,
            "a multiple of dx (the grid must fit the plate exactly), at most 1e7 cells",
            format!("{len} / dx = {r}"),
        ));
    }
    Ok(n as usize)
}

impl SpliceModel {
    /// Validates the spec and builds node classes, elements, bonds, pre-crack, pattern and loads.
    pub fn new(spec: &ModelSpec) -> Result<Self> {
        check_positive("width", spec.width)?;
        check_positive("height", spec.height)?;
        check_positive("dx", spec.dx)?;
        let nx = grid_count(spec.width, spec.dx, "width")?;
        let ny = grid_count(spec.height, spec.dx, "height")?;
        let dx = spec.width / nx as f64;
        if ((spec.height / ny as f64) - dx).abs() > 1e-9 * dx {
            return Err(Error::invalid(
                "dx",
                "the same spacing along x1 and x2",
                spec.dx,
            ));
        }
        // the same memory guard as the FEM meshes (a finer PD grid also makes each SLA step slow)
        if (nx + 1) * (ny + 1) > crate::mesh::MAX_ELEMENTS {
            return Err(Error::invalid(
                "dx",
                &format!("at most {} grid nodes", crate::mesh::MAX_ELEMENTS),
                (nx + 1) * (ny + 1),
            ));
        }
        let pd = PdConstants::new(&spec.material, spec.g0, dx, spec.m)?;
        let grid = Grid {
            nx,
            ny,
            dx,
            x0: 0.0,
            y0: 0.0,
        };
        let nn = grid.n_nodes();
        // node classes
        let mut is_pd = vec![spec.all_pd(); nn];
        if spec.all_pd() {
            let two_h = 2.0 * pd.delta;
            for (name, len) in [("width", spec.width), ("height", spec.height)] {
                if len < two_h - 1e-9 * dx {
                    return Err(Error::invalid(
                        name,
                        &format!(
                            "at least two horizons (2 m dx = {two_h:.6}) for the pure PD model"
                        ),
                        len,
                    ));
                }
            }
        }
        let mut warnings = Vec::new();
        if spec.m < 2 {
            warnings.push(Warning::new(
                WarningKind::Discretisation,
                format!(
                "horizon factor m = {}: a bulk node has only {} bonds (m = 2: {}, the paper's m = \
                 4: {}); too few bonds for a peridynamic continuum, expect errors of several \
                 percent in stiffness and fracture (use m >= 2, preferably 3-4)",
                spec.m,
                crate::pd::family_stencil(spec.m).len(),
                crate::pd::family_stencil(2).len(),
                crate::pd::family_stencil(4).len()
            ),
            ));
        }
        if !spec.all_pd() {
            if spec.pd_regions.is_empty() {
                return Err(Error::invalid(
                    "pd_regions",
                    "at least one rectangle [x0, y0, x1, y1] (or the pure PD method)",
                    "none",
                ));
            }
            let tol = 1e-9 * dx;
            for (k, r) in spec.pd_regions.iter().enumerate() {
                if r.iter().any(|v| !v.is_finite())
                    || r[2] <= r[0]
                    || r[3] <= r[1]
                    || r[0] < -tol
                    || r[1] < -tol
                    || r[2] > spec.width + tol
                    || r[3] > spec.height + tol
                {
                    return Err(Error::invalid(
                        &format!("pd_regions[{k}]"),
                        "finite [x0, y0, x1, y1] with x0 < x1, y0 < y1 inside the plate",
                        format!("{r:?}"),
                    ));
                }
                // a region thinner than two horizons has no node with a full family: every node
                // is a boundary node of the PD region and the coupling dominates the solution
                let two_h = 2.0 * pd.delta;
                if r[2] - r[0] < two_h - tol || r[3] - r[1] < two_h - tol {
                    return Err(Error::invalid(
                        &format!("pd_regions[{k}]"),
                        &format!(
                            "a rectangle at least two horizons wide and high (2 m dx = {two_h:.6} \
                             with m = {}, dx = {dx:.6}): x1 - x0 >= {two_h:.6} and \
                             y1 - y0 >= {two_h:.6}",
                            spec.m
                        ),
                        format!("{:.6} x {:.6}", r[2] - r[0], r[3] - r[1]),
                    ));
                }
                for (n, flag) in is_pd.iter_mut().enumerate() {
                    let p = grid.xy(n);
                    if p[0] >= r[0] - tol
                        && p[0] <= r[2] + tol
                        && p[1] >= r[1] - tol
                        && p[1] <= r[3] + tol
                    {
                        *flag = true;
                    }
                }
            }
        }
        let pd_nodes: Vec<usize> = (0..nn).filter(|&n| is_pd[n]).collect();
        if pd_nodes.is_empty() {
            return Err(Error::invalid(
                "pd_regions",
                "rectangles containing at least one grid node",
                format!("{:?}", spec.pd_regions),
            ));
        }
        // pre-crack in grid units
        let crack: Vec<[f64; 2]> = spec
            .precrack
            .iter()
            .map(|p| [p[0] / dx, p[1] / dx])
            .collect();
        if spec.precrack.len() == 1 {
            return Err(Error::invalid(
                "precrack",
                "a polyline of at least 2 points (or none)",
                1,
            ));
        }
        for (k, p) in spec.precrack.iter().enumerate() {
            check_finite(&format!("precrack[{k}][0]"), p[0])?;
            check_finite(&format!("precrack[{k}][1]"), p[1])?;
            let tol = 1e-9 * dx;
            if p[0] < -tol || p[0] > spec.width + tol || p[1] < -tol || p[1] > spec.height + tol {
                return Err(Error::invalid(
                    &format!("precrack[{k}]"),
                    "a point inside the plate",
                    format!("{p:?}"),
                ));
            }
        }
        for s in crack.windows(2) {
            let (a, b) = (s[0], s[1]);
            let l = ((b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2)).sqrt();
            if l < 1e-9 {
                return Err(Error::invalid(
                    "precrack",
                    "segments of positive length",
                    format!("{a:?}"),
                ));
            }
            // no grid node on the segment
            let (i0, i1) = (a[0].min(b[0]).floor() as i64, a[0].max(b[0]).ceil() as i64);
            let (j0, j1) = (a[1].min(b[1]).floor() as i64, a[1].max(b[1]).ceil() as i64);
            for j in j0.max(0)..=j1.min(ny as i64) {
                for i in i0.max(0)..=i1.min(nx as i64) {
                    let p = [i as f64, j as f64];
                    let t = (((p[0] - a[0]) * (b[0] - a[0]) + (p[1] - a[1]) * (b[1] - a[1]))
                        / (l * l))
                        .clamp(0.0, 1.0);
                    let c = [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])];
                    if ((p[0] - c[0]).powi(2) + (p[1] - c[1]).powi(2)).sqrt() < 1e-9 {
                        return Err(Error::invalid(
                            "precrack",
                            "a polyline passing between grid nodes (as the paper's x2 = 10.5)",
                            format!("it passes through node ({}, {})", p[0] * dx, p[1] * dx),
                        ));
                    }
                }
            }
        }
        // elements
        let mut ke = Vec::new();
        let sq = [[0.0, 0.0], [dx, 0.0], [dx, dx], [0.0, dx]];
        element_stiffness(&sq, &spec.material, &subquad_rule(1, 2), &mut ke);
        let mut elements = Vec::new();
        let mut n_removed = 0;
        for j in 0..ny {
            for i in 0..nx {
                let n0 = grid.node(i, j);
                let e = [n0, n0 + 1, n0 + nx + 2, n0 + nx + 1];
                if e.iter().all(|&n| is_pd[n]) {
                    continue;
                }
                let bx = [i as f64, j as f64, i as f64 + 1.0, j as f64 + 1.0];
                if crack
                    .windows(2)
                    .any(|s| clipped_length(s[0], s[1], bx) > 1e-9)
                {
                    n_removed += 1;
                    continue;
                }
                elements.push(e);
            }
        }
        // bonds and pre-crack
        let bonds = find_bonds(&grid, spec.m, &is_pd)?;
        let precrack_broken: Vec<bool> = bonds
            .iter()
            .map(|b| {
                let (pi, pj) = (grid.ij(b.i as usize), grid.ij(b.j as usize));
                let p = [pi.0 as f64, pi.1 as f64];
                let q = [pj.0 as f64, pj.1 as f64];
                crack.windows(2).any(|s| bond_crosses(p, q, s[0], s[1]))
            })
            .collect();
        // blocks and pattern
        let mut rows_of = Vec::with_capacity(elements.len() + bonds.len());
        let mut cols_of = Vec::with_capacity(elements.len() + bonds.len());
        for e in &elements {
            let mut r = Vec::with_capacity(8);
            let mut c = Vec::with_capacity(8);
            for &n in e {
                if !is_pd[n] {
                    r.extend([2 * n, 2 * n + 1]);
                }
                c.extend([2 * n, 2 * n + 1]);
            }
            rows_of.push(r);
            cols_of.push(c);
        }
        for b in &bonds {
            let (i, j) = (b.i as usize, b.j as usize);
            let mut r = vec![2 * i, 2 * i + 1];
            if is_pd[j] {
                r.extend([2 * j, 2 * j + 1]);
            }
            rows_of.push(r);
            cols_of.push(vec![2 * i, 2 * i + 1, 2 * j, 2 * j + 1]);
        }
        let ndof = 2 * nn;
        let pattern = Pattern::new(ndof, &rows_of, &cols_of)?;
        // loading: edge rows (coupled) or volumetric layers of m rows (pure PD)
        let layers = if spec.all_pd() {
            spec.m.min(ny / 2).max(1)
        } else {
            1
        };
        let mut top = Vec::new();
        let mut bottom = Vec::new();
        let mut top_len = Vec::new();
        let mut bottom_len = Vec::new();
        let xs: Vec<f64> = (0..=nx).map(|i| i as f64 * dx).collect();
        let trib = tributary_lengths(&xs);
        for j in (ny + 1 - layers)..=ny {
            for (i, &t) in trib.iter().enumerate() {
                top.push(grid.node(i, j));
                top_len.push(if j == ny { t } else { 0.0 });
            }
        }
        for j in (0..layers).rev() {
            for (i, &t) in trib.iter().enumerate() {
                bottom.push(grid.node(i, j));
                bottom_len.push(if j == 0 { t } else { 0.0 });
            }
        }
        let edges = PlateEdges {
            top,
            bottom,
            top_len,
            bottom_len,
        };
        let (bc, f, anchor) = plate_conditions(&edges, &spec.load, ndof, spec.material.thickness)?;
        let (mask, prescribed) = bc.to_mask(ndof)?;
        // crack-mouth nodes
        let cmod_nodes = if crack.len() >= 2 {
            let (a, b) = (crack[0], crack[1]);
            let l = ((b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2)).sqrt();
            let nrm = [-(b[1] - a[1]) / l, (b[0] - a[0]) / l];
            let mut best = [(f64::INFINITY, usize::MAX); 2];
            let (ic, jc) = (a[0].round() as i64, a[1].round() as i64);
            for j in (jc - 2).max(0)..=(jc + 2).min(ny as i64) {
                for i in (ic - 2).max(0)..=(ic + 2).min(nx as i64) {
                    let p = [i as f64, j as f64];
                    let side = (p[0] - a[0]) * nrm[0] + (p[1] - a[1]) * nrm[1];
                    let d = (p[0] - a[0]).powi(2) + (p[1] - a[1]).powi(2);
                    let k = usize::from(side > 0.0);
                    if d < best[k].0 {
                        best[k] = (d, grid.node(i as usize, j as usize));
                    }
                }
            }
            if best[0].1 != usize::MAX && best[1].1 != usize::MAX {
                Some((best[0].1, best[1].1, nrm))
            } else {
                None
            }
        } else {
            None
        };
        // node -> bonds incidence (both ends)
        let mut node_bond_ptr = vec![0usize; nn + 1];
        for b in &bonds {
            node_bond_ptr[b.i as usize + 1] += 1;
            node_bond_ptr[b.j as usize + 1] += 1;
        }
        for n in 0..nn {
            node_bond_ptr[n + 1] += node_bond_ptr[n];
        }
        let mut fill = node_bond_ptr.clone();
        let mut node_bonds = vec![0u32; node_bond_ptr[nn]];
        for (k, b) in bonds.iter().enumerate() {
            for n in [b.i as usize, b.j as usize] {
                node_bonds[fill[n]] = k as u32;
                fill[n] += 1;
            }
        }
        Ok(Self {
            node_bond_ptr,
            node_bonds,
            warnings,
            spec: spec.clone(),
            grid,
            pd,
            is_pd,
            pd_nodes,
            elements,
            n_removed_elements: n_removed,
            bonds,
            precrack_broken,
            ke,
            rows_of,
            cols_of,
            pattern,
            edges,
            bc,
            f,
            anchor,
            mask,
            prescribed,
            cmod_nodes,
        })
    }

    pub fn n_dofs(&self) -> usize {
        2 * self.grid.n_nodes()
    }

    /// Bond rank-1 data: alpha and the unit vector n; the bond adds alpha a b^T to the matrix with
    /// a = [n at dofs(i); -n at dofs(j) if j is PD] and b = [n at dofs(i); -n at dofs(j)].
    pub fn bond_alpha_n(&self, b: usize) -> (f64, [f64; 2]) {
        let bond = &self.bonds[b];
        let l = bond.length();
        (self.pd.bond_alpha(bond), [bond.xi[0] / l, bond.xi[1] / l])
    }

    /// Bonds of node `n` (indices into `bonds`).
    pub fn bonds_of(&self, n: usize) -> &[u32] {
        &self.node_bonds[self.node_bond_ptr[n]..self.node_bond_ptr[n + 1]]
    }

    /// Stiffness of the grounding springs: the force constant c V^2 / dx of a full
    /// nearest-neighbour bond (eq. 46 with beta = 1), so the spring is of the size of the node's
    /// other matrix entries. Its value never changes a result: it acts only along directions in
    /// which the node has no other stiffness, where the node carries no force.
    pub fn spring_stiffness(&self) -> f64 {
        self.pd.c * self.pd.volume * self.pd.volume / self.pd.dx
    }

    /// The unit directions (0, 1 or 2, orthonormal) of the free dofs of PD node `n` in which its
    /// intact bonds give no stiffness (the null space of sum n n^T over its intact bonds, restricted
    /// to its free dofs), decided exactly on integer grid offsets. Empty for FEM nodes (their
    /// element rows never change) and for fully prescribed nodes. A PD node's rows hold only its
    /// bonds, so such a direction makes the system singular: the SLA grounds it with a
    /// [`Spring`] (the node is *detached* along it; with no external force it carries none).
    pub fn null_directions(&self, n: usize, broken: &[bool]) -> Vec<[f64; 2]> {
        if !self.is_pd[n] {
            return Vec::new();
        }
        let (fx, fy) = (!self.mask[2 * n], !self.mask[2 * n + 1]);
        if !fx && !fy {
            return Vec::new();
        }
        // first intact offset, and whether another one is not parallel to it
        let mut first: Option<(i64, i64)> = None;
        let mut rank2 = false;
        let (mut any_x, mut any_y) = (false, false);
        for &b in self.bonds_of(n) {
            if broken[b as usize] {
                continue;
            }
            let xi = self.bonds[b as usize].xi;
            let o = (
                (xi[0] / self.grid.dx).round() as i64,
                (xi[1] / self.grid.dx).round() as i64,
            );
            any_x |= o.0 != 0;
            any_y |= o.1 != 0;
            match first {
                None => first = Some(o),
                Some(f) => rank2 |= f.0 * o.1 - f.1 * o.0 != 0,
            }
        }
        match (fx, fy) {
            (true, true) => match first {
                None => vec![[1.0, 0.0], [0.0, 1.0]],
                Some(_) if rank2 => Vec::new(),
                Some((a, b)) => {
                    let l = ((a * a + b * b) as f64).sqrt();
                    vec![[-(b as f64) / l, a as f64 / l]]
                }
            },
            (true, false) if !any_x => vec![[1.0, 0.0]],
            (false, true) if !any_y => vec![[0.0, 1.0]],
            _ => Vec::new(),
        }
    }

    /// Is node `n` *held*: a FEM node (its element rows tie it to the mesh), or a node with a
    /// prescribed dof or an applied force? A fragment of PD nodes connected to no held node floats
    /// freely and carries no load (debris, see [`crate::sla`]).
    pub fn is_held(&self, n: usize) -> bool {
        !self.is_pd[n]
            || self.mask[2 * n]
            || self.mask[2 * n + 1]
            || self.f[2 * n] != 0.0
            || self.f[2 * n + 1] != 0.0
    }

    /// The grounding springs a state needs from scratch: for every PD node, its null directions
    /// under `broken` (see [`SpliceModel::null_directions`]).
    pub fn springs_for(&self, broken: &[bool]) -> Vec<Spring> {
        self.pd_nodes
            .iter()
            .flat_map(|&n| {
                self.null_directions(n, broken)
                    .into_iter()
                    .map(move |p| Spring { node: n, p })
            })
            .collect()
    }

    /// [`SpliceModel::assemble`] plus the grounding `springs` (k p p^T on each node's 2 x 2 block,
    /// which the bond blocks always put in the pattern).
    pub fn assemble_with(&self, broken: &[bool], springs: &[Spring]) -> CscMatrix {
        let mut k = self.assemble(broken);
        let ks = self.spring_stiffness();
        for s in springs {
            for (a, &pa) in s.p.iter().enumerate() {
                for (b, &pb) in s.p.iter().enumerate() {
                    let (r, c) = (2 * s.node + a, 2 * s.node + b);
                    let v = ks * pa * pb;
                    if v == 0.0 || self.mask[r] || self.mask[c] {
                        continue;
                    }
                    let rows = &k.row_idx[k.col_ptr[c]..k.col_ptr[c + 1]];
                    if let Some(pos) = rows.iter().position(|&x| x == r) {
                        k.val[k.col_ptr[c] + pos] += v;
                    }
                }
            }
        }
        k
    }

    /// Assembles the splice matrix (PD rows scaled by node volume) with `broken` bonds removed.
    pub fn assemble(&self, broken: &[bool]) -> CscMatrix {
        let ne = self.elements.len();
        self.pattern
            .assemble(&self.rows_of, &self.cols_of, |blk, out| {
                if blk < ne {
                    let e = &self.elements[blk];
                    for (a, &n) in e.iter().enumerate() {
                        if !self.is_pd[n] {
                            out.extend_from_slice(&self.ke[(2 * a) * 8..(2 * a + 1) * 8]);
                            out.extend_from_slice(&self.ke[(2 * a + 1) * 8..(2 * a + 2) * 8]);
                        }
                    }
                } else {
                    let b = blk - ne;
                    let nr = self.rows_of[blk].len();
                    if broken[b] {
                        out.resize(nr * 4, 0.0);
                        return;
                    }
                    let (alpha, n) = self.bond_alpha_n(b);
                    let bvec = [n[0], n[1], -n[0], -n[1]];
                    for r in 0..nr {
                        let ar = alpha * if r < 2 { n[r] } else { -n[r - 2] };
                        for bv in bvec {
                            out.push(ar * bv);
                        }
                    }
                }
            })
    }

    /// sigma22 from the full displacement vector: (sum over top nodes of (K u)_2) / (W h).
    pub fn sigma22_from(&self, ku: &[f64]) -> f64 {
        let fy: f64 = self.edges.top.iter().map(|&n| ku[2 * n + 1]).sum();
        fy / (self.spec.width * self.spec.material.thickness)
    }

    /// Crack-mouth opening (u_above - u_below) . n, zero without a pre-crack.
    pub fn cmod_from(&self, u: &[f64]) -> f64 {
        match self.cmod_nodes {
            Some((lo, hi, n)) => {
                (u[2 * hi] - u[2 * lo]) * n[0] + (u[2 * hi + 1] - u[2 * lo + 1]) * n[1]
            }
            None => 0.0,
        }
    }

    /// Prescribed values at load factor `scale`.
    pub fn prescribed_at(&self, scale: f64) -> Vec<f64> {
        self.prescribed.iter().map(|v| v * scale).collect()
    }

    /// Post-processing of a full displacement vector with the matrix `k` used to compute it.
    pub fn postprocess(&self, k: &CscMatrix, u: Vec<f64>, residual: f64) -> StaticSolution {
        let ku = k.matvec(&u);
        let reactions: Vec<f64> = ku.iter().zip(&self.f).map(|(a, b)| a - b).collect();
        let mut oob = [0.0; 2];
        for (d, v) in ku.iter().enumerate() {
            oob[d % 2] += v;
        }
        StaticSolution {
            sigma22: self.sigma22_from(&ku),
            cmod: self.cmod_from(&u),
            u,
            reactions,
            out_of_balance: oob,
            residual,
        }
    }

    /// Direct solve (general sparse LU) with `broken` bonds removed, at the reference load.
    /// Nodes left without stiffness in some direction by `broken` are grounded there
    /// ([`SpliceModel::springs_for`]).
    pub fn solve(&self, broken: &[bool]) -> Result<StaticSolution> {
        let k = self.assemble_with(broken, &self.springs_for(broken));
        let red = Reduction::new(&k, &self.mask)?;
        let kff = red.reduce(&k);
        let lu = Lu::new(&kff)?;
        solve_with(self, &k, &red, &lu)
    }
}

/// Solve with an existing factorisation of the reduced matrix.
pub fn solve_with(
    model: &SpliceModel,
    k: &CscMatrix,
    red: &Reduction,
    lu: &Lu,
) -> Result<StaticSolution> {
    let rhs = red.rhs(k, &model.f, &model.prescribed);
    let uf = lu.solve(&rhs)?;
    let u = red.expand(&uf, &model.prescribed);
    let ku = k.matvec(&u);
    let (mut rn, mut bn) = (0.0f64, 0.0f64);
    for (i, &d) in red.free.iter().enumerate() {
        rn += (ku[d] - model.f[d]).powi(2);
        bn += rhs[i] * rhs[i];
    }
    let res = if bn > 0.0 {
        (rn / bn).sqrt()
    } else {
        rn.sqrt()
    };
    Ok(model.postprocess(k, u, res))
}
