//! The voidage models, selected by name.

use std::fmt;
use std::str::FromStr;

/// How a particle's volume is distributed over the cells.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Method {
    /// `centre` (CFDEM `centre`): the whole volume to the cell holding the centre. Jumps when
    /// the centre crosses a face.
    Centre,
    /// `divided` (CFDEM `divided`): 29 marker points of 1/29 of the volume each
    /// ([`crate::divided`]); markers outside the mesh go to the centre's cell. Jumps by V/29.
    Divided,
    /// `trilinear` (CFDEM `trilinear`): the volume shared among the 8 cells whose centres
    /// surround the particle centre with trilinear weights ([`crate::trilinear`]), as CFDEM
    /// does at the mesh boundary. Only on structured grids of equal axis-aligned cells
    /// (elsewhere [`crate::VoidageError::UnsupportedMesh`]). Continuous except in the cells
    /// along the lower walls; independent of the particle size.
    Trilinear,
    /// `cube`: the fraction of the circumscribing cube (side d) in each cell ([`crate::cube`]).
    /// Continuous; up to ≈20 % of the volume misplaced.
    Cube,
    /// `corrected-cube`: Khawaja et al.'s (2012) polynomial applied to the cube fractions,
    /// renormalised over the particle's cells. Continuous; ≈2.5 % maximum error.
    CorrectedCube,
    /// `exact`: the exact volume of ball ∩ cell ([`crate::sphere_box`], [`crate::sphere_poly`]).
    Exact,
    /// `bigParticle` (CFDEM `bigParticle`, for particles larger than a cell): equal shares to
    /// the centre's cell and the cells whose centre lies within the radius, reached from it
    /// through faces (`engine::big`). Jumps when a cell centre enters or leaves the ball.
    BigParticle,
    /// `GaussVoidFraction` (CFDEM's, which stops on it): the volume spread over the cells
    /// whose centre lies within 3r in proportion to e^(−d²/(2r²)) V_cell, **normalised** so
    /// that the shares sum to the particle volume (CFDEM's weights sum to about 8 times it;
    /// `engine::gauss`). Jumps when a cell centre crosses the 3r sphere.
    Gauss,
}

impl Method {
    /// Every method, in the order of the CLI help.
    pub const ALL: [Method; 8] = [
        Method::Centre,
        Method::Divided,
        Method::Trilinear,
        Method::Cube,
        Method::CorrectedCube,
        Method::Exact,
        Method::BigParticle,
        Method::Gauss,
    ];

    /// The methods defined on every mesh that the studies compare by default: all but
    /// `trilinear`, which needs a structured grid of equal axis-aligned cells
    /// ([`crate::VoidageMesh::check_method`]), and `bigParticle` and `gauss` (defined on every
    /// mesh, but meant for particles larger than a cell).
    pub const ANY_MESH: [Method; 5] = [
        Method::Centre,
        Method::Divided,
        Method::Cube,
        Method::CorrectedCube,
        Method::Exact,
    ];

    /// The name used on the command line and in reports.
    pub fn name(self) -> &'static str {
        match self {
            Method::Centre => "centre",
            Method::Divided => "divided",
            Method::Trilinear => "trilinear",
            Method::Cube => "cube",
            Method::CorrectedCube => "corrected-cube",
            Method::Exact => "exact",
            Method::BigParticle => "bigParticle",
            Method::Gauss => "gauss",
        }
    }

    /// Every spelling that selects the method, the one alias list of voidage names ([`FromStr`]
    /// and couple's `voidFractionModel` read it): the `voidFractionModel` name first (CFDEM's
    /// where CFDEM has the model), then CFDEM's class names (`…VoidFraction`), the command
    /// line's `corrected-cube` and `center`.
    pub const fn names(self) -> &'static [&'static str] {
        match self {
            Method::Centre => &["centre", "center", "centreVoidFraction"],
            Method::Divided => &["divided", "dividedVoidFraction"],
            Method::Trilinear => &["trilinear", "trilinearVoidFraction"],
            Method::Cube => &["cube"],
            Method::CorrectedCube => &["correctedCube", "corrected-cube"],
            Method::Exact => &["exact", "exactVoidFraction"],
            Method::BigParticle => &["bigParticle", "bigParticleVoidFraction"],
            Method::Gauss => &["GaussVoidFraction", "gauss"],
        }
    }

    /// The CFDEMcoupling `voidFractionModel` of the same behaviour, where one exists.
    pub fn cfdem_name(self) -> Option<&'static str> {
        match self {
            Method::Centre => Some("centre"),
            Method::Divided => Some("divided"),
            Method::Trilinear => Some("trilinear"),
            Method::BigParticle => Some("bigParticle"),
            Method::Gauss => Some("GaussVoidFraction"),
            _ => None,
        }
    }

    /// True for the methods whose cell shares vary continuously with the particle position
    /// everywhere (`trilinear` is continuous except near the lower walls, as CFDEM's corner
    /// search makes it: [`crate::trilinear`]).
    pub fn is_continuous(self) -> bool {
        matches!(self, Method::Cube | Method::CorrectedCube | Method::Exact)
    }
}

impl fmt::Display for Method {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// A method name that is none of [`Method::ALL`]; its message lists the valid names.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct UnknownMethod(pub String);

impl fmt::Display for UnknownMethod {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let names: Vec<&str> = Method::ALL.iter().map(|m| m.name()).collect();
        write!(
            f,
            "unknown voidage method `{}`: expected one of {}",
            self.0,
            names.join(", ")
        )
    }
}

impl std::error::Error for UnknownMethod {}

impl FromStr for Method {
    type Err = UnknownMethod;

    /// Accepts every spelling of [`Method::names`].
    fn from_str(s: &str) -> Result<Method, UnknownMethod> {
        Method::ALL
            .into_iter()
            .find(|m| m.names().contains(&s))
            .ok_or_else(|| UnknownMethod(s.into()))
    }
}
