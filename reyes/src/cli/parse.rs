//! The value parsers of the command line that clap has no built-in for:
//! byte counts, vectors and camera pans.

use glam::Vec3;

/// A byte count: digits with an optional binary suffix K, M, G or T
/// (case-insensitive, an optional trailing `B` or `iB` allowed: `16M`, `2GiB`).
pub(crate) fn parse_bytes(text: &str) -> Result<u64, String> {
    let trimmed = text.trim();
    let upper = trimmed.to_ascii_uppercase();
    let unitless = upper
        .strip_suffix("IB")
        .or_else(|| upper.strip_suffix('B'))
        .unwrap_or(&upper);
    let (digits, shift) = match unitless.as_bytes().last() {
        Some(b'K') => (&unitless[..unitless.len() - 1], 10),
        Some(b'M') => (&unitless[..unitless.len() - 1], 20),
        Some(b'G') => (&unitless[..unitless.len() - 1], 30),
        Some(b'T') => (&unitless[..unitless.len() - 1], 40),
        _ => (unitless, 0),
    };
    let value: u64 = digits
        .trim()
        .parse()
        .map_err(|_| format!("{text:?} is not a byte count (e.g. 1048576, 512K, 16M, 2G)"))?;
    value
        .checked_mul(1u64 << shift)
        .ok_or_else(|| format!("{text:?} is too large"))
}

/// Three comma-separated finite numbers, `x,y,z`.
pub(crate) fn parse_vec3(text: &str) -> Result<Vec3, String> {
    let parts: Vec<&str> = text.split(',').map(str::trim).collect();
    if parts.len() != 3 {
        return Err(format!(
            "expected x,y,z (three comma-separated numbers), got {text:?}"
        ));
    }
    let mut v = [0.0f32; 3];
    for (slot, part) in v.iter_mut().zip(&parts) {
        *slot = part
            .parse()
            .map_err(|e| format!("{part:?} is not a number: {e}"))?;
        if !slot.is_finite() {
            return Err(format!("{part:?} is not finite"));
        }
    }
    Ok(Vec3::from_array(v))
}

/// A camera pan in degrees, within (-180, 180): the orientation in between
/// turns the shorter way (slerp), so a larger pan would turn the other way.
pub(crate) fn parse_pan(text: &str) -> Result<f32, String> {
    let degrees: f32 = text
        .trim()
        .parse()
        .map_err(|e| format!("{text:?} is not a number: {e}"))?;
    if degrees.abs() < 180.0 {
        Ok(degrees)
    } else {
        Err(format!(
            "{text} is not in (-180, 180): the camera turns the shorter way between its two poses"
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::parse_bytes;

    #[test]
    fn byte_counts_parse_with_binary_suffixes() {
        assert_eq!(parse_bytes("1048576"), Ok(1 << 20));
        assert_eq!(parse_bytes("512K"), Ok(512 << 10));
        assert_eq!(parse_bytes("16m"), Ok(16 << 20));
        assert_eq!(parse_bytes("2GiB"), Ok(2 << 30));
        assert_eq!(parse_bytes("1TB"), Ok(1 << 40));
        assert!(parse_bytes("lots").is_err());
        assert!(parse_bytes("-1").is_err());
        assert!(parse_bytes("99999999999T").is_err());
    }
}
