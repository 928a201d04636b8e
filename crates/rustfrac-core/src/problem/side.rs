//! The sides of the rectangular domain [0, W] x [0, L] (edge cracks, supports and loads on
//! regions, the mesh's boundary node sets).

use crate::error::{Error, Result};

/// A boundary side of the rectangle (in the order of [`super::schema::SIDES`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Side {
    Left,
    Right,
    Bottom,
    Top,
}

impl Side {
    /// Parses "left" | "right" | "bottom" | "top".
    pub fn parse(s: &str) -> Result<Self> {
        match s {
            "left" => Ok(Side::Left),
            "right" => Ok(Side::Right),
            "bottom" => Ok(Side::Bottom),
            "top" => Ok(Side::Top),
            _ => Err(Error::invalid("side", "one of left, right, bottom, top", s)),
        }
    }
    /// The scene name ([`super::schema::SIDES`]; the inverse of [`Side::parse`]).
    pub fn name(self) -> &'static str {
        super::schema::SIDES[self as usize]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip() {
        for n in super::super::schema::SIDES {
            assert_eq!(Side::parse(n).unwrap().name(), n);
        }
    }
}
