//! blastsph-solver: the SPH library. It knows no exact answers and no command line; a scene
//! (particles, materials, domain, configuration) drives it through [`Simulation`].
//!
//! Order of operations in one step (see [`step`]): kick → drift → images → neighbours →
//! density → equation of state (times the burn fraction of a detonating charge) → forces → kick →
//! health check.

// `!(x >= limit)` is used on purpose: unlike `x < limit` it is also true for a NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

pub mod axisymmetric;
pub mod block_steps;
pub mod boundary;
pub mod burn;
pub mod dem;
pub mod eos;
pub mod error;
pub mod formulation;
pub mod kernel;
pub mod neighbours;
pub mod operators;
pub mod pairs;
pub mod particles;
pub mod physics;
pub mod radial;
pub mod random;
pub mod step;
pub mod strength;
pub mod total_lagrangian;

pub use boundary::{Boundary, Domain};
pub use burn::ProgrammedBurn;
pub use eos::{Compaction, EquationOfState, IdealGas, Jwl, Material, MieGruneisen, StiffenedGas};
pub use error::SolverError;
pub use formulation::{Density, Formulation, ShellDensity, SmoothingLength};
pub use kernel::{Kernel, KernelShape};
pub use particles::Particles;
pub use physics::{
    ArtificialStress, ArtificialViscosity, EnergyEquation, InterfacePenalty, ViscositySwitch,
};
pub use radial::Geometry;
pub use step::{
    ArtificialHeating, Checkpoint, Departed, ExternalLoad, InitialState, PhaseTimes,
    PrescribedMotion, Simulation, SimulationConfig, TimeSteps,
};
pub use strength::{
    DruckerPrager, JohnsonCook, PlasticHeating, Strength, VonMises, YieldState, YieldSurface,
};

/// A point or vector in D dimensions.
pub type Vector<const D: usize> = nalgebra::SVector<f64, D>;
/// A D×D tensor (the in-plane block of the deviatoric stress, a velocity gradient).
pub type Tensor<const D: usize> = nalgebra::SMatrix<f64, D, D>;
