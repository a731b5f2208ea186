//! Counts as people write them (the command line's `--paths`, `--spp`): `4000000`, `4_000_000`, `4,000,000`, `4M`, `2.5k`,
//! `1e6`, `1.5e6`. Suffixes k, M, G, T are powers of 1000. The value must be a whole number of
//! at least 1 that fits 64 bits; it is computed exactly (no floating point), so `1e6` is
//! 1000000 and `1.0000001e6` is refused as not whole. A negative count is refused as such (the
//! command line's options take hyphen values so that `-5` reaches this parser instead of clap's
//! advice to write `-- -5`). [`parse_spp`] reads camera paths per pixel the same way, up to 32 bits.

/// A text that is not a count.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum CountError {
    /// It starts with a minus sign.
    #[error("'{0}': a count must be positive (at least 1)")]
    Negative(String),
    /// Not digits, a point, an exponent and a suffix.
    #[error("'{0}' is not a count (e.g. 4000000, 4M, 4e6)")]
    NotACount(String),
    /// A fraction is left.
    #[error("'{0}' is not a whole number")]
    NotWhole(String),
    /// It is 0.
    #[error("'{0}': the count must be at least 1")]
    Zero(String),
    /// Beyond 64 bits.
    #[error("'{0}' is more than a 64-bit count ({max})", max = u64::MAX)]
    TooBig(String),
    /// Beyond 32 bits, for camera paths per pixel.
    #[error("'{0}': at most {max} camera paths per pixel", max = u32::MAX)]
    TooManyPerPixel(String),
}

/// Parses a count (see the module documentation).
pub fn parse_count(s: &str) -> Result<u64, CountError> {
    let t: String = s.trim().chars().filter(|c| *c != '_' && *c != ',').collect();
    if t.starts_with('-') {
        return Err(CountError::Negative(s.into()));
    }
    let (number, suffix) = match t.char_indices().last() {
        Some((i, c)) if "kKMGT".contains(c) => (
            &t[..i],
            match c {
                'k' | 'K' => 3,
                'M' => 6,
                'G' => 9,
                _ => 12,
            },
        ),
        _ => (t.as_str(), 0),
    };
    let (mantissa, exponent) = match number.split_once(['e', 'E']) {
        Some((m, e)) => match e.parse::<i32>() {
            Ok(e) => (m, e),
            Err(_) => return Err(CountError::NotACount(s.into())),
        },
        None => (number, 0),
    };
    let (whole, fraction) = mantissa.split_once('.').unwrap_or((mantissa, ""));
    if whole.is_empty() && fraction.is_empty()
        || !whole.chars().chain(fraction.chars()).all(|c| c.is_ascii_digit())
    {
        return Err(CountError::NotACount(s.into()));
    }
    let digits: String = format!("{whole}{fraction}");
    let digits = digits.trim_start_matches('0');
    let scale = exponent as i64 + suffix - fraction.len() as i64;
    let too_big = || CountError::TooBig(s.into());
    let value: u128 = if digits.is_empty() {
        0
    } else if scale >= 0 {
        if digits.len() as i64 + scale > 20 {
            return Err(too_big());
        }
        digits.parse::<u128>().map_err(|_| too_big())? * 10u128.pow(scale as u32)
    } else {
        let cut = (-scale) as usize;
        let (int, rest) = if digits.len() > cut { digits.split_at(digits.len() - cut) } else { ("", digits) };
        if rest.chars().any(|c| c != '0') {
            return Err(CountError::NotWhole(s.into()));
        }
        if int.len() > 20 {
            return Err(too_big());
        }
        if int.is_empty() { 0 } else { int.parse::<u128>().map_err(|_| too_big())? }
    };
    if value == 0 {
        return Err(CountError::Zero(s.into()));
    }
    u64::try_from(value).map_err(|_| too_big())
}

/// Parses camera paths per pixel (`--spp`): a count as [`parse_count`] reads it, at most
/// `u32::MAX`.
pub fn parse_spp(s: &str) -> Result<u32, CountError> {
    let n = parse_count(s)?;
    u32::try_from(n).map_err(|_| CountError::TooManyPerPixel(s.into()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn negative_counts_and_too_many_paths_per_pixel_are_worded() {
        let e = parse_count("-5").unwrap_err().to_string();
        assert!(e.contains("must be positive"), "{e}");
        assert_eq!(parse_spp("1e9").unwrap(), 1_000_000_000);
        assert_eq!(parse_spp("16").unwrap(), 16);
        assert!(parse_spp("1e10").unwrap_err().to_string().contains("4294967295"));
        assert!(parse_spp("0").is_err());
    }

    #[test]
    fn counts_are_read_the_ways_people_write_them() {
        for (s, n) in [
            ("4000000", 4_000_000),
            ("4_000_000", 4_000_000),
            ("2,000,000", 2_000_000),
            ("4M", 4_000_000),
            ("2.5k", 2500),
            ("1e6", 1_000_000),
            ("1.5E6", 1_500_000),
            ("0.5M", 500_000),
            ("18446744073709551615", u64::MAX),
            ("1G", 1_000_000_000),
        ] {
            assert_eq!(parse_count(s).unwrap(), n, "{s}");
        }
        for bad in [
            "",
            "0",
            "0e5",
            "1.5",
            "1e-1",
            "-3",
            "4m",
            "x",
            "1e",
            "18446744073709551616",
            "1e20",
            "1e400",
            ".",
        ] {
            assert!(parse_count(bad).is_err(), "{bad}");
        }
    }
}
