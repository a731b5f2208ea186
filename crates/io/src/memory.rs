//! How much memory the machine can give a new allocation, so that a command can refuse a film
//! (an image, a meter grid) or any work held in memory (a benchmark's traced paths) that cannot
//! fit before it does any work, with a clear error, instead
//! of being killed or aborting halfway. Linux: `MemAvailable` of `/proc/meminfo`, lowered to a
//! cgroup v2 limit (`memory.max` − `memory.current`) when the process runs under one.

use std::path::Path;

/// Bytes available for new allocations, or `None` where that is unknown (other systems).
pub fn available_bytes() -> Option<u64> {
    let meminfo = std::fs::read_to_string("/proc/meminfo").ok()?;
    let mut available = meminfo_available(&meminfo)?;
    if let Some(limit) = cgroup_headroom(Path::new("/sys/fs/cgroup")) {
        available = available.min(limit);
    }
    Some(available)
}

/// `MemAvailable` of a `/proc/meminfo` text, in bytes.
fn meminfo_available(text: &str) -> Option<u64> {
    let line = text.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    kb.checked_mul(1024)
}

/// `memory.max − memory.current` of the cgroup v2 mounted at `root`, if it has a limit.
fn cgroup_headroom(root: &Path) -> Option<u64> {
    let read = |name: &str| std::fs::read_to_string(root.join(name)).ok()?.trim().parse::<u64>().ok();
    let (max, current) = (read("memory.max")?, read("memory.current")?);
    Some(max.saturating_sub(current))
}

/// `n` bytes readably: "832 bytes", "1.4 MB", "2.10 GB", "3.20 TB", "161.00 PB", "18.45 EB"
/// (the largest unit below the size, so no figure has more than three digits before its point).
pub fn readable_bytes(n: u64) -> String {
    let x = n as f64;
    if n < 1000 {
        format!("{n} bytes")
    } else if x < 1e6 {
        format!("{:.1} kB", x / 1e3)
    } else if x < 1e9 {
        format!("{:.1} MB", x / 1e6)
    } else if x < 1e12 {
        format!("{:.2} GB", x / 1e9)
    } else if x < 1e15 {
        format!("{:.2} TB", x / 1e12)
    } else if x < 1e18 {
        format!("{:.2} PB", x / 1e15)
    } else {
        format!("{:.2} EB", x / 1e18)
    }
}

/// A film too large for the memory available.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error(
    "{what} of {width}x{height} needs about {} of memory ({} bytes a pixel to accumulate, {output_bytes} to \
     write), but {} are available: choose a smaller size",
    readable_bytes(*need), opticks_core::film::FILM_BYTES_PER_PIXEL, readable_bytes(*available)
)]
pub struct FilmTooLarge {
    /// What the film is ("an image", "a meter").
    pub what: String,
    /// Its width.
    pub width: u32,
    /// Its height.
    pub height: u32,
    /// Bytes a pixel of its output needs.
    pub output_bytes: u64,
    /// Bytes needed in all.
    pub need: u64,
    /// Bytes available.
    pub available: u64,
}

/// Work that needs more memory than is available.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{what} needs about {} of memory, but {} are available", readable_bytes(*need), readable_bytes(*available))]
pub struct NotEnoughMemory {
    /// What needs it.
    pub what: String,
    /// Bytes needed.
    pub need: u64,
    /// Bytes available.
    pub available: u64,
}

/// Refuses, before any work, `what` needing `need` bytes when fewer are available (unknown
/// availability refuses nothing).
pub fn check_fits(what: &str, need: u64) -> Result<(), NotEnoughMemory> {
    match available_bytes() {
        Some(available) if need > available => {
            Err(NotEnoughMemory { what: what.to_string(), need, available })
        }
        _ => Ok(()),
    }
}

/// Bytes a pixel of an image output needs while it is written (the f32 RGB copy the writers
/// take, and their own buffer).
pub const IMAGE_OUTPUT_BYTES: u64 = 12 + 8;

/// Refuses, before any work, a `width`×`height` film (an image, or a meter's cells) whose
/// accumulation over `threads` threads ([`opticks_core::film::accumulation_bytes`]) and output
/// (`output_bytes` a pixel: the f32 image or the CSV) need more memory than is available.
pub fn check_film_fits(
    what: &str,
    (width, height): (u32, u32),
    output_bytes: u64,
    threads: usize,
) -> Result<(), FilmTooLarge> {
    let pixels = width as u64 * height as u64;
    let need = opticks_core::film::accumulation_bytes(width, height, threads)
        .saturating_add(pixels.saturating_mul(output_bytes));
    match available_bytes() {
        Some(available) if need > available => {
            Err(FilmTooLarge { what: what.to_string(), width, height, output_bytes, need, available })
        }
        _ => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn meminfo_and_cgroup_limits_are_read() {
        let text = "MemTotal:       24000000 kB\nMemFree:  100 kB\nMemAvailable:   22279392 kB\n";
        assert_eq!(meminfo_available(text), Some(22_279_392 * 1024));
        assert_eq!(meminfo_available("MemTotal: 5 kB\n"), None);
        let dir = tempfile::tempdir().unwrap();
        assert_eq!(cgroup_headroom(dir.path()), None);
        std::fs::write(dir.path().join("memory.max"), "max\n").unwrap();
        std::fs::write(dir.path().join("memory.current"), "1000\n").unwrap();
        assert_eq!(cgroup_headroom(dir.path()), None, "no limit");
        std::fs::write(dir.path().join("memory.max"), "3000\n").unwrap();
        assert_eq!(cgroup_headroom(dir.path()), Some(2000));
        assert_eq!(
            (readable_bytes(25_769_803_776), readable_bytes(403_000_000)),
            ("25.77 GB".into(), "403.0 MB".into())
        );
        assert_eq!(readable_bytes(224), "224 bytes");
        assert_eq!(readable_bytes(1_400_000), "1.4 MB");
        assert_eq!(readable_bytes(3_200_000_000_000), "3.20 TB");
        assert_eq!(readable_bytes(161_000_000_000_000_000), "161.00 PB", "not 161000000.00 GB");
        assert_eq!(readable_bytes(u64::MAX), "18.45 EB");
        #[cfg(target_os = "linux")]
        assert!(available_bytes().is_some_and(|b| b > 0));
    }
}
