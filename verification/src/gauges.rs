//! Gauges: the overpressure and particle velocity at fixed places through a run, and what a
//! blast engineer reads off them: arrival, rise time, peak and positive impulse.

use serde::Serialize;

/// What a gauge read, summed up (SI). Pressures are above the ambient pressure.
#[derive(Clone, Debug, PartialEq, Serialize, serde::Deserialize)]
pub struct Gauge {
    pub name: String,
    pub position_m: f64,
    /// The first time the overpressure reached 5 % of its peak (NaN if it never rose).
    pub arrival_s: f64,
    pub peak_pressure_pa: f64,
    /// The largest |v|.
    pub peak_velocity_m_s: f64,
    /// ∫ overpressure dt over the positive phase: from the arrival until the overpressure
    /// first falls below zero after its peak (or to the end of the record).
    pub impulse_pa_s: f64,
    /// Whether the positive phase ended within the record (else the impulse is a lower bound).
    pub positive_phase_ended: bool,
    /// The front's rise: from the first time the overpressure reached 10 % of its peak to the
    /// first time it reached 90 % (NaN if it never rose). A structure's response to a pulse
    /// depends on how fast it loads, not only on its peak.
    #[serde(
        default = "not_a_number",
        deserialize_with = "crate::record::number_or_nan"
    )]
    pub rise_time_s: f64,
}

impl Gauge {
    /// What loads a structure the gauge stands for, by name: the peak stress (or
    /// overpressure), the peak velocity, the positive impulse and the rise time.
    pub fn loading(&self) -> [(&'static str, f64); 4] {
        [
            ("peak_stress", self.peak_pressure_pa),
            ("peak_velocity", self.peak_velocity_m_s),
            ("impulse", self.impulse_pa_s),
            ("rise_time", self.rise_time_s),
        ]
    }
}

fn not_a_number() -> f64 {
    f64::NAN
}

/// The fractions of the peak between whose first crossings the rise time runs.
pub const RISE_FROM: f64 = 0.1;
pub const RISE_TO: f64 = 0.9;

/// The fraction of the peak whose first crossing counts as the arrival.
pub const ARRIVAL_FRACTION: f64 = 0.05;

/// A gauge's history: time, overpressure, velocity.
#[derive(Clone, Debug, Default)]
pub struct GaugeTrace {
    pub name: String,
    pub position_m: f64,
    pub time: Vec<f64>,
    pub overpressure: Vec<f64>,
    pub velocity: Vec<f64>,
}

impl GaugeTrace {
    pub fn new(name: impl Into<String>, position_m: f64) -> Self {
        Self {
            name: name.into(),
            position_m,
            ..Self::default()
        }
    }

    pub fn push(&mut self, time: f64, overpressure: f64, velocity: f64) {
        self.time.push(time);
        self.overpressure.push(overpressure);
        self.velocity.push(velocity);
    }

    /// Where `values` (sampled at `self.time`) crosses `level` between samples k and k + 1,
    /// linearly interpolated.
    fn crossing(&self, k: usize, level: f64) -> f64 {
        let (p0, p1) = (self.overpressure[k], self.overpressure[k + 1]);
        let (t0, t1) = (self.time[k], self.time[k + 1]);
        if p1 == p0 {
            t1
        } else {
            t0 + (level - p0) / (p1 - p0) * (t1 - t0)
        }
    }

    /// The first time the overpressure reaches `level` (interpolated between samples; NaN if
    /// it never does).
    fn first_crossing(&self, level: f64) -> f64 {
        match self.overpressure.iter().position(|&x| x >= level) {
            None => f64::NAN,
            Some(0) => self.time[0],
            Some(k) => self.crossing(k - 1, level),
        }
    }

    /// The overpressure against time as a line labelled `label`, in ms and kPa.
    pub fn overpressure_series(&self, label: impl Into<String>) -> crate::svg::Series {
        crate::svg::Series {
            label: label.into(),
            points: self
                .time
                .iter()
                .zip(&self.overpressure)
                .map(|(&t, &p)| (1e3 * t, 1e-3 * p))
                .collect(),
            style: crate::svg::Style::Line,
        }
    }

    pub fn summary(&self) -> Gauge {
        let p = &self.overpressure;
        let peak = p.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
        let peak_velocity = self.velocity.iter().map(|v| v.abs()).fold(0.0, f64::max);
        let mut gauge = Gauge {
            name: self.name.clone(),
            position_m: self.position_m,
            arrival_s: f64::NAN,
            peak_pressure_pa: peak,
            peak_velocity_m_s: peak_velocity,
            impulse_pa_s: 0.0,
            positive_phase_ended: false,
            rise_time_s: f64::NAN,
        };
        if p.len() < 2 || peak.is_nan() || peak <= 0.0 {
            return gauge;
        }
        let level = ARRIVAL_FRACTION * peak;
        let first = p
            .iter()
            .position(|&x| x >= level)
            .expect("the peak is above");
        gauge.arrival_s = if first == 0 {
            self.time[0]
        } else {
            self.crossing(first - 1, level)
        };
        gauge.rise_time_s =
            self.first_crossing(RISE_TO * peak) - self.first_crossing(RISE_FROM * peak);
        let peak_at = p
            .iter()
            .position(|&x| x == peak)
            .expect("the peak is a sample");
        // trapezoids from the arrival to the end of the positive phase
        let mut impulse = 0.5 * (level + p[first]) * (self.time[first] - gauge.arrival_s);
        for k in first..p.len() - 1 {
            if k >= peak_at && p[k + 1] < 0.0 {
                let end = self.crossing(k, 0.0);
                impulse += 0.5 * p[k] * (end - self.time[k]);
                gauge.positive_phase_ended = true;
                break;
            }
            impulse += 0.5 * (p[k] + p[k + 1]) * (self.time[k + 1] - self.time[k]);
        }
        gauge.impulse_pa_s = impulse;
        gauge
    }
}

/// Gauge histories sampled at the same times as one table: `t`, then per trace its
/// overpressure (or stress) and velocity columns, named by `columns`.
pub fn history_table(
    traces: &[GaugeTrace],
    columns: impl Fn(&GaugeTrace) -> [String; 2],
) -> crate::record::Table {
    let mut names = vec!["t".to_string()];
    names.extend(traces.iter().flat_map(&columns));
    let names: Vec<&str> = names.iter().map(String::as_str).collect();
    let mut table = crate::record::Table::new(&names);
    if let Some(first) = traces.first() {
        for (k, &t) in first.time.iter().enumerate() {
            let mut row = vec![t];
            for trace in traces {
                row.push(trace.overpressure[k]);
                row.push(trace.velocity[k]);
            }
            table.rows.push(row);
        }
    }
    table
}

/// The value of a 1D profile at `x`: linear interpolation between the two samples that
/// straddle it in `sorted` (x ascending), the end value beyond either end.
pub fn interpolate(sorted: &[(f64, f64)], x: f64) -> f64 {
    let k = sorted.partition_point(|s| s.0 < x);
    match k {
        0 => sorted[0].1,
        k if k == sorted.len() => sorted[k - 1].1,
        k => {
            let (a, b) = (sorted[k - 1], sorted[k]);
            a.1 + (x - a.0) / (b.0 - a.0) * (b.1 - a.1)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The Friedlander waveform p = P (1 − τ) e^{−bτ}, τ = (t − t_a)/t_d: its positive
    /// impulse is P t_d [1/b − (1 − e^{−b})/b²], its peak P at t_a.
    #[test]
    fn a_friedlander_wave_reads_its_exact_arrival_peak_and_impulse() {
        let (arrival, duration, peak, b) = (2e-3, 4e-3, 1e5, 1.5);
        let mut trace = GaugeTrace::new("g", 3.0);
        let steps = 20_000;
        for k in 0..=steps {
            let t = 12e-3 * k as f64 / steps as f64;
            let tau = (t - arrival) / duration;
            let p = if tau < 0.0 {
                0.0
            } else {
                peak * (1.0 - tau) * (-b * tau).exp()
            };
            trace.push(t, p, p / 400.0);
        }
        let g = trace.summary();
        let exact_impulse = peak * duration * (1.0 / b - (1.0 - (-b).exp()) / (b * b));
        // the sampling interval 6e-7 s bounds the arrival's error; the trapezoids' error on
        // the impulse is of order (Δt/t_d)² plus the missing sliver before the arrival
        assert!((g.arrival_s - arrival).abs() < 1e-6, "{}", g.arrival_s);
        assert!((g.peak_pressure_pa / peak - 1.0).abs() < 1e-3);
        assert!((g.impulse_pa_s / exact_impulse - 1.0).abs() < 1e-3, "{g:?}");
        assert!(g.positive_phase_ended);
        assert!((g.peak_velocity_m_s - peak / 400.0).abs() < 1.0);
        // a jump: the rise is shorter than a sampling interval
        assert!(
            g.rise_time_s >= 0.0 && g.rise_time_s < 6e-7,
            "{}",
            g.rise_time_s
        );
    }

    /// A linear ramp from 0 at t0 to P at t0 + T rises from 10 % to 90 % in 0.8 T, exactly
    /// (the crossings are interpolated linearly, as the ramp is).
    #[test]
    fn a_ramp_rises_over_four_fifths_of_its_length() {
        let (t0, length, peak) = (1e-3, 4e-3, 2e5);
        let mut trace = GaugeTrace::new("ramp", 1.0);
        for k in 0..=1000 {
            let t = 10e-3 * k as f64 / 1000.0;
            let p = (peak * (t - t0) / length).clamp(0.0, peak);
            trace.push(t, p, 0.0);
        }
        let g = trace.summary();
        assert!(
            (g.rise_time_s - 0.8 * length).abs() < 1e-12,
            "{}",
            g.rise_time_s
        );
    }

    /// The loading names each summary field it reads, in the order peak stress, peak
    /// velocity, impulse, rise time.
    #[test]
    fn a_gauges_loading_names_its_fields() {
        let g = Gauge {
            name: "g".into(),
            position_m: 1.0,
            arrival_s: 0.5,
            peak_pressure_pa: 2.0,
            peak_velocity_m_s: 3.0,
            impulse_pa_s: 4.0,
            positive_phase_ended: true,
            rise_time_s: 5.0,
        };
        assert_eq!(
            g.loading(),
            [
                ("peak_stress", 2.0),
                ("peak_velocity", 3.0),
                ("impulse", 4.0),
                ("rise_time", 5.0)
            ]
        );
    }

    /// A gauge kept before the rise time was read comes back with a NaN rise time, never a
    /// made-up number; one written with a NaN (JSON's null) likewise.
    #[test]
    fn a_gauge_without_a_rise_time_reads_nan() {
        let old = r#"{"name":"g","position_m":1.0,"arrival_s":0.5,"peak_pressure_pa":2.0,
            "peak_velocity_m_s":3.0,"impulse_pa_s":4.0,"positive_phase_ended":true}"#;
        let g: Gauge = serde_json::from_str(old).unwrap();
        assert!(g.rise_time_s.is_nan());
        let null = old.replace("true}", r#"true,"rise_time_s":null}"#);
        let g: Gauge = serde_json::from_str(&null).unwrap();
        assert!(g.rise_time_s.is_nan());
    }

    #[test]
    fn a_gauge_that_saw_nothing_has_no_arrival() {
        let mut trace = GaugeTrace::new("quiet", 1.0);
        for k in 0..10 {
            trace.push(k as f64, 0.0, 0.0);
        }
        let g = trace.summary();
        assert!(g.arrival_s.is_nan());
        assert!(g.rise_time_s.is_nan());
        assert_eq!(g.impulse_pa_s, 0.0);
    }

    #[test]
    fn interpolation_is_linear_between_samples_and_flat_beyond() {
        let profile = [(0.0, 1.0), (1.0, 3.0), (3.0, 7.0)];
        assert_eq!(interpolate(&profile, 0.5), 2.0);
        assert_eq!(interpolate(&profile, 2.0), 5.0);
        assert_eq!(interpolate(&profile, -1.0), 1.0);
        assert_eq!(interpolate(&profile, 4.0), 7.0);
    }
}
