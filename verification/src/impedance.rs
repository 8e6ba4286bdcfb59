//! Exact state at a material interface (impedance mismatch) for any equation of state.
//!
//! Material A (left) in state 1 meets material B (right) in its own state. Two waves leave the
//! interface: one into A (left-facing), one into B (right-facing); the interface state (u*, p*)
//! has one particle velocity and one pressure (the seed's §2-17). Each wave is
//! - a shock where p* exceeds the pressure ahead of it: the Rankine–Hugoniot jump
//!   e − e_a = ½ (p + p_a)(v_a − v), Δu = √((p − p_a)(v_a − v)), shock speed j/ρ_a relative to
//!   the material ahead with j² = (p − p_a)/(v_a − v), solved with the material's own EOS;
//! - a rarefaction where p* is lower: the isentrope de = −p dv integrated from the state ahead,
//!   with Δu = ∫ dp/(ρc) (Riemann invariant), by RK4 in p.
//!
//! u* = u_1 − f_A(p*) = u_B + f_B(p*), where f is the velocity jump across the wave (negative for
//! a rarefaction); f increases with p, so bisection finds p*.
//!
//! The seed's eq. 2-16 instead mirrors A's principal Hugoniot about u_1:
//! p = ρ0A Us_A(2u_1 − u)(2u_1 − u). That neglects the difference between a second shock (or an
//! isentrope) from state 1 and the principal Hugoniot from rest; [`mirrored_hugoniot`] gives it
//! beside the exact state so that difference can be reported.

use crate::materials::Library;
use crate::VerifyError;
use blastsph_solver::{EquationOfState, MieGruneisen};
use serde::Serialize;

/// A uniform state of a material.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct MaterialState {
    pub density: f64,
    pub internal_energy: f64,
    pub pressure: f64,
    pub velocity: f64,
}

impl MaterialState {
    /// The state (ρ, e) moving at `velocity`, with its pressure from the EOS.
    pub fn new(
        eos: &dyn EquationOfState,
        density: f64,
        internal_energy: f64,
        velocity: f64,
    ) -> Self {
        Self {
            density,
            internal_energy,
            pressure: eos.pressure(density, internal_energy),
            velocity,
        }
    }
}

/// Shock or rarefaction.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum WaveKind {
    Shock,
    Rarefaction,
}

impl WaveKind {
    pub fn name(self) -> &'static str {
        match self {
            WaveKind::Shock => "shock",
            WaveKind::Rarefaction => "rarefaction",
        }
    }
}

/// One wave leaving the interface: the state behind it and the speeds (lab frame) of its front
/// (head) and back (tail), equal for a shock.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Wave {
    pub kind: WaveKind,
    pub behind: MaterialState,
    pub head_speed: f64,
    pub tail_speed: f64,
}

/// The two waves and the interface state between them.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct InterfaceSolution {
    /// Particle velocity u* at the interface (m/s).
    pub velocity: f64,
    /// Pressure p* at the interface (Pa).
    pub pressure: f64,
    /// The wave into A (left-facing: reflected).
    pub into_a: Wave,
    /// The wave into B (right-facing: transmitted).
    pub into_b: Wave,
}

/// Which way a wave travels.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Facing {
    Left,
    Right,
}

impl Facing {
    fn sign(self) -> f64 {
        match self {
            Facing::Left => -1.0,
            Facing::Right => 1.0,
        }
    }
}

/// Steps of the RK4 isentrope integration: the rarefactions here span at most a few GPa in
/// smooth EOS, where 400 steps put the error far below 1e-9 of Δu.
const ISENTROPE_STEPS: usize = 400;

/// The velocity jump |u − u_a| signed as f (positive for a shock), and the wave it takes, for a
/// wave facing `facing` that takes `ahead` to pressure `p`.
fn wave(eos: &dyn EquationOfState, ahead: &MaterialState, p: f64, facing: Facing) -> (f64, Wave) {
    let s = facing.sign();
    if p >= ahead.pressure {
        let (rho, e) = shock_density(eos, ahead, p);
        let dv = 1.0 / ahead.density - 1.0 / rho;
        let du = ((p - ahead.pressure) * dv).max(0.0).sqrt();
        // mass flux j = √((p − p_a)/(v_a − v)); the front moves at j/ρ_a relative to the material
        let shock_speed = if dv > 0.0 {
            ((p - ahead.pressure) / dv).sqrt() / ahead.density
        } else {
            eos.sound_speed(ahead.density, ahead.internal_energy)
        };
        let behind = MaterialState {
            density: rho,
            internal_energy: e,
            pressure: p,
            velocity: ahead.velocity + s * du,
        };
        let speed = ahead.velocity + s * shock_speed;
        let wave = Wave {
            kind: WaveKind::Shock,
            behind,
            head_speed: speed,
            tail_speed: speed,
        };
        (du, wave)
    } else {
        let (rho, e, du) = isentrope(eos, ahead, p);
        let behind = MaterialState {
            density: rho,
            internal_energy: e,
            pressure: p,
            velocity: ahead.velocity - s * du,
        };
        let c_ahead = eos.sound_speed(ahead.density, ahead.internal_energy);
        let c_behind = eos.sound_speed(rho, e);
        let wave = Wave {
            kind: WaveKind::Rarefaction,
            behind,
            head_speed: ahead.velocity + s * c_ahead,
            tail_speed: behind.velocity + s * c_behind,
        };
        (-du, wave)
    }
}

/// Density and energy behind a shock of pressure p ≥ p_a: the root of
/// p_EOS(ρ, e_a + ½(p + p_a)(1/ρ_a − 1/ρ)) = p, bracketed by growing ρ from ρ_a, then bisected.
fn shock_density(eos: &dyn EquationOfState, ahead: &MaterialState, p: f64) -> (f64, f64) {
    let energy = |rho: f64| {
        ahead.internal_energy + 0.5 * (p + ahead.pressure) * (1.0 / ahead.density - 1.0 / rho)
    };
    let excess = |rho: f64| eos.pressure(rho, energy(rho)) - p;
    let (mut lo, mut hi) = (ahead.density, ahead.density);
    let mut grow = 1e-3;
    while excess(hi) < 0.0 {
        lo = hi;
        hi = ahead.density * (1.0 + grow);
        grow *= 2.0;
        if grow > 1e6 {
            break; // no root: the caller's bisection in p sees a non-finite jump
        }
    }
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if excess(mid) < 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
        if hi - lo <= 1e-15 * hi {
            break;
        }
    }
    let rho = 0.5 * (lo + hi);
    (rho, energy(rho))
}

/// The isentrope from `ahead` down to pressure p < p_a, integrated in p:
/// dρ/dp = 1/c², de/dp = p/(ρc)², du/dp = 1/(ρc). Returns (ρ, e, |Δu|).
fn isentrope(eos: &dyn EquationOfState, ahead: &MaterialState, p: f64) -> (f64, f64, f64) {
    let &(_, rho, e, du) = isentrope_path(eos, ahead, p, ISENTROPE_STEPS)
        .last()
        .expect("the path holds its start");
    (rho, e, du)
}

/// The isentrope from `ahead` to pressure p by RK4 in `steps` equal pressure steps, as
/// (p, ρ, e, |Δu|) at each step, the start included.
fn isentrope_path(
    eos: &dyn EquationOfState,
    ahead: &MaterialState,
    p: f64,
    steps: usize,
) -> Vec<(f64, f64, f64, f64)> {
    let rates = |pressure: f64, rho: f64, e: f64| {
        let c = eos.sound_speed(rho, e);
        let c2 = c * c;
        (1.0 / c2, pressure / (rho * rho * c2), 1.0 / (rho * c))
    };
    let dp = (p - ahead.pressure) / steps as f64;
    let (mut rho, mut e, mut du) = (ahead.density, ahead.internal_energy, 0.0);
    let mut path = vec![(ahead.pressure, rho, e, du)];
    for k in 0..steps {
        let p0 = ahead.pressure + k as f64 * dp;
        let k1 = rates(p0, rho, e);
        let k2 = rates(p0 + 0.5 * dp, rho + 0.5 * dp * k1.0, e + 0.5 * dp * k1.1);
        let k3 = rates(p0 + 0.5 * dp, rho + 0.5 * dp * k2.0, e + 0.5 * dp * k2.1);
        let k4 = rates(p0 + dp, rho + dp * k3.0, e + dp * k3.1);
        rho += dp / 6.0 * (k1.0 + 2.0 * k2.0 + 2.0 * k3.0 + k4.0);
        e += dp / 6.0 * (k1.1 + 2.0 * k2.1 + 2.0 * k3.1 + k4.1);
        du -= dp / 6.0 * (k1.2 + 2.0 * k2.2 + 2.0 * k3.2 + k4.2);
        path.push((p0 + dp, rho, e, du));
    }
    path
}

/// The states inside a left-facing rarefaction fan from `ahead` down to pressure p, as
/// (ξ, ρ, u, p) with ξ = u − c the characteristic speed, increasing from head to tail: the fan
/// centred at (x0, t0) holds the state with ξ = (x − x0)/(t − t0).
pub fn left_fan(
    eos: &dyn EquationOfState,
    ahead: &MaterialState,
    p: f64,
    points: usize,
) -> Vec<(f64, f64, f64, f64)> {
    fan(eos, ahead, p, points, Facing::Left)
}

/// As [`left_fan`] for a right-facing fan (ξ = u + c, decreasing from head to tail), e.g. the
/// Taylor wave behind a detonation.
pub fn right_fan(
    eos: &dyn EquationOfState,
    ahead: &MaterialState,
    p: f64,
    points: usize,
) -> Vec<(f64, f64, f64, f64)> {
    fan(eos, ahead, p, points, Facing::Right)
}

fn fan(
    eos: &dyn EquationOfState,
    ahead: &MaterialState,
    p: f64,
    points: usize,
    facing: Facing,
) -> Vec<(f64, f64, f64, f64)> {
    let s = facing.sign();
    isentrope_path(eos, ahead, p, points)
        .into_iter()
        .map(|(pressure, rho, e, du)| {
            // the material behind a rarefaction moves away from the way the wave faces
            let u = ahead.velocity - s * du;
            (u + s * eos.sound_speed(rho, e), rho, u, pressure)
        })
        .collect()
}

/// The interface state when A (left, state `a`) meets B (right, state `b`).
pub fn solve(
    eos_a: &dyn EquationOfState,
    a: MaterialState,
    eos_b: &dyn EquationOfState,
    b: MaterialState,
) -> Result<InterfaceSolution, VerifyError> {
    // g(p) = f_A(p) + f_B(p) − (u_A − u_B), increasing in p; its root is p*
    let g = |p: f64| {
        wave(eos_a, &a, p, Facing::Left).0 + wave(eos_b, &b, p, Facing::Right).0
            - (a.velocity - b.velocity)
    };
    // the lowest pressure both materials can carry, just above it so that c stays positive
    let floor = eos_a.min_pressure().max(eos_b.min_pressure());
    let floor = if floor.is_finite() {
        floor
    } else {
        -a.pressure.abs().max(b.pressure.abs()).max(1.0)
    };
    let mut lo = floor + 1e-9 * floor.abs().max(1.0);
    if g(lo) > 0.0 {
        return Err(VerifyError::bad_value(
            "interface",
            format!("u_A − u_B = {} m/s", a.velocity - b.velocity),
            "states that stay in contact (these separate: the interface pressure would fall below \
             the materials' tensile limit)",
        ));
    }
    let mut hi = a.pressure.max(b.pressure).max(1.0);
    while g(hi) < 0.0 {
        lo = hi;
        hi *= 2.0;
        if hi > 1e16 {
            return Err(VerifyError::bad_value(
                "interface pressure",
                format!("{hi:e} Pa"),
                "below 1e16 Pa (no interface state found)",
            ));
        }
    }
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if g(mid) < 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
        if hi - lo <= 1e-13 * hi.abs().max(1.0) {
            break;
        }
    }
    let p = 0.5 * (lo + hi);
    let (_, into_a) = wave(eos_a, &a, p, Facing::Left);
    let (_, into_b) = wave(eos_b, &b, p, Facing::Right);
    Ok(InterfaceSolution {
        velocity: 0.5 * (into_a.behind.velocity + into_b.behind.velocity),
        pressure: p,
        into_a,
        into_b,
    })
}

/// The self-similar solution of a Riemann problem between `left` (material A) and `right`
/// (material B): the wave into A (shock or rarefaction fan), the contact, and the shock into B.
pub struct WavePattern {
    pub left: MaterialState,
    pub right: MaterialState,
    pub solution: InterfaceSolution,
    /// The fan into A as (ξ, ρ, u, p), empty when that wave is a shock.
    fan: Vec<(f64, f64, f64, f64)>,
}

impl WavePattern {
    /// Solves the problem; the wave into B must be a shock (a right-facing rarefaction is not
    /// sampled here).
    pub fn new(
        eos_a: &dyn EquationOfState,
        left: MaterialState,
        eos_b: &dyn EquationOfState,
        right: MaterialState,
    ) -> Result<Self, VerifyError> {
        let solution = solve(eos_a, left, eos_b, right)?;
        if solution.into_b.kind != WaveKind::Shock {
            return Err(VerifyError::bad_value(
                "right state",
                "a rarefaction into B",
                "states that send a shock into B",
            ));
        }
        let fan = if solution.into_a.kind == WaveKind::Rarefaction {
            left_fan(eos_a, &left, solution.pressure, 400)
        } else {
            Vec::new()
        };
        Ok(Self {
            left,
            right,
            solution,
            fan,
        })
    }

    /// (ρ, u, p) at ξ = (x − x0)/(t − t0).
    pub fn sample(&self, xi: f64) -> (f64, f64, f64) {
        let state = |s: &MaterialState| (s.density, s.velocity, s.pressure);
        let (into_a, into_b) = (&self.solution.into_a, &self.solution.into_b);
        if xi < into_a.head_speed {
            state(&self.left)
        } else if xi < into_a.tail_speed {
            let k = self
                .fan
                .windows(2)
                .position(|w| xi <= w[1].0)
                .unwrap_or(self.fan.len().saturating_sub(2));
            let (a, b) = (self.fan[k], self.fan[k + 1]);
            let f = ((xi - a.0) / (b.0 - a.0)).clamp(0.0, 1.0);
            (
                a.1 + f * (b.1 - a.1),
                a.2 + f * (b.2 - a.2),
                a.3 + f * (b.3 - a.3),
            )
        } else if xi < self.solution.velocity {
            state(&into_a.behind)
        } else if xi < into_b.head_speed {
            state(&into_b.behind)
        } else {
            state(&self.right)
        }
    }
}

/// The state behind a right-facing shock of pressure `p` driven into material at rest.
pub fn shocked_from_rest(eos: &dyn EquationOfState, rest: MaterialState, p: f64) -> Wave {
    wave(eos, &rest, p, Facing::Right).1
}

/// The seed's eq. 2-16: the interface (u, p) from A's principal Hugoniot mirrored about the
/// incident particle velocity u_1 (A initially moving at `centre` = 2u_1 for a shock arriving
/// in A, or at the impact velocity for a flyer), intersected with B's principal Hugoniot from
/// rest: ρ0A Us_A(centre − u)(centre − u) = ρ0B Us_B(u) u.
pub fn mirrored_hugoniot(a: &MieGruneisen, b: &MieGruneisen, centre: f64) -> (f64, f64) {
    let p_a = |u: f64| a.rho0 * a.shock_velocity(centre - u) * (centre - u);
    let p_b = |u: f64| b.rho0 * b.shock_velocity(u) * u;
    let (mut lo, mut hi) = (0.0, centre);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if p_b(mid) < p_a(mid) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let u = 0.5 * (lo + hi);
    (u, p_b(u))
}

/// How the wave reaches the interface in [`library_case`].
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Drive {
    /// A, moving at this velocity (m/s), hits B at rest.
    Impact(f64),
    /// A shock of this pressure (Pa) in A, which was at rest, reaches B at rest.
    Pressure(f64),
}

/// An interface case between two library materials: the exact state, the seed's eq. 2-16
/// estimate where both have a Us–up Hugoniot, and the incident state in A.
#[derive(Clone, Debug, Serialize)]
pub struct InterfaceCase {
    pub a: String,
    pub b: String,
    pub drive: Drive,
    /// A's state as the wave reaches the interface (behind the incident shock, or the flyer).
    pub incident: MaterialState,
    /// Interface particle velocity (m/s).
    pub up: f64,
    /// Interface pressure (Pa).
    pub p: f64,
    /// Transmitted shock speed in B (m/s, lab frame).
    pub us_b: f64,
    /// The wave that goes back into A: "shock" or "rarefaction".
    pub reflected: &'static str,
    pub solution: InterfaceSolution,
    /// (u, p) of the seed's eq. 2-16 (mirrored principal Hugoniot), where both materials have one.
    pub eq_2_16: Option<(f64, f64)>,
}

/// The interface state of `a` driven onto `b` (both library materials; B at its ambient state).
pub fn library_case(
    library: &Library,
    a: &str,
    b: &str,
    drive: Drive,
) -> Result<InterfaceCase, VerifyError> {
    let (material_a, material_b) = (library.material(a)?, library.material(b)?);
    let (eos_a, eos_b) = (&*material_a.eos, &*material_b.eos);
    let (rho_a, e_a) = library.ambient_state(a)?;
    let (rho_b, e_b) = library.ambient_state(b)?;
    let rest_a = MaterialState::new(eos_a, rho_a, e_a, 0.0);
    let (incident, centre) = match drive {
        Drive::Impact(v) => {
            if !(v > 0.0 && v.is_finite()) {
                return Err(VerifyError::bad_value("--impact", v, "finite and > 0 m/s"));
            }
            (
                MaterialState {
                    velocity: v,
                    ..rest_a
                },
                v,
            )
        }
        Drive::Pressure(p) => {
            if !(p > rest_a.pressure && p.is_finite()) {
                return Err(VerifyError::bad_value(
                    "--pressure",
                    p,
                    &format!(
                        "finite and above A's ambient pressure {} Pa",
                        rest_a.pressure
                    ),
                ));
            }
            let behind = shocked_from_rest(eos_a, rest_a, p).behind;
            (behind, 2.0 * behind.velocity)
        }
    };
    let solution = solve(
        eos_a,
        incident,
        eos_b,
        MaterialState::new(eos_b, rho_b, e_b, 0.0),
    )?;
    let eq_2_16 = match (library.mie_gruneisen(a), library.mie_gruneisen(b)) {
        (Ok(hugoniot_a), Ok(hugoniot_b)) => {
            Some(mirrored_hugoniot(&hugoniot_a, &hugoniot_b, centre))
        }
        _ => None,
    };
    Ok(InterfaceCase {
        a: a.to_string(),
        b: b.to_string(),
        drive,
        incident,
        up: solution.velocity,
        p: solution.pressure,
        us_b: solution.into_b.head_speed,
        reflected: solution.into_a.kind.name(),
        solution,
        eq_2_16,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use blastsph_solver::IdealGas;

    fn copper() -> MieGruneisen {
        MieGruneisen::linear(8930.0, 3940.0, 1.489, 2.02, f64::NEG_INFINITY).unwrap()
    }
    fn aluminium() -> MieGruneisen {
        MieGruneisen::linear(2703.0, 5240.0, 1.4, 1.97, f64::NEG_INFINITY).unwrap()
    }
    fn rest(eos: &MieGruneisen) -> MaterialState {
        MaterialState::new(eos, eos.rho0, 0.0, 0.0)
    }

    /// Symmetric impact: u* = V/2 exactly, p* = ρ0 (C0 + S V/2) V/2 (1e-9: bisection tolerance).
    #[test]
    fn symmetric_impact_splits_the_velocity() {
        let cu = copper();
        let flyer = MaterialState::new(&cu, cu.rho0, 0.0, 1000.0);
        let s = solve(&cu, flyer, &cu, rest(&cu)).unwrap();
        assert!((s.velocity - 500.0).abs() < 1e-9 * 500.0, "{}", s.velocity);
        let p = 8930.0 * (3940.0 + 1.489 * 500.0) * 500.0;
        assert!((s.pressure / p - 1.0).abs() < 1e-9, "{}", s.pressure);
        assert_eq!(s.into_a.kind, WaveKind::Shock);
        assert!((s.into_b.head_speed - (3940.0 + 1.489 * 500.0)).abs() < 1e-6);
    }

    /// A flyer hitting a target at rest: both waves run into material at rest, so the exact
    /// state is the intersection of the two principal Hugoniots, which eq. 2-16 centred on the
    /// impact velocity also is (1e-9).
    #[test]
    fn impact_state_is_the_intersection_of_principal_hugoniots() {
        let (al, cu) = (aluminium(), copper());
        let flyer = MaterialState::new(&al, al.rho0, 0.0, 2000.0);
        let s = solve(&al, flyer, &cu, rest(&cu)).unwrap();
        let (u, p) = mirrored_hugoniot(&al, &cu, 2000.0);
        assert!((s.velocity / u - 1.0).abs() < 1e-9, "{} vs {u}", s.velocity);
        assert!((s.pressure / p - 1.0).abs() < 1e-9, "{} vs {p}", s.pressure);
    }

    /// A shock in Al reaching Cu reflects as a shock and the interface pressure exceeds the
    /// incident one; Cu into Al reflects a rarefaction and the pressure falls. Eq. 2-16 (mirrored
    /// Hugoniot) agrees with the exact second shock / isentrope to a few per cent at these
    /// strengths (the difference is third order in the shock strength).
    #[test]
    fn reflected_wave_types_follow_the_impedances() {
        let (al, cu) = (aluminium(), copper());
        for (a, b, kind) in [
            (&al, &cu, WaveKind::Shock),
            (&cu, &al, WaveKind::Rarefaction),
        ] {
            let incident = shocked_from_rest(a, rest(a), 20e9).behind;
            let s = solve(a, incident, b, rest(b)).unwrap();
            assert_eq!(s.into_a.kind, kind);
            assert_eq!(s.into_b.kind, WaveKind::Shock);
            assert_eq!(s.pressure > incident.pressure, kind == WaveKind::Shock);
            let (u, p) = mirrored_hugoniot(a, b, 2.0 * incident.velocity);
            assert!((u / s.velocity - 1.0).abs() < 0.03, "{u} vs {}", s.velocity);
            assert!((p / s.pressure - 1.0).abs() < 0.03, "{p} vs {}", s.pressure);
        }
    }

    /// On the ideal gas the general solver reproduces the exact Riemann solver's star state of
    /// Sod's problem (Toro's Table 4.2: p* = 0.30313, u* = 0.92745).
    #[test]
    fn ideal_gas_riemann_star_state() {
        let gas = IdealGas::new(1.4).unwrap();
        let left = MaterialState::new(&gas, 1.0, gas.internal_energy(1.0, 1.0), 0.0);
        let right = MaterialState::new(&gas, 0.125, gas.internal_energy(0.125, 0.1), 0.0);
        let s = solve(&gas, left, &gas, right).unwrap();
        assert!((s.pressure - 0.30313).abs() < 1e-5, "{}", s.pressure);
        assert!((s.velocity - 0.92745).abs() < 1e-5, "{}", s.velocity);
        assert_eq!(s.into_a.kind, WaveKind::Rarefaction);
    }

    /// The shock relations hold: Hugoniot from rest gives p = ρ0 Us up with Us = C0 + S up.
    #[test]
    fn shock_from_rest_is_on_the_hugoniot() {
        let cu = copper();
        let w = shocked_from_rest(&cu, rest(&cu), 30e9);
        let up = w.behind.velocity;
        assert!((w.head_speed - (3940.0 + 1.489 * up)).abs() < 1e-6 * w.head_speed);
        assert!((30e9 / (8930.0 * w.head_speed * up) - 1.0).abs() < 1e-9);
    }
}
