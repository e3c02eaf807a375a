/*---------------------------------------------------------------------------*\
  grainPisoFoam (foamgrain) — transient incompressible volume-averaged (VANS) PISO solver
  for CFD-DEM coupling, built against Debian's OpenFOAM v1912 (openfoam-cases/solver/build.sh).

  Equations (foamgrain ADR 0004; Zhou et al. 2010 as in seed 002 eq. 3–4), kinematic
  pressure p [m²/s²], interstitial velocity U [m/s], voidfraction ε, face flux φ = (εU)_f·S:

    ∂(εU)/∂t + ∇·(φU) − ∇·(εν∇U) − ∇·(εν dev2((∇U)ᵀ))
        = −k∇p − (Ksl/ρ)(U − Us) + f/ρ,           k = ε (model A) or 1 (models B, Bfull)
    ∂ε/∂t + ∇·φ = 0                                (the ∂ε/∂t term switchable)

  Ksl is implicit (−fvm::Sp(Ksl/ρ, U) + (Ksl/ρ)Us), f explicit. With ε ≡ 1, Ksl ≡ 0, f ≡ 0
  the equations and their discretisation are those of pisoFoam with a laminar (Stokes) model.

  PISO step: momentum matrix with the viscous stress written as pisoFoam's laminar model does,
  optional predictor with the old pressure, then per corrector
    HbyA = H/A,  φ* = ε_f ((HbyA)_f·S + (1/A)_f ddtCorr(U, φ/ε_f))
    ∇·(ε_f (k/A)_f ∇p) = ∇·φ* + ∂ε/∂t,   φ = φ* − ε_f (k/A)_f |S| snGrad p,   U = HbyA − (k/A)∇p;
  on faces next to porous cells (ε < 1 or Ksl > 0) the face coefficient is the series
  resistance of the two half cells, φ* and the face pressure of ∇p are interpolated to match,
  φ* carries the time derivative as the face's own balance with its old flux instead of
  ddtCorr (so the steady state does not depend on Δt), and fixedFluxPressure patches take the
  gradient of the half cell next to them (porousFaces.H). Between clear cells the forms above
  are pisoFoam's.

  fvOptions: meanVelocityForce and CFDEM's meanSupVelocityForce, holding a mean (superficial)
  velocity in periodic channels (meanForceSources.H); other sources are refused.

  Turbulence: constant/turbulenceProperties when present (laminar or RAS, e.g. kEpsilon with
  wall functions), νeff = ν + νt in the stress above (ν → νeff), k–ε solved after the
  correctors on the flux φ as CFDEM's cfdemSolverPiso does; without the file, ν alone.

  Temperature (heat on only; heatTransport.H): cfdemSolverPisoScalar's voidage-weighted
  equation, solved before the momentum equation on this step's ε and the flux ε_f φ_U.

  Fields: U, p as pisoFoam; voidfraction, Ksl, Us, f read from the start time (couplingFields.H)
  and updated each step by the selected couplingSource (couplingSource.H), which also drives
  the time loop (the mpi source: as the coupler commands, mpiCouplingSource.H).
\*---------------------------------------------------------------------------*/

#include "fvCFD.H"
#include "pisoControl.H"
#include "singlePhaseTransportModel.H"
#include "turbulentTransportModel.H"
#include "vansSettings.H"
#include "couplingFields.H"
#include "couplingSource.H"
#include "porousFaces.H"
#include "porousTimeFlux.H"
#include "meanForceSources.H"
#include "heatTransport.H"

int main(int argc, char *argv[])
{
    // Spawned by the coupler (serial): MPI first, so that the coupler's spawn returns.
    grainPisoFoamLink::initSerialMpi(argc, argv);

    argList::addNote
    (
        "Transient incompressible volume-averaged (CFD-DEM) PISO solver of foamgrain:"
        " model A/B, implicit Ksl, explicit f, optional ddt(voidfraction)."
    );

    #include "setRootCase.H"
    #include "createTime.H"
    #include "createMesh.H"

    pisoControl piso(mesh);

    #include "createFields.H"

    // Linked to the coupler: a FatalError is sent to it before the solver stops, so the
    // coupler can name it (see mpiCouplingSource.H).
    mpiCouplingSource* link = dynamic_cast<mpiCouplingSource*>(source.get());
    if (link)
    {
        FatalError.throwExceptions();
        FatalIOError.throwExceptions();
    }

    Info<< "\nStarting time loop\n" << endl;

    // The temperature equation (heatTransport.H), only when heat is on: created inside the
    // try so that a missing 0/T reaches the coupler as a FatalError.
    autoPtr<heatTransport> heat;

    try
    {
        if (source->heat(vans.heat()))
        {
            Info<< "Reading T, Tsource, alphat (heat on)\n" << endl;
            heat.reset(new heatTransport(mesh, vans.nu(), turbulence.get()));
            source->attachHeat(heat->T, heat->Tsource);
        }

        source->start(U, p, phi);

        while (source->advance(runTime))
        {
            Info<< "Time = " << runTime.timeName() << nl << endl;

            source->receive(coupling);
            coupling.checkVoidfraction();

            const surfaceScalarField voidfractionf(fvc::interpolate(voidfraction));

            // ∂ε/∂t of this step (1/s), evaluated once and used by every pressure equation and
            // continuity error: OpenFOAM v1912's CrankNicolson advances its ddt0 field on every
            // fvc::ddt call, so one call per use applied its recursion several times per step
            // (with ψ = 1 and an even number of calls the stored derivative never changed and
            // ∂ε/∂t did not converge with Δt; fv's tests/coupled_time.rs).
            tmp<volScalarField> tddtVoidfraction;
            if (vans.ddtVoidfraction())
            {
                tddtVoidfraction = fvc::ddt(voidfraction);
            }

            #include "interstitialCourantNo.H"

            // Temperature before the PISO, on this step's ε and the flux ε_f φ_U the step
            // starts from, as cfdemSolverPisoScalar (the reason: heatTransport.H). The flux
            // is named phi (unregistered), so its scheme is div(phi,T), as in CFDEM's cases
            // and scalarTransportFoam's.
            if (heat.valid())
            {
                const surfaceScalarField phiT
                (
                    IOobject
                    (
                        "phi", runTime.timeName(), mesh,
                        IOobject::NO_READ, IOobject::NO_WRITE, false
                    ),
                    voidfractionf*phiU
                );
                const tmp<volScalarField> ddtEps
                (
                    tddtVoidfraction.valid()
                  ? tmp<volScalarField>(tddtVoidfraction())
                  : fvc::ddt(voidfraction)
                );
                heat->solve(phiT, voidfraction, ddtEps(), turbulence.get());
            }

            if (vans.solveFlow())
            {
                {
                    #include "UEqn.H"

                    while (piso.correct())
                    {
                        #include "pEqn.H"
                    }
                }

                // The turbulence model after the correctors, as pisoFoam and cfdemSolverPiso.
                if (turbulence.valid())
                {
                    laminarTransport->correct();
                    turbulence->correct();
                }
            }
            else
            {
                Info<< "solveFlow off: U and p held" << nl << endl;
            }

            source->send(U, p, phi);

            meanForces.write();
            runTime.write();

            runTime.printExecutionTime(Info);
        }
    }
    catch (const Foam::error& err)
    {
        OStringStream msg;
        err.write(msg);
        Serr<< msg.str() << endl;
        if (link)
        {
            link->reportError(msg.str());
        }
        // Leave without MPI_Finalize/Pstream::exit: the other ranks may wait in a reduction;
        // the coupler has the message and ends the run.
        std::_Exit(1);
    }

    Info<< "End\n" << endl;

    return 0;
}
