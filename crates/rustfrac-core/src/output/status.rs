//! The statuses a run ends with, per method, with their meanings: the values of
//! `meta["status"]` (stable snake_case names, [`GrowthStatus::name`], [`SlaStatus::name`]).

use crate::pd::sla::SlaStatus;
use crate::xfem::GrowthStatus;

/// One status a method's run may end with.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Status {
    /// the stable name (`meta["status"]`)
    pub name: &'static str,
    /// what it means
    pub doc: &'static str,
}

/// Every XFEM growth status.
pub const GROWTH_STATUSES: [GrowthStatus; 7] = [
    GrowthStatus::SingleSolve,
    GrowthStatus::AStopReached,
    GrowthStatus::LigamentUsedUp,
    GrowthStatus::MaxStepsReached,
    GrowthStatus::CracksMeet,
    GrowthStatus::CrackCloses,
    GrowthStatus::Cancelled,
];

/// Every SLA status.
pub const SLA_STATUSES: [SlaStatus; 6] = [
    SlaStatus::Completed,
    SlaStatus::CrackLengthReached,
    SlaStatus::Separated,
    SlaStatus::NoBondInTension,
    SlaStatus::LoadedBoundaryReached,
    SlaStatus::Cancelled,
];

/// What a growth status means.
pub fn growth_meaning(s: GrowthStatus) -> &'static str {
    match s {
        GrowthStatus::SingleSolve => "no growth: one solve at the reference load",
        GrowthStatus::AStopReached => "the next length of a crack would exceed xfem.a_stop",
        GrowthStatus::LigamentUsedUp => {
            "a new tip would come too close to the boundary, a hole or a notch, or a tip's SIF \
             domain would have to shrink too far to keep a hole out"
        }
        GrowthStatus::MaxStepsReached => "the growth ran xfem.max_steps steps",
        GrowthStatus::CracksMeet => {
            "the cracks would cross or touch, or another crack would enter a tip's SIF domain"
        }
        GrowthStatus::CrackCloses => "no tip has K_eq > 0",
        GrowthStatus::Cancelled => {
            "the progress callback asked to stop (the steps so far are kept)"
        }
    }
}

/// What an SLA status means.
pub fn sla_meaning(s: SlaStatus) -> &'static str {
    match s {
        SlaStatus::Completed => "every requested step ran (pd.sla_steps)",
        SlaStatus::CrackLengthReached => "the crack reached pd.stop_crack_length",
        SlaStatus::Separated => {
            "a part of the body is no longer held (the Schur pivot vanished or the load path is \
             cut)"
        }
        SlaStatus::NoBondInTension => "no intact bond is in tension",
        SlaStatus::LoadedBoundaryReached => {
            "the next critical bond ends at a PD node that carries an applied force (a loaded \
             edge or point load inside the PD region): bond-based PD breaks \
             bonds there that the edge's nodal forces make (its nodes miss half their neighbours), \
             not the crack; the step is not taken. Keep the PD region off loaded and supported \
             edges (pd.center / pd.size; adaptive: a larger plate), or load through the FEM part"
        }
        SlaStatus::Cancelled => "the progress callback asked to stop (the steps so far are kept)",
    }
}

/// The statuses of `method` (none for FEM, whose run is one solve).
pub fn statuses(method: &str) -> Vec<Status> {
    match method {
        "xfem" => GROWTH_STATUSES
            .iter()
            .map(|&s| Status {
                name: s.name(),
                doc: growth_meaning(s),
            })
            .collect(),
        "pd" | "ccm_pd" => SLA_STATUSES
            .iter()
            .map(|&s| Status {
                name: s.name(),
                doc: sla_meaning(s),
            })
            .collect(),
        _ => Vec::new(),
    }
}
