//! The scene's values written as text, as flags (`pelt render --size 640x360`) and `pelt
//! sweep`'s knob lists give them, each within a range it is given: a knob's range is its spec's
//! ([`crate::knobs::spec`], which the scene file checks too), so a value the command line
//! accepts is one a scene file accepts. Errors say what was given and what is allowed.

use std::ops::RangeInclusive;

/// The longest side of an output, in pixels.
pub const MAX_SIDE: u32 = 8192;

/// `WIDTHxHEIGHT`, each side 1 to [`MAX_SIDE`] (an output size).
pub fn size(s: &str) -> Result<(u32, u32), String> {
    sides(s, 1..=MAX_SIDE)
}

/// `WIDTHxHEIGHT`, each side in `range`.
pub fn sides(s: &str, range: RangeInclusive<u32>) -> Result<(u32, u32), String> {
    let parsed = s
        .split_once(['x', 'X'])
        .and_then(|(w, h)| Some((w.parse::<u32>().ok()?, h.parse::<u32>().ok()?)));
    match parsed {
        Some((w, h)) if range.contains(&w) && range.contains(&h) => Ok((w, h)),
        _ => Err(format!(
            "{s:?} is not WIDTHxHEIGHT with sides {} to {}",
            range.start(),
            range.end()
        )),
    }
}

/// A scale in `range`.
pub fn scale(s: &str, range: RangeInclusive<f32>) -> Result<f32, String> {
    match s.parse::<f32>() {
        Ok(v) if range.contains(&v) => Ok(v),
        _ => Err(format!(
            "{s:?} is not a scale from {} to {}",
            range.start(),
            range.end()
        )),
    }
}

/// A power of two in `r`.
pub fn power_of_two(s: &str, r: RangeInclusive<u32>) -> Result<u32, String> {
    match s.parse::<u32>() {
        Ok(v) if v.is_power_of_two() && r.contains(&v) => Ok(v),
        _ => Err(format!(
            "{s:?} is not a power of two from {} to {}",
            r.start(),
            r.end()
        )),
    }
}

/// A count in `range` (one of the scene's ranges: shells, steps, layers, bounces).
pub fn count(s: &str, range: RangeInclusive<u32>) -> Result<u32, String> {
    match s.parse::<u32>() {
        Ok(v) if range.contains(&v) => Ok(v),
        _ => Err(format!(
            "{s:?} is not a whole number from {} to {}",
            range.start(),
            range.end()
        )),
    }
}

/// A finite number (a time, an angle).
pub fn finite(s: &str) -> Result<f32, String> {
    match s.parse::<f32>() {
        Ok(v) if v.is_finite() => Ok(v),
        _ => Err(format!("{s:?} is not a finite number")),
    }
}

/// A positive, finite number of milliseconds (a frame budget).
pub fn positive_ms(s: &str) -> Result<f64, String> {
    match s.parse::<f64>() {
        Ok(v) if v.is_finite() && v > 0.0 => Ok(v),
        _ => Err(format!("{s:?} is not a positive number of milliseconds")),
    }
}

/// A switch: `on` or `off` (`true` and `false` too).
pub fn switch(s: &str) -> Result<bool, String> {
    match s {
        "on" | "true" => Ok(true),
        "off" | "false" => Ok(false),
        _ => Err(format!("{s:?} is not on or off")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::LBUFFER_SCALE;
    use crate::scene::reflection_limits::{CUBE_SIZE, LAYERS};

    #[test]
    fn parsers_accept_the_scene_files_ranges_and_nothing_else() {
        assert_eq!(size("640x360"), Ok((640, 360)));
        assert_eq!(size("8192X1"), Ok((MAX_SIDE, 1)));
        for bad in ["8193x10", "0x10", "640", "640x", "axb", "-1x4"] {
            assert!(size(bad).is_err(), "{bad}");
        }
        let lbuffer_scale = |s| scale(s, LBUFFER_SCALE);
        assert_eq!(lbuffer_scale("0.5"), Ok(0.5));
        assert!(lbuffer_scale("0.05").is_err() && lbuffer_scale("NaN").is_err());
        let cube_size = |s| power_of_two(s, CUBE_SIZE);
        assert_eq!(cube_size("256"), Ok(256));
        assert!(cube_size("100").is_err() && cube_size("4").is_err());
        assert_eq!(count("8", LAYERS), Ok(8));
        let e = count("9", LAYERS).expect_err("9 layers");
        assert_eq!(e, "\"9\" is not a whole number from 3 to 8");
        assert_eq!((switch("on"), switch("false")), (Ok(true), Ok(false)));
        assert!(switch("yes").is_err());
    }
}
