//! Whether a model fits in the machine's memory, known before a run: a
//! run's peak memory grows with its elements (the Newton matrix's values
//! and factors, the element data, the outputs' buffers) at about
//! [`BYTES_PER_ELEMENT`] (measured: peak resident size of the pendulum
//! scene at 10 000 and 40 000 elements, 0.58 and 2.18 GB; BENCHMARKS.md).

/// Peak memory per element of a dynamic run, bytes (the measurement's
/// 53 KB rounded up).
pub const BYTES_PER_ELEMENT: u64 = 56_000;

/// Peak memory of a run of no elements, bytes.
pub const BASE_BYTES: u64 = 64 << 20;

/// The peak memory a run of `elements` elements needs, bytes.
pub fn needed_bytes(elements: usize) -> u64 {
    BASE_BYTES.saturating_add((elements as u64).saturating_mul(BYTES_PER_ELEMENT))
}

/// The memory available to a new process, bytes (`MemAvailable` of
/// /proc/meminfo); `None` where it cannot be read.
pub fn available_bytes() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = text.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb.saturating_mul(1024))
}

/// Why `elements` elements will not fit in `available` bytes, with the
/// count that would (`None`: they fit).
pub fn shortfall(elements: usize, available: u64) -> Option<String> {
    let needed = needed_bytes(elements);
    (needed > available).then(|| {
        let fit = available.saturating_sub(BASE_BYTES) / BYTES_PER_ELEMENT;
        format!(
            "{elements} elements need about {:.1} GB, and this machine has {:.1} GB available: \
             at most about {fit} elements fit",
            needed as f64 / 1e9,
            available as f64 / 1e9
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_million_elements_do_not_fit_in_24_gb() {
        let gb = 1u64 << 30;
        let message = shortfall(1_000_000, 24 * gb).expect("too large");
        assert!(
            message.contains("at most about 458976 elements fit"),
            "{message}"
        );
        assert!(shortfall(10_000, 24 * gb).is_none());
    }
}
