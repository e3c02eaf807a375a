//! CFDEM-PFM's bed heat models as the run hands them to its sides: the `thermCondModel`
//! ([`couple::config::BedConductivity`]) to the native fluid's temperature equation.

use couple::config::BedConductivity;
use fv::temperature::BedConduction;

/// The native fluid's bed conduction for the `thermCondModel` `bed`, with the fluid's
/// conductivity `lambda` (W/(m·K), the heat model's λ: PFM's `kf`) giving
/// Zehner & Schlünder's ratio A = k_s/λ.
pub fn fluid_bed(bed: BedConductivity, lambda: f64) -> BedConduction {
    match bed {
        BedConductivity::Syamlal => BedConduction::Syamlal,
        BedConductivity::ZehnerSchluender { ks } => BedConduction::ZehnerSchluender {
            ks_over_kf: ks / lambda,
        },
    }
}
