//! Reading a problem from a scene tree: [`super::parse`] (kinds, ranges, defaults), then the
//! cross-parameter rules of [`super::validate`], before anything is built.

use super::value::{Table, Value};
use super::{parse, validate, Problem, XfemOptions};
use crate::error::Result;

impl Problem {
    /// Reads and validates a scene tree (see [`super::parse`]).
    pub fn from_scene(scene: &Table) -> Result<Self> {
        Ok(Self::checked(scene)?.0)
    }

    /// [`Problem::from_scene`], with the checked scene tree (every key of every section the
    /// method reads, defaults filled in, the cracks as a list).
    pub fn checked(scene: &Table) -> Result<(Self, Table)> {
        let c = parse::check(scene)?;
        let p = parse::from_checked(&c)?;
        validate::problem(&p)?;
        Ok((p, c.to_tree()))
    }

    /// The paper's case (section 3; every default of [`super::schema`]) solved by `method` ("fem",
    /// "xfem", "pd" or "ccm_pd"): the starting point of Rust tests and examples, which then
    /// change what they need (`p.xfem_mut().grid.nx = 88`).
    pub fn paper(method: &str) -> Self {
        let mut t = Table::new();
        t.insert("method".into(), Value::Str(method.into()));
        Self::from_scene(&t).expect("the paper's case is valid for every method")
    }
}

impl XfemOptions {
    /// The scene's ranges of these options ([`validate::xfem_options`]).
    pub fn validate(&self) -> Result<()> {
        validate::xfem_options(self)
    }
}
