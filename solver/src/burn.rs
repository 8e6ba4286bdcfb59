//! Programmed burn of a high explosive (Wilkins 1964; the hydrocode standard for JWL charges):
//! each explosive particle lights at the time the detonation front, running at D_CJ from the
//! nearest detonation point, reaches it; after that its burn fraction F rises linearly to one
//! while the front crosses a ramp of `ramp_lengths` smoothing lengths, and its pressure is
//! F·p_JWL(ρ, e). The detonation energy is in e from the start, so the burn moves no energy:
//! it only releases pressure in the order the front sets.

use crate::error::SolverError;
use crate::Vector;

/// The default ramp: two smoothing lengths, enough to spread the front over the four or so
/// particles the kernel needs to carry a jump without ringing.
pub const DEFAULT_RAMP_LENGTHS: f64 = 2.0;

#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ProgrammedBurn {
    /// Lighting time of each particle (in the order of the particles given to the simulation);
    /// −∞ for particles that are not explosive (they carry their full pressure throughout).
    pub lighting_time: Vec<f64>,
    /// Detonation speed D_CJ (m/s).
    pub speed: f64,
    /// Width of the burn ramp in smoothing lengths.
    pub ramp_lengths: f64,
}

impl ProgrammedBurn {
    /// Lighting times t_i = min_k |x_i − x_k| / D for the particles where `is_explosive` holds,
    /// from detonation points x_k lit at t = 0.
    pub fn from_points<const D: usize>(
        positions: &[Vector<D>],
        is_explosive: impl Fn(usize) -> bool,
        detonation_points: &[Vector<D>],
        speed: f64,
        ramp_lengths: f64,
    ) -> Result<Self, SolverError> {
        if detonation_points.is_empty() {
            return Err(SolverError::invalid("detonation points", 0, "at least one"));
        }
        if !(speed > 0.0 && speed.is_finite()) {
            return Err(SolverError::invalid(
                "detonation speed",
                speed,
                "finite and > 0",
            ));
        }
        if !(ramp_lengths > 0.0 && ramp_lengths <= 10.0) {
            return Err(SolverError::invalid(
                "burn ramp",
                ramp_lengths,
                "0 < ramp ≤ 10 smoothing lengths",
            ));
        }
        let lighting_time = positions
            .iter()
            .enumerate()
            .map(|(i, x)| {
                if is_explosive(i) {
                    detonation_points
                        .iter()
                        .map(|p| (x - p).norm())
                        .fold(f64::INFINITY, f64::min)
                        / speed
                } else {
                    f64::NEG_INFINITY
                }
            })
            .collect();
        Ok(Self {
            lighting_time,
            speed,
            ramp_lengths,
        })
    }

    /// The burn fraction at time t of a particle lit at `lighting_time` with smoothing length h.
    #[inline]
    pub fn fraction(&self, time: f64, lighting_time: f64, h: f64) -> f64 {
        ((time - lighting_time) * self.speed / (self.ramp_lengths * h)).clamp(0.0, 1.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lighting_follows_the_nearest_point_at_the_detonation_speed() {
        let x: Vec<Vector<1>> = [0.0, 1.0, 3.0, 5.0]
            .iter()
            .map(|&v| Vector::<1>::new(v))
            .collect();
        let points = [Vector::<1>::new(0.0), Vector::<1>::new(4.0)];
        let burn = ProgrammedBurn::from_points(&x, |i| i < 3, &points, 2.0, 2.0).unwrap();
        assert_eq!(burn.lighting_time[..3], [0.0, 0.5, 0.5]);
        assert_eq!(burn.lighting_time[3], f64::NEG_INFINITY);
        // the fraction ramps from 0 at lighting to 1 after the front has crossed 2h
        assert_eq!(burn.fraction(0.4, 0.5, 0.1), 0.0);
        assert!((burn.fraction(0.55, 0.5, 0.1) - 0.5).abs() < 1e-12);
        assert_eq!(burn.fraction(1.0, 0.5, 0.1), 1.0);
    }

    #[test]
    fn bad_burn_input_is_named() {
        let x = [Vector::<1>::new(0.0)];
        let err = ProgrammedBurn::from_points(&x, |_| true, &[], 1.0, 2.0).unwrap_err();
        assert!(err.to_string().contains("detonation points"));
        let p = [Vector::<1>::new(0.0)];
        // a charge that never detonates, or never finishes, is refused
        for speed in [-1.0, 0.0, f64::INFINITY] {
            let err = ProgrammedBurn::from_points(&x, |_| true, &p, speed, 2.0).unwrap_err();
            assert!(err.to_string().contains("detonation speed"), "{speed}");
        }
        for ramp in [0.0, 10.5] {
            let err = ProgrammedBurn::from_points(&x, |_| true, &p, 1.0, ramp).unwrap_err();
            assert!(err.to_string().contains("burn ramp"), "{ramp}");
        }
        assert!(ProgrammedBurn::from_points(&x, |_| true, &p, 1.0, 10.0).is_ok());
    }
}
