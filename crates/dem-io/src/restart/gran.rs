//! The contact model of `pair_style gran` as a restart file records it: one 64-bit code made
//! of the numbers LIGGGHTS 3.8 gives its normal, tangential, cohesion, rolling-friction and
//! surface sub-models, 6 bits apart (normal in bits 0–5, tangential 6–11, cohesion 12–17,
//! rolling 18–23, surface from bit 24). `model hertz tangential history` is 3 + 2·2⁶ = 131;
//! adding `cohesion sjkr rolling_friction epsd2` gives 131 + 1·2¹² + 3·2¹⁸ = 790659 (both
//! read from files Debian's LIGGGHTS 3.8.0 wrote).

use std::fmt;

/// The sub-model numbers of a granular contact model.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct GranModel {
    /// Normal model (3 = `hertz`).
    pub normal: u8,
    /// Tangential model (2 = `history`).
    pub tangential: u8,
    /// Cohesion model (0 = off, 1 = `sjkr`).
    pub cohesion: u8,
    /// Rolling-friction model (0 = off, 1 = `cdt`, 3 = `epsd2`).
    pub rolling: u8,
    /// Surface model (0 = `default`).
    pub surface: u8,
}

/// LIGGGHTS 3.8.0's names of the sub-model numbers, per kind.
const NORMAL: &[(u8, &str)] = &[
    (0, "hooke"),
    (1, "hooke/stiffness"),
    (2, "hooke/hysteresis"),
    (3, "hertz"),
    (4, "hertz/stiffness"),
    (8, "thornton_ning"),
    (9, "off"),
    (10, "edinburgh"),
    (11, "edinburgh/stiffness"),
    (12, "luding"),
];
const TANGENTIAL: &[(u8, &str)] = &[
    (0, "off"),
    (1, "no_history"),
    (2, "history"),
    (4, "tan_luding"),
];
const COHESION: &[(u8, &str)] = &[
    (0, "off"),
    (1, "sjkr"),
    (2, "sjkr2"),
    (7, "washino/capillary/viscous"),
    (8, "easo/capillary/viscous"),
];
const ROLLING: &[(u8, &str)] = &[
    (0, "off"),
    (1, "cdt"),
    (2, "epsd"),
    (3, "epsd2"),
    (4, "epsd3"),
    (6, "luding"),
];
const SURFACE: &[(u8, &str)] = &[(0, "default"), (2, "multicontact"), (5, "superquadric")];

fn name(table: &[(u8, &str)], id: u8) -> String {
    table
        .iter()
        .find(|(k, _)| *k == id)
        .map(|(_, n)| n.to_string())
        .unwrap_or_else(|| format!("#{id}"))
}

impl GranModel {
    /// `model hertz tangential history`, no cohesion, no rolling friction.
    pub const HERTZ_HISTORY: GranModel = GranModel {
        normal: 3,
        tangential: 2,
        cohesion: 0,
        rolling: 0,
        surface: 0,
    };

    /// The code stored in the file.
    pub fn hashcode(&self) -> i64 {
        i64::from(self.normal)
            | i64::from(self.tangential) << 6
            | i64::from(self.cohesion) << 12
            | i64::from(self.rolling) << 18
            | i64::from(self.surface) << 24
    }

    /// Splits a stored code; `None` if it has bits no sub-model uses.
    pub fn from_hashcode(code: i64) -> Option<GranModel> {
        if !(0..1 << 30).contains(&code) {
            return None;
        }
        let part = |shift: u32| ((code >> shift) & 63) as u8;
        Some(GranModel {
            normal: part(0),
            tangential: part(6),
            cohesion: part(12),
            rolling: part(18),
            surface: part(24),
        })
    }

    /// The rolling-friction model's name (`off`, `cdt`, `epsd2`, …).
    pub fn rolling_name(&self) -> String {
        name(ROLLING, self.rolling)
    }

    /// The cohesion model's name (`off`, `sjkr`, …).
    pub fn cohesion_name(&self) -> String {
        name(COHESION, self.cohesion)
    }
}

impl fmt::Display for GranModel {
    /// The `pair_style gran` arguments that select this model (unknown numbers as `#n`).
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "model {} tangential {}",
            name(NORMAL, self.normal),
            name(TANGENTIAL, self.tangential)
        )?;
        if self.cohesion != 0 {
            write!(f, " cohesion {}", name(COHESION, self.cohesion))?;
        }
        if self.rolling != 0 {
            write!(f, " rolling_friction {}", name(ROLLING, self.rolling))?;
        }
        if self.surface != 0 {
            write!(f, " surface {}", name(SURFACE, self.surface))?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn codes_of_debian_files() {
        assert_eq!(GranModel::HERTZ_HISTORY.hashcode(), 131);
        let m = GranModel::from_hashcode(790659).unwrap();
        assert_eq!(
            (m.normal, m.tangential, m.cohesion, m.rolling),
            (3, 2, 1, 3)
        );
        assert_eq!(
            m.to_string(),
            "model hertz tangential history cohesion sjkr rolling_friction epsd2"
        );
        assert_eq!(m.hashcode(), 790659);
        assert!(GranModel::from_hashcode(-1).is_none());
    }
}
