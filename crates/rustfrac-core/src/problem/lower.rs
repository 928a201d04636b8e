//! The drivers' parameters of a [`Problem`].

use super::{CrackKind, Method, Problem};
use crate::pd::sla::CcmPdParams;
use crate::pd::splice::{self as coupling, ModelSpec};
use crate::xfem::{GrowthParams, XfemParams};

impl Problem {
    /// XFEM plate parameters (method "xfem").
    pub fn xfem_params(&self) -> Option<XfemParams> {
        let Method::Xfem(x) = &self.method else {
            return None;
        };
        let mut lines = self.crack_polylines();
        let crack = lines.remove(0);
        Some(XfemParams {
            width: self.domain.width,
            height: self.domain.height,
            nx: x.grid.nx,
            ny: x.grid.ny,
            material: self.material.elastic,
            crack,
            extra_cracks: lines,
            load: self.boundary.plate_load(),
            nsub: x.options.nsub,
            tip_nsub: x.options.tip_nsub,
            r_i_factor: x.r_i,
            extra_radius_factors: x.extra_radii.clone(),
            fixed_area_radius: x.options.fixed_area_radius,
            area_threshold: x.options.area_threshold,
            growth: x.growth.map(|g| GrowthParams {
                g0: self.material.g0,
                da: g.da,
                a_stop: g.a_stop,
                max_steps: g.max_steps,
            }),
            condition: x.condition,
        })
    }

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
