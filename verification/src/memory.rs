//! How much memory a run needs and how much this machine has, so that a run too large for it is
//! refused before it starts instead of failing an allocation part-way.

/// Peak resident bytes per particle of a run in `dimension` dimensions: the particle fields,
/// the mirror and periodic images, the neighbour lists (searched with h widened by the skin, so
/// (1.2)^D times the pairs the kernel reaches), the pairs the kernel reaches with their kernel
/// derivatives (`KernelPairs`, 32 bytes a pair) and the output snapshot. Measured peaks
/// (`/usr/bin/time`, release build): sedov-3d at 27 000 particles 143 MB (5.3 kB each),
/// sedov-2d at 25 600 particles 68 MB (2.7 kB), sod at 22 500 particles 27 MB (1.2 kB, most of
/// it the program itself); rounded up so that the estimate is an upper bound.
pub fn bytes_per_particle(dimension: usize) -> f64 {
    match dimension {
        1 => 1536.0,
        2 => 3584.0,
        _ => 7168.0,
    }
}

/// The memory available to a new run (Linux `MemAvailable`), or None where it cannot be read.
pub fn available_bytes() -> Option<f64> {
    let info = std::fs::read_to_string("/proc/meminfo").ok()?;
    parse_available(&info)
}

fn parse_available(meminfo: &str) -> Option<f64> {
    let line = meminfo.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kib: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib * 1024.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_the_available_memory_in_bytes() {
        let info = "MemTotal:       24576000 kB\nMemFree:  100 kB\nMemAvailable:   20000000 kB\n";
        assert_eq!(parse_available(info), Some(20_000_000.0 * 1024.0));
        assert_eq!(parse_available("MemTotal: 1 kB\n"), None);
    }
}
