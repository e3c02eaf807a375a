//! A fluid side that does not move: U, p, ∇p and ∇·τ given once — uniform, or those of a
//! case's time directory with ∇p and ∇·τ computed by `fv`'s operators
//! (`fv::frozen::FrozenFields`). [`FluidSide::advance`] only moves the clock; the exchange
//! fields are kept ([`FrozenFluid::last_exchange`]) for the caller to write.

use crate::error::SideError;
use crate::exchange::Exchange;
use crate::sides::{ExchangeFields, FluidSide, FluidState};
use foam::PolyMesh;
use mesh::v3::V3;

/// A frozen fluid (module docs).
#[derive(Clone, Debug)]
pub struct FrozenFluid {
    mesh: PolyMesh,
    u: Vec<V3>,
    p: Vec<f64>,
    grad_p: Vec<V3>,
    div_tau: Vec<V3>,
    time: f64,
    last: Option<(Vec<f64>, Exchange)>,
}

impl FrozenFluid {
    /// Uniform velocity `u` (m/s) and zero pressure on `mesh`: ∇p = ∇·τ = 0.
    pub fn uniform(mesh: PolyMesh, u: V3) -> FrozenFluid {
        let n = mesh.n_cells;
        let zero = vec![V3::zeros(); n];
        FrozenFluid::new(mesh, vec![u; n], vec![0.0; n], zero.clone(), zero, 0.0)
    }

    /// The fields `u`, `p`, `grad_p`, `div_tau` (one value per cell of `mesh`) at time `time`
    /// (s): those of a case's time directory are `fv::frozen::FrozenFields::read`'s.
    pub fn new(
        mesh: PolyMesh,
        u: Vec<V3>,
        p: Vec<f64>,
        grad_p: Vec<V3>,
        div_tau: Vec<V3>,
        time: f64,
    ) -> FrozenFluid {
        FrozenFluid {
            mesh,
            u,
            p,
            grad_p,
            div_tau,
            time,
            last: None,
        }
    }

    /// The last exchange received: ε (new) and Ksl, Us, f.
    pub fn last_exchange(&self) -> Option<&(Vec<f64>, Exchange)> {
        self.last.as_ref()
    }

    /// The clock, s.
    pub fn time(&self) -> f64 {
        self.time
    }
}

impl FluidSide for FrozenFluid {
    fn mesh(&self) -> &PolyMesh {
        &self.mesh
    }

    fn set_exchange(&mut self, fields: &ExchangeFields<'_>) -> Result<(), SideError> {
        self.last = Some((fields.voidage_new.to_vec(), fields.exchange.clone()));
        Ok(())
    }

    fn advance(&mut self, dt: f64) -> Result<(), SideError> {
        self.time += dt;
        Ok(())
    }

    fn state(&self) -> FluidState<'_> {
        FluidState {
            vorticity: None,
            ddt_u: None,
            turbulence: None,
            temperature: None,
            u: &self.u,
            p: &self.p,
            grad_p: &self.grad_p,
            div_tau: &self.div_tau,
        }
    }
}
