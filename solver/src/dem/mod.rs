//! Discrete elements for moist sand (issue 5): grains joined by pendular liquid bridges. So far
//! the bridge force laws ([`capillary`]); the grain dynamics build on them.

pub mod capillary;
