//! Warnings a result carries: the run completed, but its numbers may be less accurate than usual.
//! Each has a [`WarningKind`] so callers (the Python bindings map it to a warning class) need not
//! parse the message.

use std::fmt;

/// What a [`Warning`] is about.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum WarningKind {
    /// a solve's condition estimate exceeds [`crate::la::COND_WARN`]: round-off may be
    /// comparable with the discretisation error
    IllConditioned,
    /// volumetric locking of the fully integrated Q4 elements near nu = 0.5 in plane strain
    /// ([`crate::problem::Elastic::locking_warning`])
    Locking,
    /// a known limit of the discretisation: PD horizon factor m < 2, PD nodes grounded after
    /// losing all stiffness along a direction
    Discretisation,
}

impl WarningKind {
    /// Every kind, in declaration order.
    pub const ALL: [WarningKind; 3] = [
        WarningKind::IllConditioned,
        WarningKind::Locking,
        WarningKind::Discretisation,
    ];

    /// Stable lower-case name (the Python bindings and saved results use it).
    pub fn name(&self) -> &'static str {
        match self {
            WarningKind::IllConditioned => "ill_conditioned",
            WarningKind::Locking => "locking",
            WarningKind::Discretisation => "discretisation",
        }
    }
}

/// One warning of a result: its kind and a readable message saying what and by how much.
#[derive(Debug, Clone, PartialEq)]
pub struct Warning {
    pub kind: WarningKind,
    pub message: String,
}

impl Warning {
    pub fn new(kind: WarningKind, message: impl Into<String>) -> Self {
        Self {
            kind,
            message: message.into(),
        }
    }
}

impl fmt::Display for Warning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.message)
    }
}
