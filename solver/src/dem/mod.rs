//! Discrete elements for moist sand (issue 5): grains joined by pendular liquid bridges. The
//! bridge force laws ([`capillary`]) and 2D disc dynamics with contacts, walls and bridges
//! ([`discs`]).

pub mod capillary;
pub mod discs;
