//! Sample preparation for disc assemblies: a seeded, graded size distribution and a loose
//! non-overlapping placement in a rectangle, the start of radius expansion (the discs then grow
//! inside walls until the packing is dense).

use crate::error::SolverError;
use crate::random::SplitMix64;
use crate::Vector;

/// `n` diameters between d_min and d_max graded with many small and few large grains: the
/// number density of diameters falls as 1/d² (uniform in 1/d), so that the grains of each
/// size class cover comparable areas.
pub fn graded_diameters(
    n: usize,
    d_min: f64,
    d_max: f64,
    rng: &mut SplitMix64,
) -> Result<Vec<f64>, SolverError> {
    if !(d_min > 0.0 && d_max > d_min && d_max.is_finite()) {
        return Err(SolverError::invalid(
            "grain diameters",
            format!("{d_min}..{d_max}"),
            "0 < d_min < d_max",
        ));
    }
    let (lo, hi) = (1.0 / d_max, 1.0 / d_min);
    Ok((0..n)
        .map(|_| 1.0 / (lo + (hi - lo) * rng.uniform()))
        .collect())
}

/// Random sequential placement: each disc of radius `scale`·r_k at a uniformly drawn point of
/// the rectangle [0, width] × [0, height] that keeps it inside and off every disc placed
/// before (up to `attempts` draws each). Returns the centres, or an error naming the disc that
/// found no room (lower `scale`).
pub fn place_without_overlap(
    radii: &[f64],
    (width, height): (f64, f64),
    scale: f64,
    attempts: usize,
    rng: &mut SplitMix64,
) -> Result<Vec<Vector<2>>, SolverError> {
    let mut placed: Vec<(Vector<2>, f64)> = Vec::with_capacity(radii.len());
    // the largest discs first: they are the hardest to fit
    let mut order: Vec<usize> = (0..radii.len()).collect();
    order.sort_by(|&a, &b| radii[b].total_cmp(&radii[a]));
    let mut centres = vec![Vector::zeros(); radii.len()];
    for &k in &order {
        let r = scale * radii[k];
        let spot = (0..attempts).find_map(|_| {
            let x = Vector::<2>::new(
                r + (width - 2.0 * r) * rng.uniform(),
                r + (height - 2.0 * r) * rng.uniform(),
            );
            placed
                .iter()
                .all(|(y, s)| (x - y).norm() >= r + s)
                .then_some(x)
        });
        let Some(x) = spot else {
            return Err(SolverError::invalid(
                &format!("placement of disc {k}"),
                format!("no room after {attempts} tries"),
                "a smaller initial radius scale or a larger box",
            ));
        };
        placed.push((x, r));
        centres[k] = x;
    }
    Ok(centres)
}

/// Where radius expansion stopped.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Expansion {
    /// Mean normal stress on the walls ½(σ_xx + σ_yy) (Pa, over the layer thickness).
    pub wall_stress: f64,
    /// 1 − (grain cross-sections)/(box area), in the plane.
    pub porosity: f64,
    /// Mean contacts per load-carrying disc.
    pub coordination: f64,
    pub steps: usize,
}

/// Radius expansion inside the four walls of a `width` × `height` box (already added to the
/// discs, in the order left, right, bottom, top): cycles of `steps_per_cycle` steps, after each
/// of which the radii grow by a factor 1 + g. While the mean wall stress p is below 5 % of the
/// target the packing is loose and g = `growth`; then g = ½ (δ/r)(1 − p/p_target), where
/// δ/r = 2 p_target t/k_n is the overlap per radius that carries the target stress (t the
/// layer thickness): a cycle never presses the grains by more than half the overlap they will
/// hold, so the stress does not overshoot the target several times over and then relax by
/// rearrangement. Stops when p has stayed within 2 % of the target for five cycles in a row
/// (local damping in the contact model keeps the loading quasi-static; a lone rattler may
/// still drift, so the test is on the stress, not on the kinetic energy). Gives up with a
/// named error after `max_cycles`.
pub fn expand_to_stress(
    discs: &mut super::discs::Discs,
    (width, height): (f64, f64),
    target_stress: f64,
    (growth, steps_per_cycle, max_cycles): (f64, usize, usize),
) -> Result<Expansion, SolverError> {
    if discs.walls.len() != 4 {
        return Err(SolverError::invalid(
            "walls",
            discs.walls.len(),
            "4 (left, right, bottom, top) for radius expansion",
        ));
    }
    let dt = discs.critical_time_step(0.2);
    let (mut steps, mut steady) = (0, 0);
    for _ in 0..max_cycles {
        for _ in 0..steps_per_cycle {
            discs.step(dt)?;
        }
        steps += steps_per_cycle;
        let f = &discs.wall_force;
        let t = discs.layer_thickness();
        let sigma_xx = 0.5 * (f[0][0].abs() + f[1][0].abs()) / (height * t);
        let sigma_yy = 0.5 * (f[2][1].abs() + f[3][1].abs()) / (width * t);
        let stress = 0.5 * (sigma_xx + sigma_yy);
        steady = if (stress / target_stress - 1.0).abs() < 0.02 {
            steady + 1
        } else {
            0
        };
        if steady == 5 {
            return Ok(Expansion {
                wall_stress: stress,
                porosity: 1.0 - discs.grain_area() / (width * height),
                coordination: discs.coordination(),
                steps,
            });
        }
        let fine = 2.0 * target_stress * discs.layer_thickness() / discs.normal_stiffness();
        let g = if stress < 0.05 * target_stress {
            growth
        } else {
            0.5 * fine * (1.0 - stress / target_stress).max(-1.0)
        };
        discs.scale_radii(1.0 + g)?;
    }
    Err(SolverError::invalid(
        "radius expansion",
        format!("not within 2 % of {target_stress} Pa after {max_cycles} cycles"),
        "more cycles or a larger growth",
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Diameters stay in range, the small outnumber the large (the lower third of the range,
    /// below 0.233 mm, holds (1/0.1 − 1/0.2333)/(1/0.1 − 1/0.5) = 71.4 % of the grains for a 1/d²
    /// density; 4000 draws land within 3 % of it), and the same seed gives the same sample.
    #[test]
    fn graded_diameters_are_in_range_and_mostly_small() {
        let mut rng = SplitMix64::new(7);
        let d = graded_diameters(4000, 1e-4, 5e-4, &mut rng).unwrap();
        assert!(d.iter().all(|&x| (1e-4..=5e-4).contains(&x)));
        let small = d
            .iter()
            .filter(|&&x| x < 1e-4 + (5e-4 - 1e-4) / 3.0)
            .count();
        let share = small as f64 / d.len() as f64;
        assert!((share - 0.714).abs() < 0.03, "{share}");
        let again = graded_diameters(4000, 1e-4, 5e-4, &mut SplitMix64::new(7)).unwrap();
        assert_eq!(d, again);
    }

    /// A range is 0 < d_min < d_max < ∞: reversed, empty, starting at zero or open-ended
    /// ranges are refused by name.
    #[test]
    fn a_range_of_diameters_must_be_finite_and_positive() {
        let mut rng = SplitMix64::new(7);
        for (d_min, d_max) in [
            (5e-4, 1e-4),
            (1e-4, 1e-4),
            (0.0, 1e-4),
            (-1e-4, 1e-4),
            (1e-4, f64::INFINITY),
            (f64::NAN, 1e-4),
        ] {
            let error = graded_diameters(10, d_min, d_max, &mut rng).unwrap_err();
            assert!(error.to_string().contains("grain diameters"), "{error}");
        }
        assert!(graded_diameters(10, 1e-4, 1.0001e-4, &mut rng).is_ok());
    }

    /// A loose placement has no overlaps and keeps every disc inside the box.
    #[test]
    fn placement_leaves_no_overlap() {
        let mut rng = SplitMix64::new(3);
        let radii: Vec<f64> = graded_diameters(300, 1e-4, 5e-4, &mut rng)
            .unwrap()
            .iter()
            .map(|d| 0.5 * d)
            .collect();
        let (w, h) = (6e-3, 12e-3);
        let x = place_without_overlap(&radii, (w, h), 0.6, 1000, &mut rng).unwrap();
        for i in 0..x.len() {
            let r = 0.6 * radii[i];
            assert!(x[i][0] >= r && x[i][0] <= w - r && x[i][1] >= r && x[i][1] <= h - r);
            for j in 0..i {
                assert!((x[i] - x[j]).norm() >= r + 0.6 * radii[j] - 1e-15);
            }
        }
    }

    /// The largest disc goes first: one disc of radius 0.45 fits a unit box only while the
    /// box is empty (its centre within 0.05 of the middle along each axis), and forty of radius 0.02 fit
    /// around it in the corners; placed after them, it would find a small disc in its way.
    #[test]
    fn the_largest_disc_is_placed_first() {
        let mut radii = vec![0.02; 40];
        radii.insert(17, 0.45);
        let placed =
            place_without_overlap(&radii, (1.0, 1.0), 1.0, 10_000, &mut SplitMix64::new(5));
        assert!(placed.is_ok(), "{placed:?}");
    }

    /// A box too small for a disc is named, with the disc, rather than left half-filled.
    #[test]
    fn a_disc_without_room_is_named() {
        let error =
            place_without_overlap(&[0.3, 0.3], (1.0, 1.0), 1.0, 1000, &mut SplitMix64::new(1))
                .unwrap_err();
        assert!(error.to_string().contains("placement of disc"), "{error}");
    }
}
