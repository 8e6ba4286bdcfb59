//! 2D discrete elements: rigid discs with a linear normal spring, a tangential spring capped by
//! Coulomb friction (Cundall & Strack 1979), viscous normal damping and Cundall's local
//! damping, frictionless plane walls moving at prescribed velocities, and pendular liquid
//! bridges ([`super::capillary`]) formed at contact and broken at the rupture gap. Explicit
//! leapfrog in time with the critical step √(m/k_n) times a safety factor.
//!
//! Contacts are found with the SPH neighbour search: a disc's "smoothing length" is its
//! diameter plus twice the largest bridge reach, so every pair that can touch or hold a bridge
//! is listed. Contact and bridge state live in ordered maps keyed by the pair, so the result
//! does not depend on the thread count.

use super::capillary::{
    bridge_force, effective_radius, rupture_gap, BridgeLaw, Liquid, RuptureCriterion,
};
use crate::error::SolverError;
use crate::neighbours::{find_neighbours, PairReach};
use crate::Vector;
use std::collections::BTreeMap;

/// The contact law shared by every pair.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactModel {
    /// k_n (N/m).
    pub normal_stiffness: f64,
    /// k_t (N/m).
    pub tangential_stiffness: f64,
    /// Coulomb coefficient μ between grains.
    pub friction: f64,
    /// ζ: the normal dashpot c_n = 2ζ√(k_n m_eff), so a binary collision has the restitution
    /// e = exp(−πζ/√(1 − ζ²)).
    pub damping_ratio: f64,
    /// Cundall's local damping α: each disc's force is reduced by α|F| against its velocity
    /// (0 for dynamics, about 0.7 for quasi-static loading).
    pub local_damping: f64,
}

impl ContactModel {
    pub fn validate(&self) -> Result<(), SolverError> {
        for (field, value) in [
            ("normal stiffness", self.normal_stiffness),
            ("tangential stiffness", self.tangential_stiffness),
        ] {
            if !(value > 0.0 && value.is_finite()) {
                return Err(SolverError::invalid(field, value, "finite and > 0 (N/m)"));
            }
        }
        if !(self.friction >= 0.0 && self.friction.is_finite()) {
            return Err(SolverError::invalid(
                "friction",
                self.friction,
                "finite and ≥ 0",
            ));
        }
        if !(0.0..1.0).contains(&self.damping_ratio) {
            return Err(SolverError::invalid(
                "damping ratio",
                self.damping_ratio,
                "0 ≤ ζ < 1",
            ));
        }
        if !(0.0..1.0).contains(&self.local_damping) {
            return Err(SolverError::invalid(
                "local damping",
                self.local_damping,
                "0 ≤ α < 1",
            ));
        }
        Ok(())
    }
}

/// A frictionless plane wall: the discs stay on the side its unit normal points to; it moves
/// at a prescribed velocity.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Wall {
    pub point: Vector<2>,
    pub normal: Vector<2>,
    pub velocity: Vector<2>,
}

/// Wet grains: the bridge law, where bridges break, and the liquid: its surface tension and
/// contact angle, and as `liquid.volume` the film each grain carries at the start.
///
/// The liquid is conserved, bridge by bridge (Mani, Kadau & Herrmann 2013 keep it the same
/// way; the halves are this project's rule): a bridge forms when two grains touch and takes
/// half of each grain's film, V = (f_i + f_j)/2; while the grains part it keeps its volume; at
/// its rupture gap it breaks and gives V/2 back to each grain's film.
/// [`Discs::distribute_liquid`] instead shares a given volume among the present contacts in
/// proportion to their centre distances (the source paper's rule for a prepared sample).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Wetting {
    pub law: BridgeLaw,
    pub rupture: RuptureCriterion,
    pub liquid: Liquid,
}

/// A touching pair's tangential spring.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct Contact {
    tangential: Vector<2>,
}

/// The discs (structure of arrays) and their walls, contacts and bridges.
#[derive(Clone, Debug)]
pub struct Discs {
    pub position: Vec<Vector<2>>,
    pub velocity: Vec<Vector<2>>,
    pub angular_velocity: Vec<f64>,
    pub radius: Vec<f64>,
    pub mass: Vec<f64>,
    /// Moment of inertia about the centre.
    pub inertia: Vec<f64>,
    pub force: Vec<Vector<2>>,
    pub torque: Vec<f64>,
    pub walls: Vec<Wall>,
    /// Total force each wall receives from the discs (N).
    pub wall_force: Vec<Vector<2>>,
    model: ContactModel,
    wetting: Option<Wetting>,
    contacts: BTreeMap<(u32, u32), Contact>,
    /// The pairs holding a bridge, and its liquid volume (m³).
    bridges: BTreeMap<(u32, u32), f64>,
    /// Each grain's liquid film (m³), not in any bridge.
    pub film: Vec<f64>,
    pub time: f64,
}

/// The unit-thickness disc of radius r and density ρ: mass ρπr², inertia mr²/2.
pub fn disc_mass(radius: f64, density: f64) -> (f64, f64) {
    let mass = density * std::f64::consts::PI * radius * radius;
    (mass, 0.5 * mass * radius * radius)
}

impl Discs {
    /// Discs at rest at `positions` with `radii` and density ρ (unit thickness).
    pub fn new(
        positions: Vec<Vector<2>>,
        radii: Vec<f64>,
        density: f64,
        model: ContactModel,
        wetting: Option<Wetting>,
    ) -> Result<Self, SolverError> {
        model.validate()?;
        if let Some(w) = &wetting {
            w.liquid.validate()?;
        }
        if positions.len() != radii.len() || positions.is_empty() {
            return Err(SolverError::invalid(
                "discs",
                format!("{} positions, {} radii", positions.len(), radii.len()),
                "as many radii as positions, at least one",
            ));
        }
        if let Some(k) = radii.iter().position(|r| !(*r > 0.0 && r.is_finite())) {
            return Err(SolverError::invalid(
                &format!("disc {k} radius"),
                radii[k],
                "finite and > 0",
            ));
        }
        if !(density > 0.0 && density.is_finite()) {
            return Err(SolverError::invalid(
                "grain density",
                density,
                "finite and > 0",
            ));
        }
        let n = positions.len();
        let (mass, inertia): (Vec<f64>, Vec<f64>) =
            radii.iter().map(|&r| disc_mass(r, density)).unzip();
        Ok(Self {
            position: positions,
            velocity: vec![Vector::zeros(); n],
            angular_velocity: vec![0.0; n],
            radius: radii,
            mass,
            inertia,
            force: vec![Vector::zeros(); n],
            torque: vec![0.0; n],
            walls: Vec::new(),
            wall_force: Vec::new(),
            model,
            wetting,
            contacts: BTreeMap::new(),
            bridges: BTreeMap::new(),
            film: vec![wetting.map_or(0.0, |w| w.liquid.volume); n],
            time: 0.0,
        })
    }

    pub fn len(&self) -> usize {
        self.position.len()
    }

    pub fn is_empty(&self) -> bool {
        self.position.is_empty()
    }

    /// Grows (or shrinks) every disc's radius by `factor`, keeping its density: mass ∝ r²,
    /// inertia ∝ r⁴ (radius expansion).
    pub fn scale_radii(&mut self, factor: f64) {
        for k in 0..self.len() {
            self.radius[k] *= factor;
            self.mass[k] *= factor * factor;
            self.inertia[k] *= factor.powi(4);
        }
    }

    /// Contacts per disc (with discs and walls), counting only discs with at least two (a
    /// rattler carries no load).
    pub fn coordination(&self) -> f64 {
        let mut per_disc = vec![0usize; self.len()];
        for &(i, j) in self.contacts.keys() {
            per_disc[i as usize] += 1;
            per_disc[j as usize] += 1;
        }
        for wall in &self.walls {
            for (k, count) in per_disc.iter_mut().enumerate() {
                if (self.position[k] - wall.point).dot(&wall.normal) < self.radius[k] {
                    *count += 1;
                }
            }
        }
        let carrying: Vec<usize> = per_disc.into_iter().filter(|&c| c >= 2).collect();
        carrying.iter().sum::<usize>() as f64 / carrying.len().max(1) as f64
    }

    /// k_n of the contact model (N/m).
    pub fn normal_stiffness(&self) -> f64 {
        self.model.normal_stiffness
    }

    pub fn add_wall(&mut self, wall: Wall) {
        self.walls.push(Wall {
            normal: wall.normal.normalize(),
            ..wall
        });
        self.wall_force.push(Vector::zeros());
    }

    /// The number of pairs in contact (overlapping) and of bridges.
    pub fn counts(&self) -> (usize, usize) {
        (self.contacts.len(), self.bridges.len())
    }

    /// The stable step: √(m_min/k_n) times `safety` (a lone spring's leapfrog limit is
    /// 2√(m_eff/k); a disc among several contacts feels their sum, hence a safety ≤ 0.2).
    pub fn critical_time_step(&self, safety: f64) -> f64 {
        let m_min = self.mass.iter().cloned().fold(f64::INFINITY, f64::min);
        safety * (m_min / self.model.normal_stiffness).sqrt()
    }

    /// The liquid in bridges and films together (m³): constant while bridges form and break.
    pub fn total_liquid(&self) -> f64 {
        self.bridges.values().sum::<f64>() + self.film.iter().sum::<f64>()
    }

    /// The liquid volume of each bridge, by pair.
    pub fn bridge_volumes(&self) -> impl Iterator<Item = ((usize, usize), f64)> + '_ {
        self.bridges
            .iter()
            .map(|(&(i, j), &v)| ((i as usize, j as usize), v))
    }

    /// Puts `volume` (m³) into bridges at the pairs now in contact, shared in proportion to
    /// their centre-to-centre distances, and empties the films (the source paper's rule for the
    /// pore water of a prepared sample). An error if the grains are dry or none touch.
    pub fn distribute_liquid(&mut self, volume: f64) -> Result<(), SolverError> {
        if self.wetting.is_none() {
            return Err(SolverError::invalid(
                "wetting",
                "none",
                "wet grains to hold liquid",
            ));
        }
        if !(volume > 0.0 && volume.is_finite()) {
            return Err(SolverError::invalid(
                "liquid volume",
                volume,
                "finite and > 0 (m³)",
            ));
        }
        let distance =
            |&(i, j): &(u32, u32)| (self.position[j as usize] - self.position[i as usize]).norm();
        let total: f64 = self.contacts.keys().map(distance).sum();
        if total == 0.0 {
            return Err(SolverError::invalid(
                "contacts",
                0,
                "at least one to hold liquid",
            ));
        }
        self.bridges = self
            .contacts
            .keys()
            .map(|key| (*key, volume * distance(key) / total))
            .collect();
        self.film.iter_mut().for_each(|f| *f = 0.0);
        Ok(())
    }

    /// The wetting and the liquid of a bridge of `volume`.
    fn bridge_liquid(&self, volume: f64) -> Option<(Wetting, Liquid)> {
        self.wetting.map(|w| (w, Liquid { volume, ..w.liquid }))
    }

    /// Forces and torques of the current positions and velocities (contacts, bridges,
    /// walls); contact springs advance by `dt`; bridges form, keep or break (see [`Wetting`]).
    pub fn compute_forces(&mut self, dt: f64) {
        let n = self.len();
        for k in 0..n {
            self.force[k] = Vector::zeros();
            self.torque[k] = 0.0;
        }
        // the search reaches every contact and every standing bridge (Willett's rupture gap
        // is largest for the smallest radius)
        let r_min = self.radius.iter().cloned().fold(f64::INFINITY, f64::min);
        let margin = self
            .bridges
            .values()
            .filter_map(|&v| self.bridge_liquid(v))
            .map(|(w, liquid)| rupture_gap(w.rupture, &liquid, r_min))
            .fold(0.0, f64::max);
        // pairs within r_i + r_j + margin: (reach_i + reach_j)/2 with reach = 2r + margin
        let reach: Vec<f64> = self.radius.iter().map(|r| 2.0 * r + margin).collect();
        let neighbours = find_neighbours(&self.position, &reach, 1.0, PairReach::MeanH, n);
        let mut contacts = BTreeMap::new();
        let mut bridges = BTreeMap::new();
        for i in 0..n {
            for j in neighbours.of(i).filter(|&j| j > i) {
                let key = (i as u32, j as u32);
                let (ri, rj) = (self.radius[i], self.radius[j]);
                let d_vec = self.position[j] - self.position[i];
                let d = d_vec.norm();
                let normal = d_vec / d;
                let gap = d - ri - rj;
                if gap < 0.0 {
                    let previous = self.contacts.get(&key).copied().unwrap_or_default();
                    let contact = self.contact_force(i, j, normal, -gap, previous, dt);
                    contacts.insert(key, contact);
                }
                if self.wetting.is_none() {
                    continue;
                }
                // a standing bridge keeps its liquid; a new one forms at contact from the films
                let volume = match self.bridges.get(&key) {
                    Some(&v) => v,
                    None if gap < 0.0 && self.film[i] + self.film[j] > 0.0 => {
                        let v = 0.5 * (self.film[i] + self.film[j]);
                        self.film[i] *= 0.5;
                        self.film[j] *= 0.5;
                        v
                    }
                    None => continue,
                };
                let (w, liquid) = self.bridge_liquid(volume).expect("wet grains");
                let radius = effective_radius(ri, rj);
                if gap < rupture_gap(w.rupture, &liquid, radius) {
                    let f = bridge_force(w.law, &liquid, radius, gap) * normal;
                    self.force[i] += f;
                    self.force[j] -= f;
                    bridges.insert(key, volume);
                }
            }
        }
        // every bridge that did not survive (beyond its rupture gap, or out of the search
        // altogether) gives half of its liquid back to each grain
        for (&(i, j), &volume) in &self.bridges {
            if !bridges.contains_key(&(i, j)) {
                self.film[i as usize] += 0.5 * volume;
                self.film[j as usize] += 0.5 * volume;
            }
        }
        self.contacts = contacts;
        self.bridges = bridges;
        self.wall_forces();
        self.local_damping();
    }

    /// The contact force between overlapping i and j (overlap δ > 0, unit normal from i to
    /// j), added to both; returns the advanced tangential spring.
    fn contact_force(
        &mut self,
        i: usize,
        j: usize,
        normal: Vector<2>,
        overlap: f64,
        previous: Contact,
        dt: f64,
    ) -> Contact {
        let m = &self.model;
        let tangent = Vector::<2>::new(-normal[1], normal[0]);
        let (ri, rj) = (self.radius[i], self.radius[j]);
        // the velocity of j's contact point relative to i's (ω × r in 2D: ω(−r_y, r_x))
        let relative = (self.velocity[j] - self.velocity[i])
            - tangent * (self.angular_velocity[j] * rj + self.angular_velocity[i] * ri);
        let normal_speed = relative.dot(&normal);
        let m_eff = self.mass[i] * self.mass[j] / (self.mass[i] + self.mass[j]);
        let dashpot = 2.0 * m.damping_ratio * (m.normal_stiffness * m_eff).sqrt();
        // repulsive only: the dashpot may not pull the discs together
        let normal_force = (m.normal_stiffness * overlap - dashpot * normal_speed).max(0.0);
        // the tangential spring, kept in the current tangent line, then capped at μ F_n
        let mut spring = previous.tangential - normal * previous.tangential.dot(&normal);
        spring += (relative - normal * normal_speed) * dt;
        let mut tangential = spring * m.tangential_stiffness;
        let limit = m.friction * normal_force;
        if tangential.norm() > limit {
            tangential *= limit / tangential.norm();
            spring = tangential / m.tangential_stiffness;
        }
        let on_i = -normal * normal_force + tangential;
        self.force[i] += on_i;
        self.force[j] -= on_i;
        // torque r × f about each centre: i's contact point at +r_i n, j's at −r_j n
        let cross = |r: Vector<2>, f: Vector<2>| r[0] * f[1] - r[1] * f[0];
        self.torque[i] += cross(normal * ri, tangential);
        self.torque[j] += cross(-normal * rj, -tangential);
        Contact { tangential: spring }
    }

    /// Frictionless walls: a normal spring and dashpot on each disc that crosses one.
    fn wall_forces(&mut self) {
        let m = self.model;
        for (w, wall) in self.walls.iter().enumerate() {
            let mut total = Vector::zeros();
            for k in 0..self.position.len() {
                let distance = (self.position[k] - wall.point).dot(&wall.normal);
                let overlap = self.radius[k] - distance;
                if overlap > 0.0 {
                    let speed = (self.velocity[k] - wall.velocity).dot(&wall.normal);
                    let dashpot =
                        2.0 * m.damping_ratio * (m.normal_stiffness * self.mass[k]).sqrt();
                    let push = (m.normal_stiffness * overlap - dashpot * speed).max(0.0);
                    self.force[k] += wall.normal * push;
                    total -= wall.normal * push;
                }
            }
            self.wall_force[w] = total;
        }
    }

    /// Cundall's local damping: F −= α|F| sign(v) per component (and for the torque).
    fn local_damping(&mut self) {
        let alpha = self.model.local_damping;
        if alpha == 0.0 {
            return;
        }
        for k in 0..self.len() {
            for a in 0..2 {
                let f = self.force[k][a];
                self.force[k][a] -= alpha * f.abs() * self.velocity[k][a].signum();
            }
            let t = self.torque[k];
            self.torque[k] -= alpha * t.abs() * self.angular_velocity[k].signum();
        }
    }

    /// One leapfrog step: forces at the current state (velocities at the half step), then
    /// v += F/m dt, x += v dt, walls move.
    pub fn step(&mut self, dt: f64) -> Result<(), SolverError> {
        self.compute_forces(dt);
        for k in 0..self.len() {
            self.velocity[k] += self.force[k] * (dt / self.mass[k]);
            self.angular_velocity[k] += self.torque[k] * (dt / self.inertia[k]);
            self.position[k] += self.velocity[k] * dt;
            if !self.position[k].iter().all(|x| x.is_finite()) {
                return Err(SolverError::invalid(
                    &format!("disc {k} position at t = {:e}", self.time),
                    "non-finite",
                    "finite (reduce the time step)",
                ));
            }
        }
        for wall in &mut self.walls {
            wall.point += wall.velocity * dt;
        }
        self.time += dt;
        Ok(())
    }

    /// Kinetic energy (translation and rotation).
    pub fn kinetic_energy(&self) -> f64 {
        (0..self.len())
            .map(|k| {
                0.5 * self.mass[k] * self.velocity[k].norm_squared()
                    + 0.5 * self.inertia[k] * self.angular_velocity[k].powi(2)
            })
            .sum()
    }
}
