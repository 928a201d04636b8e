//! The grips of the paper's plate (eq. 61): opposite displacements u0 on the top and bottom
//! edges with u1 free or clamped, or a uniform traction on both edges ([`crate::fe::loading`]
//! turns them into conditions on a mesh).

use crate::error::{Error, Result};

/// The grip condition on the loaded edges.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Grip {
    /// u2 = +-u0, u1 free (rigid translation removed at the anchor node)
    Free,
    /// u2 = +-u0, u1 = 0 on both edges
    Clamped,
    /// uniform normal traction on both edges
    Traction,
}

impl Grip {
    /// Parses "free" | "clamped" | "traction".
    pub fn parse(s: &str) -> Result<Self> {
        match s {
            "free" => Ok(Grip::Free),
            "clamped" => Ok(Grip::Clamped),
            "traction" => Ok(Grip::Traction),
            _ => Err(Error::invalid(
                "bc",
                "one of 'free', 'clamped', 'traction'",
                s,
            )),
        }
    }
    pub fn name(&self) -> &'static str {
        match self {
            Grip::Free => "free",
            Grip::Clamped => "clamped",
            Grip::Traction => "traction",
        }
    }
}

/// Loading of the plate; `u0` for displacement grips, `traction` (stress) for [`Grip::Traction`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlateLoad {
    pub grip: Grip,
    pub u0: f64,
    pub traction: f64,
}
