//! Structured rectangular Q4 meshes: grid lines (non-uniform spacing allowed), node and element
//! numbering, named boundary node and edge sets, point location, and the seam (duplicated-node)
//! crack used as an independent FEM reference for XFEM.
//!
//! Numbering: node (i, j) = j (nx + 1) + i, element (i, j) = j nx + i, element nodes counter-clockwise
//! from the lower-left corner, as in eq. (6) of the paper.

use crate::error::{check_finite, check_positive, Error, Result};
use crate::problem::{Domain, FeGrid, Side, MAX_ELEMENTS};

/// A Q4 mesh on a rectangle, built from its grid lines; nodes may be duplicated along a seam.
#[derive(Debug, Clone)]
pub struct Mesh {
    /// x coordinates of the vertical grid lines (strictly increasing), nx + 1 values
    pub xs: Vec<f64>,
    /// y coordinates of the horizontal grid lines (strictly increasing), ny + 1 values
    pub ys: Vec<f64>,
    /// node coordinates (grid nodes first, then seam duplicates)
    pub coords: Vec<[f64; 2]>,
    /// element connectivity, counter-clockwise
    pub elements: Vec<[usize; 4]>,
    /// for a seam duplicate: the grid node it duplicates
    pub duplicate_of: Vec<(usize, usize)>,
}

fn check_grid_size(nx: usize, ny: usize) -> Result<()> {
    if nx.saturating_mul(ny) > MAX_ELEMENTS {
        return Err(Error::invalid(
            "nx * ny",
            &format!("at most {MAX_ELEMENTS} elements (problem::MAX_ELEMENTS)"),
            format!("{nx} x {ny}"),
        ));
    }
    Ok(())
}

impl Mesh {
    /// Uniform grid: origin (x0, y0), size (width, height), nx x ny elements (at most
    /// [`MAX_ELEMENTS`]).
    pub fn uniform(
        x0: f64,
        y0: f64,
        width: f64,
        height: f64,
        nx: usize,
        ny: usize,
    ) -> Result<Self> {
        check_finite("x0", x0)?;
        check_finite("y0", y0)?;
        check_positive("width", width)?;
        check_positive("height", height)?;
        if nx == 0 {
            return Err(Error::invalid("nx", "an integer >= 1", nx));
        }
        if ny == 0 {
            return Err(Error::invalid("ny", "an integer >= 1", ny));
        }
        check_grid_size(nx, ny)?;
        // n equal cells from o to o + len, the last line exactly at o + len
        let lines = |o: f64, len: f64, n: usize| -> Vec<f64> {
            (0..=n)
                .map(|i| {
                    if i == n {
                        o + len
                    } else {
                        o + len * i as f64 / n as f64
                    }
                })
                .collect()
        };
        Self::from_lines(lines(x0, width, nx), lines(y0, height, ny))
    }

    /// The mesh of a problem's grid over the domain's rectangle: [`Mesh::uniform`] for a uniform
    /// grid, else [`Mesh::from_lines`] (a direction without lines divided uniformly).
    pub fn of_grid(grid: &FeGrid, d: &Domain) -> Result<Self> {
        let uniform = Self::uniform(0.0, 0.0, d.width, d.height, grid.nx, grid.ny);
        if grid.xs.is_empty() && grid.ys.is_empty() {
            return uniform;
        }
        let lines = |v: &Vec<f64>, len: f64, n: usize| {
            if v.is_empty() {
                (0..=n)
                    .map(|i| {
                        if i == n {
                            len
                        } else {
                            len * i as f64 / n as f64
                        }
                    })
                    .collect()
            } else {
                v.clone()
            }
        };
        Self::from_lines(
            lines(&grid.xs, d.width, grid.nx),
            lines(&grid.ys, d.height, grid.ny),
        )
    }

    /// Grid from explicit line coordinates (non-uniform spacing; at most [`MAX_ELEMENTS`]).
    pub fn from_lines(xs: Vec<f64>, ys: Vec<f64>) -> Result<Self> {
        for (name, v) in [("xs", &xs), ("ys", &ys)] {
            if v.len() < 2 {
                return Err(Error::invalid(name, "at least 2 grid lines", v.len()));
            }
            if v.iter().any(|x| !x.is_finite()) {
                return Err(Error::invalid(name, "finite coordinates", "NaN/inf"));
            }
            if v.windows(2).any(|w| w[1] <= w[0]) {
                return Err(Error::invalid(
                    name,
                    "strictly increasing coordinates",
                    "a non-increasing pair",
                ));
            }
        }
        let (nx, ny) = (xs.len() - 1, ys.len() - 1);
        check_grid_size(nx, ny)?;
        let mut coords = Vec::with_capacity((nx + 1) * (ny + 1));
        for &y in &ys {
            for &x in &xs {
                coords.push([x, y]);
            }
        }
        let mut elements = Vec::with_capacity(nx * ny);
        for j in 0..ny {
            for i in 0..nx {
                let n0 = j * (nx + 1) + i;
                elements.push([n0, n0 + 1, n0 + nx + 2, n0 + nx + 1]);
            }
        }
        Ok(Self {
            xs,
            ys,
            coords,
            elements,
            duplicate_of: Vec::new(),
        })
    }

    pub fn nx(&self) -> usize {
        self.xs.len() - 1
    }
    pub fn ny(&self) -> usize {
        self.ys.len() - 1
    }
    pub fn n_nodes(&self) -> usize {
        self.coords.len()
    }
    pub fn n_elements(&self) -> usize {
        self.elements.len()
    }
    /// Grid node index of (i, j).
    pub fn node(&self, i: usize, j: usize) -> usize {
        j * (self.nx() + 1) + i
    }
    /// Element index of (i, j).
    pub fn element(&self, i: usize, j: usize) -> usize {
        j * self.nx() + i
    }
    /// Width and height of the rectangle.
    pub fn size(&self) -> (f64, f64) {
        (
            self.xs[self.nx()] - self.xs[0],
            self.ys[self.ny()] - self.ys[0],
        )
    }
    /// Element corner coordinates, counter-clockwise.
    pub fn element_coords(&self, e: usize) -> [[f64; 2]; 4] {
        self.elements[e].map(|n| self.coords[n])
    }
    /// Smallest element edge length.
    pub fn min_spacing(&self) -> f64 {
        let dx = self
            .xs
            .windows(2)
            .map(|w| w[1] - w[0])
            .fold(f64::INFINITY, f64::min);
        let dy = self
            .ys
            .windows(2)
            .map(|w| w[1] - w[0])
            .fold(f64::INFINITY, f64::min);
        dx.min(dy)
    }

    /// Nodes on one side of the rectangle (including seam duplicates there), sorted by the
    /// coordinate along the side.
    pub fn side_nodes(&self, side: Side) -> Vec<usize> {
        let (nx, ny) = (self.nx(), self.ny());
        let mut v: Vec<usize> = match side {
            Side::Bottom => (0..=nx).map(|i| self.node(i, 0)).collect(),
            Side::Top => (0..=nx).map(|i| self.node(i, ny)).collect(),
            Side::Left => (0..=ny).map(|j| self.node(0, j)).collect(),
            Side::Right => (0..=ny).map(|j| self.node(nx, j)).collect(),
        };
        for &(dup, orig) in &self.duplicate_of {
            if v.contains(&orig) {
                v.push(dup);
            }
        }
        let axis = if matches!(side, Side::Bottom | Side::Top) {
            0
        } else {
            1
        };
        v.sort_by(|a, b| self.coords[*a][axis].total_cmp(&self.coords[*b][axis]));
        v
    }

    /// Boundary edges of one side as node pairs (counter-clockwise around the body).
    pub fn side_edges(&self, side: Side) -> Vec<[usize; 2]> {
        let (nx, ny) = (self.nx(), self.ny());
        match side {
            Side::Bottom => (0..nx)
                .map(|i| {
                    let e = self.elements[self.element(i, 0)];
                    [e[0], e[1]]
                })
                .collect(),
            Side::Right => (0..ny)
                .map(|j| {
                    let e = self.elements[self.element(nx - 1, j)];
                    [e[1], e[2]]
                })
                .collect(),
            Side::Top => (0..nx)
                .map(|i| {
                    let e = self.elements[self.element(i, ny - 1)];
                    [e[2], e[3]]
                })
                .collect(),
            Side::Left => (0..ny)
                .map(|j| {
                    let e = self.elements[self.element(0, j)];
                    [e[3], e[0]]
                })
                .collect(),
        }
    }

    /// Locates a point: (element, xi, eta) with natural coordinates in [-1, 1]. Points on a shared
    /// line go to the element with the larger index. `None` outside the rectangle.
    pub fn locate(&self, x: f64, y: f64) -> Option<(usize, f64, f64)> {
        let i = locate_1d(&self.xs, x)?;
        let j = locate_1d(&self.ys, y)?;
        let xi = 2.0 * (x - self.xs[i]) / (self.xs[i + 1] - self.xs[i]) - 1.0;
        let eta = 2.0 * (y - self.ys[j]) / (self.ys[j + 1] - self.ys[j]) - 1.0;
        Some((self.element(i, j), xi, eta))
    }

    /// Index of the grid line nearest to `v` among `lines` and its distance.
    pub fn nearest_line(lines: &[f64], v: f64) -> (usize, f64) {
        let mut best = (0, f64::INFINITY);
        for (k, &l) in lines.iter().enumerate() {
            let d = (l - v).abs();
            if d < best.1 {
                best = (k, d);
            }
        }
        best
    }

    /// Seam crack: duplicates the grid nodes on the horizontal grid line `j_line` with
    /// x < `x_tip` (the tip node itself is not duplicated) and reconnects the elements above the
    /// line to the duplicates. The crack faces are then traction-free and the nodes on the mouth
    /// (x = x0) come in pairs. Returns the mesh and the (lower, upper) node pairs along the crack.
    pub fn with_seam(&self, j_line: usize, x_tip: f64) -> Result<(Self, Vec<(usize, usize)>)> {
        let (nx, ny) = (self.nx(), self.ny());
        if j_line == 0 || j_line >= ny {
            return Err(Error::invalid(
                "seam line",
                &format!("an interior grid line 1..{}", ny - 1),
                j_line,
            ));
        }
        let mut m = self.clone();
        let mut pairs = Vec::new();
        for i in 0..=nx {
            if self.xs[i] >= x_tip - 1e-12 * (self.xs[nx] - self.xs[0]) {
                break;
            }
            let orig = self.node(i, j_line);
            let dup = m.coords.len();
            m.coords.push(self.coords[orig]);
            m.duplicate_of.push((dup, orig));
            pairs.push((orig, dup));
            // elements above the line touching `orig`: (i-1, j_line) and (i, j_line)
            for ii in [i.wrapping_sub(1), i] {
                if ii < nx {
                    let e = self.element(ii, j_line);
                    for n in m.elements[e].iter_mut() {
                        if *n == orig {
                            *n = dup;
                        }
                    }
                }
            }
        }
        if pairs.is_empty() {
            return Err(Error::invalid(
                "seam crack length",
                "at least one element length",
                x_tip - self.xs[0],
            ));
        }
        Ok((m, pairs))
    }
}

fn locate_1d(lines: &[f64], v: f64) -> Option<usize> {
    let n = lines.len() - 1;
    let tol = 1e-12 * (lines[n] - lines[0]);
    if !(v >= lines[0] - tol && v <= lines[n] + tol) {
        return None;
    }
    let k = lines.partition_point(|&l| l <= v);
    Some(k.saturating_sub(1).min(n - 1))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbering_and_sets() {
        let m = Mesh::uniform(0.0, 0.0, 2.0, 1.0, 4, 2).unwrap();
        assert_eq!(m.n_nodes(), 15);
        assert_eq!(m.n_elements(), 8);
        assert_eq!(m.elements[0], [0, 1, 6, 5]);
        assert_eq!(m.side_nodes(Side::Top), vec![10, 11, 12, 13, 14]);
        assert_eq!(m.side_nodes(Side::Left), vec![0, 5, 10]);
        assert_eq!(m.side_edges(Side::Top).len(), 4);
        let (e, xi, eta) = m.locate(0.75, 0.25).unwrap();
        assert_eq!(e, 1);
        assert!((xi - 0.0).abs() < 1e-14 && (eta - 0.0).abs() < 1e-14);
        assert!(m.locate(2.5, 0.1).is_none());
        assert_eq!(m.locate(2.0, 1.0).unwrap().0, 7);
        assert!(Mesh::uniform(0.0, 0.0, 1.0, 1.0, 0, 1).is_err());
        assert!(Mesh::uniform(0.0, 0.0, -1.0, 1.0, 1, 1).is_err());
        assert!(Mesh::from_lines(vec![0.0, 1.0, 0.5], vec![0.0, 1.0]).is_err());
    }

    #[test]
    fn seam_duplicates_nodes_left_of_tip() {
        let m = Mesh::uniform(0.0, 0.0, 4.0, 2.0, 4, 2).unwrap();
        let (s, pairs) = m.with_seam(1, 2.0).unwrap();
        assert_eq!(pairs.len(), 2); // x = 0 and x = 1; tip node at x = 2 not duplicated
        assert_eq!(s.n_nodes(), m.n_nodes() + 2);
        // element (0,1) above the seam uses the duplicate of node (0,1) and (1,1)
        let e = s.elements[s.element(0, 1)];
        assert_eq!(e[0], pairs[0].1);
        assert_eq!(e[1], pairs[1].1);
        // element (1,1) keeps the tip node (2,1)
        assert_eq!(s.elements[s.element(1, 1)][1], m.node(2, 1));
        assert_eq!(s.side_nodes(Side::Left).len(), 4);
    }
}
