//! 2D discrete elements: rigid spheres moving in a plane (a monolayer; the "2D discs" of PFC2D
//! with sphere masses) with a linear normal spring, a tangential spring capped by Coulomb
//! friction (Cundall & Strack 1979), viscous normal damping and Cundall's local damping,
//! frictionless plane walls moving at prescribed velocities, and pendular liquid bridges
//! ([`super::capillary`]) formed at contact and broken at the rupture gap. Explicit leapfrog in
//! time with the critical step √(m/k_n) times a safety factor.
//!
//! The grains may be joined by boundary particles (a membrane, [`super::biaxial`]): those touch
//! grains without friction or liquid and ignore one another.
//!
//! Pairs come from a Verlet list: the SPH neighbour search lists every pair within the contact
//! distance plus the largest bridge's rupture gap plus a skin, and the list is rebuilt only
//! when some particle has moved more than half the skin. Contact and bridge state live in the
//! list, sorted by pair, and the force loop runs in that order, so the result does not depend
//! on the thread count.

use super::capillary::{
    effective_radius, rupture_gap, Bridge, BridgeLaw, Liquid, RuptureCriterion,
};
use crate::error::SolverError;
use crate::neighbours::{find_neighbours, PairReach};
use crate::Vector;

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
/// contact angle, and as `liquid.volume` the film each grain carries at the start (0 for
/// grains whose liquid is put into bridges by [`Discs::distribute_liquid`]).
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

/// One listed pair: its normal dashpot, its tangential spring while the two touch, and its
/// bridge if it has one.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Pair {
    i: u32,
    j: u32,
    touching: bool,
    /// The normal dashpot 2ζ√(k_n m_eff), m_eff = m_i m_j/(m_i + m_j) (N·s/m).
    dashpot: f64,
    tangential: Vector<2>,
    bridge: Option<Bridge>,
}

impl Pair {
    fn new(i: u32, j: u32, dashpot: f64) -> Self {
        Self {
            i,
            j,
            touching: false,
            dashpot,
            tangential: Vector::zeros(),
            bridge: None,
        }
    }
}

/// The grains (structure of arrays), then the boundary particles, and their walls, pairs and
/// bridges.
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
    /// Total force each wall receives from the particles (N).
    pub wall_force: Vec<Vector<2>>,
    /// Each grain's liquid film (m³), not in any bridge (0 for boundary particles).
    pub film: Vec<f64>,
    pub time: f64,
    /// Particles 0..grains are grains; the rest are boundary particles.
    grains: usize,
    model: ContactModel,
    wetting: Option<Wetting>,
    /// The Verlet list, sorted by (i, j), i < j.
    pairs: Vec<Pair>,
    /// Positions when the list was built; `None` forces a rebuild.
    listed_at: Option<Vec<Vector<2>>>,
    /// The list's margin beyond contact and rupture (m).
    skin: f64,
}

/// |v| > limit (≥ 0), exactly as the rounded norm compares, without the square root where
/// |v|² lies clearly below limit²: a sticking contact's spring (most contacts) skips the
/// square root's latency.
#[inline]
fn exceeds(v: &Vector<2>, limit: f64) -> bool {
    // 1e-12 below limit², far beyond the rounding of either side, |v| is certainly below limit
    v.norm_squared() >= limit * limit * (1.0 - 1e-12) && v.norm() > limit
}

/// A sphere of radius r and density ρ: mass 4πr³ρ/3, inertia 2mr²/5.
pub fn sphere_mass(radius: f64, density: f64) -> (f64, f64) {
    let mass = 4.0 / 3.0 * std::f64::consts::PI * radius.powi(3) * density;
    (mass, 0.4 * mass * radius * radius)
}

impl Discs {
    /// Grains at rest at `positions` with `radii` and density ρ.
    pub fn new(
        positions: Vec<Vector<2>>,
        radii: Vec<f64>,
        density: f64,
        model: ContactModel,
        wetting: Option<Wetting>,
    ) -> Result<Self, SolverError> {
        model.validate()?;
        if let Some(w) = &wetting {
            // dry films are allowed: only the liquid's properties need checking
            let volume = if w.liquid.volume == 0.0 {
                1.0
            } else {
                w.liquid.volume
            };
            Liquid { volume, ..w.liquid }.validate()?;
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
            radii.iter().map(|&r| sphere_mass(r, density)).unzip();
        let r_min = radii.iter().cloned().fold(f64::INFINITY, f64::min);
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
            film: vec![wetting.map_or(0.0, |w| w.liquid.volume); n],
            time: 0.0,
            grains: n,
            model,
            wetting,
            pairs: Vec::new(),
            listed_at: None,
            // a fifth of the smallest radius: rebuilt every few thousand steps when loading
            // quasi-statically, and a pair list only slightly longer than the contacts
            skin: 0.2 * r_min,
        })
    }

    /// All particles, grains and boundary.
    pub fn len(&self) -> usize {
        self.position.len()
    }

    pub fn is_empty(&self) -> bool {
        self.position.is_empty()
    }

    /// The number of grains (they come first).
    pub fn grains(&self) -> usize {
        self.grains
    }

    /// Appends a boundary particle at rest: it touches grains without friction or liquid and
    /// ignores other boundary particles. Returns its index.
    pub fn add_boundary_particle(&mut self, position: Vector<2>, radius: f64, mass: f64) -> usize {
        self.position.push(position);
        self.velocity.push(Vector::zeros());
        self.angular_velocity.push(0.0);
        self.radius.push(radius);
        self.mass.push(mass);
        self.inertia.push(0.4 * mass * radius * radius);
        self.force.push(Vector::zeros());
        self.torque.push(0.0);
        self.film.push(0.0);
        self.listed_at = None;
        self.len() - 1
    }

    /// The thickness of the layer the grains form, for stresses: one mean grain diameter.
    pub fn layer_thickness(&self) -> f64 {
        2.0 * self.radius[..self.grains].iter().sum::<f64>() / self.grains as f64
    }

    /// Area of the grains' cross-sections, Σπr² (m²).
    pub fn grain_area(&self) -> f64 {
        self.radius[..self.grains]
            .iter()
            .map(|r| std::f64::consts::PI * r * r)
            .sum()
    }

    /// Volume of the grains, Σ4πr³/3 (m³).
    pub fn grain_volume(&self) -> f64 {
        self.radius[..self.grains]
            .iter()
            .map(|r| 4.0 / 3.0 * std::f64::consts::PI * r.powi(3))
            .sum()
    }

    /// Grows (or shrinks) every grain's radius by `factor`, keeping its density: mass ∝ r³,
    /// inertia ∝ r⁵ (radius expansion).
    pub fn scale_radii(&mut self, factor: f64) -> Result<(), SolverError> {
        for k in 0..self.grains {
            self.radius[k] *= factor;
            self.mass[k] *= factor.powi(3);
            self.inertia[k] *= factor.powi(5);
        }
        // a pair's dashpot depends on its masses, a bridge's law on its pair's radius
        for p in 0..self.pairs.len() {
            let (i, j) = (self.pairs[p].i as usize, self.pairs[p].j as usize);
            self.pairs[p].dashpot = self.dashpot(i, j);
            if let Some(bridge) = self.pairs[p].bridge {
                self.pairs[p].bridge = Some(self.bridge(i, j, bridge.liquid)?);
            }
        }
        self.listed_at = None;
        Ok(())
    }

    /// Sets Cundall's local damping α from now on (a packing settles fastest under heavy
    /// damping; a test that deforms it may need less, see [`crate::dem::biaxial`]).
    pub fn set_local_damping(&mut self, alpha: f64) -> Result<(), SolverError> {
        let model = ContactModel {
            local_damping: alpha,
            ..self.model
        };
        model.validate()?;
        self.model = model;
        Ok(())
    }

    /// Contacts per grain (with grains, boundary particles and walls), counting only grains
    /// with at least two (a rattler carries no load).
    pub fn coordination(&self) -> f64 {
        let mut per_grain = vec![0usize; self.grains];
        for pair in self.pairs.iter().filter(|p| p.touching) {
            for k in [pair.i as usize, pair.j as usize] {
                if k < self.grains {
                    per_grain[k] += 1;
                }
            }
        }
        for wall in &self.walls {
            for (k, count) in per_grain.iter_mut().enumerate() {
                if (self.position[k] - wall.point).dot(&wall.normal) < self.radius[k] {
                    *count += 1;
                }
            }
        }
        let carrying: Vec<usize> = per_grain.into_iter().filter(|&c| c >= 2).collect();
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
        let touching = self.pairs.iter().filter(|p| p.touching).count();
        (touching, self.bridge_volumes().count())
    }

    /// The stable step: √(m_min/k_n) times `safety` (a lone spring's leapfrog limit is
    /// 2√(m_eff/k); a particle among several contacts feels their sum, hence a safety ≤ 0.2).
    pub fn critical_time_step(&self, safety: f64) -> f64 {
        let m_min = self.mass.iter().cloned().fold(f64::INFINITY, f64::min);
        safety * (m_min / self.model.normal_stiffness).sqrt()
    }

    /// The liquid in bridges and films together (m³): constant while bridges form and break.
    pub fn total_liquid(&self) -> f64 {
        self.bridge_volumes().map(|(_, v)| v).sum::<f64>() + self.film.iter().sum::<f64>()
    }

    /// The liquid volume of each bridge, by pair.
    pub fn bridge_volumes(&self) -> impl Iterator<Item = ((usize, usize), f64)> + '_ {
        self.pairs
            .iter()
            .filter_map(|p| Some(((p.i as usize, p.j as usize), p.bridge?.liquid.volume)))
    }

    /// Puts `volume` (m³) into bridges at the grain pairs now in contact, shared in proportion
    /// to their centre-to-centre distances, and empties the films (the source paper's rule for
    /// the pore water of a prepared sample). An error if the grains are dry or none touch.
    pub fn distribute_liquid(&mut self, volume: f64) -> Result<(), SolverError> {
        let Some(w) = self.wetting else {
            return Err(SolverError::invalid(
                "wetting",
                "none",
                "wet grains to hold liquid",
            ));
        };
        if !(volume > 0.0 && volume.is_finite()) {
            return Err(SolverError::invalid(
                "liquid volume",
                volume,
                "finite and > 0 (m³)",
            ));
        }
        let grains = self.grains as u32;
        let wet = |p: &Pair| p.touching && p.j < grains;
        let distance =
            |p: &Pair| (self.position[p.j as usize] - self.position[p.i as usize]).norm();
        let total: f64 = self.pairs.iter().filter(|p| wet(p)).map(distance).sum();
        if total == 0.0 {
            return Err(SolverError::invalid(
                "contacts",
                0,
                "at least one to hold liquid",
            ));
        }
        let bridges: Vec<Option<Bridge>> = self
            .pairs
            .iter()
            .map(|p| {
                wet(p)
                    .then(|| {
                        let liquid = Liquid {
                            volume: volume * distance(p) / total,
                            ..w.liquid
                        };
                        self.bridge(p.i as usize, p.j as usize, liquid)
                    })
                    .transpose()
            })
            .collect::<Result<_, _>>()?;
        for (pair, bridge) in self.pairs.iter_mut().zip(bridges) {
            pair.bridge = bridge;
        }
        self.film.iter_mut().for_each(|f| *f = 0.0);
        // the list's reach grows with the largest bridge
        self.listed_at = None;
        Ok(())
    }

    /// The largest rupture gap any bridge can reach: of the largest standing bridge or of one
    /// the largest film could form (Willett's gap is largest at the smallest radius).
    fn bridge_reach(&self) -> f64 {
        let Some(w) = self.wetting else {
            return 0.0;
        };
        let largest = self
            .pairs
            .iter()
            .filter_map(|p| Some(p.bridge?.liquid.volume))
            .chain(self.film.iter().copied())
            .fold(0.0, f64::max);
        if largest == 0.0 {
            return 0.0;
        }
        let r_min = self.radius.iter().cloned().fold(f64::INFINITY, f64::min);
        let liquid = Liquid {
            volume: largest,
            ..w.liquid
        };
        rupture_gap(w.rupture, &liquid, r_min)
    }

    /// Whether some particle has moved more than half the skin since the list was built (then
    /// a pair not listed may have come within reach).
    fn list_is_stale(&self) -> bool {
        let Some(listed_at) = &self.listed_at else {
            return true;
        };
        let limit = (0.5 * self.skin).powi(2);
        self.position
            .iter()
            .zip(listed_at)
            .any(|(x, x0)| (x - x0).norm_squared() > limit)
    }

    /// Lists every pair within r_i + r_j + bridge reach + skin, keeping the state of the pairs
    /// listed before; a dropped pair's bridge (already beyond its rupture gap) returns its
    /// liquid to the films.
    fn rebuild_pairs(&mut self) {
        let n = self.len();
        let margin = self.bridge_reach() + self.skin;
        // pairs within (reach_i + reach_j)/2 with reach = 2r + margin
        let reach: Vec<f64> = self.radius.iter().map(|r| 2.0 * r + margin).collect();
        let neighbours = find_neighbours(&self.position, &reach, 1.0, PairReach::MeanH, n);
        let grains = self.grains;
        let mut listed: Vec<(u32, u32)> = (0..n)
            .flat_map(|i| {
                neighbours
                    .of(i)
                    .filter(move |&j| j > i && i < grains)
                    .map(move |j| (i as u32, j as u32))
            })
            .collect();
        listed.sort_unstable();
        let mut old = std::mem::take(&mut self.pairs).into_iter().peekable();
        let mut pairs = Vec::with_capacity(listed.len());
        for (i, j) in listed {
            while let Some(dropped) = old.next_if(|p| (p.i, p.j) < (i, j)) {
                self.return_liquid(&dropped);
            }
            match old.next_if(|p| (p.i, p.j) == (i, j)) {
                Some(kept) => pairs.push(kept),
                None => pairs.push(Pair::new(i, j, self.dashpot(i as usize, j as usize))),
            }
        }
        for dropped in old {
            self.return_liquid(&dropped);
        }
        self.pairs = pairs;
        self.listed_at = Some(self.position.clone());
    }

    /// The normal dashpot of a contact between i and j: 2ζ√(k_n m_eff) with the effective mass
    /// m_eff = m_i m_j/(m_i + m_j), critically damped at ζ = 1.
    fn dashpot(&self, i: usize, j: usize) -> f64 {
        let m = &self.model;
        let m_eff = self.mass[i] * self.mass[j] / (self.mass[i] + self.mass[j]);
        2.0 * m.damping_ratio * (m.normal_stiffness * m_eff).sqrt()
    }

    /// A broken bridge gives half of its liquid back to each grain.
    fn return_liquid(&mut self, pair: &Pair) {
        if let Some(bridge) = pair.bridge {
            self.film[pair.i as usize] += 0.5 * bridge.liquid.volume;
            self.film[pair.j as usize] += 0.5 * bridge.liquid.volume;
        }
    }

    /// A bridge of `liquid` between grains i and j (the grains are wet).
    fn bridge(&self, i: usize, j: usize, liquid: Liquid) -> Result<Bridge, SolverError> {
        let w = self.wetting.expect("a bridge between wet grains");
        let radius = effective_radius(self.radius[i], self.radius[j]);
        Bridge::new(w.law, w.rupture, liquid, radius)
    }

    /// Forces and torques of the current positions and velocities (contacts, bridges,
    /// walls); contact springs advance by `dt`; bridges form, keep or break (see [`Wetting`]).
    pub fn compute_forces(&mut self, dt: f64) -> Result<(), SolverError> {
        if self.list_is_stale() {
            self.rebuild_pairs();
        }
        self.force.iter_mut().for_each(|f| *f = Vector::zeros());
        self.torque.iter_mut().for_each(|t| *t = 0.0);
        // the pairs are updated in place (they are large: a bridge carries its law's constants)
        let mut pairs = std::mem::take(&mut self.pairs);
        let formed = pairs
            .iter_mut()
            .try_for_each(|pair| self.pair_force(pair, dt));
        self.pairs = pairs;
        formed?;
        self.wall_forces();
        Ok(())
    }

    /// The contact and bridge forces of one pair, added to both; updates its state.
    fn pair_force(&mut self, pair: &mut Pair, dt: f64) -> Result<(), SolverError> {
        let (i, j) = (pair.i as usize, pair.j as usize);
        let (ri, rj) = (self.radius[i], self.radius[j]);
        let d_vec = self.position[j] - self.position[i];
        // most listed pairs neither touch nor hold a bridge, and then nothing acts
        if pair.bridge.is_none() && d_vec.norm_squared() >= (ri + rj).powi(2) {
            pair.touching = false;
            pair.tangential = Vector::zeros();
            return Ok(());
        }
        let d = d_vec.norm();
        let normal = d_vec / d;
        let gap = d - ri - rj;
        let grain_pair = j < self.grains;
        let previous = if pair.touching {
            pair.tangential
        } else {
            Vector::zeros()
        };
        pair.touching = gap < 0.0;
        pair.tangential = if pair.touching {
            let friction = if grain_pair { self.model.friction } else { 0.0 };
            self.contact_force(pair, normal, -gap, previous, friction, dt)
        } else {
            Vector::zeros()
        };
        let Some(w) = self.wetting.filter(|_| grain_pair) else {
            return Ok(());
        };
        // a standing bridge keeps its liquid; a new one forms at contact from the films
        if pair.bridge.is_none() && pair.touching && self.film[i] + self.film[j] > 0.0 {
            let liquid = Liquid {
                volume: 0.5 * (self.film[i] + self.film[j]),
                ..w.liquid
            };
            pair.bridge = Some(self.bridge(i, j, liquid)?);
            self.film[i] *= 0.5;
            self.film[j] *= 0.5;
        }
        let Some(bridge) = &pair.bridge else {
            return Ok(());
        };
        if gap < bridge.rupture_gap {
            let f = bridge.force(gap) * normal;
            self.force[i] += f;
            self.force[j] -= f;
        } else {
            self.return_liquid(pair);
            pair.bridge = None;
        }
        Ok(())
    }

    /// The contact force between the overlapping pair i and j (overlap δ > 0, unit normal from
    /// i to j) with Coulomb coefficient `friction`, added to both; returns the advanced
    /// tangential spring.
    fn contact_force(
        &mut self,
        pair: &Pair,
        normal: Vector<2>,
        overlap: f64,
        previous: Vector<2>,
        friction: f64,
        dt: f64,
    ) -> Vector<2> {
        let m = &self.model;
        let (i, j) = (pair.i as usize, pair.j as usize);
        let tangent = Vector::<2>::new(-normal[1], normal[0]);
        let (ri, rj) = (self.radius[i], self.radius[j]);
        // the velocity of j's contact point relative to i's (ω × r in 2D: ω(−r_y, r_x))
        let relative = (self.velocity[j] - self.velocity[i])
            - tangent * (self.angular_velocity[j] * rj + self.angular_velocity[i] * ri);
        let normal_speed = relative.dot(&normal);
        // repulsive only: the dashpot may not pull the discs together
        let normal_force = (m.normal_stiffness * overlap - pair.dashpot * normal_speed).max(0.0);
        // the tangential spring, kept in the current tangent line, then capped at μ F_n
        let mut spring = previous - normal * previous.dot(&normal);
        spring += (relative - normal * normal_speed) * dt;
        let mut tangential = spring * m.tangential_stiffness;
        let limit = friction * normal_force;
        if exceeds(&tangential, limit) {
            tangential *= if limit > 0.0 {
                limit / tangential.norm()
            } else {
                0.0
            };
            spring = tangential / m.tangential_stiffness;
        }
        let on_i = -normal * normal_force + tangential;
        self.force[i] += on_i;
        self.force[j] -= on_i;
        // torque r × f about each centre: i's contact point at +r_i n, j's at −r_j n
        let cross = |r: Vector<2>, f: Vector<2>| r[0] * f[1] - r[1] * f[0];
        self.torque[i] += cross(normal * ri, tangential);
        self.torque[j] += cross(-normal * rj, -tangential);
        spring
    }

    /// Frictionless walls: a normal spring and dashpot on each particle that crosses one.
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

    /// The second half of a step, after [`Self::compute_forces`] and any external forces:
    /// local damping, then v += F/m dt, x += v dt (leapfrog), and the walls move.
    pub fn advance(&mut self, dt: f64) -> Result<(), SolverError> {
        self.local_damping();
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

    /// One leapfrog step: forces at the current state (velocities at the half step), then
    /// [`Self::advance`].
    pub fn step(&mut self, dt: f64) -> Result<(), SolverError> {
        self.compute_forces(dt)?;
        self.advance(dt)
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dem::capillary::{bridge_force, BridgeLaw, RuptureCriterion};
    use crate::random::SplitMix64;
    use std::f64::consts::PI;

    /// The shortcut decides as the rounded norm compares, for limits at, one ulp about, and
    /// 1e-12 and 1e-13 about the norm, and zero.
    #[test]
    fn exceeds_decides_as_the_rounded_norm_compares() {
        let mut rng = SplitMix64::new(7);
        for _ in 0..20_000 {
            let scale = 10f64.powf(16.0 * rng.uniform() - 8.0);
            let v = Vector::<2>::new(rng.uniform() - 0.5, rng.uniform() - 0.5) * scale;
            let norm = v.norm();
            let ulp = |k: i64| f64::from_bits((norm.to_bits() as i64 + k) as u64);
            for limit in [
                norm,
                ulp(1),
                ulp(-1),
                ulp(2),
                ulp(-2),
                norm * (1.0 + 1e-12),
                norm * (1.0 - 1e-12),
                norm * (1.0 + 1e-13),
                norm * (1.0 - 1e-13),
                0.0,
                2.0 * norm,
            ] {
                assert_eq!(exceeds(&v, limit), norm > limit, "{v:?} {limit:e}");
            }
        }
        assert!(!exceeds(&Vector::zeros(), 0.0));
    }

    /// A water sphere of 1 m radius weighs 4188.79 kg (4π/3 · 1000), with moment of inertia
    /// 2/5 m r² about its centre; both scale as r³ and r⁵. Limits at round-off: 1e-9 kg is
    /// a few ulps of 4188 kg, and a power-of-two radius scales exactly.
    #[test]
    fn a_sphere_weighs_four_thirds_pi_r_cubed_rho() {
        let (mass, inertia) = sphere_mass(1.0, 1000.0);
        assert!((mass - 4_188.790_204_786_391).abs() < 1e-9, "{mass}");
        assert!((inertia - 1_675.516_081_914_556).abs() < 1e-9, "{inertia}");
        let (small, small_inertia) = sphere_mass(0.5, 1000.0);
        assert!((small * 8.0 / mass - 1.0).abs() < 1e-15);
        assert!((small_inertia * 32.0 / inertia - 1.0).abs() < 1e-15);
    }

    /// Grains come first and boundary particles after them; a set of discs is never empty
    /// (`Discs::new` refuses none).
    #[test]
    fn grains_come_first_and_boundary_particles_follow() {
        let centres = vec![Vector::<2>::new(0.0, 0.0), Vector::<2>::new(1.0, 0.0)];
        let mut discs =
            Discs::new(centres, vec![0.1, 0.2], 1000.0, sand_contact(), None).expect("two grains");
        assert_eq!((discs.len(), discs.grains()), (2, 2));
        assert!(!discs.is_empty());
        assert_eq!(
            discs.add_boundary_particle(Vector::<2>::new(2.0, 0.0), 0.1, 1.0),
            2
        );
        assert_eq!((discs.len(), discs.grains()), (3, 2));
        assert!(Discs::new(vec![], vec![], 1000.0, sand_contact(), None).is_err());
    }

    /// Two grains of radii 1 and 2 and a boundary particle: the grains' cross-sections
    /// π(1 + 4) = 5π, volumes 4π(1 + 8)/3 = 12π, layer one mean diameter, 3; the boundary
    /// particle counts in none of them. Scaling the radii by 2 scales each grain's mass by 8 and
    /// its inertia by 32, as a sphere of twice the radius has, and leaves the boundary alone.
    #[test]
    fn grain_measures_and_radius_scaling() {
        let centres = vec![Vector::<2>::new(0.0, 0.0), Vector::<2>::new(10.0, 0.0)];
        let mut discs =
            Discs::new(centres, vec![1.0, 2.0], 1000.0, sand_contact(), None).expect("two grains");
        discs.add_boundary_particle(Vector::<2>::new(20.0, 0.0), 5.0, 1.0);
        assert!((discs.grain_area() / (5.0 * PI) - 1.0).abs() < 1e-15);
        assert!((discs.grain_volume() / (12.0 * PI) - 1.0).abs() < 1e-15);
        assert_eq!(discs.layer_thickness(), 3.0);
        discs.scale_radii(2.0).expect("a positive factor");
        assert_eq!(discs.radius, [2.0, 4.0, 5.0]);
        for k in 0..2 {
            let (mass, inertia) = sphere_mass(discs.radius[k], 1000.0);
            assert!((discs.mass[k] / mass - 1.0).abs() < 1e-14, "grain {k}");
            assert!(
                (discs.inertia[k] / inertia - 1.0).abs() < 1e-14,
                "grain {k}"
            );
        }
        assert_eq!((discs.mass[2], discs.inertia[2]), (1.0, 10.0));
    }

    /// Cundall's local damping takes α|F| from each force component against its velocity
    /// component, and α|T| from the torque against the spin: v += (F − α|F| sign v) dt/m,
    /// ω += (T − α|T| sign ω) dt/I. `set_local_damping` sets α from then on and refuses α = 1
    /// by name.
    #[test]
    fn local_damping_opposes_the_motion_by_alpha_times_the_force() {
        let mut discs = Discs::new(
            vec![Vector::<2>::zeros()],
            vec![0.01],
            1000.0,
            sand_contact(),
            None,
        )
        .expect("one grain");
        let alpha = 0.7;
        discs.set_local_damping(alpha).expect("α < 1");
        let err = discs.set_local_damping(1.0).unwrap_err().to_string();
        assert!(err.contains("local damping"), "{err}");
        let (m, i) = (discs.mass[0], discs.inertia[0]);
        discs.velocity[0] = Vector::<2>::new(1.0, -1.0);
        discs.angular_velocity[0] = -2.0;
        discs.force[0] = Vector::<2>::new(3.0, 3.0);
        discs.torque[0] = 5.0;
        let dt = 1e-3;
        discs.advance(dt).expect("a finite step");
        // changes of order 0.1 to 10 on values of order 1: round-off below 1e-14
        let dv = discs.velocity[0] - Vector::<2>::new(1.0, -1.0);
        assert!(
            (dv[0] / (3.0 * (1.0 - alpha) * dt / m) - 1.0).abs() < 1e-12,
            "{dv:?}"
        );
        assert!(
            (dv[1] / (3.0 * (1.0 + alpha) * dt / m) - 1.0).abs() < 1e-12,
            "{dv:?}"
        );
        let dw = discs.angular_velocity[0] + 2.0;
        assert!(
            (dw / (5.0 * (1.0 + alpha) * dt / i) - 1.0).abs() < 1e-12,
            "{dw}"
        );
    }

    /// Coordination counts each grain's contacts with grains, boundary particles and walls,
    /// over the grains with two or more. Three unit grains overlap in a row (A–B–C), a
    /// boundary particle touches A, a wall below (not through the origin) overlaps all three:
    /// A and B have 3 contacts, C 2. A pair of touching grains rests exactly one radius above
    /// the wall, which they do not touch: one contact each, so they carry nothing. Hence 8/3;
    /// the boundary particle's own contacts are not a grain's.
    #[test]
    fn coordination_counts_the_load_carrying_grains_contacts() {
        let centres = vec![
            Vector::<2>::new(0.0, 100.0),
            Vector::<2>::new(1.9, 100.0),
            Vector::<2>::new(3.8, 100.0),
            Vector::<2>::new(20.0, 100.25),
            Vector::<2>::new(21.5, 100.25),
        ];
        let mut discs =
            Discs::new(centres, vec![1.0; 5], 1000.0, sand_contact(), None).expect("five grains");
        discs.add_boundary_particle(Vector::<2>::new(0.0, 101.9), 1.0, 1.0);
        discs.add_wall(Wall {
            point: Vector::<2>::new(0.0, 99.25),
            normal: Vector::<2>::new(0.0, 2.0),
            velocity: Vector::zeros(),
        });
        discs.compute_forces(1e-6).expect("forces");
        assert_eq!(discs.counts(), (4, 0));
        assert!(
            (discs.coordination() - 8.0 / 3.0).abs() < 1e-15,
            "{}",
            discs.coordination()
        );
    }

    /// The pore water goes into bridges at the touching grain pairs only: not at a listed
    /// grain pair with a gap, nor where a grain touches a boundary particle (the first one,
    /// whose index is the grain count). A volume that is not finite and positive, dry grains
    /// and grains without contacts are refused by name.
    #[test]
    fn pore_water_goes_to_touching_grain_pairs_only() {
        let r = 1e-4;
        let wetting = water_films(0.0);
        let centres = vec![
            Vector::<2>::new(0.0, 0.0),
            Vector::<2>::new(1.9 * r, 0.0),
            Vector::<2>::new(3.95 * r, 0.0),
        ];
        let mut discs = Discs::new(
            centres.clone(),
            vec![r; 3],
            2650.0,
            sand_contact(),
            Some(wetting),
        )
        .expect("three grains");
        discs.add_boundary_particle(Vector::<2>::new(1.9 * r, 1.9 * r), r, 1e-9);
        let err = discs.distribute_liquid(1e-15).unwrap_err().to_string();
        assert!(err.contains("contacts"), "{err}");
        discs.compute_forces(0.0).expect("forces");
        assert_eq!(discs.counts(), (2, 0));
        for volume in [0.0, -1e-15, f64::INFINITY, f64::NAN] {
            let err = discs.distribute_liquid(volume).unwrap_err().to_string();
            assert!(err.contains("liquid volume"), "{volume}: {err}");
        }
        discs
            .distribute_liquid(1e-15)
            .expect("one touching grain pair");
        let bridges: Vec<((usize, usize), f64)> = discs.bridge_volumes().collect();
        assert_eq!(bridges, [((0, 1), 1e-15)]);
        let mut dry = Discs::new(centres, vec![r; 3], 2650.0, sand_contact(), None).expect("dry");
        dry.compute_forces(0.0).expect("forces");
        let err = dry.distribute_liquid(1e-15).unwrap_err().to_string();
        assert!(err.contains("wetting"), "{err}");
    }

    /// A bridge holds its grains up to its rupture gap even where that is wider than the
    /// list's skin: two grains given V/R³ = 0.1 of pore water (Lian's rupture gap 2.3 skins)
    /// and pulled apart to 0.8 of it feel the law's force for that volume and gap.
    #[test]
    fn a_standing_bridge_stays_listed_up_to_its_rupture_gap() {
        let r = 1e-4;
        let volume = 0.1 * r * r * r;
        let liquid = Liquid::water(volume, 0.0).expect("water");
        let wetting = water_films(0.0);
        let centres = vec![Vector::<2>::zeros(), Vector::<2>::new(1.99 * r, 0.0)];
        let mut discs = Discs::new(centres, vec![r; 2], 2650.0, sand_contact(), Some(wetting))
            .expect("two grains");
        discs.compute_forces(0.0).expect("forces");
        discs.distribute_liquid(volume).expect("one contact");
        let radius = effective_radius(r, r);
        let gap = 0.8 * rupture_gap(RuptureCriterion::Lian, &liquid, radius);
        assert!(gap > discs.skin, "{gap} {}", discs.skin);
        discs.position[1] = Vector::<2>::new(2.0 * r + gap, 0.0);
        discs.compute_forces(0.0).expect("forces");
        let expected = bridge_force(BridgeLaw::WillettFitted, &liquid, radius, gap).expect("law");
        assert!(expected > 0.0);
        assert!(
            (discs.force[0][0] / expected - 1.0).abs() < 1e-12,
            "{:?}",
            discs.force
        );
    }

    /// A rebuilt list keeps the state of the pairs it keeps. Three wet grains in a row touch;
    /// each pair takes half of each film as it forms (films V: A–B holds V, B–C 0.75 V). Moving
    /// A away drops A–B, whose liquid goes back to A's and B's films, while B–C keeps its bridge
    /// of 0.75 V; the liquid is conserved throughout.
    #[test]
    fn a_rebuilt_list_keeps_the_state_of_the_pairs_it_keeps() {
        let r = 1e-4;
        let film = 1e-15;
        let wetting = water_films(film);
        let centres = vec![
            Vector::<2>::zeros(),
            Vector::<2>::new(1.99 * r, 0.0),
            Vector::<2>::new(3.98 * r, 0.0),
        ];
        let mut discs = Discs::new(centres, vec![r; 3], 2650.0, sand_contact(), Some(wetting))
            .expect("three grains");
        discs.compute_forces(0.0).expect("forces");
        let volumes = |discs: &Discs| discs.bridge_volumes().collect::<Vec<_>>();
        assert_eq!(volumes(&discs).len(), 2);
        assert!((volumes(&discs)[1].1 / (0.75 * film) - 1.0).abs() < 1e-12);
        discs.position[0] = Vector::<2>::new(-10.0 * r, 0.0);
        discs.compute_forces(0.0).expect("forces");
        let kept = volumes(&discs);
        assert_eq!(kept.len(), 1, "{kept:?}");
        assert_eq!(kept[0].0, (1, 2));
        assert!((kept[0].1 / (0.75 * film) - 1.0).abs() < 1e-12, "{kept:?}");
        assert!((discs.total_liquid() / (3.0 * film) - 1.0).abs() < 1e-12);
        assert!((discs.film[0] / film - 1.0).abs() < 1e-12);
    }

    /// Boundary particles touch grains but not one another: two overlapping boundary
    /// particles feel no force.
    #[test]
    fn boundary_particles_ignore_one_another() {
        let mut discs = Discs::new(
            vec![Vector::<2>::new(10.0, 0.0)],
            vec![1.0],
            1000.0,
            sand_contact(),
            None,
        )
        .expect("one grain");
        discs.add_boundary_particle(Vector::<2>::new(0.0, 0.0), 1.0, 1.0);
        discs.add_boundary_particle(Vector::<2>::new(1.5, 0.0), 1.0, 1.0);
        discs.compute_forces(1e-6).expect("forces");
        assert_eq!(discs.counts(), (0, 0));
        assert!(discs.force.iter().all(|f| *f == Vector::<2>::zeros()));
    }

    /// A wet grain sliding along the first boundary particle (its index is the grain count)
    /// feels only the normal spring: no friction and no bridge, whatever its film. Two wet
    /// grains of which only one carries a film still form a bridge on touching, of half that
    /// film.
    #[test]
    fn boundary_contacts_are_frictionless_and_dry_and_one_film_makes_a_bridge() {
        let r = 1e-4;
        let film = 1e-15;
        let wetting = water_films(film);
        let centres = vec![Vector::<2>::zeros(), Vector::<2>::new(50.0 * r, 0.0)];
        let mut discs = Discs::new(centres, vec![r; 2], 2650.0, sand_contact(), Some(wetting))
            .expect("two grains");
        let boundary = discs.add_boundary_particle(Vector::<2>::new(0.0, 1.99 * r), r, 1e-9);
        assert_eq!(boundary, discs.grains());
        discs.velocity[0] = Vector::<2>::new(0.1, 0.0);
        for _ in 0..3 {
            discs.compute_forces(1e-7).expect("forces");
        }
        assert_eq!(discs.counts(), (1, 0));
        assert_eq!(discs.force[0][0], 0.0);
        assert!(discs.force[0][1] < 0.0);
        assert_eq!(discs.torque[0], 0.0);
        // the second grain, dry, touches the first on its far side
        discs.film[1] = 0.0;
        discs.position[1] = Vector::<2>::new(-1.99 * r, 0.0);
        discs.compute_forces(1e-7).expect("forces");
        let bridges: Vec<((usize, usize), f64)> = discs.bridge_volumes().collect();
        assert_eq!(bridges, [((0, 1), 0.5 * film)]);
    }

    /// Water with Willett's fitted law and Lian's rupture gap, a film of `film` (m³, 0 for
    /// none) on each grain at the start.
    fn water_films(film: f64) -> Wetting {
        Wetting {
            law: BridgeLaw::WillettFitted,
            rupture: RuptureCriterion::Lian,
            liquid: Liquid {
                volume: film,
                ..Liquid::water(1e-15, 0.0).expect("water")
            },
        }
    }

    fn sand_contact() -> ContactModel {
        ContactModel {
            normal_stiffness: 1e5,
            tangential_stiffness: 5e4,
            friction: 0.5,
            damping_ratio: 0.1,
            local_damping: 0.0,
        }
    }

    /// Each field of the contact model is refused by name just past each edge of its range
    /// (zero, infinite and NaN stiffness; negative, infinite and NaN friction; damping ratios
    /// below 0 and at 1) and accepted at the closed edges (no friction, no damping).
    #[test]
    fn the_contact_models_edges_are_named() {
        type Edit = fn(&mut ContactModel, f64);
        let fields: [(&str, Edit); 5] = [
            ("normal stiffness", |m, x| m.normal_stiffness = x),
            ("tangential stiffness", |m, x| m.tangential_stiffness = x),
            ("friction", |m, x| m.friction = x),
            ("damping ratio", |m, x| m.damping_ratio = x),
            ("local damping", |m, x| m.local_damping = x),
        ];
        let refused: [&[f64]; 5] = [
            &[0.0, -1.0, f64::INFINITY, f64::NAN],
            &[0.0, -1.0, f64::INFINITY, f64::NAN],
            &[-1e-9, f64::INFINITY, f64::NAN],
            &[-1e-9, 1.0, f64::NAN],
            &[-1e-9, 1.0, f64::NAN],
        ];
        let accepted: [&[f64]; 5] = [
            &[1e-9, 1e12],
            &[1e-9, 1e12],
            &[0.0, 10.0],
            &[0.0, 0.999],
            &[0.0, 0.999],
        ];
        assert!(sand_contact().validate().is_ok());
        for (((name, edit), bad), good) in fields.iter().zip(refused).zip(accepted) {
            for &x in bad {
                let mut model = sand_contact();
                edit(&mut model, x);
                let err = model.validate().expect_err(name).to_string();
                assert!(err.contains(name), "{name} = {x}: {err}");
            }
            for &x in good {
                let mut model = sand_contact();
                edit(&mut model, x);
                assert!(model.validate().is_ok(), "{name} = {x} refused");
            }
        }
    }

    /// A wall pushes a disc that crosses it by δ with k_n δ along its normal, plus the dashpot
    /// 2ζ√(k_n m) times the speed into it (never pulling), and feels the opposite; a disc clear
    /// of it feels nothing. The wall stands off the origin, slants and moves, so that neither its
    /// point, its normal nor its velocity can be mistaken for another.
    #[test]
    fn a_wall_pushes_with_its_spring_and_dashpot_and_feels_the_reaction() {
        let model = sand_contact();
        let normal = Vector::<2>::new(0.6, 0.8);
        let point = Vector::<2>::new(0.3, -0.2);
        let r = 1e-3;
        let overlap = 1e-5;
        let tangent = Vector::<2>::new(-0.8, 0.6);
        let centres = vec![
            point + normal * (r - overlap) + tangent * 0.01,
            point + normal * (r - 2.0 * overlap) - tangent * 0.02,
            point + normal * (r + 1e-6),
        ];
        let mut discs = Discs::new(centres, vec![r; 3], 2650.0, model, None).unwrap();
        discs.add_wall(Wall {
            point,
            normal,
            velocity: normal * 0.004 + tangent * 0.3,
        });
        // the first approaches the moving wall, the second leaves it fast enough to be let go
        let approach = 0.01;
        discs.velocity[0] = normal * (0.004 - approach) + tangent * 0.5;
        discs.velocity[1] = normal * 10.0;
        discs.compute_forces(1e-7).unwrap();
        let dashpot = 2.0 * model.damping_ratio * (model.normal_stiffness * discs.mass[0]).sqrt();
        let push = model.normal_stiffness * overlap + dashpot * approach;
        assert!(
            (discs.force[0] - normal * push).norm() < 1e-9 * push,
            "{}",
            discs.force[0]
        );
        assert_eq!(discs.force[1], Vector::<2>::zeros());
        assert_eq!(discs.force[2], Vector::<2>::zeros());
        assert!((discs.wall_force[0] + normal * push).norm() < 1e-9 * push);
    }

    /// The step: local damping, then v += F/m Δt and ω += T/I Δt, then x += v Δt with the new
    /// velocity (leapfrog); the walls move at their velocity and the clock advances. A position
    /// that is no longer finite stops the step with the disc's number.
    #[test]
    fn advance_kicks_then_drifts_and_moves_the_walls() {
        let centres = vec![Vector::<2>::new(1.0, 2.0), Vector::<2>::new(5.0, 2.0)];
        let mut discs = Discs::new(centres, vec![0.5, 0.25], 1000.0, sand_contact(), None).unwrap();
        discs.add_wall(Wall {
            point: Vector::<2>::new(0.0, -1.0),
            normal: Vector::<2>::new(0.0, 1.0),
            velocity: Vector::<2>::new(0.5, 2.0),
        });
        discs.velocity[0] = Vector::<2>::new(3.0, -1.0);
        discs.angular_velocity[0] = 2.0;
        discs.force[0] = Vector::<2>::new(4.0, 8.0);
        discs.torque[0] = 6.0;
        let (m, inertia) = (discs.mass[0], discs.inertia[0]);
        let dt = 0.1;
        discs.time = 1.0;
        discs.advance(dt).unwrap();
        let v = Vector::<2>::new(3.0 + 4.0 / m * dt, -1.0 + 8.0 / m * dt);
        assert!(
            (discs.velocity[0] - v).norm() < 1e-15,
            "{}",
            discs.velocity[0]
        );
        assert!((discs.angular_velocity[0] - (2.0 + 6.0 / inertia * dt)).abs() < 1e-15);
        let x = Vector::<2>::new(1.0, 2.0) + v * dt;
        assert!(
            (discs.position[0] - x).norm() < 1e-15,
            "{}",
            discs.position[0]
        );
        assert_eq!(discs.position[1], Vector::<2>::new(5.0, 2.0));
        assert!((discs.walls[0].point - Vector::<2>::new(0.05, -0.8)).norm() < 1e-15);
        assert!((discs.time - 1.1).abs() < 1e-15);
        discs.force[1] = Vector::<2>::new(f64::INFINITY, 0.0);
        let err = discs.advance(dt).unwrap_err().to_string();
        assert!(err.contains("disc 1 position"), "{err}");
    }

    /// ½ m v² + ½ I ω², summed over the discs.
    #[test]
    fn kinetic_energy_counts_translation_and_rotation() {
        let centres = vec![Vector::<2>::new(0.0, 0.0), Vector::<2>::new(3.0, 0.0)];
        let mut discs = Discs::new(centres, vec![0.5, 1.0], 1000.0, sand_contact(), None).unwrap();
        discs.velocity[0] = Vector::<2>::new(3.0, 4.0);
        discs.angular_velocity[1] = 2.0;
        let want = 0.5 * discs.mass[0] * 25.0 + 0.5 * discs.inertia[1] * 4.0;
        assert!((discs.kinetic_energy() / want - 1.0).abs() < 1e-15);
    }
}
