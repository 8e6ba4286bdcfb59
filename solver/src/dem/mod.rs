//! Discrete elements for moist sand: grains joined by pendular liquid bridges. The
//! bridge force laws ([`capillary`]), 2D disc dynamics with contacts, walls and bridges
//! ([`discs`]), sample preparation ([`sample`]), the biaxial test ([`biaxial`]) and the
//! Mohr–Coulomb fit of failure states ([`strength_fit`]).

pub mod biaxial;
pub mod capillary;
pub mod discs;
pub mod sample;
pub mod strength_fit;
