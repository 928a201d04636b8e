//! The drivers' parameters of a [`Problem`].

use super::{CrackKind, Method, Problem};
use crate::pd::sla::CcmPdParams;
use crate::pd::splice::{self as coupling, ModelSpec};

impl Problem {
    /// PD / CCM-PD parameters (methods "pd" and "ccm_pd").
    pub fn pd_params(&self) -> Option<CcmPdParams> {
        let (method, pd) = match &self.method {
            Method::Pd(pd) => (coupling::Method::Pd, pd),
            Method::CcmPd(pd) => (coupling::Method::CcmPd, pd),
            _ => return None,
        };
        Some(CcmPdParams {
            model: ModelSpec {
                method,
                width: self.domain.width,
                height: self.domain.height,
                dx: pd.dx,
                m: pd.m,
                material: self.material.elastic,
                g0: self.material.g0,
                pd_regions: pd.region.into_iter().collect(),
                precrack: self
                    .cracks
                    .iter()
                    .filter(|c| c.kind == CrackKind::Edge)
                    .map(|c| c.polyline(&self.domain))
                    .next()
                    .unwrap_or_default(),
                load: self.boundary.plate_load(),
            },
            sla: pd.sla.clone(),
        })
    }
}
