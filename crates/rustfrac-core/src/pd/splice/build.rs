//! [`SpliceModel::new`] in named phases: the grid and the PD constants, the node classes (PD
//! rectangles or pure PD), the pre-crack (`precrack.rs`), the hybrid elements, the bonds, the
//! blocks of the matrix pattern, the loading (`boundary.rs`), the crack-mouth nodes, the
//! node -> bonds incidence and the surface correction's bond factors
//! ([`crate::pd::surface_correction`]). The problem's rules are checked first
//! ([`validate::problem`]).

use super::boundary::loading;
use super::graded;
use super::holes;
use super::precrack;
use super::{ElementStiffness, SpliceModel};
use crate::error::{Error, Result};
use crate::fe::fictitious::{ElementKind, FictitiousDomain};
use crate::fe::q4::element_stiffness;
use crate::fe::quadrature::{subquad_rule, QPoint};
use crate::la::Pattern;
use crate::memory;
use crate::pd::cost::{factor_nnz_guess, CostEstimate};
use crate::pd::lps::{LpsConstants, LpsModel};
use crate::pd::surface_correction::energy_factors;
use crate::pd::{
    family_stencil, find_bonds, find_bonds_where, Bond, Grid, PdConstants, BYTES_PER_BOND,
};
use crate::problem::{validate, Method, PdMethod, Problem, S0Calibration, SurfaceCorrection};
use crate::problem::{Calibration, PdModel};
use crate::warning::{Warning, WarningKind};

impl SpliceModel {
    /// The model of a PD or CCM-PD problem (its rules checked first, [`validate::problem`]),
    /// pre-cracked by the problem's edge crack ([`Problem::pd_precrack`]), its critical stretch
    /// scaled by `s0`, the calibration of the scene's `pd.s0_calibration` (made above the SLA,
    /// `crate::pd::analysis`, since its `"sla"` rule runs an SLA; an error if its rule is not
    /// the scene's).
    pub fn new(p: &Problem, s0: Calibration) -> Result<Self> {
        Self::build(p, p.pd_precrack(), p.pd_mouth_vertex(), s0)
    }

    /// [`SpliceModel::new`] with another pre-crack: any polyline (plate coordinates, mouth first;
    /// validated here: inside the plate, passing between grid nodes), e.g. a closed loop.
    pub fn with_precrack(p: &Problem, precrack: Vec<[f64; 2]>, s0: Calibration) -> Result<Self> {
        Self::build(p, precrack, 0, s0)
    }

    /// The model with `precrack`, its CMOD read at vertex `mouth` of the polyline.
    fn build(p: &Problem, precrack: Vec<[f64; 2]>, mouth: usize, s0: Calibration) -> Result<Self> {
        validate::problem(p)?;
        let Some(pm) = p.pd() else {
            return Err(Error::invalid(
                "method",
                "'pd' or 'ccm_pd' for the splice model",
                format!("'{}'", p.method.name()),
            ));
        };
        let all_pd = matches!(p.method, Method::Pd(_));
        let (grid, pd) = grid_and_constants(p, pm, s0)?;
        let mut material = holes::material_nodes(&p.domain, &grid);
        let (is_pd, pd_nodes, warnings) = node_classes(pm, &grid, &material)?;
        let fd = holes::fem_domain(&p.domain, &grid, &pm.regions, all_pd)?;
        if let Some(fd) = &fd {
            holes::fem_material(&p.domain, &grid, fd, &is_pd, &pm.regions, &mut material);
        }
        memory::check(
            &format!(
                "the {} model ({} grid nodes, {} PD nodes, m = {})",
                p.method.name(),
                grid.n_nodes(),
                pd_nodes.len(),
                pm.m
            ),
            memory_estimate(grid.n_nodes(), pd_nodes.len(), pm.m),
        )?;
        let crack = precrack::in_grid_units(&precrack, &p.domain, &grid)?;
        let ke = element_matrix(p, [grid.dx; 2], None);
        let fem = FemPart {
            grid: &grid,
            is_pd: &is_pd,
            material: &material,
            fd: fd.as_ref(),
        };
        let (elements, n_removed, own_ke) = fem.elements(p, &crack)?;
        let bonds = if p.domain.holes.is_empty() {
            find_bonds(&grid, pm.m, &is_pd)?
        } else {
            let exists = |a, b| holes::bond_exists(&p.domain, &grid, &material, a, b);
            let mut bonds = find_bonds_where(&grid, pm.m, &is_pd, &exists)?;
            let rule = (pm.hole_volumes, pm.regions.as_slice(), all_pd);
            holes::apply_hole_volumes(&p.domain, &grid, rule, &mut bonds);
            bonds
        };
        graded::check_families(&grid, &bonds)?;
        let precrack_broken = precrack::broken_bonds(&crack, &grid, &bonds);
        let (rows_of, cols_of, pattern) = blocks(&grid, &elements, &bonds, &is_pd)?;
        let layers = if all_pd { pm.m } else { 1 };
        let lo = loading(p, layers, &grid, &material)?;
        let cmod_nodes = precrack::mouth_nodes(&crack, mouth, &grid);
        let (node_bond_ptr, node_bonds) = crate::pd::bonds::incidence(grid.n_nodes(), &bonds);
        let surface = match pm.surface_correction {
            SurfaceCorrection::None => None,
            SurfaceCorrection::Energy => Some(energy_factors(
                &p.domain,
                &grid,
                pm.m,
                &precrack,
                &bonds,
                &precrack_broken,
                &pd_nodes,
            )),
        };
        let lps = match pm.model {
            PdModel::Bond => None,
            PdModel::Lps => Some(LpsModel::new(
                lps_constants(p, pm, grid.dx)?,
                &grid,
                &bonds,
                &precrack_broken,
            )?),
        };
        Ok(Self {
            lps,
            node_bond_ptr,
            node_bonds,
            warnings,
            problem: p.clone(),
            all_pd,
            precrack,
            grid,
            pd,
            is_pd,
            pd_nodes,
            elements,
            n_removed_elements: n_removed,
            bonds,
            precrack_broken,
            ke,
            own_ke,
            rows_of,
            cols_of,
            pattern,
            edges: lo.edges,
            bc: lo.bc,
            f: lo.f,
            anchor: lo.anchor,
            mask: lo.mask,
            prescribed: lo.prescribed,
            material,
            regions: lo.regions,
            response: lo.response,
            cmod_nodes,
            mouth,
            surface,
            s0_calibration: s0,
        })
    }

    /// The same model with other PD rectangles (the adaptive region's growth,
    /// [`crate::problem::pd_region`]): the problem with `regions`, the same pre-crack.
    pub fn with_regions(&self, regions: Vec<[f64; 4]>) -> Result<Self> {
        let mut p = self.problem.clone();
        p.pd_mut().regions = regions;
        Self::build(&p, self.precrack.clone(), self.mouth, self.s0_calibration)
    }
}

/// An upper bound of the bytes a model and its SLA need: at most `m`'s family of bonds per PD
/// node, each with its matrix blocks (8 + 8 indices, 16 entries of the pattern), incidence and
/// SLA state (about 400 bytes besides the bond itself); the FEM part's factor
/// ([`memory::BYTES_PER_DOF`] per unknown); and the SLA solver the cost model would choose
/// ([`CostEstimate`], with nnz(L) guessed from the bond count, [`factor_nnz_guess`]): the dense
/// condensed system (three n x n matrices of the 2 n_PD unknowns) or the sparse factor and its
/// update vectors.
fn memory_estimate(n_nodes: usize, n_pd: usize, m: usize) -> f64 {
    let bonds = n_pd as f64 * family_stencil(m).len() as f64;
    let per_bond = BYTES_PER_BOND as f64 + 400.0;
    let fem = 2.0 * n_nodes as f64 * memory::BYTES_PER_DOF;
    let n_p = 2 * n_pd;
    let est = CostEstimate::new(n_p, factor_nnz_guess(n_p, bonds / 2.0), 0);
    let solver = est.solver_bytes(est.choice());
    bonds * per_bond + fem + solver
}

/// The grid (its fit and node count are rules of the problem, [`validate::problem`]; graded
/// away from the PD rectangles with `pd.fem_grading` > 1, `graded.rs`) and the PD constants on
/// its uniform spacing, s0 scaled by the calibration `cal` of `pd.s0_calibration`.
fn grid_and_constants(p: &Problem, pm: &PdMethod, cal: Calibration) -> Result<(Grid, PdConstants)> {
    let d = &p.domain;
    let fit = |len: f64| validate::grid_count(len, pm.dx).expect("checked by validate::problem");
    let (nx, ny) = (fit(d.width), fit(d.height));
    let dx = d.width / nx as f64;
    let mut pd = match pm.model {
        PdModel::Bond => PdConstants::new(&p.material.elastic, p.material.g0, dx, pm.m)?,
        PdModel::Lps => lps_constants(p, pm, dx)?.pd_constants(),
    };
    if cal.rule != pm.s0_calibration {
        return Err(Error::Internal {
            detail: format!(
                "the splice model was handed the s0 calibration '{}' for pd.s0_calibration = '{}'",
                cal.rule.name(),
                pm.s0_calibration.name()
            ),
        });
    }
    if pm.s0_calibration != S0Calibration::Continuum {
        pd.s0 *= cal.factor;
    }
    let grid = graded::grid(pm, nx, ny, dx);
    Ok((grid, pd))
}

/// The LPS constants of the problem on spacing `dx` ([`crate::pd::lps`]).
fn lps_constants(p: &Problem, pm: &PdMethod, dx: f64) -> Result<LpsConstants> {
    LpsConstants::new(&p.material.elastic, p.material.g0, dx, pm.m, pm.influence)
}

/// Node classes: every node PD (pure PD model, the plate at least two horizons wide and high), or
/// the nodes inside the PD rectangles. Returns the PD flags, the PD node ids (ascending; the
/// material ones, `holes.rs`) and the discretisation warnings.
fn node_classes(
    pm: &PdMethod,
    grid: &Grid,
    material: &[bool],
) -> Result<(Vec<bool>, Vec<usize>, Vec<Warning>)> {
    let nn = grid.n_nodes();
    // pure PD has no rectangle, CCM-PD at least one (validated)
    let mut is_pd = vec![pm.regions.is_empty(); nn];
    for &r in &pm.regions {
        mark_pd_region(r, grid, &mut is_pd);
    }
    let pd_nodes: Vec<usize> = (0..nn).filter(|&n| is_pd[n] && material[n]).collect();
    if pd_nodes.is_empty() {
        return Err(Error::invalid(
            "pd.size",
            "a PD rectangle containing at least one grid node",
            format!("{:?}", pm.regions),
        ));
    }
    Ok((is_pd, pd_nodes, horizon_warnings(pm.m)))
}

/// The warning of a horizon factor m < 2 (too few bonds per node).
fn horizon_warnings(m: usize) -> Vec<Warning> {
    let mut warnings = Vec::new();
    if m < 2 {
        warnings.push(Warning::new(
            WarningKind::Discretisation,
            format!(
                "horizon factor m = {}: a bulk node has only {} bonds (m = 2: {}, the paper's m = \
             4: {}); too few bonds for a peridynamic continuum, expect errors of several \
             percent in stiffness and fracture (use m >= 2, preferably 3-4)",
                m,
                crate::pd::family_stencil(m).len(),
                crate::pd::family_stencil(2).len(),
                crate::pd::family_stencil(4).len()
            ),
        ));
    }
    warnings
}

/// Flags the grid nodes inside the PD rectangle (closed, tolerance 1e-9 dx; its size and place
/// are rules of the problem, [`validate::problem`]).
fn mark_pd_region(r: [f64; 4], grid: &Grid, is_pd: &mut [bool]) {
    let tol = 1e-9 * grid.dx;
    for (n, flag) in is_pd.iter_mut().enumerate() {
        let q = grid.xy(n);
        if q[0] >= r[0] - tol && q[0] <= r[2] + tol && q[1] >= r[1] - tol && q[1] <= r[3] + tol {
            *flag = true;
        }
    }
}

/// The element stiffness of the h[0] x h[1] rectangle (exact 2 x 2 Gauss, row-major 8 x 8; every
/// whole FEM element of a uniform grid is the dx x dx square), or with `rule` (a cut element's
/// material part, [`FictitiousDomain::rule`]).
fn element_matrix(p: &Problem, h: [f64; 2], rule: Option<&[QPoint]>) -> Vec<f64> {
    let mut ke = Vec::new();
    let sq = [[0.0, 0.0], [h[0], 0.0], [h[0], h[1]], [0.0, h[1]]];
    let full = subquad_rule(1, 2);
    element_stiffness(&sq, &p.material.elastic, rule.unwrap_or(&full), &mut ke);
    ke
}

/// The grid's FEM part: node classes, material flags and the fictitious domain of FEM holes.
struct FemPart<'a> {
    grid: &'a Grid,
    is_pd: &'a [bool],
    material: &'a [bool],
    fd: Option<&'a FictitiousDomain>,
}

impl FemPart<'_> {
    /// The FEM elements: every Q4 element with at least one FEM node (hybrid elements included)
    /// whose interior the pre-crack does not cut. Without FEM holes all four nodes must be
    /// material (the centre rule of PD holes); with them (`holes.rs`) an element of FEM nodes
    /// is kept whole, dropped (void) or cut, and a hybrid element must be left whole by them.
    /// Returns (elements, number removed by the pre-crack, the own stiffness of the cut and the
    /// graded elements by element index).
    fn elements(
        &self,
        p: &Problem,
        crack: &[[f64; 2]],
    ) -> Result<(Vec<[usize; 4]>, usize, ElementStiffness)> {
        let (grid, is_pd, material) = (self.grid, self.is_pd, self.material);
        let (nx, ny) = (grid.nx, grid.ny);
        let mut elements = Vec::new();
        let mut own_ke = ElementStiffness::default();
        let mut n_removed = 0;
        let full = subquad_rule(1, 2);
        for j in 0..ny {
            for i in 0..nx {
                let n0 = grid.node(i, j);
                let e = [n0, n0 + 1, n0 + nx + 2, n0 + nx + 1];
                let n_pd = e.iter().filter(|&&n| is_pd[n]).count();
                if n_pd == 4 {
                    continue;
                }
                let mut kind = ElementKind::Material;
                if let Some(fd) = self.fd {
                    let id = j * nx + i;
                    if n_pd > 0 {
                        holes::check_hybrid(fd, grid, id, &e)?;
                    }
                    kind = fd.kind(id);
                }
                let whole_material = e.iter().all(|&n| material[n]);
                // a cut element keeps removed nodes (held at 0), as in FEM
                if kind == ElementKind::Void || (kind == ElementKind::Material && !whole_material) {
                    continue;
                }
                if precrack::cuts_cell(crack, i, j) {
                    n_removed += 1;
                    continue;
                }
                let graded = graded::is_graded_cell(grid, i, j);
                let h = if graded {
                    grid.cell_size(i, j)
                } else {
                    [grid.dx; 2]
                };
                if let (Some(fd), ElementKind::Cut) = (self.fd, kind) {
                    let ke = element_matrix(p, h, Some(fd.rule(j * nx + i, &full)));
                    own_ke.push(elements.len(), &ke);
                } else if graded {
                    own_ke.push(elements.len(), &element_matrix(p, h, None));
                }
                elements.push(e);
            }
        }
        Ok((elements, n_removed, own_ke))
    }
}

/// The blocks of the splice matrix and their pattern: an element writes the rows of its FEM nodes
/// (all 8 columns), a bond the rows of its PD end(s) (4 columns).
#[allow(clippy::type_complexity)]
fn blocks(
    grid: &Grid,
    elements: &[[usize; 4]],
    bonds: &[Bond],
    is_pd: &[bool],
) -> Result<(Vec<Vec<usize>>, Vec<Vec<usize>>, Pattern)> {
    let mut rows_of = Vec::with_capacity(elements.len() + bonds.len());
    let mut cols_of = Vec::with_capacity(elements.len() + bonds.len());
    for e in elements {
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
    for b in bonds {
        let (i, j) = (b.i as usize, b.j as usize);
        let mut r = vec![2 * i, 2 * i + 1];
        if is_pd[j] {
            r.extend([2 * j, 2 * j + 1]);
        }
        rows_of.push(r);
        cols_of.push(vec![2 * i, 2 * i + 1, 2 * j, 2 * j + 1]);
    }
    let ndof = 2 * grid.n_nodes();
    let pattern = Pattern::new(ndof, &rows_of, &cols_of)?;
    Ok((rows_of, cols_of, pattern))
}
