//! Per-atom quantities by their LIGGGHTS names — the one table that `dump custom` columns,
//! `compute reduce` inputs and per-atom references in formulas (`vx[1]`) share.
//!
//! Units are the deck's (SI: m, m/s, N, rad/s, N·m, kg, kg/m³). `f_dragforce[k]` is the
//! per-atom explicit force the CFD side hands the DEM (LIGGGHTS's `dragforce` property, created
//! by `fix couple/cfd/force[/implicit]`): foamgrain's F_ext ([`Coupling`]), which with an
//! implicit drag excludes the β(u_f − v) part, as in CFDEM. Image flags `ix iy iz` count the
//! crossings of periodic faces ([`crate::periodic`]). The heat values ([`crate::heat`]) are
//! LIGGGHTS's `fix property/atom` vectors `Temp` (K), `heatFlux` (W, the heat flow of the last
//! step) and `convectiveHeatFlux` (W), named `f_Temp` or `f_Temp[0]` (LIGGGHTS's `dump custom`
//! reads `[0]` as the fix's per-atom vector); the `heat/gran` fix's own id names `Temp` too
//! ([`AtomValue::parse_in`]).

use crate::coupling::Coupling;
use crate::heat::Heat;
use crate::particles::Particles;

/// A per-atom quantity.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AtomValue {
    /// `id`.
    Id,
    /// `type`.
    Type,
    /// `x y z` (component 0..3).
    Position(usize),
    /// `vx vy vz`.
    Velocity(usize),
    /// `fx fy fz`: the total force of the last step.
    Force(usize),
    /// `omegax omegay omegaz`.
    Omega(usize),
    /// `tqx tqy tqz`.
    Torque(usize),
    /// `radius`.
    Radius,
    /// `diameter`.
    Diameter,
    /// `mass`.
    Mass,
    /// `density`.
    Density,
    /// `ix iy iz`: periodic image counters.
    Image(usize),
    /// `f_dragforce[1..3]`: the explicit coupling force F_ext.
    DragForce(usize),
    /// `f_Temp[0]`: the temperature (K).
    Temperature,
    /// `f_heatFlux[0]`: the heat flow of the last step (W).
    HeatFlux,
    /// `f_convectiveHeatFlux[0]`: the convective heat flow the coupler set (W).
    ConvectiveHeatFlux,
}

/// The names [`AtomValue::parse`] knows, for messages.
pub const NAMES: &str = "id type x y z vx vy vz fx fy fz omegax omegay omegaz tqx tqy tqz \
                         radius diameter mass density ix iy iz f_dragforce[1..3] f_Temp[0] \
                         f_heatFlux[0] f_convectiveHeatFlux[0]";

impl AtomValue {
    /// The quantity named `name` (a dump column or a `compute reduce` input).
    pub fn parse(name: &str) -> Option<AtomValue> {
        let xyz = |c: &str| match c {
            "x" => Some(0),
            "y" => Some(1),
            "z" => Some(2),
            _ => None,
        };
        Some(match name {
            "id" => AtomValue::Id,
            "type" => AtomValue::Type,
            "radius" => AtomValue::Radius,
            "diameter" => AtomValue::Diameter,
            "mass" => AtomValue::Mass,
            "density" => AtomValue::Density,
            "f_dragforce[1]" => AtomValue::DragForce(0),
            "f_dragforce[2]" => AtomValue::DragForce(1),
            "f_dragforce[3]" => AtomValue::DragForce(2),
            "f_Temp" | "f_Temp[0]" => AtomValue::Temperature,
            "f_heatFlux" | "f_heatFlux[0]" => AtomValue::HeatFlux,
            "f_convectiveHeatFlux" | "f_convectiveHeatFlux[0]" => AtomValue::ConvectiveHeatFlux,
            _ => {
                let (stem, c) = name.split_at(name.len().checked_sub(1)?);
                let k = xyz(c)?;
                match stem {
                    "" => AtomValue::Position(k),
                    "v" => AtomValue::Velocity(k),
                    "f" => AtomValue::Force(k),
                    "omega" => AtomValue::Omega(k),
                    "tq" => AtomValue::Torque(k),
                    "i" => AtomValue::Image(k),
                    _ => return None,
                }
            }
        })
    }

    /// [`AtomValue::parse`], with `f_ID` and `f_ID[0]` of the ids in `temperature_fixes` (the
    /// `heat/gran` fix and its transport equation `ste_heattransfer`, whose per-atom vector is
    /// `Temp`) naming the temperature.
    pub fn parse_in(name: &str, temperature_fixes: &[String]) -> Option<AtomValue> {
        let id = name
            .strip_prefix("f_")
            .map(|s| s.strip_suffix("[0]").unwrap_or(s));
        match id {
            Some(id) if temperature_fixes.iter().any(|f| f == id) => Some(AtomValue::Temperature),
            _ => AtomValue::parse(name),
        }
    }

    /// Whether the value needs the coupling fix (`f_dragforce`).
    pub fn needs_coupling(self) -> bool {
        matches!(self, AtomValue::DragForce(_))
    }

    /// Whether the value needs the heat state (`heat/gran` or `couple/cfd/convection`).
    pub fn needs_heat(self) -> bool {
        matches!(
            self,
            AtomValue::Temperature | AtomValue::HeatFlux | AtomValue::ConvectiveHeatFlux
        )
    }

    /// The value of particle index `i`; `coupling` supplies F_ext (0 before the first exchange,
    /// as LIGGGHTS's property starts at 0), `heat` the heat values (0 without it: the deck
    /// executor refuses them before a heat fix exists).
    #[inline]
    pub fn get(self, p: &Particles, coupling: &Coupling, heat: Option<&Heat>, i: usize) -> f64 {
        match self {
            AtomValue::Id => p.id[i] as f64,
            AtomValue::Type => p.atom_type[i] as f64,
            AtomValue::Position(k) => p.x[i][k],
            AtomValue::Velocity(k) => p.v[i][k],
            AtomValue::Force(k) => p.f[i][k],
            AtomValue::Omega(k) => p.omega[i][k],
            AtomValue::Torque(k) => p.torque[i][k],
            AtomValue::Radius => p.radius[i],
            AtomValue::Diameter => 2.0 * p.radius[i],
            AtomValue::Mass => p.mass[i],
            AtomValue::Density => p.density[i],
            AtomValue::Image(k) => p.image[i][k] as f64,
            AtomValue::DragForce(k) => coupling.f_ext.get(i).map_or(0.0, |f| f[k]),
            AtomValue::Temperature => heat.map_or(0.0, |h| h.temp[i]),
            AtomValue::HeatFlux => heat.map_or(0.0, |h| h.flux[i]),
            AtomValue::ConvectiveHeatFlux => heat.map_or(0.0, |h| h.convective[i]),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip() {
        for name in NAMES.split_whitespace() {
            if name == "f_dragforce[1..3]" {
                continue;
            }
            assert!(AtomValue::parse(name).is_some(), "{name}");
        }
        assert_eq!(AtomValue::parse("vz"), Some(AtomValue::Velocity(2)));
        assert_eq!(
            AtomValue::parse("f_dragforce[2]"),
            Some(AtomValue::DragForce(1))
        );
        for bad in [
            "",
            "w",
            "vw",
            "f_dragforce[4]",
            "c_x",
            "omega",
            "xx",
            "f_Temp[1]",
        ] {
            assert_eq!(AtomValue::parse(bad), None, "{bad}");
        }
        let heat = ["heattransfer".to_string()];
        assert_eq!(
            AtomValue::parse_in("f_heattransfer[0]", &heat),
            Some(AtomValue::Temperature)
        );
        assert_eq!(AtomValue::parse_in("f_heattransfer[1]", &heat), None);
        assert_eq!(
            AtomValue::parse_in("f_heatFlux[0]", &heat),
            Some(AtomValue::HeatFlux)
        );
    }
}
