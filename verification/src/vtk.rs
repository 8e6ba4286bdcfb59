//! Particle snapshots for viewing, written as VTK XML unstructured grids (`.vtu`, one vertex
//! cell per particle, ASCII) that ParaView opens.

use blastsph_solver::strength::von_mises;
use blastsph_solver::Simulation;
use std::fmt::Write;

/// Elastic, plastic (on the yield surface) or failed (no shear strength left), as a number for
/// the file: 0, 1, 2; fluids are 0.
pub(crate) fn status_code<const D: usize>(sim: &Simulation<D>, i: usize) -> f64 {
    let p = sim.particles();
    let Some(strength) = &sim.materials()[p.material_of(i)].strength else {
        return 0.0;
    };
    if strength.failed_in_tension(p.pressure[i], &p.deviatoric_stress[i]) {
        return 2.0;
    }
    let limit = strength.current_yield(&p.yield_state(i));
    if von_mises(&p.deviatoric_stress[i]) >= limit * (1.0 - 1e-9) {
        1.0
    } else {
        0.0
    }
}

/// The state of every real particle at one time, in 3D coordinates (missing axes are zero).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Snapshot {
    pub time: f64,
    pub positions: Vec<[f64; 3]>,
    pub vectors: Vec<(String, Vec<[f64; 3]>)>,
    pub scalars: Vec<(String, Vec<f64>)>,
}

fn padded<const D: usize>(v: &blastsph_solver::Vector<D>) -> [f64; 3] {
    let mut out = [0.0; 3];
    out[..D].copy_from_slice(v.as_slice());
    out
}

impl Snapshot {
    /// Position, velocity, density, pressure, specific internal energy and material of every
    /// real particle; for solids also von Mises stress, equivalent plastic strain, plastic work
    /// per unit mass, status (0 elastic, 1 plastic, 2 failed) and, where a material knows its
    /// plastic heating, the temperature rise.
    pub fn of<const D: usize>(sim: &Simulation<D>) -> Self {
        let p = sim.particles();
        let n = p.n_real();
        let field = |f: &dyn Fn(usize) -> f64| (0..n).map(f).collect::<Vec<f64>>();
        let mut scalars = vec![
            ("density".to_string(), p.density[..n].to_vec()),
            ("pressure".to_string(), p.pressure[..n].to_vec()),
            (
                "internal_energy".to_string(),
                p.internal_energy[..n].to_vec(),
            ),
            ("material".to_string(), field(&|i| p.material_of(i) as f64)),
        ];
        if !p.deviatoric_stress.is_empty() {
            scalars.push((
                "von_mises".to_string(),
                field(&|i| von_mises(&p.deviatoric_stress[i])),
            ));
            scalars.push(("plastic_strain".to_string(), p.plastic_strain.clone()));
            scalars.push(("plastic_work".to_string(), p.plastic_work.clone()));
            scalars.push(("status".to_string(), field(&|i| status_code(sim, i))));
            let rise = |i: usize| {
                let strength = sim.materials()[p.material_of(i)].strength.as_ref()?;
                strength.temperature_rise(p.plastic_work[i])
            };
            if (0..n).any(|i| rise(i).is_some()) {
                // K; 0 where a material does not know its heating
                scalars.push((
                    "temperature_rise".to_string(),
                    field(&|i| rise(i).unwrap_or(0.0)),
                ));
            }
        }
        Self {
            time: sim.time(),
            positions: p.position[..n].iter().map(padded).collect(),
            vectors: vec![(
                "velocity".to_string(),
                p.velocity[..n].iter().map(padded).collect(),
            )],
            scalars,
        }
    }

    /// The snapshot as a VTK XML UnstructuredGrid (ASCII).
    pub fn to_vtu(&self) -> String {
        let n = self.positions.len();
        let mut s = String::new();
        let _ = writeln!(s, r#"<?xml version="1.0"?>"#);
        let _ = writeln!(
            s,
            r#"<VTKFile type="UnstructuredGrid" version="0.1" byte_order="LittleEndian">"#
        );
        let _ = writeln!(s, "<UnstructuredGrid>");
        let _ = writeln!(
            s,
            r#"<FieldData><DataArray type="Float64" Name="TIME" NumberOfTuples="1" format="ascii">{:e}</DataArray></FieldData>"#,
            self.time
        );
        let _ = writeln!(s, r#"<Piece NumberOfPoints="{n}" NumberOfCells="{n}">"#);
        let _ = writeln!(s, "<PointData>");
        for (name, values) in &self.scalars {
            let _ = writeln!(
                s,
                r#"<DataArray type="Float64" Name="{name}" format="ascii">"#
            );
            for v in values {
                let _ = write!(s, "{v:e} ");
            }
            let _ = writeln!(s, "\n</DataArray>");
        }
        for (name, values) in &self.vectors {
            let _ = writeln!(
                s,
                r#"<DataArray type="Float64" Name="{name}" NumberOfComponents="3" format="ascii">"#
            );
            for v in values {
                let _ = write!(s, "{:e} {:e} {:e} ", v[0], v[1], v[2]);
            }
            let _ = writeln!(s, "\n</DataArray>");
        }
        let _ = writeln!(s, "</PointData>");
        let _ = writeln!(
            s,
            r#"<Points><DataArray type="Float64" NumberOfComponents="3" format="ascii">"#
        );
        for x in &self.positions {
            let _ = write!(s, "{:e} {:e} {:e} ", x[0], x[1], x[2]);
        }
        let _ = writeln!(s, "\n</DataArray></Points>");
        let _ = writeln!(s, "<Cells>");
        let _ = writeln!(
            s,
            r#"<DataArray type="Int64" Name="connectivity" format="ascii">"#
        );
        for k in 0..n {
            let _ = write!(s, "{k} ");
        }
        let _ = writeln!(s, "\n</DataArray>");
        let _ = writeln!(
            s,
            r#"<DataArray type="Int64" Name="offsets" format="ascii">"#
        );
        for k in 1..=n {
            let _ = write!(s, "{k} ");
        }
        let _ = writeln!(s, "\n</DataArray>");
        // VTK_VERTEX = 1
        let _ = writeln!(s, r#"<DataArray type="UInt8" Name="types" format="ascii">"#);
        for _ in 0..n {
            s.push_str("1 ");
        }
        let _ = writeln!(s, "\n</DataArray>");
        let _ = writeln!(s, "</Cells>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>");
        s
    }
}
